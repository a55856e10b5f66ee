// direct_light.cpp: analytic unshadowed irradiance of triangle emitters + the visibility ratio.
#include "ltm/render/direct_light.h"

#include <algorithm>
#include <cmath>

#include "ltm/core/error.h"
#include "ltm/core/rng.h"
#include "ltm/core/sampling.h"
#include "ltm/render/ray.h"

namespace ltm {

namespace {
constexpr uint64_t k_ratio_domain = 5ull << 60;   // streams disjoint from the path tracer's
}

float triangle_irradiance(Vec3f p, Vec3f n, Vec3f v0, Vec3f v1, Vec3f v2) {
    // One-sided emitter: the receiver must be on the side its normal points to.
    const Vec3f ng = cross(v1 - v0, v2 - v0);
    if (!(dot(ng, p - v0) > 0.f)) return 0.f;
    // Clip to the receiver's upper hemisphere (Sutherland–Hodgman against n·(x − p) = 0), in
    // coordinates relative to p: a convex polygon of at most 4 vertices above the horizon.
    const Vec3f in[3] = {v0 - p, v1 - p, v2 - p};
    Vec3f poly[4];
    int m = 0;
    for (int i = 0; i < 3; ++i) {
        const Vec3f a = in[i], b = in[(i + 1) % 3];
        const float da = dot(n, a), db = dot(n, b);
        if (da >= 0.f) poly[m++] = a;
        if ((da >= 0.f) != (db >= 0.f)) {
            const float t = da / (da - db);
            poly[m++] = a + (b - a) * t;
        }
    }
    if (m < 3) return 0.f;
    // Lambert: E = 1/2 · Σ_i θ_i · n·(r_i × r_{i+1})/|r_i × r_{i+1}| with unit r_i; the clipped
    // polygon is convex and above the horizon, so the terms share one sign (the winding's).
    double sum = 0.0;
    for (int i = 0; i < m; ++i) {
        const Vec3f a = normalize(poly[i]), b = normalize(poly[(i + 1) % m]);
        const Vec3f c = cross(a, b);
        const float len = length(c);
        if (!(len > 0.f)) continue;   // a vertex on p itself or collinear: no area from this edge
        const double theta = std::atan2(double(len), double(dot(a, b)));   // accurate for small angles
        sum += theta * double(dot(n, c)) / double(len);
    }
    return float(std::abs(0.5 * sum));
}

bool RatioDirectLight::supports(const Scene &scene) {
    for (const auto &m : scene.materials)
        if (m.is_emissive() && !m.emission.is_constant()) return false;
    return true;
}

RatioDirectLight::RatioDirectLight(const EmbreeAccel &accel, uint64_t seed) : m_accel(accel), m_seed(seed) {
    const Scene &scene = accel.scene();
    for (const auto &mesh : scene.meshes) {
        const Material &mat = scene.materials[size_t(mesh.material)];
        if (!mat.is_emissive()) continue;
        if (!mat.emission.is_constant())
            LTM_THROW(scene.name, ": material '", mat.name, "' has textured emission; the ratio estimator needs constant radiance");
        Light l;
        l.radiance = mat.emission.color_a;
        double total = 0.0;
        for (size_t t = 0; t < mesh.n_triangles(); ++t) {
            if (!(mesh.area(t) > 0.f)) continue;
            for (int k = 0; k < 3; ++k) l.v.push_back(mesh.vertex(t, k));
            l.normal.push_back(normalize(mesh.cross_normal(t)));
            total += double(mesh.area(t));
            l.cdf.push_back(total);
        }
        if (l.cdf.empty()) continue;
        for (double &c : l.cdf) c /= total;
        l.cdf.back() = 1.0;
        m_lights.push_back(std::move(l));
    }
}

float RatioDirectLight::unoccluded_factor(const Light &l, Vec3f p, Vec3f n) const {
    float g = 0.f;
    for (size_t t = 0; t < l.v.size(); t += 3) g += triangle_irradiance(p, n, l.v[t], l.v[t + 1], l.v[t + 2]);
    return g;
}

Vec3f RatioDirectLight::unoccluded(Vec3f p, Vec3f n) const {
    Vec3f e(0.f);
    for (const Light &l : m_lights) e += l.radiance * unoccluded_factor(l, p, n);
    return e;
}

Vec3f RatioDirectLight::irradiance(Vec3f p, Vec3f n, uint64_t key, int n_samples) const {
    if (n_samples <= 0) LTM_THROW("direct light: samples per point must be > 0, got ", n_samples);
    // E_unocc per light, and the luminance that shares the samples out.
    const size_t n_lights = m_lights.size();
    std::vector<float> g(n_lights);
    double total = 0.0;
    for (size_t i = 0; i < n_lights; ++i) {
        g[i] = unoccluded_factor(m_lights[i], p, n);
        total += double(g[i]) * double(luminance(m_lights[i].radiance));
    }
    if (!(total > 0.0)) return Vec3f(0.f);
    Pcg32 rng(hash_keys({m_seed, k_ratio_domain, key}));
    Vec3f e(0.f);
    for (size_t i = 0; i < n_lights; ++i) {
        const Light &l = m_lights[i];
        const double share = double(g[i]) * double(luminance(l.radiance)) / total;
        if (!(share > 0.0)) continue;
        const int k = std::max(1, int(std::lround(share * double(n_samples))));
        double seen = 0.0, all = 0.0;
        for (int s = 0; s < k; ++s) {
            // Uniform on the light's area: triangle by area, then a uniform point on it.
            const double u0 = double(rng.next_float());
            const size_t tri = size_t(std::lower_bound(l.cdf.begin(), l.cdf.end(), u0) - l.cdf.begin()), t = 3 * tri;
            const Vec2f b = sample_uniform_triangle({rng.next_float(), rng.next_float()});
            const Vec3f q = l.v[t] * b.x + l.v[t + 1] * b.y + l.v[t + 2] * (1.f - b.x - b.y);
            const Vec3f to = q - p;
            const float d2 = dot(to, to);
            if (!(d2 > 0.f)) continue;
            const Vec3f wl = to / std::sqrt(d2);
            const float cos_x = dot(n, wl), cos_light = -dot(l.normal[tri], wl);
            if (cos_x <= 0.f || cos_light <= 0.f) continue;   // w = 0 in both sums
            const double w = double(cos_x) * double(cos_light) / double(d2);   // the constant area pdf cancels
            all += w;
            if (!m_accel.occluded(shadow_ray(p, n, q))) seen += w;
        }
        // No sample on the part above the horizon (a sliver): its visibility is unknown; 0, as
        // the MIS estimator would give from these samples.
        if (all > 0.0) e += l.radiance * (g[i] * float(seen / all));
    }
    return e;
}

IrradianceImages direct_images_ratio(const RatioDirectLight &light, const GBuffer &gb, int spp) {
    if (spp <= 0) LTM_THROW("direct light: samples per pixel must be > 0, got ", spp);
    return estimate_images(gb, "direct light", [&](size_t k) {
        return IrradianceEstimate{light.irradiance(gb.position[k], gb.normal[k], uint64_t(gb.hit_pixels[k]), spp), Vec3f(0.f)};
    });
}

}  // namespace ltm
