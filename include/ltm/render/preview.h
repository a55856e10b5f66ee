// preview.h: a quick look at a scene from a camera: albedo, normals, or albedo shaded by a
// head-light, traced with Embree (one primary ray per pixel centre; no global illumination).
#pragma once

#include <string>

#include "ltm/core/image.h"
#include "ltm/render/embree_accel.h"
#include "ltm/scene/camera.h"

namespace ltm {

enum class PreviewMode { shaded, albedo, normal };
PreviewMode parse_preview_mode(const std::string &s);

/// Renders camera.width × camera.height. Emitters show as their radiance scaled to max 1.
/// Misses are black. Also returns the fraction of pixels that hit geometry in `hit_fraction`.
Image render_preview(const EmbreeAccel &accel, const Camera &camera, PreviewMode mode,
                     float *hit_fraction = nullptr);

/// A camera that frames the whole scene from outside its bounds, or, for a closed interior,
/// from inside the largest free space: eye at the centre of the bounds, looking along +x/−z.
Camera automatic_camera(const Scene &scene, int width, int height);

}  // namespace ltm
