// image_renderer.h: path-traced camera images with AOVs (the reference for every comparison).
#pragma once

#include <string>
#include <vector>

#include "ltm/core/image.h"
#include "ltm/render/path_tracer.h"
#include "ltm/scene/camera.h"

namespace ltm {

/// Per pixel: Le + albedo/π·(E_direct + E⁺) at the first hit for diffuse surfaces (E from the
/// path tracer's irradiance estimator, one stratum per pixel sample), full path tracing for
/// conductors. AOVs are averages over the pixel's samples (jittered, so edges are anti-aliased).
struct RenderedImage {
    int width = 0, height = 0;
    Image color, irradiance, direct, albedo, normal, position;   ///< irradiance = E⁺, direct = E_direct
    std::vector<float> depth;                                    ///< ray distance; 0 where nothing is hit
    float hit_fraction = 0.f;
    double seconds = 0.0;
};

/// Renders with spp samples per pixel; progress on stderr. Deterministic in (seed, pixel, sample).
/// jitter = false sends every sample through the pixel centre, the G-buffer's ray
/// (render/gbuffer.h): an image that compares pixel by pixel with the neural renderer's.
RenderedImage render_pathtraced(const PathTracer &pt, const Camera &camera, int spp, bool jitter = true);

/// Writes `<prefix>.exr` (channels R,G,B, irradiance.*, direct.*, albedo.*, N.*, P.*, Z) and
/// `<prefix>.png` (tone-mapped sRGB: exposure scale, clamp). The EXR's radiometric and shading
/// channels are half where they fit (fits_half), as pbrt-v4 (film "writefp16", default true) and
/// Mitsuba 3 (hdrfilm "component_format", default float16) write theirs; P and Z stay float (half's
/// steps at a room's scale are millimetres, 2⁻⁸ between 4 and 8 units). exr_float: every channel float.
void write_rendered_image(const RenderedImage &img, const std::string &prefix, float exposure, bool exr_float = false);

/// Checks a camera before a long render: throws if it sees nothing, or if it sits inside a
/// closed solid (most rays from the eye hit back faces).
void check_camera(const EmbreeAccel &accel, const Camera &camera, const std::string &where);

}  // namespace ltm
