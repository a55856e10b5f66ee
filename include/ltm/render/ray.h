// ray.h: rays, hits, and the self-intersection offset shared by every intersector.
#pragma once

#include <cstdint>
#include <limits>

#include "ltm/core/math.h"

namespace ltm {

struct Ray {
    Vec3f o, d;   ///< origin and direction (need not be unit; t is in units of |d|)
    float tmin = 0.f;
    float tmax = std::numeric_limits<float>::infinity();
};

struct Hit {
    float t = 0.f;
    uint32_t mesh = 0, triangle = 0;
    float b1 = 0.f, b2 = 0.f;   ///< barycentrics of vertices 1 and 2: p = (1-b1-b2)p0 + b1 p1 + b2 p2
    Vec3f n;                    ///< unit geometric normal of the triangle (winding side)
};

/// Origin for a ray leaving surface point p (normal n) along direction d: pushed off the surface
/// on d's side by an offset that grows with |p| (float spacing), so the ray cannot re-hit the
/// surface it starts on. `length` is the offset's floor near the origin, in scene units: 1 (a
/// metre) for rendering; a scene's extent where a decision must not depend on the unit of length
/// (render/enclosure.h: the same scene in centimetres must drop the same points).
inline Vec3f offset_ray_origin(Vec3f p, Vec3f n, Vec3f d, float length = 1.f) {
    const float scale = 1e-4f * (length + max_component(Vec3f(std::abs(p.x), std::abs(p.y), std::abs(p.z))));
    return p + n * (dot(n, d) >= 0.f ? scale : -scale);
}

/// Shadow ray from surface point (p, n) to `target`: unnormalised direction from the offset
/// origin straight to the target, so t = 1 is the target and the interval stops just short of it.
/// `length`: the offset's floor, as offset_ray_origin's.
inline Ray shadow_ray(Vec3f p, Vec3f n, Vec3f target, float length = 1.f) {
    const Vec3f o = offset_ray_origin(p, n, target - p, length);
    return {o, target - o, 0.f, 1.f - 1e-4f};
}

}  // namespace ltm
