// reachable_air.h: which air the scene's light can reach, whatever way its faces are wound.
//
// Real files do not orient their faces: a pbrt room's walls and floor are often one-sided quads
// whose normals point out of the room (pbrt's diffuse material is two-sided, so pbrt does not
// care), and then every test that reads "inside a solid" from back faces finds the whole room
// inside one (living-room-3: the sampler kept 7 400 of its 8 192 points on the walls' outer sides,
// and the prior's first bounce came out 2× too bright). Air that light can reach is a question of
// connectivity instead, which needs no orientation: the free space of a voxel grid, flooded from
// the air in front of every emitter's emitting side and from every camera, is the air light can be
// in; a surface side that faces other air — inside a closed sofa, under a box, outside the house —
// gets no light and no view.
//
// Construction: cells of edge h (a fixed fraction of the scene's largest extent, so the grid is
// unit-free) over the bounds plus a margin. Each triangle blocks the cells of a lattice of points
// on it no farther than h/2 apart, so consecutive lattice points lie in 26-adjacent cells and the
// blocked cells of a surface separate 6-connected air on its two sides. Gaps narrower than ~2h
// (a door left ajar by a few cm) may close; cameras seed the air they are in, so a room a camera
// looks at is reached even then. Where every cell in front of a side is blocked (details and gaps
// finer than the grid) the grid gives no verdict, and the enclosure test's rays decide.
#pragma once

#include <cstdint>
#include <vector>

#include "ltm/core/math.h"
#include "ltm/scene/scene.h"

namespace ltm {

class ReachableAir {
public:
    /// Cells per the scene's largest extent (the grid's resolution; h = extent / cells_per_extent).
    static constexpr int k_cells_per_extent = 256;
    /// A side's air is looked for up to this many cells in front of it (past the blocked cells of
    /// its own surface and of small objects on it).
    static constexpr int k_search_cells = 4;

    /// Builds the grid and floods it from the seeds. A scene with neither an emitter nor a camera
    /// has no seeds (has_seeds() false; reaches() is then true everywhere).
    explicit ReachableAir(const Scene &scene, int cells_per_extent = k_cells_per_extent);

    /// False if the first free cell in front of side (p, n) — along n, within k_search_cells — is
    /// air that is not reached (inside a closed solid, outside a closed house); true if it is
    /// reached, or if every cell there is blocked (a detail or a gap finer than the grid: no verdict).
    bool reaches(Vec3f p, Vec3f n) const;
    /// reaches(p, −d) for a ray's hit point p and direction d: the air the ray came through is
    /// reached (or finer than the grid).
    bool approach_reached(Vec3f p, Vec3f d) const { return reaches(p, -d); }

    bool has_seeds() const { return m_seeds > 0; }
    float cell() const { return m_h; }
    int64_t reached_cells() const { return m_reached; }
    int64_t blocked_cells() const { return m_blocked; }

private:
    enum : uint8_t { k_free = 0, k_blocked = 1, k_reached = 2 };
    int64_t index(int i, int j, int k) const { return (int64_t(k) * m_n[1] + j) * m_n[0] + i; }
    bool cell_of(Vec3f p, int &i, int &j, int &k) const;   // false outside the grid
    /// The first non-blocked cell along p + n·h·s, s = 1 … k_search_cells (p's own cell first):
    /// its state, or k_blocked if all are blocked.
    uint8_t state_in_front(Vec3f p, Vec3f n) const;
    void block_triangle(Vec3f a, Vec3f b, Vec3f c);
    void seed(Vec3f p, Vec3f n, std::vector<int64_t> &queue);

    Vec3f m_origin{0.f};
    float m_h = 1.f;
    int m_n[3] = {1, 1, 1};
    std::vector<uint8_t> m_state;
    int64_t m_seeds = 0, m_reached = 0, m_blocked = 0;
};

}  // namespace ltm
