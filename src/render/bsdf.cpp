// bsdf.cpp: Lambert and GGX conductor. The GGX sampler draws visible normals (Heitz 2018,
// "Sampling the GGX Distribution of Visible Normals"), pdf = G1(wo)·max(0, wo·h)·D(h)/(wo.z) /(4 wo·h).
#include "ltm/render/bsdf.h"

#include <cmath>

#include "ltm/core/sampling.h"

namespace ltm {

float ggx_d(Vec3f h, float a) {
    if (h.z <= 0.f) return 0.f;
    const float a2 = a * a, c2 = h.z * h.z;
    const float t = c2 * (a2 - 1.f) + 1.f;
    return a2 / (k_pi * t * t);
}

float ggx_lambda(Vec3f w, float a) {
    const float c2 = w.z * w.z;
    if (c2 <= 0.f) return 0.f;
    const float tan2 = std::max(0.f, 1.f - c2) / c2;
    return 0.5f * (std::sqrt(1.f + a * a * tan2) - 1.f);
}

float ggx_g2(Vec3f wo, Vec3f wi, float a) { return 1.f / (1.f + ggx_lambda(wo, a) + ggx_lambda(wi, a)); }

namespace {
float ggx_g1(Vec3f w, float a) { return 1.f / (1.f + ggx_lambda(w, a)); }

Vec3f schlick(Vec3f f0, float cos_theta) {
    const float m = std::pow(clamp(1.f - cos_theta, 0.f, 1.f), 5.f);
    return f0 + (Vec3f(1.f) - f0) * m;
}

// Heitz 2018, listing 1: visible normal for view direction wo (local, z up).
Vec3f sample_ggx_vndf(Vec3f wo, float a, Vec2f u) {
    const Vec3f vh = normalize(Vec3f(a * wo.x, a * wo.y, wo.z));
    const float len2 = vh.x * vh.x + vh.y * vh.y;
    const Vec3f t1 = len2 > 0.f ? Vec3f(-vh.y, vh.x, 0.f) / std::sqrt(len2) : Vec3f(1.f, 0.f, 0.f);
    const Vec3f t2 = cross(vh, t1);
    const float r = std::sqrt(u.x), phi = 2.f * k_pi * u.y;
    const float p1 = r * std::cos(phi);
    float p2 = r * std::sin(phi);
    const float s = 0.5f * (1.f + vh.z);
    p2 = (1.f - s) * std::sqrt(std::max(0.f, 1.f - p1 * p1)) + s * p2;
    const Vec3f nh = t1 * p1 + t2 * p2 + vh * std::sqrt(std::max(0.f, 1.f - p1 * p1 - p2 * p2));
    return normalize(Vec3f(a * nh.x, a * nh.y, std::max(1e-6f, nh.z)));
}
}  // namespace

Vec3f Bsdf::eval(Vec3f wo, Vec3f wi) const {
    if (wo.z <= 0.f || wi.z <= 0.f) return Vec3f(0.f);
    if (kind == BsdfKind::diffuse) return albedo * k_inv_pi;
    const Vec3f h = normalize(wo + wi);
    const float d = ggx_d(h, alpha), g = ggx_g2(wo, wi, alpha);
    return schlick(f0, dot(wi, h)) * (d * g / (4.f * wo.z * wi.z));
}

float Bsdf::pdf(Vec3f wo, Vec3f wi) const {
    if (wo.z <= 0.f || wi.z <= 0.f) return 0.f;
    if (kind == BsdfKind::diffuse) return wi.z * k_inv_pi;
    const Vec3f h = normalize(wo + wi);
    // VNDF pdf of h is G1(wo)·max(0,wo·h)·D(h)/wo.z; the reflection Jacobian is 1/(4 wo·h).
    return ggx_g1(wo, alpha) * ggx_d(h, alpha) / (4.f * wo.z);
}

BsdfSample Bsdf::sample(Vec3f wo, Vec2f u) const {
    BsdfSample s;
    if (wo.z <= 0.f) return s;
    if (kind == BsdfKind::diffuse) {
        s.wi = sample_cosine_hemisphere(u);
        s.pdf = s.wi.z * k_inv_pi;
        s.weight = s.pdf > 0.f ? albedo : Vec3f(0.f);   // (albedo/π)·cos / (cos/π)
        return s;
    }
    const Vec3f h = sample_ggx_vndf(wo, alpha, u);
    s.wi = h * (2.f * dot(wo, h)) - wo;
    if (s.wi.z <= 0.f) return BsdfSample{};
    s.pdf = pdf(wo, s.wi);
    // f·cos/pdf = F·G2/G1(wo) for VNDF sampling.
    s.weight = schlick(f0, dot(s.wi, h)) * (ggx_g2(wo, s.wi, alpha) / ggx_g1(wo, alpha));
    return s;
}

}  // namespace ltm
