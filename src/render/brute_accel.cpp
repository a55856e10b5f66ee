// brute_accel.cpp: every triangle, double precision, two-sided (as Embree by default).
#include "ltm/render/brute_accel.h"

#include <cmath>

namespace ltm {

std::optional<Hit> BruteAccel::intersect(const Ray &ray) const {
    std::optional<Hit> best;
    double best_t = double(ray.tmax);
    for (size_t m = 0; m < m_scene.meshes.size(); ++m) {
        const TriangleMesh &mesh = m_scene.meshes[m];
        for (size_t t = 0; t < mesh.n_triangles(); ++t) {
            const Vec3f p0 = mesh.vertex(t, 0), p1 = mesh.vertex(t, 1), p2 = mesh.vertex(t, 2);
            const double e1[3] = {double(p1.x) - p0.x, double(p1.y) - p0.y, double(p1.z) - p0.z};
            const double e2[3] = {double(p2.x) - p0.x, double(p2.y) - p0.y, double(p2.z) - p0.z};
            const double d[3] = {ray.d.x, ray.d.y, ray.d.z};
            const double pv[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
            const double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
            if (std::abs(det) < 1e-300) continue;
            const double inv = 1.0 / det;
            const double s[3] = {double(ray.o.x) - p0.x, double(ray.o.y) - p0.y, double(ray.o.z) - p0.z};
            const double u = (s[0] * pv[0] + s[1] * pv[1] + s[2] * pv[2]) * inv;
            if (u < 0.0 || u > 1.0) continue;
            const double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
            const double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv;
            if (v < 0.0 || u + v > 1.0) continue;
            const double tt = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
            if (tt <= double(ray.tmin) || tt >= best_t) continue;
            best_t = tt;
            Hit h;
            h.t = float(tt);
            h.mesh = uint32_t(m), h.triangle = uint32_t(t);
            h.b1 = float(u), h.b2 = float(v);
            h.n = normalize(mesh.cross_normal(t));
            best = h;
        }
    }
    return best;
}

}  // namespace ltm
