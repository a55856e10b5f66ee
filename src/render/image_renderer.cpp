// image_renderer.cpp: camera rays → first hit → (Le + albedo/π·E) or path tracing.
#include "ltm/render/image_renderer.h"

#include <atomic>
#include <chrono>

#include "ltm/core/error.h"
#include "ltm/core/exr.h"
#include "ltm/core/parallel.h"
#include "ltm/core/progress.h"
#include "ltm/core/rng.h"

namespace ltm {

namespace {
constexpr uint64_t k_pixel_domain = 1ull << 62;   // pixel streams never collide with point streams
}

RenderedImage render_pathtraced(const PathTracer &pt, const Camera &cam, int spp, bool jitter) {
    if (spp <= 0) LTM_THROW("render: samples per pixel must be > 0, got ", spp);
    const Scene &scene = pt.accel().scene();
    RenderedImage out;
    out.width = cam.width, out.height = cam.height;
    for (Image *img : {&out.color, &out.irradiance, &out.direct, &out.albedo, &out.normal, &out.position})
        *img = Image(cam.width, cam.height);
    out.depth.assign(size_t(cam.width) * size_t(cam.height), 0.f);
    const auto t0 = std::chrono::steady_clock::now();
    Progress progress("render", uint64_t(cam.height), "rows");
    std::atomic<int64_t> hits{0};
    const float inv = 1.f / float(spp);
    parallel_for(0, cam.height, 1, [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y) {
            for (int x = 0; x < cam.width; ++x) {
                const uint64_t pixel = uint64_t(y) * uint64_t(cam.width) + uint64_t(x);
                Vec3f color(0.f), irr(0.f), dir(0.f), alb(0.f), nrm(0.f), pos(0.f);
                float depth = 0.f;
                int n_hit = 0;
                for (int s = 0; s < spp; ++s) {
                    const uint64_t key = pt.stream_key(k_pixel_domain | pixel, uint64_t(s));
                    Pcg32 rng(key ^ 0x9e3779b97f4a7c15ull);
                    const bool centre = spp == 1 || !jitter;
                    const float jx = centre ? 0.5f : rng.next_float(), jy = centre ? 0.5f : rng.next_float();
                    const Ray ray{cam.eye, cam.ray_direction(float(x) + jx, float(y) + jy)};
                    const auto hit = pt.accel().intersect(ray);
                    if (!hit) continue;
                    ++n_hit;
                    const SurfaceInteraction si = make_interaction(scene, ray, *hit);
                    const Vec3f n_side = si.front ? si.n : -si.n;
                    const IrradianceEstimate e = pt.irradiance_sample(si.p, n_side, key, s, spp);
                    color += si.emitted();
                    if (si.material->bsdf == BsdfKind::diffuse)
                        color += si.albedo() * k_inv_pi * (e.direct + e.indirect);
                    else
                        color += pt.reflected_radiance(si, -ray.d, pt.config().max_depth + 1, rng);
                    irr += e.indirect, dir += e.direct, alb += si.albedo(), nrm += n_side, pos += si.p;
                    depth += hit->t;
                }
                const size_t i = size_t(pixel);
                out.color.pixels[i] = color * inv;
                out.irradiance.pixels[i] = irr * inv;
                out.direct.pixels[i] = dir * inv;
                out.albedo.pixels[i] = alb * inv;
                if (n_hit > 0) {
                    out.normal.pixels[i] = normalize(nrm);
                    out.position.pixels[i] = pos / float(n_hit);
                    out.depth[i] = depth / float(n_hit);
                    hits += 1;
                }
            }
            progress.add(1);
        }
    });
    progress.finish();
    out.hit_fraction = float(hits.load()) / float(int64_t(cam.width) * cam.height);
    out.seconds = seconds_since(t0);
    return out;
}

void write_rendered_image(const RenderedImage &img, const std::string &prefix, float exposure, bool exr_float) {
    // Half halves the bytes that ZIP compresses: most of a frame's write (docs/performance.md, session 34).
    const size_t n = size_t(img.width) * size_t(img.height);
    auto rgb = [&](const std::string &base, const Image &im, const char *a, const char *b, const char *c, bool may_half) {
        const float *d = &im.pixels[0].x;
        std::vector<ExrChannel> out{{base + a, d, 3}, {base + b, d + 1, 3}, {base + c, d + 2, 3}};
        for (ExrChannel &e : out) e.half = may_half && !exr_float && fits_half(e.data, n, 3);
        return out;
    };
    std::vector<ExrChannel> ch = rgb("", img.color, "R", "G", "B", true);
    for (const auto &group : {rgb("irradiance.", img.irradiance, "R", "G", "B", true), rgb("direct.", img.direct, "R", "G", "B", true),
                              rgb("albedo.", img.albedo, "R", "G", "B", true), rgb("N.", img.normal, "X", "Y", "Z", true),
                              rgb("P.", img.position, "X", "Y", "Z", false)})
        ch.insert(ch.end(), group.begin(), group.end());
    ch.push_back({"Z", img.depth.data(), 1});
    write_exr(prefix + ".exr", img.width, img.height, ch);
    write_png(prefix + ".png", img.color, exposure);
}

void check_camera(const EmbreeAccel &accel, const Camera &cam, const std::string &where) {
    // 1. Does it see anything? A 32×32 probe of primary rays.
    int seen = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
            seen += accel.intersect({cam.eye, cam.ray_direction((float(x) + 0.5f) * float(cam.width) / 32.f,
                                                                (float(y) + 0.5f) * float(cam.height) / 32.f)})
                        .has_value();
    if (seen == 0) LTM_THROW(where, ": camera '", cam.name, "' looks at nothing (no primary ray hits geometry)");
    // 2. Is the eye inside a closed solid? Rays in all directions then hit back faces.
    int back = 0, total = 0;
    for (int i = 0; i < 16; ++i)
        for (int j = 0; j < 16; ++j) {
            const float z = 1.f - 2.f * (float(i) + 0.5f) / 16.f, phi = 2.f * k_pi * (float(j) + 0.5f) / 16.f;
            const float r = std::sqrt(std::max(0.f, 1.f - z * z));
            const Vec3f d{r * std::cos(phi), z, r * std::sin(phi)};
            const auto hit = accel.intersect({cam.eye, d});
            ++total;
            if (hit && dot(hit->n, d) > 0.f) ++back;
        }
    if (back >= total * 9 / 10)
        LTM_THROW(where, ": camera '", cam.name, "' at ", cam.eye, " is inside geometry (", back, "/", total,
                  " rays hit back faces)");
}

}  // namespace ltm
