// guide_distribution.h: importance sampling from predicted hemisphere bins (paper §7, Fig. 13;
// issue #11 item 5). A piecewise-constant density over the R×R cells of the unit square, mapped
// to the hemisphere like the bins (render/hemisphere_bins.h: concentric map + cosine lift), so a
// local direction ω with square point u(ω) in cell b has the solid-angle pdf
//     p(ω) = p_u(u) · cosθ / π,   p_u = R² · w_b / Σ_c w_c,
// exactly (the cosine warp's density is cosθ/π for uniform u). With w_b = L̂_b · f(ωo, ω_b) — the
// predicted radiance times the BSDF at the bin centre; the cosine is in the warp — it samples
// the product L·f·cosθ up to the piecewise-constant approximation.
//
// GuidedSampler mixes it defensively with BSDF sampling: p = α p_bsdf + (1 − α) p_guide, so
// wherever f > 0 the density is at least α p_bsdf (the estimator's variance is never more than
// 1/α times BSDF sampling's) and every pdf is evaluated exactly: an unbiased estimator.
#pragma once

#include <vector>

#include "ltm/core/math.h"
#include "ltm/render/bsdf.h"

namespace ltm {

class BinDistribution {
public:
    BinDistribution() = default;
    /// weights [R²] (bin i·R + j as the bins), finite and ≥ 0. All zero: an invalid
    /// distribution (valid() false; a sampler then falls back to the BSDF alone).
    BinDistribution(int resolution, const std::vector<float> &weights);
    bool valid() const { return m_total > 0.0; }
    int resolution() const { return m_res; }
    struct Sample {
        Vec3f w;          ///< local direction (z = normal)
        float pdf = 0.f;  ///< solid-angle pdf
    };
    /// CDF inversion over the cells (u.x), uniform inside the chosen cell (u.x's remainder, u.y).
    Sample sample(Vec2f u) const;
    /// Solid-angle pdf of a local direction; 0 below the horizon.
    float pdf(Vec3f w) const;

private:
    int m_res = 0;
    double m_total = 0.0;
    std::vector<double> m_cdf;   ///< [R² + 1], m_cdf[0] = 0, m_cdf[R²] = 1
};

/// Product weights for one vertex: w_b = lum(L̂_b) · lum(f(ωo, ω_b)), ω_b the bin centres.
///   radiance [R²] (local bins), bsdf, wo local -> [R²]
std::vector<float> product_weights(const std::vector<Vec3f> &radiance, int resolution, const Bsdf &bsdf, Vec3f wo);
/// The same on R² bins held elsewhere (a guide cache's, read in place at every glossy vertex).
std::vector<float> product_weights(const Vec3f *radiance, int resolution, const Bsdf &bsdf, Vec3f wo);

/// The defensive mixture α · BSDF + (1 − α) · guide.
struct GuidedSampler {
    const Bsdf *bsdf = nullptr;
    const BinDistribution *guide = nullptr;   ///< null or invalid: BSDF sampling alone
    float alpha = 0.25f;                      ///< BSDF share (0 < α ≤ 1)
    /// u_pick chooses the strategy, u the direction. pdf = the mixture's; weight = f cosθ / pdf.
    BsdfSample sample(Vec3f wo, float u_pick, Vec2f u) const;
    float pdf(Vec3f wo, Vec3f wi) const;
};

}  // namespace ltm
