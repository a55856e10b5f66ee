// rank_launcher.cpp: fork + execve (the environment is built before fork, so the child calls
// nothing but execve: the parent may have threads), then waitpid over the group.
#include "rank_launcher.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <map>
#include <thread>

#include "ltm/core/error.h"
#include "ltm/core/log.h"

extern char **environ;

namespace ltm::cli {

int free_local_port() {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) LTM_THROW("--nproc: cannot open a socket to find a free port (", std::strerror(errno), ")");
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = 0;
    socklen_t len = sizeof a;
    const bool ok = ::bind(fd, reinterpret_cast<sockaddr *>(&a), sizeof a) == 0 &&
                    ::getsockname(fd, reinterpret_cast<sockaddr *>(&a), &len) == 0;
    ::close(fd);
    if (!ok) LTM_THROW("--nproc: cannot bind a local port (", std::strerror(errno), ")");
    return ntohs(a.sin_port);
}

void launch_local_ranks(int nproc, const std::vector<std::string> &args) {
    if (nproc < 1) LTM_THROW("--nproc ", nproc, ": must be >= 1");
    const int port = free_local_port();
    // The parent's environment minus the torchrun variables, plus this rank's.
    std::vector<std::string> base;
    for (char **e = environ; *e; ++e) {
        const std::string v = *e;
        bool ours = false;
        for (const char *k : {"RANK=", "WORLD_SIZE=", "LOCAL_RANK=", "MASTER_ADDR=", "MASTER_PORT="}) ours |= v.rfind(k, 0) == 0;
        if (!ours) base.push_back(v);
    }
    std::vector<std::string> argv_s = {"ltm"};
    argv_s.insert(argv_s.end(), args.begin(), args.end());
    std::vector<char *> argv;
    for (auto &a : argv_s) argv.push_back(a.data());
    argv.push_back(nullptr);

    std::map<pid_t, int> rank_of;
    for (int r = 0; r < nproc; ++r) {
        std::vector<std::string> env_s = base;
        for (const std::string &v : {"RANK=" + std::to_string(r), "LOCAL_RANK=" + std::to_string(r), "WORLD_SIZE=" + std::to_string(nproc),
                                     std::string("MASTER_ADDR=127.0.0.1"), "MASTER_PORT=" + std::to_string(port)})
            env_s.push_back(v);
        std::vector<char *> envp;
        for (auto &v : env_s) envp.push_back(v.data());
        envp.push_back(nullptr);
        const pid_t pid = ::fork();
        if (pid < 0) LTM_THROW("--nproc: fork failed (", std::strerror(errno), ")");
        if (pid == 0) {
            ::execve("/proc/self/exe", argv.data(), envp.data());
            ::_exit(127);
        }
        rank_of[pid] = r;
    }
    log_info("launched ", nproc, " ranks (MASTER_ADDR=127.0.0.1 MASTER_PORT=", port, ")");
    std::string failure;
    std::chrono::steady_clock::time_point term_sent;
    bool killed = false;
    while (!rank_of.empty()) {
        int status = 0;
        const pid_t pid = ::waitpid(-1, &status, failure.empty() ? 0 : WNOHANG);
        if (pid == 0) {   // failing: escalate to SIGKILL after 10 s
            if (!killed && std::chrono::steady_clock::now() - term_sent > std::chrono::seconds(10)) {
                for (const auto &[p, r] : rank_of) ::kill(p, SIGKILL);
                killed = true;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
            continue;
        }
        if (pid < 0) {
            if (errno == EINTR) continue;
            break;
        }
        const auto it = rank_of.find(pid);
        if (it == rank_of.end()) continue;
        const int r = it->second;
        rank_of.erase(it);
        const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
        if (!ok && failure.empty()) {
            failure = "rank " + std::to_string(r) + " " +
                      (WIFSIGNALED(status) ? "was killed by signal " + std::to_string(WTERMSIG(status))
                                           : "exited with status " + std::to_string(WEXITSTATUS(status)));
            for (const auto &[p, other] : rank_of) ::kill(p, SIGTERM);
            term_sent = std::chrono::steady_clock::now();
        }
    }
    if (!failure.empty()) LTM_THROW("--nproc ", nproc, ": ", failure, "; the other ranks were stopped");
}

}  // namespace ltm::cli
