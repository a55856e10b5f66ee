// gbuffer.h: one primary ray per pixel centre → the surface each pixel sees. Every irradiance
// image that is compared (path-traced reference, PT at 64 spp, PT at equal time, the neural
// prediction) is evaluated at these same points, so the comparison is of irradiance alone.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "ltm/core/image.h"
#include "ltm/render/image_renderer.h"
#include "ltm/render/path_tracer.h"

namespace ltm {

struct GBuffer {
    int width = 0, height = 0;
    std::vector<int64_t> hit_pixels;   ///< pixel indices (y·width + x) whose primary ray hits, ascending
    /// Per hit (parallel to hit_pixels): position, unit normal on the side facing the eye, albedo,
    /// emitted radiance towards the eye, ray distance, whether the BSDF is diffuse.
    std::vector<Vec3f> position, normal, albedo, emitted;
    std::vector<float> depth;
    std::vector<uint8_t> diffuse;
    size_t n_hits() const { return hit_pixels.size(); }
};

/// Primary rays through the pixel centres (no jitter: one surface point per pixel).
GBuffer render_gbuffer(const EmbreeAccel &accel, const Camera &camera);

/// Irradiance at every G-buffer point with spp stratified samples (path_tracer.h estimators);
/// with_indirect = false computes E_direct only. Pixels without a hit stay 0.
struct IrradianceImages {
    Image direct, indirect;   ///< E_direct, E⁺ (W/m²)
    double seconds = 0.0;
};
IrradianceImages irradiance_images(const PathTracer &pt, const GBuffer &gb, int spp, bool with_indirect);
/// The same loop for any per-point estimator: estimate(k) for every hit k in parallel, with a
/// progress bar named `label` and the wall time; the irradiance_images of other estimators
/// (render/direct_light.h) are built on it.
IrradianceImages estimate_images(const GBuffer &gb, const char *label,
                                 const std::function<IrradianceEstimate(size_t hit)> &estimate);

/// Image of the G-buffer's values at hit pixels (black elsewhere).
Image scatter_to_image(const GBuffer &gb, const std::vector<Vec3f> &per_hit);
/// The inverse: the image's values at the hit pixels, in hit order (sizes must match).
std::vector<Vec3f> gather_hits(const GBuffer &gb, const Image &img);

/// Le + albedo/π·(E_direct + E⁺) per pixel, with AOVs, in the form write_rendered_image takes.
/// Conductor pixels are shaded as diffuse with their albedo (an approximation: the irradiance
/// models predict E only); the caller is told how many there are through `n_conductor`.
RenderedImage compose_image(const GBuffer &gb, const Image &direct, const Image &indirect, int64_t *n_conductor = nullptr);

}  // namespace ltm
