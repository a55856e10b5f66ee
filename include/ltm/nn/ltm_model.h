// ltm_model.h: the light transport model (paper §4): NN embedding → PTv3 encoder → latents at
// the m FPS anchors; local query decoder → z = log1p(E⁺) at any surface point.
// Inference API: encode() once per scene, decode() any number of query chunks.
#pragma once

#include <cstdint>

#include <torch/torch.h>

#include "ltm/nn/model_config.h"
#include "ltm/nn/nn_embedding.h"
#include "ltm/nn/ptv3.h"
#include "ltm/nn/query_decoder.h"

namespace ltm {

/// FPS centres and their kNN groups: geometry only, so computed once per scene and cached.
struct SceneGeometry {
    torch::Tensor centers;   ///< [m] int64 indices into the scene points
    torch::Tensor groups;    ///< [m, k] int64
};

/// What the encoder leaves for the decoder.
struct SceneLatents {
    torch::Tensor features;  ///< [m, C]
    torch::Tensor anchors;   ///< [m, 3] anchor positions, normalised (scene-centred) frame
    torch::Tensor center;    ///< [3] the scene centre subtracted from every position
};

/// Scene-centred model inputs (ARCHITECTURE.md §6): p − centre (metres), n, albedo,
/// log1p(emission).   scene_points [M, 12] -> [M, 12];  center [3] = bounding-box centre.
torch::Tensor normalize_scene_points(const torch::Tensor &scene_points, const torch::Tensor &center);
torch::Tensor normalize_query_points(const torch::Tensor &query_points, const torch::Tensor &center);
torch::Tensor bounding_box_center(const torch::Tensor &positions);

/// Where predict_irradiance spends its time (seconds, accumulated over chunks).
struct PredictTimings {
    double knn = 0.0;      ///< anchor kNN of the queries (fused CPU path only; else inside decode)
    double decode = 0.0;   ///< normalisation + decoder + expm1
};

struct LtmModelImpl : torch::nn::Module {
    explicit LtmModelImpl(const ModelConfig &cfg);

    //   scene_points [M, 12] (raw: metres, emission radiance) -> FPS/kNN indices
    SceneGeometry scene_geometry(const torch::Tensor &scene_points) const;
    //   scene_points [M, 12] raw -> latents at m anchors
    SceneLatents encode(const torch::Tensor &scene_points, const SceneGeometry &geometry);
    //   query_points [N, 9] raw -> z [N, 3] = log1p(E⁺); kNN among anchors computed here
    torch::Tensor decode(const torch::Tensor &query_points, const SceneLatents &latents);
    //   the same with precomputed anchor neighbours idx [N, κ]
    torch::Tensor decode_with_neighbors(const torch::Tensor &query_points, const SceneLatents &latents,
                                        const torch::Tensor &idx);
    /// Inference in chunks (no autograd): E⁺ = expm1(z).  query [N, 9] -> [N, 3].
    /// On CPU the "attention" decoder runs as a FusedDecoder, built from the current weights at every
    /// call (a few ms, so it never sees stale weights) unless fused_inference is false. The fused
    /// kernel tiles internally, so large chunks cost nothing and avoid per-chunk thread start-up;
    /// the libtorch path prefers ~1024 (its [chunk, κ, D] temporaries then stay in cache).
    torch::Tensor predict_irradiance(const torch::Tensor &query_points, const SceneLatents &latents,
                                     int64_t chunk = 16384, PredictTimings *timings = nullptr);
    int64_t n_parameters() const;

    ModelConfig cfg;
    NNEmbedding embedding{nullptr};
    PTv3 encoder{nullptr};
    QueryDecoder decoder{nullptr};
    bool fused_inference = true;   ///< predict_irradiance on CPU uses FusedDecoder (false: libtorch modules)
};
TORCH_MODULE(LtmModel);

/// Relative L2 in log space (paper §5, NRC): mean(((z − log1p(y)) / (stopgrad(z) + ε))²).
///   z [N, 3] >= 0, target [N, 3] (E⁺ >= 0) -> scalar
torch::Tensor relative_l2_log_loss(const torch::Tensor &z, const torch::Tensor &target, double eps = 1e-2);

}  // namespace ltm
