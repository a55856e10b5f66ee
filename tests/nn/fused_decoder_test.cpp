// fused_decoder_test.cpp: the fused CPU decoder against the libtorch modules (reference
// equivalence), its thread-count invariance, and predict_irradiance on both paths.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include "ltm/nn/fused_decoder.h"
#include "ltm/nn/ltm_model.h"
#include "ltm/nn/point_tensor.h"
#include "ltm/points/surface_sampler.h"
#include "ltm/scene/builtin_scenes.h"
#include "test_util.h"

#include <cmath>
#include <string>

using namespace ltm;

namespace {
// Weights ~ N(0, 1/fan_in), LayerNorm scales ~ N(1, 0.2²), biases ~ N(0, 0.2²): unlike the
// default init (unit scales, zero biases) every term of the fused algebra is exercised.
void randomise(torch::nn::Module &m) {
    torch::NoGradGuard no_grad;
    for (auto &kv : m.named_parameters()) {
        auto &p = kv.value();
        const bool is_weight = kv.key().size() >= 6 && kv.key().compare(kv.key().size() - 6, 6, "weight") == 0;
        if (p.dim() == 2)
            p.normal_(0.0, 1.0 / std::sqrt(double(p.size(1))));
        else
            p.normal_(is_weight ? 1.0 : 0.0, 0.2);
    }
}

struct Inputs {
    torch::Tensor query, latents, anchors, idx;
};
// Random queries among random anchors; kNN-like indices are not needed for equivalence.
Inputs random_inputs(int64_t n, int64_t m, int64_t latent_dim, int64_t kappa, int64_t width = 9) {
    Inputs in;
    in.query = torch::randn({n, width});
    in.latents = torch::randn({m, latent_dim});
    in.anchors = torch::randn({m, 3});
    in.idx = torch::randint(0, m, {n, kappa}, torch::kInt64);
    return in;
}

void expect_fused_matches_module(const DecoderConfig &cfg, int64_t latent_dim) {
    QueryDecoder dec(cfg, latent_dim);
    randomise(*dec);
    const Inputs in = random_inputs(/*n=*/203, /*m=*/300, latent_dim, cfg.n_neighbors, 9 + cfg.extra_inputs);   // 203: a partial tile
    torch::NoGradGuard no_grad;
    const auto expect = dec->forward(in.query, in.latents, in.anchors, in.idx);
    FusedDecoder fused(*dec);
    fused.prepare(in.latents);
    const auto z = fused.forward(in.query, in.anchors, in.idx);
    ASSERT_EQ(z.sizes(), expect.sizes());
    ::testing::Test::RecordProperty("max_abs_diff", std::to_string((z - expect).abs().max().item<float>()));
    EXPECT_TRUE(torch::allclose(z, expect, /*rtol=*/1e-4, /*atol=*/1e-5))
        << "max |Δz| = " << (z - expect).abs().max().item<float>();
}
}  // namespace

TEST(FusedDecoder, MatchesModuleTinyConfig) {
    torch::manual_seed(11);
    DecoderConfig cfg;
    cfg.dim = 16, cfg.groups = 4, cfg.n_neighbors = 8, cfg.n_layers = 1;
    expect_fused_matches_module(cfg, /*latent_dim=*/24);
}

// The FFN width comes from the config (issue #14 item 2), in both paths.
TEST(FusedDecoder, MatchesModuleWithAnotherFfnRatio) {
    torch::manual_seed(14);
    DecoderConfig cfg;
    cfg.dim = 16, cfg.groups = 4, cfg.n_neighbors = 8, cfg.n_layers = 2, cfg.ffn_ratio = 3;
    expect_fused_matches_module(cfg, /*latent_dim=*/24);
    QueryDecoder dec(cfg, 24);
    for (const auto &p : dec->named_parameters()) {
        if (p.key() == "ffn.1.0.weight") {
            EXPECT_EQ(p.value().size(0), 48) << "hidden width = ffn_ratio · dim";
        }
    }
    ModelConfig mc = ModelConfig::from_file(test::source_path("configs/model/cpu.json"));
    EXPECT_FALSE(mc.to_json()["decoder"].contains("ffn_ratio")) << "default not written: old JSON unchanged";
    mc.decoder.ffn_ratio = 3;
    EXPECT_EQ(ModelConfig::from_json(mc.to_json(), "t").decoder.ffn_ratio, 3);
}

TEST(FusedDecoder, MatchesModuleCpuConfig) {
    torch::manual_seed(12);
    const ModelConfig mc = ModelConfig::from_file(test::source_path("configs/model/cpu.json"));
    expect_fused_matches_module(mc.decoder, /*latent_dim=*/64);
}

// Without absolute positions (PhysicsConfig::translation_invariant) the fused path zeroes 𝓗's
// position columns; the module zeroes the input: the same decoder.
TEST(FusedDecoder, MatchesModuleWithoutAbsolutePosition) {
    torch::manual_seed(13);
    DecoderConfig cfg = ModelConfig::from_file(test::source_path("configs/model/cpu.json")).decoder;
    cfg.absolute_position = false;
    expect_fused_matches_module(cfg, /*latent_dim=*/64);
}

TEST(FusedDecoder, ResultIndependentOfThreadCount) {
    torch::manual_seed(13);
    DecoderConfig cfg;   // defaults = cpu preset decoder
    QueryDecoder dec(cfg, /*latent_dim=*/64);
    randomise(*dec);
    const Inputs in = random_inputs(/*n=*/517, /*m=*/200, 64, cfg.n_neighbors);
    FusedDecoder fused(*dec);
    fused.prepare(in.latents);
    const int threads = at::get_num_threads();
    at::set_num_threads(1);
    const auto z1 = fused.forward(in.query, in.anchors, in.idx);
    at::set_num_threads(2);
    const auto z2 = fused.forward(in.query, in.anchors, in.idx);
    at::set_num_threads(threads);
    // On failure, say by how much (torch 2.11 on a 16-core machine once failed here; the size of
    // the difference tells rounding from a real fault).
    EXPECT_TRUE(torch::equal(z1, z2)) << "max |1 thread − 2 threads| = " << (z1 - z2).abs().max().item<float>();
    // A query's result does not depend on its batch: one query alone gives the same bits.
    const auto z_one = fused.forward(in.query.slice(0, 9, 10), in.anchors, in.idx.slice(0, 9, 10));
    EXPECT_TRUE(torch::equal(z_one, z1.slice(0, 9, 10)))
        << "alone " << z_one << " in the batch " << z1.slice(0, 9, 10);
}

TEST(FusedDecoder, RejectsKnnMeanDecoder) {
    DecoderConfig cfg;
    cfg.type = "knn-mean";
    QueryDecoder dec(cfg, /*latent_dim=*/8);
    EXPECT_THROW(FusedDecoder{*dec}, c10::Error);
}

// Prior inputs (ModelConfig::prior_inputs): 12 query columns, the same in both paths.
TEST(FusedDecoder, MatchesModuleWithPriorInputs) {
    torch::manual_seed(15);
    DecoderConfig cfg = ModelConfig::from_file(test::source_path("configs/model/cpu-pi.json")).decoder;
    cfg.absolute_position = false;
    cfg.extra_inputs = 3;
    expect_fused_matches_module(cfg, /*latent_dim=*/64);
}

// predict_irradiance (fused on CPU) equals the libtorch path and output·expm1(decode()) on a real scene.
TEST(FusedDecoder, PredictIrradianceMatchesLibtorchPath) {
    torch::manual_seed(14);
    const ModelConfig cfg = ModelConfig::from_file(test::source_path("configs/model/tiny.json"));
    LtmModel model(cfg);
    randomise(*model->decoder);
    model->eval();
    const Scene scene = quad_light_room();
    const auto sp = point_tensor(to_scene_points(sample_surface(scene, cfg.scene_points, 1, SampleStream::scene_points)));
    const auto qp = point_tensor(to_query_points(sample_surface(scene, 700, 1, SampleStream::query_points)));
    torch::NoGradGuard no_grad;
    const SceneLatents lat = model->encode(sp, model->scene_geometry(sp));
    const auto fused = model->predict_irradiance(qp, lat, /*chunk=*/256);
    model->fused_inference = false;
    const auto reference = model->predict_irradiance(qp, lat, /*chunk=*/256);
    ::testing::Test::RecordProperty("max_rel_diff", std::to_string(((fused - reference).abs() / (reference.abs() + 1e-6)).max().item<float>()));
    EXPECT_TRUE(torch::allclose(fused, reference, 1e-4, 1e-5)) << "max |ΔE| = " << (fused - reference).abs().max().item<float>();
    EXPECT_TRUE(torch::allclose(fused, irradiance_from_z(model->decode(qp, lat), output_scale(qp, lat.norm)), 1e-4, 1e-5));
}
