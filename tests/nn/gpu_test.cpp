// gpu_test.cpp: CUDA paths equal the CPU paths (label gpu; skips cleanly without a GPU).
#include <gtest/gtest.h>
#include <torch/torch.h>

#include "ltm/nn/knn.h"
#include "ltm/nn/ltm_model.h"
#include "test_util.h"

using namespace ltm;

namespace {
bool have_cuda() { return torch::cuda::is_available(); }
}  // namespace

TEST(Gpu, KnnAndFpsOnCudaEqualCpu) {
    if (!have_cuda()) GTEST_SKIP() << "no CUDA device";
    torch::manual_seed(1);
    const auto ref = torch::rand({3000, 3}), q = torch::rand({700, 3});
    EXPECT_TRUE(torch::equal(knn(q.cuda(), ref.cuda(), 16).cpu(), knn(q, ref, 16)));
    EXPECT_TRUE(torch::equal(farthest_point_sampling(ref.cuda(), 200).cpu(), farthest_point_sampling(ref, 200)));
}

TEST(Gpu, TinyModelOnCudaMatchesCpu) {
    if (!have_cuda()) GTEST_SKIP() << "no CUDA device";
    torch::manual_seed(2);
    const ModelConfig cfg = ModelConfig::from_file(test::source_path("configs/model/tiny.json"));
    LtmModel model(cfg);
    model->eval();
    auto sp = torch::rand({cfg.scene_points, 12});
    sp.slice(1, 3, 6) = torch::nn::functional::normalize(sp.slice(1, 3, 6), torch::nn::functional::NormalizeFuncOptions().dim(1));
    const auto qp = torch::rand({500, 9});
    const SceneGeometry g = model->scene_geometry(sp);
    const auto cpu = model->predict_irradiance(qp, model->encode(sp, g));
    model->to(torch::kCUDA);
    const SceneGeometry gg{g.centers.cuda(), g.groups.cuda()};
    const auto gpu = model->predict_irradiance(qp.cuda(), model->encode(sp.cuda(), gg)).cpu();
    EXPECT_TRUE(torch::allclose(cpu, gpu, 1e-3, 1e-4));
}
