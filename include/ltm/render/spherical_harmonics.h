// spherical_harmonics.h: real orthonormal spherical harmonics and their best fit to hemisphere
// bins — the baseline the directional head is compared with (paper Fig. 12, issue #11 item 4).
//
// Y_lm, l ≤ l_max, (l_max + 1)² functions indexed k = l² + l + m, orthonormal over the sphere
// (∫ Y_k Y_k' dω = δ_kk'), with the usual real basis: m > 0 ∝ cos(mφ), m < 0 ∝ sin(|m|φ), in the
// local frame z = normal (θ from z, φ from x). A bin of hemisphere_bins.h holds the
// projected-solid-angle mean of L over its cell, so an SH expansion is compared bin against bin
// through its bin means Ȳ_kb (the mean of Y_k over the cell, uniform in the unit square).
#pragma once

#include <vector>

#include "ltm/core/math.h"

namespace ltm {

/// (l_max + 1)²: the number of real SH of degree ≤ l_max.
inline int sh_count(int l_max) { return (l_max + 1) * (l_max + 1); }

/// Y_k(w) for k < sh_count(l_max) into out[0 .. sh_count). w: unit vector (local frame).
void sh_evaluate(int l_max, Vec3f w, double *out);

/// The best SH approximation of degree ≤ l_max to R×R bins, in the bins' own metric: the
/// coefficients c minimise Σ_b (Σ_k c_k Ȳ_kb − L_b)² (equal projected solid angle per bin), so no
/// other SH of that degree — the plain projection c_k = ∫ L Y_k dω included — is closer to the
/// bins. Full-sphere SH are not orthogonal over the hemisphere; a ridge of 1e-9 · mean diagonal
/// keeps the normal equations solvable.
class BinShFit {
public:
    /// sub × sub points per cell for the bin means (uniform in the cell, mapped like the bins).
    BinShFit(int resolution, int l_max, int sub = 6);
    int resolution() const { return m_res; }
    int l_max() const { return m_lmax; }
    /// The fit of degree l ≤ l_max, reconstructed as bin values.  bins [R², 3] -> [R², 3]
    std::vector<Vec3f> fit(const std::vector<Vec3f> &bins, int l) const;

private:
    int m_res, m_lmax;
    std::vector<double> m_mean;   ///< [R², K] Ȳ_kb
};

}  // namespace ltm
