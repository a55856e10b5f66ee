// bsdf.h: the two reflection models of ltm, in the local shading frame (z = normal):
// Lambertian (albedo/π) and GGX conductor (Walter et al. 2007; visible-normal sampling, Heitz 2018).
#pragma once

#include "ltm/core/math.h"
#include "ltm/scene/material.h"

namespace ltm {

struct BsdfSample {
    Vec3f wi;        ///< sampled incident direction (local)
    Vec3f weight;    ///< f·cosθi / pdf
    float pdf = 0;   ///< solid-angle pdf of wi
};

/// A BSDF at one surface point. Directions are local, both on the normal side (reflection only).
struct Bsdf {
    BsdfKind kind = BsdfKind::diffuse;
    Vec3f albedo;          ///< diffuse reflectance
    Vec3f f0;              ///< conductor: Fresnel reflectance at normal incidence
    float alpha = 0.3f;    ///< conductor: GGX roughness

    /// f(wo, wi) (without the cosine).
    Vec3f eval(Vec3f wo, Vec3f wi) const;
    float pdf(Vec3f wo, Vec3f wi) const;
    /// Importance-samples wi; pdf = 0 means the sample failed (below the horizon).
    BsdfSample sample(Vec3f wo, Vec2f u) const;
};

/// GGX normal distribution D(h) and Smith height-correlated masking-shadowing G2.
float ggx_d(Vec3f h, float alpha);
float ggx_lambda(Vec3f w, float alpha);
float ggx_g2(Vec3f wo, Vec3f wi, float alpha);

}  // namespace ltm
