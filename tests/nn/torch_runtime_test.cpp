// torch_runtime_test.cpp: the libtorch dependency links and computes on this machine.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include "ltm/nn/torch_runtime.h"

// A 2×2 GEMM against its closed form: the BLAS backend Debian's libtorch uses is wired up.
TEST(TorchRuntime, MatmulMatchesClosedForm) {
    const auto a = torch::tensor({1.f, 2.f, 3.f, 4.f}).view({2, 2});
    const auto c = torch::mm(a, a);
    EXPECT_FLOAT_EQ(c[0][0].item<float>(), 7.f);
    EXPECT_FLOAT_EQ(c[1][1].item<float>(), 22.f);
}

TEST(TorchRuntime, ThreadCountIsApplied) {
    ltm::configure_torch_threads(1);
    EXPECT_EQ(torch::get_num_threads(), 1);
    EXPECT_NE(ltm::torch_runtime_description().find("libtorch"), std::string::npos);
}
