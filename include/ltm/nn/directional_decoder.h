// directional_decoder.h: the second task head on the shared encoder (paper §7, issue #11): a
// query point, a direction ω in its hemisphere and the same κ nearest anchors' latents -> incident
// radiance L_in(p, ω), RGB, ≥ 0. Built like the irradiance decoder (vector cross-attention blocks,
// the shared γ(Δp)), with the direction entering 𝓗 as ω, n·ω and Fourier features sin/cos(2^k π ω).
// The output is in the irradiance head's frame (model_config.h DirectionalConfig):
//     L_in = (scale / π) · expm1(z),   z = softplus(𝓦_out(h)) ≥ 0,
// so a zeroed 𝓦_out predicts the uniform radiance scale/π, whose cosine integral is the scale.
#pragma once

#include <torch/torch.h>

#include "ltm/nn/model_config.h"
#include "ltm/nn/query_decoder.h"
#include "ltm/points/scene_record.h"

namespace ltm {

/// The head's direction features: ω, n·ω, then sin(2^k π ω), cos(2^k π ω) for k < F.
///   direction [N, 3] (unit, world frame), normal [N, 3] -> [N, 4 + 6F]
torch::Tensor direction_features(const torch::Tensor &direction, const torch::Tensor &normal, int frequencies);

/// Throws ltm::Error naming the record's file unless it holds L_in bins of the head's resolution
/// and of the radiance it predicts (data preset bin_radiance vs directional.radiance).
void check_directional_record(const SceneRecord &r, const DirectionalConfig &cfg);

struct DirectionalDecoderImpl : torch::nn::Module {
    /// absolute_position false: 𝓗 sees the query with its position zeroed (PhysicsConfig::translation_invariant).
    DirectionalDecoderImpl(const DirectionalConfig &cfg, int64_t latent_dim, bool absolute_position);
    //   query [N, 9] (normalised p, n, albedo), direction [N, 3] unit, latents [m, C], anchors [m, 3],
    //   idx [N, κ]  ->  z [N, 3] >= 0  (L_in = scale/π · expm1(z))
    torch::Tensor forward(const torch::Tensor &query, const torch::Tensor &direction, const torch::Tensor &latents,
                          const torch::Tensor &anchors, const torch::Tensor &idx);
    /// Zeroes 𝓦_out's last Linear: L_in = scale/π in every direction (done at construction).
    void start_uniform();
    DirectionalConfig cfg;
    bool absolute_position;
    torch::nn::Sequential embed{nullptr}, out{nullptr}, pos_mlp{nullptr};
    CrossAttentionBlocks blocks;
};
TORCH_MODULE(DirectionalDecoder);

}  // namespace ltm
