// material.h: diffuse surfaces with a (possibly textured) albedo and optional emission, and
// GGX conductors (the glossy material of paper §7).
#pragma once

#include <map>
#include <string>

#include "ltm/scene/texture.h"

namespace ltm {

enum class BsdfKind { diffuse, conductor };

/// Lambertian BRDF albedo/π plus emitted radiance Le (W/m²/sr, one-sided, along the normal).
/// "diffuse" materials have zero emission; "emissive" ones a non-zero radiance (they may also
/// reflect, as in the furnace box). "conductor": GGX microfacet reflection (Walter et al. 2007)
/// with Smith height-correlated masking and Schlick's Fresnel from `specular` (= F0).
struct Material {
    std::string name;
    BsdfKind bsdf = BsdfKind::diffuse;
    Texture albedo = Texture::constant(Vec3f(0.8f));
    Texture emission = Texture::constant(Vec3f(0.f));   ///< radiance Le
    float roughness = 0.3f;                             ///< conductor: GGX α (0.001–1)
    Vec3f specular{0.9f};                               ///< conductor: reflectance at normal incidence
    bool is_emissive() const {
        return !emission.is_constant() || max_component(emission.color_a) > 0.f;
    }
};

/// F0 (linear sRGB) of named metals — pbrt-v4's "metal-<X>-eta"/"-k" spectra (Ag, Al, Au, Cu,
/// CuZn, MgO, TiO2) — from their complex refractive indices at ~650/550/450 nm.
const std::map<std::string, Vec3f> &named_metal_f0();

}  // namespace ltm
