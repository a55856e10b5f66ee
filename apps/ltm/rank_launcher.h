// rank_launcher.h: `ltm train --nproc N` on one machine, as torchrun's standalone mode does it:
// N copies of this executable with the torchrun environment (RANK, WORLD_SIZE, LOCAL_RANK,
// MASTER_ADDR=127.0.0.1, MASTER_PORT = a free port), and the group torn down when one fails.
#pragma once

#include <string>
#include <vector>

namespace ltm::cli {

/// Runs /proc/self/exe with `args` (without the program name) as ranks 0..nproc-1 and waits.
/// When a rank fails, the others get SIGTERM (SIGKILL 10 s later). Throws ltm::Error naming the
/// first rank that failed and how; returns when all ranks succeeded.
void launch_local_ranks(int nproc, const std::vector<std::string> &args);

/// A TCP port on 127.0.0.1 that was free a moment ago (bound to port 0, then released).
int free_local_port();

}  // namespace ltm::cli
