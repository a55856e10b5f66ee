// prior_inputs_test.cpp: ModelConfig::prior_inputs (issue #30) — the network sees the transport
// prior's Ê⁺ at every scene point and query. Its inputs keep the exact symmetries (emission ×k,
// unit ×s leave them unchanged), they reach the output, and the fused CPU decoder reads them like
// the modules. The trainer's cached frame: tests/train/augment_test.cpp.
#include <cmath>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "ltm/core/error.h"
#include "ltm/nn/ltm_model.h"
#include "test_util.h"
#include "tiny_scene_fixture.h"

using namespace ltm;

namespace {
using test::random_model;
// The tiny model with the shipped prior's physics (cpu-tp-open) and prior inputs.
struct Fixture : test::TinySceneFixture {
    Fixture() : TinySceneFixture(300) {
        cfg = test::with_prior_inputs(cfg);
    }
};

using test::scaled;

// (scene point features [M, 3], query inputs [N, 12]) the network sees.
std::pair<torch::Tensor, torch::Tensor> inputs(LtmModel &m, const torch::Tensor &sp, const torch::Tensor &qp) {
    const SceneLatents lat = m->encode(sp, m->scene_geometry(sp));
    return {prior_features(lat.norm.point_prior, lat.norm), m->query_inputs(qp, lat.norm)};
}

double max_abs(const torch::Tensor &t) { return t.abs().max().item<double>(); }
}  // namespace

TEST(PriorInputs, ConfigNeedsTheTransportPriorAndWidensTheFirstLayers) {
    const ModelConfig pi = ModelConfig::from_file(test::source_path("configs/model/cpu-pi.json"));
    EXPECT_TRUE(pi.prior_inputs);
    EXPECT_TRUE(pi.to_json().contains("prior_inputs"));
    const ModelConfig cpu = ModelConfig::from_file(test::source_path("configs/model/cpu-tp-open.json"));
    EXPECT_FALSE(cpu.prior_inputs) << "the paper's inputs by default";
    EXPECT_FALSE(cpu.to_json().contains("prior_inputs")) << "written only when set: older weights keep their JSON";
    auto j = Fixture().cfg.to_json();
    j["physics"]["prior_field"] = "flat";
    for (const char *k : {"prior_nodes", "prior_visibility", "prior_discs", "prior_balance", "prior_blend", "prior_patches",
                          "prior_open_rays", "prior_clusters"})
        j["physics"].erase(k);
    EXPECT_THROW(ModelConfig::from_json(j, "t"), Error) << "prior inputs without the transport prior";
    LtmModel m(Fixture().cfg);
    EXPECT_EQ(m->embedding->f[0]->as<torch::nn::LinearImpl>()->weight.size(1), 15);
    EXPECT_EQ(m->decoder->embed[0]->as<torch::nn::LinearImpl>()->weight.size(1), 12);
}

// Emission ×k and unit ×s leave every input unchanged (powers of two map the prior's voxel grid
// onto itself, so the solve is the same to the bit); and the inputs do vary over the scene.
TEST(PriorInputs, InputsAreInvariantToEmissionAndUnit) {
    Fixture f;
    LtmModel m = random_model(f.cfg, 3);
    torch::NoGradGuard no_grad;
    const auto [pts, qs] = inputs(m, f.sp, f.qp);
    ASSERT_EQ(pts.sizes(), (std::vector<int64_t>{f.sp.size(0), 3}));
    ASSERT_EQ(qs.sizes(), (std::vector<int64_t>{f.qp.size(0), 12}));
    EXPECT_GT(qs.slice(1, 9, 12).std().item<double>(), 0.05) << "the prior varies between queries";
    EXPECT_GT(pts.std().item<double>(), 0.05);
    for (double k : {0.25, 8.0}) {
        const auto [p2, q2] = inputs(m, scaled(f.sp, 9, 12, k), f.qp);
        EXPECT_LT(max_abs(p2 - pts), 1e-6) << "emission x" << k;
        EXPECT_LT(max_abs(q2 - qs), 1e-6) << "emission x" << k;
    }
    for (double u : {0.5, 1024.0}) {
        const auto [p2, q2] = inputs(m, scaled(f.sp, 0, 3, u), scaled(f.qp, 0, 3, u));
        EXPECT_LT(max_abs(p2 - pts), 1e-5) << "unit x" << u;
        EXPECT_LT(max_abs(q2 - qs), 1e-5) << "unit x" << u;
    }
}

// The whole model keeps the symmetries with a random network; the prior columns reach the output.
TEST(PriorInputs, ModelIsLinearInEmissionUnitFreeAndReadsThePrior) {
    Fixture f;
    LtmModel m = random_model(f.cfg, 4);
    torch::NoGradGuard no_grad;
    const auto predict = [&](LtmModel &model, const torch::Tensor &sp, const torch::Tensor &qp) {
        return model->predict_irradiance(qp, model->encode(sp, model->scene_geometry(sp)));
    };
    const auto e = predict(m, f.sp, f.qp);
    ASSERT_TRUE(torch::isfinite(e).all().item<bool>());
    const double level = e.abs().mean().item<double>();
    EXPECT_LT(max_abs(predict(m, scaled(f.sp, 9, 12, 4.0), f.qp) - 4.0 * e), 1e-5 * level);
    EXPECT_LT(max_abs(predict(m, scaled(f.sp, 0, 3, 1024.0), scaled(f.qp, 0, 3, 1024.0)) - e), 1e-4 * level);
    // The same weights with the prior columns of both first layers zeroed: another prediction.
    LtmModel blind = random_model(f.cfg, 4);
    {
        torch::NoGradGuard g;
        blind->embedding->f[0]->as<torch::nn::LinearImpl>()->weight.slice(1, 12, 15).zero_();
        blind->decoder->embed[0]->as<torch::nn::LinearImpl>()->weight.slice(1, 9, 12).zero_();
    }
    EXPECT_GT((predict(blind, f.sp, f.qp) - e).abs().mean().item<double>(), 1e-3 * level) << "the prior inputs change the output";
}

// The libtorch path (training) and the fused CPU kernel (inference) read the same 12 columns.
TEST(PriorInputs, FusedDecoderMatchesTheModules) {
    Fixture f;
    LtmModel m = random_model(f.cfg, 5);
    torch::NoGradGuard no_grad;
    const SceneLatents lat = m->encode(f.sp, m->scene_geometry(f.sp));
    const auto fused = m->predict_irradiance(f.qp, lat, 128);
    m->fused_inference = false;
    const auto modules = m->predict_irradiance(f.qp, lat, 128);
    EXPECT_TRUE(torch::allclose(fused, modules, 1e-4, 1e-5 * modules.abs().mean().item<double>())) << max_abs(fused - modules);
}
