// delegate.cpp: find ltm-torch beside this program and exec it.
#include "delegate.h"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>

namespace ltm::cli {

bool is_libtorch_command(const std::string &name) {
    for (const LibtorchCommand &c : k_libtorch_commands)
        if (name == c.name) return true;
    return false;
}

std::string exec_libtorch_program(const std::vector<std::string> &args) {
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) return "cannot locate this program (/proc/self/exe: " + ec.message() + ")";
    const std::filesystem::path torch = self.parent_path() / "ltm-torch";
    if (!std::filesystem::exists(torch)) return "this build has no libtorch (" + torch.string() + " does not exist)";
    // Never loop: not into this very file (a link named ltm-torch), and not twice in one chain.
    if (std::filesystem::equivalent(torch, self, ec) || std::getenv(k_delegated_env))
        return torch.string() + " is not a libtorch build of ltm (it handed the command back)";
    std::vector<std::string> owned;
    owned.reserve(args.size() + 1);
    owned.push_back(torch.string());
    owned.insert(owned.end(), args.begin(), args.end());
    std::vector<char *> argv;
    for (std::string &a : owned) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::cout.flush(), std::cerr.flush(), std::fflush(nullptr);
    ::setenv(k_delegated_env, "1", 1);
    ::execv(owned[0].c_str(), argv.data());
    ::unsetenv(k_delegated_env);
    return "cannot run " + torch.string() + ": " + std::strerror(errno);
}

}  // namespace ltm::cli
