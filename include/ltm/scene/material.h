// material.h: diffuse surfaces with a (possibly textured) albedo and optional emission.
#pragma once

#include <string>

#include "ltm/scene/texture.h"

namespace ltm {

/// Lambertian BRDF albedo/π plus emitted radiance Le (W/m²/sr, one-sided, along the normal).
/// "diffuse" materials have zero emission; "emissive" ones a non-zero radiance (they may also
/// reflect, as in the furnace box).
struct Material {
    std::string name;
    Texture albedo = Texture::constant(Vec3f(0.8f));
    Texture emission = Texture::constant(Vec3f(0.f));   ///< radiance Le
    bool is_emissive() const {
        return !emission.is_constant() || max_component(emission.color_a) > 0.f;
    }
};

}  // namespace ltm
