// tiny_scene_fixture.h: the tiny model's config with scene and query points of the built-in
// quad-light room, shared by the model tests.
#pragma once

#include <cstdint>

#include <torch/torch.h>

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

}  // namespace ltm::test
