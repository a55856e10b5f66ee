// tiny_scene_fixture.h: the tiny model's config with scene and query points of the built-in
// quad-light room, and a model with one part's weights drawn at a larger scale, shared by the model
// tests.
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

}  // namespace ltm::test
