// power_balance.cpp: π · mean(e_c) · Σ_{k=1..D} mean(ρ_c)^k over area-uniform scene points, and
// the exact Φ/A of a scene's meshes.
#include "ltm/transport/power_balance.h"

#include <algorithm>

#include "ltm/core/error.h"
#include "ltm/core/math.h"
#include "ltm/core/sampling.h"

namespace ltm {

double bounce_series(double rho, int bounces) {
    double term = 1, series = 0;
    for (int k = 0; k < bounces; ++k) series += (term *= rho);
    return series;
}

std::array<double, 3> power_balance_irradiance(const PointSet &sp, int bounces, const Vec3f *emission_scale) {
    if (sp.columns != scene_point_columns()) LTM_THROW("power_balance_irradiance: not a scene point table");
    if (sp.size() == 0) LTM_THROW("power_balance_irradiance: no scene points");
    if (bounces < 0) LTM_THROW("power_balance_irradiance: bounces must be >= 0, got ", bounces);
    std::array<double, 3> rho{0, 0, 0}, e{0, 0, 0}, out{0, 0, 0};
    for (size_t i = 0; i < sp.size(); ++i)
        for (size_t c = 0; c < 3; ++c) rho[c] += double(sp.at(i, 6 + c)), e[c] += double(sp.at(i, 9 + c));
    for (size_t c = 0; c < 3; ++c) {
        const double r = std::clamp(rho[c] / double(sp.size()), 0.0, 1.0);
        const double s = emission_scale ? double((*emission_scale)[int(c)]) : double(k_pi) * e[c] / double(sp.size());
        out[c] = s * bounce_series(r, bounces);
    }
    return out;
}

Vec3f scene_emission_scale(const Scene &scene, double pass_fraction) {
    if (!(pass_fraction > 0.0 && pass_fraction <= 1.0))
        LTM_THROW("scene_emission_scale: pass fraction must be in (0, 1], got ", pass_fraction);
    double area = 0.0, flux[3] = {0, 0, 0};
    for (const TriangleMesh &mesh : scene.meshes) {
        const Material &mat = scene.materials[size_t(mesh.material)];
        for (size_t t = 0; t < mesh.n_triangles(); ++t) {
            const double a = double(mesh.area(t));
            area += a;
            if (!mat.is_emissive()) continue;
            Vec3f le = mat.emission.color_a;
            if (!mat.emission.is_constant()) {
                // Mean over 64 points spread by the R2 sequence (fixed shift: deterministic).
                constexpr int k_n = 64;
                Vec3f sum(0.f);
                for (int i = 0; i < k_n; ++i) {
                    const Vec2f b = sample_uniform_triangle(r2_sequence(uint64_t(i), Vec2f{0.5f, 0.5f}));
                    sum += mat.emission.eval(mesh.uv_at(t, b.x, b.y, 1.f - b.x - b.y));
                }
                le = sum / float(k_n);
            }
            for (int c = 0; c < 3; ++c) flux[c] += a * double(le[c]);
        }
    }
    if (!(area > 0.0)) LTM_THROW("scene_emission_scale: scene '", scene.name, "' has zero surface area");
    const double a_eff = pass_fraction * area;
    return Vec3f(float(k_pi * flux[0] / a_eff), float(k_pi * flux[1] / a_eff), float(k_pi * flux[2] / a_eff));
}

}  // namespace ltm
