// startup.h: process-wide settings every ltm binary applies first thing in main().
#pragma once

namespace ltm {

/// Raises glibc's mmap/trim thresholds so large buffers are reused instead of being mapped and
/// page-faulted afresh every time (measured 4× on GEMM in this VM, ARCHITECTURE.md §3).
void configure_process();

}  // namespace ltm
