// torch_runtime.cpp: the libtorch layer's process set-up. Model code lands beside this file.
#include "ltm/nn/torch_runtime.h"

#include <dlfcn.h>

#include <torch/torch.h>

#include "ltm/core/error.h"

namespace ltm {

std::string torch_runtime_description() {
    std::string s = "libtorch " + std::to_string(TORCH_VERSION_MAJOR) + "." +
                    std::to_string(TORCH_VERSION_MINOR) + "." + std::to_string(TORCH_VERSION_PATCH);
    if (torch::cuda::is_available())
        s += " (CUDA, " + std::to_string(torch::cuda::device_count()) + " devices)";
    else
        s += " (CPU)";
    return s;
}

std::string exception_line(const std::exception &e) {
    if (const auto *t = dynamic_cast<const c10::Error *>(&e)) return first_line(t->what_without_backtrace());
    return first_line(e.what());
}

void configure_torch_threads(int n_threads) {
    if (n_threads <= 0) return;
    torch::set_num_threads(n_threads);
    // Debian's libtorch calls OpenBLAS (the pthread build) for matrix products, and OpenBLAS keeps
    // its own pool of one thread per core: `--threads 1` ran at 145 % CPU and two training ranks
    // oversubscribed the cores. Bound it too, through the symbol where that OpenBLAS is loaded
    // (looked up, not linked: other BLAS builds lack it and need nothing).
    using SetThreads = void (*)(int);
    if (auto *f = reinterpret_cast<SetThreads>(::dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) f(n_threads);
}

}  // namespace ltm
