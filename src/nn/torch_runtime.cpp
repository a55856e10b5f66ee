// torch_runtime.cpp: the libtorch layer's process set-up. Model code lands beside this file.
#include "ltm/nn/torch_runtime.h"

#include <torch/torch.h>

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

void configure_torch_threads(int n_threads) {
    if (n_threads > 0) torch::set_num_threads(n_threads);
}

}  // namespace ltm
