// scene_points.h: the model's input point cloud of a scene, sampled one way for every user (the
// dataset's records, the neural renderer, the eval floors): area-uniform scene points (stream
// scene_points) without the surfaces enclosed by solids, and the scene's exact emission scale
// S = Φ/A over the same surface (transport/power_balance.h), which the model's emission
// normalisation uses instead of the noisy mean over the few points that land on emitters.
#pragma once

#include <algorithm>
#include <cmath>

#include <cstdint>

#include "ltm/points/point_set.h"
#include "ltm/render/embree_accel.h"

namespace ltm {

struct ScenePoints {
    PointSet points;       ///< [M, 12] scene_point_columns()
    Vec3f emission_scale;  ///< S_c = Φ_c / A (W/m²) of the sampled surface
    /// [M] each point's candidate identity (SurfaceSample::id): the model's traced inputs key their
    /// random streams on it (infer/prior_model.h traced_inputs_tracer), so a point keeps its paths
    /// when a candidate before it flips, as the points themselves do.
    std::vector<uint64_t> ids;
};

/// How near a surface must close a scene point's hemisphere for the point to count as buried
/// (EnclosureTest::buried_distance), in units of the points' nominal spacing √(A/M).
constexpr float k_buried_spacings = 0.5f;

/// Emitters get at least M / k_emitter_share_inv of the scene points (64 of 8 192). Area-uniform
/// sampling gives a lamp's bulb or a small sphere light one to three points, or none: the prior then
/// has its light leave from one disc, and shadowed by its shade it reaches almost nothing (issue
/// #29's lamp case: level 0.27).
constexpr int64_t k_emitter_share_inv = 128;

/// M scene points of accel.scene() with `seed`; exclude_enclosed drops points inside closed solids
/// and buried in gaps thinner than buried_spacings · √(A/M) (render/enclosure.h; 0: solids only) and
/// shrinks the area A of S by the filter's pass fraction.
///
/// Emitter floor: when fewer than K = M / k_emitter_share_inv of the area-uniform points lie on
/// emitters, those points and K − n_e others (a seeded uniform choice) give way to K points drawn
/// on the emitters in proportion to their power (SampleStream::emitter_points, the same filter).
/// Each then carries an equal share of the power: Le' = Le · Φ_Y / (π K a · lum(Le)), a = A/M the
/// area every node stands for, so π Σ Le' a = Φ in expectation per channel (the exact emission scale
/// then rescales it, as before); and it reflects as the area it stands for: ρ' = ρ · min(1, A_e /
/// (K a)), A_e the emitters' area. Scenes whose emitters already hold K points are unchanged.
/// The nominal spacing of n area-uniform points on the scene's surface, √(A/n) (n < 1 counts as 1):
/// what lengths measured in "point spacings" are relative to.
inline float nominal_spacing(const Scene &scene, int64_t n_points) {
    return float(std::sqrt(scene.total_area() / double(std::max<int64_t>(1, n_points))));
}

ScenePoints sample_scene_points(const EmbreeAccel &accel, int64_t n_points, uint64_t seed, bool exclude_enclosed = true,
                                float buried_spacings = k_buried_spacings);

/// `--scene-points auto` (issue #31): M from the scene's modelled detail, its triangle count T.
/// Measured (docs/performance.md, "The prior through a cluster tree"): generated houses (1–5 k
/// triangles) stop gaining at M = 16 384 (view MSE 0.0036 → 0.0029, then level to 65 536), real
/// rooms (0.25–1.4 M triangles) keep gaining to 32 768 (0.0096 → 0.0073; 65 536: 0.0075) at ~5× the
/// time. So 16 384 below k_auto_detail_triangles triangles and 32 768 at or above. The rule is fitted
/// to those 16 houses and five rooms; a scene with little modelled detail but large flat walls
/// would want more than it gives.
inline constexpr size_t k_auto_detail_triangles = 100000;
int64_t auto_scene_points(const Scene &scene);

}  // namespace ltm
