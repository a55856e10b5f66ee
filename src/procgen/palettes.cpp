// palettes.cpp: albedo palettes. Values are linear RGB (not sRGB), chosen to match measured
// reflectances of paints, woods, fabrics and floors (white paint ~0.8, dark wood ~0.1).
#include "ltm/procgen/palettes.h"

#include <cmath>
#include <vector>

namespace ltm {

float quantize(float v) { return float(std::round(double(v) * 1e4) / 1e4); }
Vec3f quantize(Vec3f v) { return {quantize(v.x), quantize(v.y), quantize(v.z)}; }

const char *surface_kind_name(SurfaceKind kind) {
    switch (kind) {
    case SurfaceKind::wall: return "wall";
    case SurfaceKind::ceiling: return "ceiling";
    case SurfaceKind::floor: return "floor";
    case SurfaceKind::wood: return "wood";
    case SurfaceKind::painted: return "painted";
    case SurfaceKind::fabric: return "fabric";
    case SurfaceKind::bedding: return "bedding";
    case SurfaceKind::metal: return "metal";
    case SurfaceKind::ceramic: return "ceramic";
    case SurfaceKind::foliage: return "foliage";
    case SurfaceKind::books: return "books";
    case SurfaceKind::carpet: return "carpet";
    }
    return "?";
}

namespace {

using Palette = std::vector<Vec3f>;
struct Pair {
    Vec3f a, b;
};

const Palette k_wall_whites = {{0.80f, 0.80f, 0.78f}, {0.78f, 0.76f, 0.72f}, {0.75f, 0.74f, 0.70f},
                               {0.82f, 0.81f, 0.80f}, {0.70f, 0.70f, 0.68f}, {0.55f, 0.56f, 0.56f}};
const Palette k_wall_pastels = {{0.55f, 0.65f, 0.75f}, {0.55f, 0.72f, 0.60f}, {0.80f, 0.62f, 0.50f},
                                {0.62f, 0.58f, 0.72f}, {0.82f, 0.76f, 0.50f}, {0.78f, 0.60f, 0.60f}};
const Palette k_accents = {{0.05f, 0.12f, 0.35f}, {0.50f, 0.15f, 0.07f}, {0.06f, 0.25f, 0.10f},
                           {0.60f, 0.40f, 0.05f}, {0.30f, 0.03f, 0.06f}, {0.02f, 0.28f, 0.30f},
                           {0.08f, 0.08f, 0.09f}};
const Palette k_ceilings = {{0.80f, 0.80f, 0.80f}, {0.78f, 0.78f, 0.76f}, {0.75f, 0.75f, 0.75f}};
// Wood: early/late wood ring colours.
const std::vector<Pair> k_woods = {{{0.45f, 0.28f, 0.14f}, {0.30f, 0.17f, 0.08f}},    // oak
                                   {{0.60f, 0.42f, 0.22f}, {0.45f, 0.28f, 0.12f}},    // pine
                                   {{0.18f, 0.10f, 0.05f}, {0.10f, 0.05f, 0.025f}},   // walnut
                                   {{0.65f, 0.52f, 0.36f}, {0.52f, 0.38f, 0.24f}},    // birch
                                   {{0.40f, 0.15f, 0.07f}, {0.25f, 0.08f, 0.04f}},    // cherry
                                   {{0.40f, 0.38f, 0.35f}, {0.28f, 0.26f, 0.24f}}};   // grey wash
const std::vector<Pair> k_tiles = {{{0.75f, 0.75f, 0.72f}, {0.08f, 0.08f, 0.08f}},
                                   {{0.55f, 0.30f, 0.18f}, {0.70f, 0.55f, 0.40f}},
                                   {{0.50f, 0.52f, 0.55f}, {0.70f, 0.71f, 0.72f}},
                                   {{0.20f, 0.30f, 0.45f}, {0.75f, 0.74f, 0.70f}}};
const Palette k_floor_plain = {{0.35f, 0.35f, 0.34f}, {0.12f, 0.11f, 0.10f}, {0.55f, 0.48f, 0.38f},
                               {0.25f, 0.35f, 0.25f}};
const Palette k_fabric_neutral = {{0.55f, 0.48f, 0.38f}, {0.30f, 0.30f, 0.31f}, {0.07f, 0.07f, 0.08f},
                                  {0.75f, 0.70f, 0.60f}, {0.25f, 0.14f, 0.08f}, {0.03f, 0.05f, 0.15f}};
const Palette k_fabric_saturated = {{0.60f, 0.04f, 0.04f}, {0.04f, 0.10f, 0.55f}, {0.05f, 0.40f, 0.08f},
                                    {0.80f, 0.60f, 0.03f}, {0.75f, 0.25f, 0.02f}, {0.25f, 0.05f, 0.40f},
                                    {0.02f, 0.35f, 0.35f}, {0.75f, 0.25f, 0.40f}};
const Palette k_bedding = {{0.80f, 0.80f, 0.78f}, {0.75f, 0.73f, 0.68f}, {0.60f, 0.62f, 0.66f}};
const Palette k_metals = {{0.55f, 0.55f, 0.56f}, {0.35f, 0.35f, 0.36f}, {0.15f, 0.15f, 0.16f},
                          {0.55f, 0.42f, 0.18f}, {0.04f, 0.04f, 0.04f}};
const Palette k_ceramics = {{0.50f, 0.20f, 0.10f}, {0.80f, 0.80f, 0.78f}, {0.05f, 0.05f, 0.05f},
                            {0.10f, 0.20f, 0.45f}};
const Palette k_foliage = {{0.05f, 0.20f, 0.04f}, {0.08f, 0.28f, 0.05f}, {0.12f, 0.30f, 0.08f}};
const Palette k_painted = {{0.78f, 0.78f, 0.76f}, {0.04f, 0.04f, 0.04f}, {0.35f, 0.36f, 0.37f},
                           {0.35f, 0.45f, 0.35f}, {0.05f, 0.08f, 0.20f}, {0.70f, 0.50f, 0.05f},
                           {0.55f, 0.06f, 0.05f}};

template <typename T> const T &pick(const std::vector<T> &v, Pcg32 &rng) {
    return v[rng.next_below(uint32_t(v.size()))];
}

// One brightness factor per object keeps hue; the clamp keeps albedo physically plausible.
Vec3f jitter(Vec3f c, float amount, Pcg32 &rng) {
    c = c * rng.uniform(1.f - amount, 1.f + amount);
    const float m = max_component(c);
    if (m > 0.85f) c = c * (0.85f / m);
    return quantize(c);
}

Texture constant_albedo(Vec3f c) { return Texture::constant(c); }

Texture pattern(TextureKind kind, Vec3f a, Vec3f b, Vec2f scale, Pcg32 &rng) {
    Texture t;
    t.kind = kind;
    t.color_a = a;
    t.color_b = b;
    t.scale = quantize(rng.uniform(scale.x, scale.y));
    t.angle_deg = rng.bernoulli(0.5f) ? 0.f : 90.f;
    t.seed = rng.next_u32() & 0xffffu;
    return t;
}

Texture wood_albedo(const GenConfig::Textures &cfg, Pcg32 &rng, bool textured) {
    const Pair &w = pick(k_woods, rng);
    const float f = rng.uniform(1.f - cfg.color_jitter, 1.f + cfg.color_jitter);
    const Vec3f a = quantize(w.a * f), b = quantize(w.b * f);   // woods are all below 0.85
    if (!textured) return constant_albedo(a);
    return pattern(TextureKind::wood, a, b, cfg.wood_scale, rng);
}

Texture fabric_albedo(const GenConfig::Textures &cfg, Pcg32 &rng, float p_pattern, bool carpet) {
    const Palette &pal = rng.bernoulli(cfg.p_saturated_fabric) ? k_fabric_saturated : k_fabric_neutral;
    const Vec3f a = jitter(pick(pal, rng), cfg.color_jitter, rng);
    if (!rng.bernoulli(p_pattern)) return constant_albedo(a);
    const Vec3f b = jitter(pick(rng.bernoulli(0.5f) ? k_fabric_neutral : k_fabric_saturated, rng),
                           cfg.color_jitter, rng);
    if (carpet && rng.bernoulli(0.5f)) return pattern(TextureKind::noise, a, b, cfg.noise_scale, rng);
    const bool checker = !carpet && rng.bernoulli(0.3f);
    return pattern(checker ? TextureKind::checker : TextureKind::stripes, a, b, cfg.stripe_scale, rng);
}

}  // namespace

Texture sample_albedo(SurfaceKind kind, const GenConfig::Textures &cfg, Pcg32 &rng) {
    const float j = cfg.color_jitter;
    switch (kind) {
    case SurfaceKind::wall: {
        const Vec3f a = rng.bernoulli(cfg.p_accent_wall) ? jitter(pick(k_accents, rng), j, rng)
                        : rng.bernoulli(0.6f)            ? jitter(pick(k_wall_whites, rng), j, rng)
                                                         : jitter(pick(k_wall_pastels, rng), j, rng);
        if (!rng.bernoulli(cfg.p_wall_pattern)) return constant_albedo(a);
        // Wallpaper: vertical stripes of the colour and a lighter or darker shade of it.
        Texture t = pattern(TextureKind::stripes, a, quantize(a * rng.uniform(0.7f, 0.9f)), cfg.stripe_scale, rng);
        t.angle_deg = 0.f;
        return t;
    }
    case SurfaceKind::ceiling: return constant_albedo(jitter(pick(k_ceilings, rng), 0.03f, rng));
    case SurfaceKind::floor: {
        const float u = rng.next_float();
        if (u < cfg.p_floor_wood) return wood_albedo(cfg, rng, /*textured=*/true);
        if (u < cfg.p_floor_wood + cfg.p_floor_tiles) {
            const Pair &p = pick(k_tiles, rng);
            const bool swap = rng.bernoulli(0.5f);
            const Vec3f a = jitter(swap ? p.b : p.a, j, rng);   // one statement per draw:
            const Vec3f b = jitter(swap ? p.a : p.b, j, rng);   // argument order is unspecified
            return pattern(TextureKind::checker, a, b, cfg.tile_scale, rng);
        }
        return constant_albedo(jitter(pick(k_floor_plain, rng), j, rng));
    }
    case SurfaceKind::wood: return wood_albedo(cfg, rng, rng.bernoulli(cfg.p_furniture_wood));
    case SurfaceKind::painted: return constant_albedo(jitter(pick(k_painted, rng), j, rng));
    case SurfaceKind::fabric: return fabric_albedo(cfg, rng, cfg.p_fabric_pattern, /*carpet=*/false);
    case SurfaceKind::carpet: return fabric_albedo(cfg, rng, cfg.p_carpet_pattern, /*carpet=*/true);
    case SurfaceKind::bedding: return constant_albedo(jitter(pick(k_bedding, rng), j, rng));
    case SurfaceKind::metal: return constant_albedo(jitter(pick(k_metals, rng), j, rng));
    case SurfaceKind::ceramic: return constant_albedo(jitter(pick(k_ceramics, rng), j, rng));
    case SurfaceKind::foliage: {
        const Vec3f a = jitter(pick(k_foliage, rng), j, rng);
        Texture t = pattern(TextureKind::noise, a, quantize(a * 0.45f), {0.04f, 0.1f}, rng);   // leaf-sized blotches
        return t;
    }
    case SurfaceKind::books: {
        // Book spines: stripes of two colours, one period per pair of books (2–5 cm each).
        const Vec3f a = jitter(pick(k_fabric_saturated, rng), j, rng);
        const Vec3f b = jitter(pick(rng.bernoulli(0.5f) ? k_fabric_neutral : k_painted, rng), j, rng);
        Texture t = pattern(TextureKind::stripes, a, b, {0.04f, 0.1f}, rng);
        t.angle_deg = 0.f;
        return t;
    }
    }
    return constant_albedo(Vec3f(0.5f));
}

}  // namespace ltm
