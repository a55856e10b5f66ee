// texture.h: albedo and emission textures: constant, image, and procedural patterns
// (checker, stripes, wood, noise) evaluated from surface uv coordinates.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "ltm/core/image.h"
#include "ltm/core/math.h"

namespace ltm {

enum class TextureKind { constant, image, checker, stripes, wood, noise };

const char *texture_kind_name(TextureKind kind);

/// A colour as a function of uv. Procedural patterns use uv in the units the mesh's uvs are in
/// (metres for generated geometry), so `scale` is a physical period.
struct Texture {
    TextureKind kind = TextureKind::constant;
    Vec3f color_a{0.8f};      ///< constant colour; first colour of a pattern (linear RGB)
    Vec3f color_b{0.2f};      ///< second colour of a pattern
    float scale = 0.25f;      ///< pattern period in uv units (checker cell, stripe pair, ring)
    float angle_deg = 0.f;    ///< rotation of the pattern in the uv plane
    uint32_t seed = 0;        ///< noise/wood seed
    std::string image_path;   ///< image texture: resolved path of the file
    bool image_srgb = true;   ///< image texture: 8-bit values are sRGB-encoded (false: linear)
    std::shared_ptr<const Image> image;   ///< decoded image (linear RGB), tiled with wrap

    static Texture constant(Vec3f c) {
        Texture t;
        t.color_a = c;
        return t;
    }
    /// Squares of side `scale` (uv units) alternating a and b, unrotated.
    static Texture checker(Vec3f a, Vec3f b, float scale) {
        Texture t;
        t.kind = TextureKind::checker;
        t.color_a = a, t.color_b = b, t.scale = scale;
        return t;
    }
    /// Albedo/emission at uv. Image textures: bilinear, repeat wrap, v = 0 at the bottom row.
    Vec3f eval(Vec2f uv) const;
    bool is_constant() const { return kind == TextureKind::constant; }
    /// Upper bound of every channel over the texture (exact for constant/procedural).
    Vec3f max_value() const;
};

/// Smooth value noise in [0,1] on a 2D lattice (deterministic in seed), for textures.
float value_noise(Vec2f p, uint32_t seed);

}  // namespace ltm
