// disc_occluder.h: occlusion from scene points as oriented discs — the alternative to the voxel
// occupancy of point_visibility.h for the transport prior (still from the points alone: no ray
// tracing of the meshes).
//
// Each point (p, n) stands for a disc of radius r in its tangent plane. A segment a → b is blocked
// when it meets some disc from its front (n · d < 0 beyond a grazing margin: a segment leaving a
// surface or passing behind it is not stopped by it) at a distance more than ε = r/4 from either
// end (the sender's and receiver's own surfaces, and their neighbours in the same plane, meet the
// segment only at its ends).
//
// Why discs: a voxel grid is either coarse — then a segment between two walls near their common
// edge runs through the voxels of both and is falsely blocked — or as fine as the points' spacing,
// and then a wall sampled at that spacing is ~40 % holes. Discs are exact where surfaces are planar:
// a segment above a floor never meets the floor's discs, however close to it, and a wall sampled
// with spacing s is covered by discs of radius r ≈ s (a stratified sample leaves few gaps).
// Doorways shrink by r on each side.
//
// The discs are binned into a cube grid of edge 2r (each disc into every cell its bounding box
// overlaps); a segment visits its cells by a 3D DDA (Amanatides & Woo 1987). The grid only
// accelerates: the answer is a pure function of the discs and the segment, so it maps with the
// scene under rotations, mirrors, translations and a change of unit (with r in units of the
// points' spacing).
//
// Most of a walk's time is its disc tests (a segment between two surfaces crosses the cells of
// both, each holding ~10 coplanar discs), so each cell keeps its discs' centres and normals as
// structure-of-arrays runs padded to 8 and tests 8 at a time (AVX2 where the CPU has it:
// core/simd_clones.h). Each lane's arithmetic is the scalar test's, in its order and without
// contraction (src/CMakeLists.txt), so the answers are the same bits on any CPU.
#pragma once

#include <cstdint>
#include <vector>

#include "ltm/core/math.h"

namespace ltm {

class DiscOccluder {
public:
    DiscOccluder() = default;
    /// points, normals (unit): the discs' centres and orientations; radius: r > 0 (same unit as
    /// the positions). Throws ltm::Error on no points, mismatched sizes, r ≤ 0 or more than 2^28
    /// grid cells.
    DiscOccluder(const std::vector<Vec3f> &points, const std::vector<Vec3f> &normals, float radius);
    bool empty() const { return m_center.empty(); }
    float radius() const { return m_r; }
    /// Is the segment from a to b blocked by a disc it meets from the front, more than r/4 from
    /// either end? A segment shorter than r/2 never is.
    bool blocked(Vec3f a, Vec3f b) const;
    /// Does the ray from `origin` along `direction` (any length > 0) meet a disc from either side
    /// (not grazing), more than r/1000 from its origin, before it leaves the discs' box? A ray that
    /// meets none escapes the scene: the share of a hemisphere's rays that escape is the point's
    /// open share (the transport prior's openness, transport/transport_prior.h).
    bool ray_meets_disc(Vec3f origin, Vec3f direction) const;

private:
    /// Does the segment a + t·d, t ∈ (t0, t1), meet a disc (from the front only, or from either side)?
    bool walk(Vec3f a, Vec3f d, float t0, float t1, bool either_side) const;
    int64_t cell_index(const int c[3]) const { return (int64_t(c[2]) * m_dim[1] + c[1]) * m_dim[0] + c[0]; }
    float m_r = 0.f;
    Vec3f m_origin{0.f};   ///< the grid's lowest corner
    int m_dim[3] = {0, 0, 0};
    std::vector<Vec3f> m_center, m_normal;
    /// [cells + 1] offsets into the runs below; each cell's run is padded to a multiple of 8 with
    /// discs of normal 0, which meet no segment (|n·d| = 0 is below any grazing bound).
    std::vector<uint32_t> m_cell_start;
    std::vector<float> m_cx, m_cy, m_cz, m_nx, m_ny, m_nz;   ///< the cells' discs: centres, normals
};

}  // namespace ltm
