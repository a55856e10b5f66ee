// point_interpolation.h: a field known at scene points, read anywhere on the surfaces between them —
// the inverse-distance mean of the K nearest points that lie on the query's own surface (issue #31).
//
// What it is for: Ê⁺ at the secondary hits of the conductors' traced bounce. A room with metals asks
// for 64 hits a conductor pixel (1.6 M in the kitchen at 512²), and a gather of the prior at each
// costs ~25 µs; Ê⁺ decoded once at the M scene points and interpolated costs ~0.5 µs a hit. The
// secondary hit's Ê⁺ is scaled by its albedo and a BRDF lobe before it reaches a pixel, so its
// error is read against the prior's own sampling noise (two point sets differ by 4–21 % rel. RMS,
// docs/performance.md), not against the primary view's.
//
// A point j takes part for a query (p, n) when it faces the same way (n_j · n ≥ cos 60°), lies
// within `spacing` of the query's tangent plane (a table top's points do not feed the floor under
// it) and within 2·spacing of p; of those, the K nearest (ties by index) weigh 1/(d² + (s/2)²).
// A query with no such point (a surface the sampler left bare, a back face) is reported, not
// guessed: the caller evaluates it exactly.
//
// Known limit: no visibility test. Where a floor runs on under a wall thinner than 2·spacing, the
// next room's floor points pass every test above and a hit at the wall's foot takes some of their
// value. Only the bounce's hits read this (a conductor pixel averages 64 of them over a lobe); the
// four pbrt rooms' conductor pixels came out no worse than decoding each hit (docs/results.md).
#pragma once

#include <cstdint>
#include <vector>

#include "ltm/core/math.h"
#include "ltm/points/point_grid.h"

namespace ltm {

class PointInterpolator {
public:
    static constexpr int k_neighbours = 8;               ///< K
    static constexpr float k_min_facing = 0.5f;          ///< cos 60°
    static constexpr float k_radius_spacings = 2.f;      ///< search radius, in spacings
    static constexpr float k_plane_spacings = 1.f;       ///< distance off the tangent plane, in spacings

    PointInterpolator() = default;
    /// positions, unit normals [M] (same length, M ≥ 1); spacing > 0: the points' nominal spacing
    /// √(A/M) (A: the scene's whole area, as the sampler's nominal spacing), in the positions' unit.
    /// Throws ltm::Error on empty or mismatched input, a non-finite point or normal.
    PointInterpolator(std::vector<Vec3f> positions, std::vector<Vec3f> normals, float spacing);
    size_t size() const { return m_position.size(); }
    float spacing() const { return m_spacing; }
    /// The field at (p, unit n) from values[M] given at the points: true and `out` set, or false
    /// when no point qualifies (out untouched). Depends on (p, n) alone: any thread, any order.
    bool interpolate(Vec3f p, Vec3f n, const Vec3f *values, Vec3f &out) const;

private:
    std::vector<Vec3f> m_position, m_normal;
    float m_spacing = 0.f;
    PointGrid m_grid;
};

}  // namespace ltm
