// startup.cpp: malloc tuning and the process's age (see startup.h).
#include "ltm/core/startup.h"

#include <malloc.h>
#include <unistd.h>

#include <fstream>
#include <mutex>
#include <sstream>
#include <string>

namespace ltm {

void configure_process() {
    static std::once_flag once;   // any thread may call it first
    std::call_once(once, [] {
        // Serve even huge blocks from the heap (no per-allocation mmap), and keep freed memory
        // instead of returning it to the OS, so repeated tensor/buffer allocations stay warm.
        mallopt(M_MMAP_MAX, 0);
        mallopt(M_TRIM_THRESHOLD, -1);   // -1: never trim (a 1 GiB threshold still trimmed between training steps)
        mallopt(M_TOP_PAD, 64 << 20);
    });
}

double process_age_seconds() {
    // Field 22 of /proc/self/stat is the start time in clock ticks after boot; the command name
    // (field 2) may hold spaces, so count fields after its closing parenthesis.
    std::ifstream stat("/proc/self/stat"), uptime("/proc/uptime");
    std::string line;
    double up = 0.0;
    if (!std::getline(stat, line) || !(uptime >> up)) return -1.0;
    const auto close = line.rfind(')');
    if (close == std::string::npos) return -1.0;
    std::istringstream rest(line.substr(close + 2));
    std::string field;
    for (int i = 3; i <= 22 && (rest >> field); ++i)
        if (i == 22) {
            const long ticks = sysconf(_SC_CLK_TCK);
            return ticks > 0 ? up - std::stod(field) / double(ticks) : -1.0;
        }
    return -1.0;
}

}  // namespace ltm
