// light_sampler.cpp: power-proportional triangle choice, uniform point on the triangle.
#include "ltm/render/light_sampler.h"

#include <algorithm>

#include "ltm/core/sampling.h"

namespace ltm {

LightSampler::LightSampler(const Scene &scene) : m_scene(scene) {
    m_index.resize(scene.meshes.size());
    double sum = 0;
    std::vector<double> w;
    for (size_t m = 0; m < scene.meshes.size(); ++m) {
        const TriangleMesh &mesh = scene.meshes[m];
        m_index[m].assign(mesh.n_triangles(), -1);
        const Material &mat = scene.materials[size_t(mesh.material)];
        if (!mat.is_emissive()) continue;
        // Textured emission: weight by the texture's maximum (sampling stays unbiased, only
        // the choice is approximate).
        const float lum = std::max(luminance(mat.emission.max_value()), 1e-6f);
        for (size_t t = 0; t < mesh.n_triangles(); ++t) {
            const float a = mesh.area(t);
            m_index[m][t] = int32_t(m_tris.size());
            m_tris.push_back({uint32_t(m), uint32_t(t), a});
            w.push_back(double(a) * lum);
            sum += w.back();
        }
    }
    m_cdf.push_back(0.0);
    double acc = 0;
    for (double x : w) {
        acc += x;
        m_cdf.push_back(acc / sum);
        m_pmf.push_back(float(x / sum));
    }
    if (!m_cdf.empty()) m_cdf.back() = 1.0;
}

LightSample LightSampler::sample(float u0, Vec2f u12) const {
    LightSample s;
    if (m_tris.empty()) return s;
    const auto it = std::upper_bound(m_cdf.begin(), m_cdf.end(), double(u0));
    const size_t k = std::min(size_t(it - m_cdf.begin()) - 1, m_tris.size() - 1);
    const Tri &tri = m_tris[k];
    const TriangleMesh &mesh = m_scene.meshes[tri.mesh];
    const Vec2f b = sample_uniform_triangle(u12);
    const float b2 = 1.f - b.x - b.y;
    s.p = mesh.position_at(tri.triangle, b.x, b.y, b2);
    s.n = normalize(mesh.cross_normal(tri.triangle));
    const Vec2f uv = mesh.uv_at(tri.triangle, b.x, b.y, b2);
    s.radiance = m_scene.materials[size_t(mesh.material)].emission.eval(uv);
    s.pdf_area = m_pmf[k] / tri.area;
    return s;
}

float LightSampler::pdf_area(uint32_t mesh, uint32_t triangle) const {
    const int32_t k = m_index[mesh][triangle];
    return k < 0 ? 0.f : m_pmf[size_t(k)] / m_tris[size_t(k)].area;
}

}  // namespace ltm
