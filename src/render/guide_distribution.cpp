// guide_distribution.cpp: a flat CDF over the cells (double: 1024 cells keep every increment).
#include "ltm/render/guide_distribution.h"

#include <algorithm>
#include <cmath>

#include "ltm/core/error.h"
#include "ltm/render/hemisphere_bins.h"

namespace ltm {

BinDistribution::BinDistribution(int resolution, const std::vector<float> &weights) : m_res(resolution) {
    const size_t nb = size_t(resolution) * size_t(resolution);
    if (resolution < 1 || weights.size() != nb)
        LTM_THROW("guide: ", weights.size(), " weights for ", resolution, "² bins");
    m_cdf.assign(nb + 1, 0.0);
    for (size_t b = 0; b < nb; ++b) {
        if (!std::isfinite(weights[b]) || weights[b] < 0.f) LTM_THROW("guide: bin ", b, " has weight ", weights[b], " (must be finite and >= 0)");
        m_cdf[b + 1] = m_cdf[b] + double(weights[b]);
    }
    m_total = m_cdf[nb];
    if (m_total > 0.0)
        for (double &c : m_cdf) c /= m_total;
}

BinDistribution::Sample BinDistribution::sample(Vec2f u) const {
    if (!valid()) return {};
    const size_t nb = m_cdf.size() - 1;
    // First cell whose upper CDF exceeds u.x (empty cells have equal bounds and are never chosen).
    const double x = double(u.x);
    size_t b = size_t(std::upper_bound(m_cdf.begin() + 1, m_cdf.end(), x) - (m_cdf.begin() + 1));
    b = std::min(b, nb - 1);
    while (m_cdf[b + 1] - m_cdf[b] <= 0.0 && b > 0) --b;   // u.x = 1 − ε past trailing empty cells
    const double width = m_cdf[b + 1] - m_cdf[b];
    const float rx = float(std::clamp((x - m_cdf[b]) / width, 0.0, double(0x1.fffffep-1f)));
    Sample s;
    s.w = square_to_direction(bin_to_square(int(b), m_res, {rx, u.y}));
    s.pdf = pdf(s.w);
    return s;
}

float BinDistribution::pdf(Vec3f w) const {
    if (!valid() || w.z <= 0.f) return 0.f;
    const int b = direction_to_bin(w, m_res);
    const double p_u = double(m_res) * double(m_res) * (m_cdf[size_t(b) + 1] - m_cdf[size_t(b)]);
    return float(p_u * double(w.z) / double(k_pi));
}

std::vector<float> product_weights(const std::vector<Vec3f> &radiance, int resolution, const Bsdf &bsdf, Vec3f wo) {
    if (radiance.size() != size_t(resolution) * size_t(resolution))
        LTM_THROW("guide: ", radiance.size(), " radiance bins for ", resolution, "²");
    return product_weights(radiance.data(), resolution, bsdf, wo);
}

std::vector<float> product_weights(const Vec3f *radiance, int resolution, const Bsdf &bsdf, Vec3f wo) {
    const size_t nb = size_t(resolution) * size_t(resolution);
    std::vector<float> w(nb);
    for (size_t b = 0; b < nb; ++b)
        w[b] = std::max(0.f, luminance(radiance[b])) *
               std::max(0.f, luminance(bsdf.eval(wo, square_to_direction(bin_to_square(int(b), resolution)))));
    return w;
}

BsdfSample GuidedSampler::sample(Vec3f wo, float u_pick, Vec2f u) const {
    if (!guide || !guide->valid() || alpha >= 1.f) return bsdf->sample(wo, u);
    BsdfSample s;
    if (u_pick < alpha) {
        s.wi = bsdf->sample(wo, u).wi;
    } else {
        s.wi = guide->sample(u).w;
    }
    s.pdf = pdf(wo, s.wi);
    if (!(s.pdf > 0.f) || s.wi.z <= 0.f) return {};
    s.weight = bsdf->eval(wo, s.wi) * (s.wi.z / s.pdf);
    return s;
}

float GuidedSampler::pdf(Vec3f wo, Vec3f wi) const {
    if (!guide || !guide->valid() || alpha >= 1.f) return bsdf->pdf(wo, wi);
    return alpha * bsdf->pdf(wo, wi) + (1.f - alpha) * guide->pdf(wi);
}

}  // namespace ltm
