// gi_upsample.cpp: geometry-aware bilinear interpolation of a lattice of decoded E⁺ values.
#include "ltm/render/gi_upsample.h"

#include <cmath>

#include "ltm/core/error.h"

namespace ltm {

std::vector<size_t> lattice_hits(const GBuffer &gb, int stride) {
    if (stride < 1) LTM_THROW("GI lattice stride must be >= 1, got ", stride);
    std::vector<size_t> out;
    for (size_t i = 0; i < gb.n_hits(); ++i) {
        const int64_t px = gb.hit_pixels[i];
        if ((px % gb.width) % stride == 0 && (px / gb.width) % stride == 0) out.push_back(i);
    }
    return out;
}

GiInterpolation interpolate_from_lattice(const GBuffer &gb, const Camera &camera, const std::vector<Vec3f> &lattice_values,
                                         const GiUpsampleOptions &opt) {
    const int s = opt.stride;
    const std::vector<size_t> lattice = lattice_hits(gb, s);
    if (lattice_values.size() != lattice.size())
        LTM_THROW("GI interpolation: ", lattice_values.size(), " lattice values for ", lattice.size(), " lattice hits");
    if (camera.width != gb.width || camera.height != gb.height)
        LTM_THROW("GI interpolation: camera ", camera.width, "x", camera.height, " but G-buffer ", gb.width, "x", gb.height);
    // Pixel → hit index and hit → lattice slot.
    std::vector<int64_t> hit_of_pixel(size_t(gb.width) * size_t(gb.height), -1);
    for (size_t i = 0; i < gb.n_hits(); ++i) hit_of_pixel[size_t(gb.hit_pixels[i])] = int64_t(i);
    std::vector<int64_t> slot_of_hit(gb.n_hits(), -1);
    for (size_t k = 0; k < lattice.size(); ++k) slot_of_hit[lattice[k]] = int64_t(k);
    // World size of one pixel at unit distance (vertical field of view over the image height).
    const float pixel_angle = 2.f * std::tan(0.5f * camera.fov_y_deg * k_pi / 180.f) / float(gb.height);

    GiInterpolation out;
    out.values.assign(gb.n_hits(), Vec3f(0.f));
    for (size_t i = 0; i < gb.n_hits(); ++i) {
        if (slot_of_hit[i] >= 0) {
            out.values[i] = lattice_values[size_t(slot_of_hit[i])];
            continue;
        }
        const int x = int(gb.hit_pixels[i] % gb.width), y = int(gb.hit_pixels[i] / gb.width);
        const int x0 = x - x % s, y0 = y - y % s;
        const Vec3f p = gb.position[i], n = gb.normal[i];
        const float tolerance = opt.plane_tolerance * float(s) * pixel_angle * gb.depth[i];
        Vec3f sum(0.f);
        float weight = 0.f;
        for (const int cy : {y0, y0 + s})
            for (const int cx : {x0, x0 + s}) {
                if (cx >= gb.width || cy >= gb.height) continue;
                const int64_t c = hit_of_pixel[size_t(cy) * size_t(gb.width) + size_t(cx)];
                if (c < 0) continue;
                if (dot(n, gb.normal[size_t(c)]) < opt.min_normal_cos) continue;
                if (std::fabs(dot(n, gb.position[size_t(c)] - p)) > tolerance) continue;
                // Bilinear weight: 1 at the corner, 0 at the opposite one.
                const float w = (1.f - float(std::abs(x - cx)) / float(s)) * (1.f - float(std::abs(y - cy)) / float(s));
                sum += lattice_values[size_t(slot_of_hit[size_t(c)])] * w;
                weight += w;
            }
        if (weight < opt.min_weight) out.needs_decode.push_back(i);
        else out.values[i] = sum / weight;
    }
    return out;
}

}  // namespace ltm
