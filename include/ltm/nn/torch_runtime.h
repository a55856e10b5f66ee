// torch_runtime.h: libtorch set-up shared by the model layers (threads, version string).
// This header does not include torch, so CLI code can call it without torch headers.
#pragma once

#include <stdexcept>
#include <string>

namespace ltm {

/// "libtorch 1.13.1 (CPU)" or with CUDA device count when available.
std::string torch_runtime_description();

/// One line for any exception: libtorch's c10::Error without its C++ backtrace
/// (what_without_backtrace), then the first line (core/error.h first_line).
std::string exception_line(const std::exception &e);

/// Applies ltm's thread count to torch's intra-op pool (torch::set_num_threads).
void configure_torch_threads(int n_threads);

}  // namespace ltm
