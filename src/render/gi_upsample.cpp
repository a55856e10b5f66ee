// gi_upsample.cpp: geometry-aware bilinear interpolation of a lattice of decoded E⁺ values, one
// level or coarse to fine.
#include "ltm/render/gi_upsample.h"

#include <algorithm>
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

namespace {

// The G-buffer's pixel -> hit map and the world size of one pixel at unit distance (the vertical
// field of view over the image height), shared by every lattice's blends.
struct PixelIndex {
    const GBuffer &gb;
    std::vector<int64_t> hit_of_pixel;
    float pixel_angle = 0.f;
    PixelIndex(const GBuffer &g, const Camera &camera) : gb(g), hit_of_pixel(size_t(g.width) * size_t(g.height), -1) {
        if (camera.width != gb.width || camera.height != gb.height)
            LTM_THROW("GI interpolation: camera ", camera.width, "x", camera.height, " but G-buffer ", gb.width, "x", gb.height);
        for (size_t i = 0; i < gb.n_hits(); ++i) hit_of_pixel[size_t(gb.hit_pixels[i])] = int64_t(i);
        pixel_angle = 2.f * std::tan(0.5f * camera.fov_y_deg * k_pi / 180.f) / float(gb.height);
    }
};

// Hit i's blend of the stride-s lattice: its corners (x0, x0 + s) × (y0, y0 + s) whose normal is
// within min_normal_cos and whose position lies within the tolerance of i's tangent plane, each
// weighted bilinearly (1 at the corner, 0 at the opposite one); lo and hi: the channels' range over
// the corners that weigh > 0. value(c): corner hit c's value, or null where the corner has none.
struct Blend {
    Vec3f sum{0.f};
    float weight = 0.f;
    Vec3f lo{0.f}, hi{0.f};
    bool rejected = false;   ///< a corner that weighs > 0 failed the tests, shows no surface or lies past the image
};
template <class Value>
Blend blend(const PixelIndex &ix, size_t i, int s, const GiUpsampleOptions &opt, Value value) {
    const GBuffer &gb = ix.gb;
    const int x = int(gb.hit_pixels[i] % gb.width), y = int(gb.hit_pixels[i] / gb.width);
    const int x0 = x - x % s, y0 = y - y % s;
    const Vec3f p = gb.position[i], n = gb.normal[i];
    const float tolerance = opt.plane_tolerance * float(s) * ix.pixel_angle * gb.depth[i];
    Blend b;
    bool any = false;
    for (const int cy : {y0, y0 + s})
        for (const int cx : {x0, x0 + s}) {
            const float w = (1.f - float(std::abs(x - cx)) / float(s)) * (1.f - float(std::abs(y - cy)) / float(s));
            if (cx >= gb.width || cy >= gb.height) {   // past the image: nothing to agree with
                if (w > 0.f) b.rejected = true;
                continue;
            }
            const int64_t c = ix.hit_of_pixel[size_t(cy) * size_t(gb.width) + size_t(cx)];
            const Vec3f *v = c < 0 ? nullptr : value(size_t(c));
            if (!v || dot(n, gb.normal[size_t(c)]) < opt.min_normal_cos || std::fabs(dot(n, gb.position[size_t(c)] - p)) > tolerance) {
                if (w > 0.f) b.rejected = true;
                continue;
            }
            b.sum += *v * w;
            b.weight += w;
            if (w > 0.f) {
                b.lo = any ? min(b.lo, *v) : *v;
                b.hi = any ? max(b.hi, *v) : *v;
                any = true;
            }
        }
    return b;
}

}  // namespace

GiInterpolation interpolate_from_lattice(const GBuffer &gb, const Camera &camera, const std::vector<Vec3f> &lattice_values,
                                         const GiUpsampleOptions &opt) {
    const int s = opt.stride;
    const std::vector<size_t> lattice = lattice_hits(gb, s);
    if (lattice_values.size() != lattice.size())
        LTM_THROW("GI interpolation: ", lattice_values.size(), " lattice values for ", lattice.size(), " lattice hits");
    const PixelIndex ix(gb, camera);
    std::vector<int64_t> slot_of_hit(gb.n_hits(), -1);
    for (size_t k = 0; k < lattice.size(); ++k) slot_of_hit[lattice[k]] = int64_t(k);

    GiInterpolation out;
    out.values.assign(gb.n_hits(), Vec3f(0.f));
    for (size_t i = 0; i < gb.n_hits(); ++i) {
        if (slot_of_hit[i] >= 0) {
            out.values[i] = lattice_values[size_t(slot_of_hit[i])];
            continue;
        }
        const Blend b = blend(ix, i, s, opt, [&](size_t c) { return &lattice_values[size_t(slot_of_hit[c])]; });
        if (b.weight < opt.min_weight) out.needs_decode.push_back(i);
        else out.values[i] = b.sum / b.weight;
    }
    return out;
}

int auto_gi_levels(int stride, int width, int height) {
    if (stride < 1) LTM_THROW("GI lattice stride must be >= 1, got ", stride);
    const int across = std::min(width, height) / 64;
    int levels = 1;
    while (levels < 4 && (stride << levels) <= across) ++levels;
    return levels;
}

GiUpsampled upsample_gi(const GBuffer &gb, const Camera &camera, const GiUpsampleOptions &opt, const GiDecode &decode) {
    if (opt.levels < 1 || opt.levels > 8) LTM_THROW("GI lattice levels must be in [1, 8], got ", opt.levels);
    if (!(opt.contrast >= 0.f)) LTM_THROW("GI lattice contrast must be >= 0, got ", opt.contrast);
    if (opt.stride < 1) LTM_THROW("GI lattice stride must be >= 1, got ", opt.stride);
    GiUpsampled out;
    auto decoded = [&](const std::vector<size_t> &hits) {
        std::vector<Vec3f> v = hits.empty() ? std::vector<Vec3f>{} : decode(hits);
        if (v.size() != hits.size()) LTM_THROW("GI lattice: the decoder returned ", v.size(), " values for ", hits.size(), " hits");
        out.decoded += int64_t(hits.size());
        return v;
    };
    // The stride-s lattice's values (lattice_hits order): decoded at once with one level, else
    // coarse to fine.
    std::vector<Vec3f> finest;
    if (opt.levels == 1) {
        finest = decoded(lattice_hits(gb, opt.stride));
    } else {
        const PixelIndex ix(gb, camera);
        std::vector<Vec3f> value(gb.n_hits(), Vec3f(0.f));
        std::vector<uint8_t> known(gb.n_hits(), 0);
        int s = opt.stride << (opt.levels - 1);
        {
            const std::vector<size_t> coarse = lattice_hits(gb, s);
            const std::vector<Vec3f> v = decoded(coarse);
            for (size_t k = 0; k < coarse.size(); ++k) value[coarse[k]] = v[k], known[coarse[k]] = 1;
        }
        const auto at = [&](size_t c) { return known[c] ? &value[c] : nullptr; };
        for (; s > opt.stride; s /= 2) {
            // The lattice of stride s/2's new pixels, blended from the stride-s lattice (all known)
            // where its corners agree; the blends are written after every pixel of this level has
            // read its corners, which lie on the stride-s lattice only.
            std::vector<size_t> refine;
            std::vector<std::pair<size_t, Vec3f>> blended;
            for (size_t i : lattice_hits(gb, s / 2)) {
                if (known[i]) continue;
                const Blend b = blend(ix, i, s, opt, at);
                const Vec3f mean = b.weight > 0.f ? b.sum / b.weight : Vec3f(0.f);
                const Vec3f range = b.hi - b.lo;
                if (!b.rejected && b.weight > 0.f && range.x + range.y + range.z <= opt.contrast * (mean.x + mean.y + mean.z))
                    blended.push_back({i, mean});
                else
                    refine.push_back(i);
            }
            const std::vector<Vec3f> v = decoded(refine);
            for (size_t k = 0; k < refine.size(); ++k) value[refine[k]] = v[k], known[refine[k]] = 1;
            for (const auto &[i, m] : blended) value[i] = m, known[i] = 1;
        }
        for (size_t i : lattice_hits(gb, opt.stride)) finest.push_back(value[i]);
    }
    GiInterpolation r = interpolate_from_lattice(gb, camera, finest, opt);
    const std::vector<Vec3f> own = decoded(r.needs_decode);
    for (size_t k = 0; k < own.size(); ++k) r.values[r.needs_decode[k]] = own[k];
    out.values = std::move(r.values);
    return out;
}

}  // namespace ltm
