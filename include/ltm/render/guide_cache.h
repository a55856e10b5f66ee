// guide_cache.h: predicted incident radiance bins at a few thousand surface points, looked up by
// the path tracer at each scattering vertex to guide its next direction (paper Fig. 13; issue
// #11 item 5). Torch-free: the bins come from the directional head (infer/guide_builder.h) or,
// in tests, from anywhere. A vertex uses the nearest cache point within `radius` whose normal is
// within ~25° of its own, and reads the bins in its own frame Frame(n) (nearby points on one
// surface share it; any guide keeps the estimator unbiased, only its variance depends on it).
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "ltm/core/math.h"
#include "ltm/render/guide_distribution.h"

namespace ltm {

class GuideCache {
public:
    GuideCache() = default;
    /// position/normal [C], radiance [C·R²] (bins in Frame(normal), non-negative), radius > 0.
    /// Throws ltm::Error on mismatched sizes, non-finite or negative radiance, radius ≤ 0.
    GuideCache(int resolution, std::vector<Vec3f> position, std::vector<Vec3f> normal, std::vector<Vec3f> radiance, float radius);
    bool empty() const { return m_position.empty(); }
    int resolution() const { return m_res; }
    size_t size() const { return m_position.size(); }
    float radius() const { return m_radius; }
    /// The nearest cache point within the radius with dot(n, n_c) ≥ 0.9; −1 if none.
    int lookup(Vec3f p, Vec3f n) const;
    /// Point c's bins [R²] and its radiance-only distribution (for diffuse vertices: f is constant).
    const Vec3f *radiance(int c) const { return m_radiance.data() + size_t(c) * size_t(m_res) * size_t(m_res); }
    const BinDistribution &diffuse(int c) const { return m_diffuse[size_t(c)]; }
    const std::vector<Vec3f> &positions() const { return m_position; }
    const std::vector<Vec3f> &normals() const { return m_normal; }

private:
    int64_t cell_key(int64_t x, int64_t y, int64_t z) const { return (x * 73856093) ^ (y * 19349663) ^ (z * 83492791); }
    int m_res = 0;
    float m_radius = 0.f;
    std::vector<Vec3f> m_position, m_normal, m_radiance;
    std::vector<BinDistribution> m_diffuse;
    std::unordered_map<int64_t, std::vector<int>> m_grid;   ///< cell of edge `radius` -> points
};

}  // namespace ltm
