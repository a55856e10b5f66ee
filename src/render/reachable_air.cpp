// reachable_air.cpp: block the cells the surfaces pass through, flood the free cells from the
// emitters' and cameras' air (6-connected), answer "is the air in front of this side reached".
#include "ltm/render/reachable_air.h"

#include <algorithm>
#include <cmath>

#include "ltm/core/error.h"

namespace ltm {

ReachableAir::ReachableAir(const Scene &scene, int cells_per_extent) {
    const Bounds3f b = scene.bounds();
    const Vec3f ext = b.extent();
    const float largest = std::max(max_component(ext), 1e-30f);
    m_h = largest / float(std::max(cells_per_extent, 8));
    // Two free cells of margin on every side (the outside of a closed scene is one region), and
    // an origin off the bounds by a non-round fraction of a cell: axis-aligned faces at round
    // offsets from the bounds (every generated wall, the bounds' own faces) then never sit on a
    // cell boundary, where float rounding would pick the cell differently in another unit.
    m_origin = b.lo - Vec3f((2.f + 0.381966f) * m_h);
    for (int a = 0; a < 3; ++a) m_n[a] = int(std::ceil(ext[a] / m_h)) + 6;
    m_state.assign(size_t(m_n[0]) * size_t(m_n[1]) * size_t(m_n[2]), k_free);

    for (const TriangleMesh &mesh : scene.meshes)
        for (size_t t = 0; t < mesh.n_triangles(); ++t) {
            block_triangle(mesh.vertex(t, 0), mesh.vertex(t, 1), mesh.vertex(t, 2));
        }
    for (uint8_t s : m_state) m_blocked += s == k_blocked;

    // Seeds: the air in front of every emitting side (emission is one-sided, along the normal) and
    // the air each camera stands in.
    std::vector<int64_t> queue;
    for (const TriangleMesh &mesh : scene.meshes) {
        if (!scene.materials[size_t(mesh.material)].is_emissive()) continue;
        for (size_t t = 0; t < mesh.n_triangles(); ++t) {
            const Vec3f c = (mesh.vertex(t, 0) + mesh.vertex(t, 1) + mesh.vertex(t, 2)) / 3.f;
            const Vec3f n = mesh.cross_normal(t);
            if (length(n) > 0.f) seed(c, normalize(n), queue);
        }
    }
    for (const Camera &cam : scene.cameras) seed(cam.eye, Vec3f(0.f), queue);
    m_seeds = int64_t(queue.size());

    // Flood (6-connected) through free cells, breadth first. The queue holds each cell's (i, j, k)
    // packed 21 bits an axis, so neither the grid bounds nor the index need a division.
    constexpr int bits = 21;
    constexpr uint64_t mask = (uint64_t(1) << bits) - 1;
    if (std::max({m_n[0], m_n[1], m_n[2]}) > int(mask)) LTM_THROW("reachable air: a grid of ", m_n[0], "x", m_n[1], "x", m_n[2], " cells");
    std::vector<uint64_t> front;
    front.reserve(m_state.size() - size_t(m_blocked));   // at most every free cell: no regrowth
    for (int64_t c : queue)
        front.push_back(uint64_t(c % m_n[0]) | uint64_t((c / m_n[0]) % m_n[1]) << bits | uint64_t(c / (int64_t(m_n[0]) * m_n[1])) << 2 * bits);
    const int64_t stride[3] = {1, m_n[0], int64_t(m_n[0]) * m_n[1]};
    for (size_t head = 0; head < front.size(); ++head) {
        const uint64_t packed = front[head];
        const int64_t ijk[3] = {int64_t(packed & mask), int64_t(packed >> bits & mask), int64_t(packed >> 2 * bits)};
        const int64_t c = ijk[0] + stride[1] * ijk[1] + stride[2] * ijk[2];
        for (int a = 0; a < 3; ++a)
            for (int s : {-1, 1}) {
                const int64_t q = ijk[a] + s;
                if (q < 0 || q >= m_n[a]) continue;
                const int64_t nb = c + s * stride[a];
                if (m_state[size_t(nb)] != k_free) continue;
                m_state[size_t(nb)] = k_reached;
                front.push_back(s < 0 ? packed - (uint64_t(1) << a * bits) : packed + (uint64_t(1) << a * bits));
            }
    }
    m_reached = int64_t(front.size());
}

bool ReachableAir::cell_of(Vec3f p, int &i, int &j, int &k) const {
    const Vec3f u = (p - m_origin) / m_h;
    if (!(u.x >= 0.f && u.y >= 0.f && u.z >= 0.f)) return false;
    i = int(u.x), j = int(u.y), k = int(u.z);
    return i < m_n[0] && j < m_n[1] && k < m_n[2];
}

void ReachableAir::block_triangle(Vec3f a, Vec3f b, Vec3f c) {
    // Lattice a + (s/nu)(b − a) + (t/nv)(c − a), s/nu + t/nv ≤ 1, from the vertex at the largest
    // angle (so a needle is a thin lattice), plus the third edge: neighbours ≤ h/2 apart.
    const float lab = length(b - a), lbc = length(c - b), lca = length(a - c);
    if (lbc >= lab && lbc >= lca) {   // a is opposite the longest edge: keep
    } else if (lca >= lab) {
        std::swap(a, b);   // b opposite ca: make it the apex
    } else {
        std::swap(a, c);   // c opposite ab
    }
    const float half = 0.5f * m_h;
    const int nu = std::max(1, int(std::ceil(length(b - a) / half)));
    const int nv = std::max(1, int(std::ceil(length(c - a) / half)));
    const int ne = std::max(1, int(std::ceil(length(c - b) / half)));
    auto block = [&](Vec3f p) {
        int i, j, k;
        if (!cell_of(p, i, j, k)) return;
        m_state[size_t(index(i, j, k))] = k_blocked;
    };
    for (int s = 0; s <= nu; ++s) {
        const float fs = float(s) / float(nu);
        const int tmax = int(std::floor((1.f - fs) * float(nv) + 1e-4f));
        for (int t = 0; t <= tmax; ++t) block(a + (b - a) * fs + (c - a) * (float(t) / float(nv)));
    }
    for (int e = 0; e <= ne; ++e) block(b + (c - b) * (float(e) / float(ne)));
}

void ReachableAir::seed(Vec3f p, Vec3f n, std::vector<int64_t> &queue) {
    for (int s = 0; s <= k_search_cells; ++s) {
        int i, j, k;
        if (!cell_of(p + n * (float(s) * m_h), i, j, k)) return;
        const int64_t c = index(i, j, k);
        if (m_state[size_t(c)] == k_blocked) {
            if (length(n) == 0.f) return;   // a camera inside geometry seeds nothing
            continue;
        }
        if (m_state[size_t(c)] == k_free) {
            m_state[size_t(c)] = k_reached;
            queue.push_back(c);
        }
        return;
    }
}

uint8_t ReachableAir::state_in_front(Vec3f p, Vec3f n) const {
    for (int s = 0; s <= k_search_cells; ++s) {
        int i, j, k;
        // Beyond the grid lies the margin's air, which is one region with it.
        if (!cell_of(p + n * (float(s) * m_h), i, j, k)) return m_state[0];
        const uint8_t st = m_state[size_t(index(i, j, k))];
        if (st != k_blocked) return st;
    }
    return k_blocked;
}

bool ReachableAir::reaches(Vec3f p, Vec3f n) const {
    if (!has_seeds()) return true;
    // Blocked cells all the way: the grid cannot tell (a detail smaller than a few cells, a thin
    // gap); the rays of the enclosure test judge such sides (measured on the 16 validation houses:
    // refusing them too cost 17 % more MSE, 0.0043 against 0.0037).
    return state_in_front(p, n) != k_free;
}

}  // namespace ltm
