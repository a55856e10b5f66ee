// key_grid.h: comparisons that a change of unit keeps. The same scene in another unit comes out of
// the sampler with its points moved by ~1e-5 spacings of float rounding; where two coordinates or
// distances are equal up to that rounding (nodes on one line or lattice, members of a symmetric
// patch at one distance from its centroid, a node halfway between two centres), comparing the floats
// lets the rounding decide, and the unit with it. Compared as whole steps of a grid far coarser than
// the rounding (and far finer than the geometry) they tie, and the caller breaks the tie by something
// the unit keeps (an index); a key changes only for a value within rounding of a step's edge. Used by
// the prior's cluster tree (transport/prior_hierarchy.h) and its clusters (transport/point_visibility.h).
#pragma once

#include <cmath>
#include <cstdint>

#include "ltm/core/math.h"

namespace ltm {

struct KeyGrid {
    /// 2 − φ: the origin's and the distances' shift, in steps, so that lattices (test grids, walls at
    /// whole spacings) and their distances do not sit on the steps' edges.
    static constexpr double k_offset = 0.3819660112501051;
    Vec3f origin{0.f};   ///< coordinates count from here (callers place it k_offset steps below their lowest point)
    double step = 1.0;
    /// Coordinate x on axis a, in whole steps from the origin.
    int64_t key(float x, int axis) const { return int64_t(std::floor((double(x) - double(origin[axis])) / step)); }
    /// A distance d ≥ 0 in whole steps (shifted by k_offset of a step).
    int64_t distance_key(double d) const { return int64_t(std::floor(d / step + k_offset)); }
    int64_t length_key(Vec3f e) const { return distance_key(double(length(e))); }
};

}  // namespace ltm
