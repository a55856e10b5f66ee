// gbuffer.cpp: primary rays at pixel centres; irradiance images at the same points; composition.
#include "ltm/render/gbuffer.h"

#include <algorithm>
#include <chrono>
#include <optional>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
#include "ltm/core/progress.h"

namespace ltm {

namespace {
constexpr uint64_t k_gbuffer_domain = 3ull << 61;   // streams disjoint from points and jittered pixels
}

GBuffer render_gbuffer(const EmbreeAccel &accel, const Camera &cam) {
    const Scene &scene = accel.scene();
    const int64_t n_pix = int64_t(cam.width) * cam.height;
    // Trace all rows in parallel into per-pixel slots, then compact in pixel order (deterministic).
    std::vector<std::optional<Hit>> hits(static_cast<size_t>(n_pix));
    std::vector<Ray> rays(static_cast<size_t>(n_pix));
    parallel_for(0, cam.height, 4, [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y)
            for (int x = 0; x < cam.width; ++x) {
                const size_t i = size_t(y * cam.width + x);
                rays[i] = Ray{cam.eye, cam.ray_direction(float(x) + 0.5f, float(y) + 0.5f)};
                hits[i] = accel.intersect(rays[i]);
            }
    });
    GBuffer gb;
    gb.width = cam.width, gb.height = cam.height;
    for (int64_t i = 0; i < n_pix; ++i) {
        if (!hits[size_t(i)]) continue;
        const Ray &ray = rays[size_t(i)];
        const SurfaceInteraction si = make_interaction(scene, ray, *hits[size_t(i)]);
        gb.hit_pixels.push_back(i);
        gb.position.push_back(si.p);
        gb.normal.push_back(si.front ? si.n : -si.n);
        gb.albedo.push_back(si.albedo());
        gb.emitted.push_back(si.emitted());
        gb.depth.push_back(hits[size_t(i)]->t);
        gb.diffuse.push_back(si.material->bsdf == BsdfKind::diffuse ? 1 : 0);
    }
    return gb;
}

IrradianceImages estimate_images(const GBuffer &gb, const char *label,
                                 const std::function<IrradianceEstimate(size_t hit)> &estimate) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<Vec3f> direct(gb.n_hits()), indirect(gb.n_hits());
    Progress progress(label, std::max<uint64_t>(1, gb.n_hits()), "pixels");
    parallel_for(0, int64_t(gb.n_hits()), 256, [&](int64_t b, int64_t e) {
        for (int64_t h = b; h < e; ++h) {
            const IrradianceEstimate est = estimate(size_t(h));
            direct[size_t(h)] = est.direct;
            indirect[size_t(h)] = est.indirect;
        }
        progress.add(uint64_t(e - b));
    });
    progress.finish();
    IrradianceImages out;
    out.direct = scatter_to_image(gb, direct);
    out.indirect = scatter_to_image(gb, indirect);
    out.seconds = seconds_since(t0);
    return out;
}

IrradianceImages irradiance_images(const PathTracer &pt, const GBuffer &gb, int spp, bool with_indirect) {
    if (spp <= 0) LTM_THROW("irradiance image: samples per pixel must be > 0, got ", spp);
    return estimate_images(gb, with_indirect ? "path trace" : "direct light", [&](size_t k) {
        return pt.irradiance(gb.position[k], gb.normal[k], k_gbuffer_domain | uint64_t(gb.hit_pixels[k]), spp, with_indirect);
    });
}

Image scatter_to_image(const GBuffer &gb, const std::vector<Vec3f> &per_hit) {
    LTM_CHECK_EQ(per_hit.size(), gb.n_hits());
    Image img(gb.width, gb.height);
    for (size_t k = 0; k < per_hit.size(); ++k) img.pixels[size_t(gb.hit_pixels[k])] = per_hit[k];
    return img;
}

std::vector<Vec3f> gather_hits(const GBuffer &gb, const Image &img) {
    if (img.width != gb.width || img.height != gb.height)
        LTM_THROW("gather_hits: image ", img.width, "x", img.height, " for a ", gb.width, "x", gb.height, " G-buffer");
    std::vector<Vec3f> out(gb.n_hits());
    for (size_t k = 0; k < out.size(); ++k) out[k] = img.pixels[size_t(gb.hit_pixels[k])];
    return out;
}

RenderedImage compose_image(const GBuffer &gb, const Image &direct, const Image &indirect, int64_t *n_conductor) {
    if (direct.width != gb.width || direct.height != gb.height || indirect.width != gb.width || indirect.height != gb.height)
        LTM_THROW("compose: irradiance images do not match the G-buffer's ", gb.width, "x", gb.height);
    RenderedImage out;
    out.width = gb.width, out.height = gb.height;
    for (Image *img : {&out.color, &out.albedo, &out.normal, &out.position}) *img = Image(gb.width, gb.height);
    out.direct = direct, out.irradiance = indirect;
    out.depth.assign(size_t(gb.width) * size_t(gb.height), 0.f);
    int64_t conductors = 0;
    for (size_t k = 0; k < gb.n_hits(); ++k) {
        const size_t i = size_t(gb.hit_pixels[k]);
        out.color.pixels[i] = gb.emitted[k] + gb.albedo[k] * k_inv_pi * (direct.pixels[i] + indirect.pixels[i]);
        out.albedo.pixels[i] = gb.albedo[k];
        out.normal.pixels[i] = gb.normal[k];
        out.position.pixels[i] = gb.position[k];
        out.depth[i] = gb.depth[k];
        conductors += gb.diffuse[k] ? 0 : 1;
    }
    out.hit_fraction = float(gb.n_hits()) / float(std::max<int64_t>(1, int64_t(gb.width) * gb.height));
    if (n_conductor) *n_conductor = conductors;
    return out;
}

}  // namespace ltm
