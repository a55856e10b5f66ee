// texture.cpp: procedural patterns. All are functions of (uv, parameters) only, so a texture
// looks the same whichever sampler or renderer evaluates it.
#include "ltm/scene/texture.h"

#include <cmath>

#include "ltm/core/rng.h"

namespace ltm {

const char *texture_kind_name(TextureKind kind) {
    switch (kind) {
    case TextureKind::constant: return "constant";
    case TextureKind::image: return "image";
    case TextureKind::checker: return "checker";
    case TextureKind::stripes: return "stripes";
    case TextureKind::wood: return "wood";
    case TextureKind::noise: return "noise";
    }
    return "?";
}

namespace {
float lattice(int64_t x, int64_t y, uint32_t seed) {
    return float(hash_keys({uint64_t(x), uint64_t(y), seed}) >> 40) * 0x1p-24f;
}
float smooth(float t) { return t * t * (3.f - 2.f * t); }
float fbm(Vec2f p, uint32_t seed) {
    float sum = 0.f, amp = 0.5f, norm = 0.f;
    for (int o = 0; o < 4; ++o) {
        sum += amp * value_noise(p, seed + uint32_t(o) * 7919u);
        norm += amp;
        p = {p.x * 2.03f, p.y * 2.03f};
        amp *= 0.5f;
    }
    return sum / norm;
}
Vec3f mix(Vec3f a, Vec3f b, float t) { return a + (b - a) * t; }
}  // namespace

float value_noise(Vec2f p, uint32_t seed) {
    const float fx = std::floor(p.x), fy = std::floor(p.y);
    const int64_t ix = int64_t(fx), iy = int64_t(fy);
    const float tx = smooth(p.x - fx), ty = smooth(p.y - fy);
    const float a = lattice(ix, iy, seed), b = lattice(ix + 1, iy, seed);
    const float c = lattice(ix, iy + 1, seed), d = lattice(ix + 1, iy + 1, seed);
    return lerp(lerp(a, b, tx), lerp(c, d, tx), ty);
}

Vec3f Texture::eval(Vec2f uv) const {
    if (kind == TextureKind::constant) return color_a;
    if (kind == TextureKind::image) {
        if (!image || image->width == 0) return color_a;
        const float x = uv.x * float(image->width) - 0.5f;
        const float y = (1.f - uv.y) * float(image->height) - 0.5f;
        const float fx = std::floor(x), fy = std::floor(y);
        const float tx = x - fx, ty = y - fy;
        auto texel = [&](int64_t ix, int64_t iy) {
            const int64_t w = image->width, h = image->height;
            return image->at(int(((ix % w) + w) % w), int(((iy % h) + h) % h));
        };
        const int64_t ix = int64_t(fx), iy = int64_t(fy);
        return mix(mix(texel(ix, iy), texel(ix + 1, iy), tx),
                   mix(texel(ix, iy + 1), texel(ix + 1, iy + 1), tx), ty);
    }
    // Rotate uv into the pattern frame and express it in periods.
    const float rad = angle_deg * k_pi / 180.f, c = std::cos(rad), s = std::sin(rad);
    const float inv = 1.f / scale;
    const Vec2f q{(c * uv.x + s * uv.y) * inv, (-s * uv.x + c * uv.y) * inv};
    switch (kind) {
    case TextureKind::checker: {
        const int64_t parity = (int64_t(std::floor(q.x)) + int64_t(std::floor(q.y))) & 1;
        return parity ? color_b : color_a;
    }
    case TextureKind::stripes: return (int64_t(std::floor(q.x)) & 1) ? color_b : color_a;
    case TextureKind::wood: {
        // Rings along u (the grain direction), perturbed by low-frequency noise.
        const float warp = 0.6f * fbm({q.x * 0.25f, q.y * 4.f}, seed);
        const float ring = q.y + warp;
        const float t = 0.5f + 0.5f * std::sin(2.f * k_pi * ring);
        const float grain = 0.85f + 0.15f * value_noise({q.x * 12.f, q.y * 40.f}, seed + 17u);
        return mix(color_a, color_b, t * t) * grain;
    }
    case TextureKind::noise: return mix(color_a, color_b, fbm(q, seed));
    default: return color_a;
    }
}

Vec3f Texture::max_value() const {
    switch (kind) {
    case TextureKind::constant: return color_a;
    case TextureKind::image: {
        Vec3f m(0.f);
        if (image)
            for (const Vec3f &p : image->pixels) m = max(m, p);
        return m;
    }
    default: return max(color_a, color_b);
    }
}

}  // namespace ltm
