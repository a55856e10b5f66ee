// interaction.h: what a ray hit: position, normal, uv, material, and its BSDF.
#pragma once

#include "ltm/render/bsdf.h"
#include "ltm/render/ray.h"
#include "ltm/scene/scene.h"

namespace ltm {

struct SurfaceInteraction {
    Vec3f p, n;        ///< hit point and unit geometric normal (winding side, not flipped)
    Vec2f uv;
    const Material *material = nullptr;
    bool front = true; ///< the ray arrived on the normal side

    /// Radiance emitted towards the ray origin (front side only).
    Vec3f emitted() const { return front ? material->emission.eval(uv) : Vec3f(0.f); }
    Vec3f albedo() const { return material->albedo.eval(uv); }
    Bsdf bsdf() const;
};

/// Builds the interaction for `hit` of `ray` (uv interpolated from the mesh).
SurfaceInteraction make_interaction(const Scene &scene, const Ray &ray, const Hit &hit);

}  // namespace ltm
