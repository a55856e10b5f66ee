// tiny_scene_fixture.h: the tiny model's config with scene and query points of the built-in
// quad-light room, a model with one part's weights drawn at a larger scale, and the helpers the
// symmetry tests share (predict, scaled, relative_error).
#pragma once

#include <cstdint>

#include <torch/torch.h>

#include "ltm/nn/ltm_model.h"
#include "ltm/nn/model_config.h"
#include "ltm/nn/point_tensor.h"
#include "ltm/points/surface_sampler.h"
#include "ltm/scene/builtin_scenes.h"
#include "test_util.h"

namespace ltm::test {

struct TinySceneFixture {
    explicit TinySceneFixture(int64_t n_queries)
        : qp(point_tensor(to_query_points(sample_surface(scene, n_queries, 1, SampleStream::query_points)))) {}
    ModelConfig cfg = ModelConfig::from_file(source_path("configs/model/tiny.json"));
    Scene scene = quad_light_room();
    torch::Tensor sp = point_tensor(to_scene_points(sample_surface(scene, cfg.scene_points, 1, SampleStream::scene_points)));
    torch::Tensor qp;   ///< [n_queries, 9]; initialised after scene (declaration order)
};

/// The tiny config with the shipped prior's physics (cpu-pi's) and prior inputs: what the prior- and
/// traced-inputs tests build on.
inline ModelConfig with_prior_inputs(ModelConfig cfg) {
    cfg.physics = ModelConfig::from_file(source_path("configs/model/cpu-pi.json")).physics;
    cfg.prior_inputs = true;
    return cfg;
}

/// The tiny room with prior inputs and traced inputs of 4 strata: what the traced-inputs and
/// traced-queries tests build on.
struct TracedSceneFixture : TinySceneFixture {
    TracedSceneFixture() : TinySceneFixture(200) {
        cfg = with_prior_inputs(cfg);
        cfg.traced_inputs = 4;
    }
};

/// A model (eval mode, seeded) with every weight matrix N(0, 0.5²), so extra input columns matter.
inline LtmModel random_model(const ModelConfig &cfg, uint64_t seed) {
    torch::manual_seed(seed);
    LtmModel m(cfg);
    torch::NoGradGuard g;
    for (auto &p : m->named_parameters())
        if (p.value().dim() == 2) p.value().normal_(0.0, 0.5);
    m->eval();
    return m;
}

/// A model (eval mode, seeded) whose submodule `part` ("decoder", "directional") has N(0, 0.5²)
/// weights: an output that is not a constant, which the default initialisation can be.
inline LtmModel model_with_random_part(const ModelConfig &cfg, uint64_t seed, const std::string &part) {
    torch::manual_seed(seed);
    LtmModel m(cfg);
    torch::NoGradGuard g;
    for (auto &p : m->named_children()[part]->parameters()) p.normal_(0.0, 0.5);
    m->eval();
    return m;
}

/// E⁺ at the queries from a fresh encode of the scene points (geometry included).
///   sp [M, 12], qp [N, 9] -> [N, 3]
inline torch::Tensor predict(LtmModel &m, const torch::Tensor &sp, const torch::Tensor &qp) {
    return m->predict_irradiance(qp, m->encode(sp, m->scene_geometry(sp)));
}

/// A copy of t with columns [c0, c1) times k (emission ×k: 9–12 of scene points; unit ×s: 0–3).
inline torch::Tensor scaled(const torch::Tensor &t, int64_t c0, int64_t c1, double k) {
    auto out = t.clone();
    out.slice(1, c0, c1).mul_(k);
    return out;
}

/// mean |a − b| / mean |b|.
inline double relative_error(const torch::Tensor &a, const torch::Tensor &b) {
    return (a - b).abs().mean().item<double>() / (b.abs().mean().item<double>() + 1e-30);
}

}  // namespace ltm::test
