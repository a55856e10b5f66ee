// startup.cpp: malloc tuning (see startup.h).
#include "ltm/core/startup.h"

#include <malloc.h>

#include <mutex>

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

}  // namespace ltm
