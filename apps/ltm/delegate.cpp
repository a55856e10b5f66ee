// delegate.cpp: find ltm-torch beside this program and exec it.
#include "delegate.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>

namespace ltm::cli {

bool is_libtorch_command(const std::string &name) {
    return name == "train" || name == "export" || name == "eval" || name == "eval-directional";
}

std::string exec_libtorch_program(const std::vector<std::string> &args) {
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) return "cannot locate this program (/proc/self/exe: " + ec.message() + ")";
    const std::filesystem::path torch = self.parent_path() / "ltm-torch";
    if (torch == self) return "this is ltm-torch";   // never loop
    if (!std::filesystem::exists(torch)) return "this build has no libtorch (" + torch.string() + " does not exist)";
    std::vector<std::string> owned;
    owned.reserve(args.size() + 1);
    owned.push_back(torch.string());
    owned.insert(owned.end(), args.begin(), args.end());
    std::vector<char *> argv;
    for (std::string &a : owned) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::cout.flush(), std::cerr.flush(), std::fflush(nullptr);
    ::execv(owned[0].c_str(), argv.data());
    return "cannot run " + torch.string() + ": " + std::strerror(errno);
}

}  // namespace ltm::cli
