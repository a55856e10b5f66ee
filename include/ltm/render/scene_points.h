// scene_points.h: the model's input point cloud of a scene, sampled one way for every user (the
// dataset's records, the neural renderer, the eval floors): area-uniform scene points (stream
// scene_points) without the surfaces enclosed by solids, and the scene's exact emission scale
// S = Φ/A over the same surface (transport/power_balance.h), which the model's emission
// normalisation uses instead of the noisy mean over the few points that land on emitters.
#pragma once

#include <cstdint>

#include "ltm/points/point_set.h"
#include "ltm/render/embree_accel.h"

namespace ltm {

struct ScenePoints {
    PointSet points;       ///< [M, 12] scene_point_columns()
    Vec3f emission_scale;  ///< S_c = Φ_c / A (W/m²) of the sampled surface
};

/// How near a surface must close a scene point's hemisphere for the point to count as buried
/// (EnclosureTest::buried_distance), in units of the points' nominal spacing √(A/M).
constexpr float k_buried_spacings = 0.5f;

/// M scene points of accel.scene() with `seed`; exclude_enclosed drops points inside closed solids
/// and buried in gaps thinner than buried_spacings · √(A/M) (render/enclosure.h; 0: solids only) and
/// shrinks the area A of S by the filter's pass fraction.
ScenePoints sample_scene_points(const EmbreeAccel &accel, int64_t n_points, uint64_t seed, bool exclude_enclosed = true,
                                float buried_spacings = k_buried_spacings);

}  // namespace ltm
