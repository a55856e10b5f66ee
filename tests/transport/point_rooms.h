// point_rooms.h: rooms made of points, shared by the transport prior and point visibility tests: a
// g×g grid over each face of an axis-aligned box with inward normals, and the prior read back at
// chosen points.
#pragma once

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

/// The prior's irradiance at points p with normals n: [p.size() × 3].
inline std::vector<float> gather(const TransportPrior &t, const std::vector<Vec3f> &p, const std::vector<Vec3f> &n) {
    std::vector<float> pos, nrm, out(3 * p.size());
    for (size_t i = 0; i < p.size(); ++i)
        for (int c = 0; c < 3; ++c) pos.push_back(p[i][c]), nrm.push_back(n[i][c]);
    gather_transport_prior(t, pos.data(), nrm.data(), 3, p.size(), out.data());
    return out;
}

}  // namespace ltm::test
