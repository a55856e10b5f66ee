// startup.h: process-wide settings every ltm binary applies first thing in main(), and the clock
// that tells how long a process took to get there.
#pragma once

namespace ltm {

/// Raises glibc's mmap/trim thresholds so large buffers are reused instead of being mapped and
/// page-faulted afresh every time (measured 4× on GEMM in this VM, ARCHITECTURE.md §3).
void configure_process();

/// Seconds since the kernel started this process (exec, the dynamic loader, static initialisers
/// included), from /proc/self/stat and /proc/uptime: 10 ms resolution. -1 where /proc is absent.
double process_age_seconds();

}  // namespace ltm
