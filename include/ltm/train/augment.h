// augment.h: training-time data augmentation by the 8 symmetries of the square in the horizontal
// plane (the dihedral group D4: yaw by k·90° about +y, optionally mirrored in x). Light transport
// is invariant under rigid motions and reflections, so a record's E⁺ targets stay valid; and the
// maps are signed permutations of the coordinates, exact in float, so pairwise distances change
// only by the rounding of their summation order — the cached FPS centres and kNN groups stay the
// ones the transformed scene would get (up to exact ties).
#pragma once

#include <torch/torch.h>

#include "ltm/nn/ltm_model.h"

namespace ltm {

inline constexpr int k_n_symmetries = 8;

/// The 3×3 matrix of symmetry s ∈ [0, 8): s & 3 quarter turns about +y, then x → −x if s & 4.
torch::Tensor symmetry_matrix(int s);

/// Points with positions (columns 0–2) and normals (3–5) mapped by symmetry s; other columns
/// (albedo, emission) unchanged. s = 0 returns the input itself.
///   points [N, C ≥ 6] float  ->  [N, C]
torch::Tensor apply_symmetry(const torch::Tensor &points, int s);

/// A scene's frame (scene_normalization of the untransformed points) for its image under
/// symmetry s: the bounding-box centre maps like the points (exactly: min and max are permuted
/// and negated); ℓ, S, the output level and point_prior are invariant (the prior is a physical
/// quantity). The transport solve, whose nodes lie in the old frame, is dropped: the caller keeps
/// the prior's values it needs (the trainer's query_scale).
SceneNormalization apply_symmetry(const SceneNormalization &frame, int s);

}  // namespace ltm
