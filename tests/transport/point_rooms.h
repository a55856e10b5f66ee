// point_rooms.h: rooms made of points, shared by the transport prior and point visibility tests: a
// g×g grid over each face of an axis-aligned box with inward normals, and the prior read back at
// chosen points.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "ltm/core/math.h"
#include "ltm/transport/transport_prior.h"

namespace ltm::test {

/// Calls visit(face, p, n) for the centre of each of the g×g cells on each face of the box
/// [lo, lo + size] (face 0..5: −x, +x, −y, +y, −z, +z; n the inward unit normal), the centre moved
/// within the face by jitter() = {du, dv} cells, called once per cell just before its visit.
template <class Jitter, class Visit> void for_each_face_cell(Vec3f lo, Vec3f size, int g, Jitter jitter, Visit visit) {
    for (int f = 0; f < 6; ++f) {
        const int axis = f / 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
        const bool hi = f % 2 == 1;
        for (int a = 0; a < g; ++a)
            for (int b = 0; b < g; ++b) {
                const std::pair<float, float> d = jitter();
                Vec3f p(0.f), n(0.f);
                p[axis] = lo[axis] + (hi ? size[axis] : 0.f);
                p[u] = lo[u] + (float(a) + 0.5f + d.first) / float(g) * size[u];
                p[v] = lo[v] + (float(b) + 0.5f + d.second) / float(g) * size[v];
                n[axis] = hi ? -1.f : 1.f;
                visit(f, p, n);
            }
    }
}

/// Maps a point set in place by a symmetry `map` (a rotation or mirror, applied to positions and
/// normals) and a change of unit `scale` (positions only): the training symmetries' tests.
template <class Map> void map_points(std::vector<Vec3f> &p, std::vector<Vec3f> &n, Map map, float scale) {
    for (size_t i = 0; i < p.size(); ++i) p[i] = map(p[i]) * scale, n[i] = map(n[i]);
}

/// The jitter of cells at their exact centres.
inline std::pair<float, float> no_jitter() { return {0.f, 0.f}; }

/// A value in [0, 1) hashed from (i, salt): jitter and random points without a generator's state.
inline float hash01(size_t i, int salt) {
    const double x = std::sin(double(i) * 12.9898 + double(salt) * 78.233) * 43758.5453;
    return float(x - std::floor(x));
}

/// A room of points: positions, unit normals, albedos, emitted radiances.
struct Points {
    std::vector<Vec3f> p, n, rho, le;
};

/// The jitter of for_each_face_cell keyed by how many points `out` holds so far: each cell's centre
/// moves by up to ±amplitude/2 cells per axis — no exact distance ties, so FPS and the cluster
/// choice do not hinge on float rounding.
inline auto jitter_by_count(const Points &out, float amplitude) {
    return [&out, amplitude] {
        return std::pair{amplitude * (hash01(out.p.size(), 1) - 0.5f), amplitude * (hash01(out.p.size(), 2) - 0.5f)};
    };
}

/// The furnace: a closed 2 m box, 16 × 16 points a face, uniform ρ = (0.5, 0.8, 0.2) and L = (1, 2, 3).
inline Points furnace_box() {
    Points pts;
    for_each_face_cell(Vec3f(0.f), Vec3f(2.f), 16, no_jitter, [&](int, Vec3f p, Vec3f n) {
        pts.p.push_back(p), pts.n.push_back(n), pts.rho.push_back(Vec3f(0.5f, 0.8f, 0.2f)), pts.le.push_back(Vec3f(1.f, 2.f, 3.f));
    });
    return pts;
}

/// The prior's irradiance at points p with normals n: [p.size() × 3]; far (optional, resized to
/// [p.size() × 3]): its part through the tree's aggregates (gather_transport_prior).
inline std::vector<float> gather(const TransportPrior &t, const std::vector<Vec3f> &p, const std::vector<Vec3f> &n,
                                 std::vector<float> *far = nullptr) {
    std::vector<float> pos, nrm, out(3 * p.size());
    for (size_t i = 0; i < p.size(); ++i)
        for (int c = 0; c < 3; ++c) pos.push_back(p[i][c]), nrm.push_back(n[i][c]);
    if (far) far->resize(3 * p.size());
    gather_transport_prior(t, pos.data(), nrm.data(), 3, p.size(), out.data(), far ? far->data() : nullptr);
    return out;
}

/// The largest |E⁺ − π L Σ_{k=1..5} ρ^k| / (π L Σ ρ^k) of a prior solved (5 bounces) on furnace_box(),
/// over every channel at two receivers (one on the floor, one near a wall's corner facing down).
inline double furnace_error(const TransportPrior &t, const Points &box) {
    const auto e = gather(t, {{1.f, 0.01f, 1.f}, {0.3f, 1.2f, 1.99f}}, {{0, 1, 0}, {0, 0, -1}});
    double worst = 0;
    for (int c = 0; c < 3; ++c) {
        const double rho = box.rho[0][c];
        const double expect = k_pi * double(box.le[0][c]) * (rho - std::pow(rho, 6)) / (1 - rho);
        for (int r = 0; r < 2; ++r) worst = std::max(worst, std::abs(double(e[size_t(3 * r + c)]) - expect) / expect);
    }
    return worst;
}

}  // namespace ltm::test
