// spherical_harmonics.cpp: associated Legendre recurrences (double precision) and a small
// Cholesky solve of the SH fit's normal equations (K ≤ (l_max + 1)²).
#include "ltm/render/spherical_harmonics.h"

#include <cmath>

#include "ltm/core/error.h"
#include "ltm/render/hemisphere_bins.h"

namespace {
constexpr double k_pi_d = 3.14159265358979323846;   // core's k_pi is a float
}

namespace ltm {

void sh_evaluate(int l_max, Vec3f w, double *out) {
    if (l_max < 0) LTM_THROW("spherical harmonics: l_max ", l_max, " < 0");
    const double x = std::clamp(double(w.z), -1.0, 1.0), s = std::sqrt(std::max(0.0, 1.0 - x * x));
    const double phi = std::atan2(double(w.y), double(w.x));
    // P_l^m(x) without the Condon–Shortley phase: P_m^m = (2m − 1)!! sᵐ, P_{m+1}^m = x (2m + 1) P_m^m,
    // P_l^m = ((2l − 1) x P_{l−1}^m − (l + m − 1) P_{l−2}^m) / (l − m).
    std::vector<double> p(size_t((l_max + 1) * (l_max + 1)));
    auto P = [&](int l, int m) -> double & { return p[size_t(l * (l_max + 1) + m)]; };
    double pmm = 1.0;
    for (int m = 0; m <= l_max; ++m) {
        if (m > 0) pmm *= double(2 * m - 1) * s;
        P(m, m) = pmm;
        if (m + 1 <= l_max) P(m + 1, m) = x * double(2 * m + 1) * pmm;
        for (int l = m + 2; l <= l_max; ++l) P(l, m) = (double(2 * l - 1) * x * P(l - 1, m) - double(l + m - 1) * P(l - 2, m)) / double(l - m);
    }
    for (int l = 0; l <= l_max; ++l) {
        double ratio = 1.0;   // (l − m)! / (l + m)!, updated as m grows
        for (int m = 0; m <= l; ++m) {
            if (m > 0) ratio /= double(l + m) * double(l - m + 1);
            const double k = std::sqrt(double(2 * l + 1) / (4.0 * k_pi_d) * ratio);
            if (m == 0) {
                out[l * l + l] = k * P(l, 0);
            } else {
                out[l * l + l + m] = std::sqrt(2.0) * k * std::cos(double(m) * phi) * P(l, m);
                out[l * l + l - m] = std::sqrt(2.0) * k * std::sin(double(m) * phi) * P(l, m);
            }
        }
    }
}

BinShFit::BinShFit(int resolution, int l_max, int sub) : m_res(resolution), m_lmax(l_max) {
    if (resolution < 1 || l_max < 0 || sub < 1) LTM_THROW("SH fit: need resolution >= 1, l_max >= 0, sub >= 1");
    const int K = sh_count(l_max), nb = resolution * resolution;
    m_mean.assign(size_t(nb) * size_t(K), 0.0);
    std::vector<double> y(static_cast<size_t>(K));
    for (int b = 0; b < nb; ++b) {
        double *row = m_mean.data() + size_t(b) * size_t(K);
        for (int su = 0; su < sub; ++su)
            for (int sv = 0; sv < sub; ++sv) {
                const Vec2f u = bin_to_square(b, resolution, {(float(su) + 0.5f) / float(sub), (float(sv) + 0.5f) / float(sub)});
                sh_evaluate(l_max, square_to_direction(u), y.data());
                for (int k = 0; k < K; ++k) row[k] += y[size_t(k)] / double(sub * sub);
            }
    }
}

std::vector<Vec3f> BinShFit::fit(const std::vector<Vec3f> &bins, int l) const {
    const int nb = m_res * m_res, K0 = sh_count(m_lmax);
    if (int(bins.size()) != nb) LTM_THROW("SH fit: ", bins.size(), " bins, expected ", m_res, "² = ", nb);
    if (l < 0 || l > m_lmax) LTM_THROW("SH fit: degree ", l, " outside [0, ", m_lmax, "]");
    const int K = sh_count(l);
    // Normal equations A c = Ȳᵀ L with A = ȲᵀȲ + λ I (first K columns of Ȳ).
    std::vector<double> a(size_t(K * K), 0.0), rhs(size_t(K * 3), 0.0);
    for (int b = 0; b < nb; ++b) {
        const double *row = m_mean.data() + size_t(b) * size_t(K0);
        for (int r = 0; r < K; ++r) {
            for (int c = 0; c <= r; ++c) a[size_t(r * K + c)] += row[r] * row[c];
            for (int ch = 0; ch < 3; ++ch) rhs[size_t(r * 3 + ch)] += row[r] * double(bins[size_t(b)][ch]);
        }
    }
    double diag = 0;
    for (int r = 0; r < K; ++r) diag += a[size_t(r * K + r)] / double(K);
    for (int r = 0; r < K; ++r) a[size_t(r * K + r)] += 1e-9 * diag;
    // Cholesky A = L Lᵀ in the lower triangle, then two triangular solves per channel.
    for (int r = 0; r < K; ++r)
        for (int c = 0; c <= r; ++c) {
            double v = a[size_t(r * K + c)];
            for (int k = 0; k < c; ++k) v -= a[size_t(r * K + k)] * a[size_t(c * K + k)];
            if (r == c) {
                if (!(v > 0.0)) LTM_THROW("SH fit: normal equations not positive definite at degree ", l);
                a[size_t(r * K + r)] = std::sqrt(v);
            } else {
                a[size_t(r * K + c)] = v / a[size_t(c * K + c)];
            }
        }
    std::vector<double> coef(size_t(K * 3));
    for (int ch = 0; ch < 3; ++ch) {
        for (int r = 0; r < K; ++r) {
            double v = rhs[size_t(r * 3 + ch)];
            for (int k = 0; k < r; ++k) v -= a[size_t(r * K + k)] * coef[size_t(k * 3 + ch)];
            coef[size_t(r * 3 + ch)] = v / a[size_t(r * K + r)];
        }
        for (int r = K - 1; r >= 0; --r) {
            double v = coef[size_t(r * 3 + ch)];
            for (int k = r + 1; k < K; ++k) v -= a[size_t(k * K + r)] * coef[size_t(k * 3 + ch)];
            coef[size_t(r * 3 + ch)] = v / a[size_t(r * K + r)];
        }
    }
    std::vector<Vec3f> out(static_cast<size_t>(nb));
    for (int b = 0; b < nb; ++b) {
        const double *row = m_mean.data() + size_t(b) * size_t(K0);
        for (int ch = 0; ch < 3; ++ch) {
            double v = 0;
            for (int k = 0; k < K; ++k) v += row[k] * coef[size_t(k * 3 + ch)];
            out[size_t(b)][ch] = float(v);
        }
    }
    return out;
}

}  // namespace ltm
