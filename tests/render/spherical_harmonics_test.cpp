// spherical_harmonics_test.cpp: the real SH basis against closed forms (Y_00, degree 1, the
// addition theorem, orthonormality by quadrature) and the bin fit (exact on its own span, error
// never growing with the degree, a sharp lobe rings).
#include <cmath>

#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/rng.h"
#include "ltm/core/sampling.h"
#include "ltm/render/hemisphere_bins.h"
#include "ltm/render/spherical_harmonics.h"

using namespace ltm;
static const double pi = std::acos(-1.0);

namespace {
Vec3f uniform_sphere(Pcg32 &rng) {
    const float z = 1.f - 2.f * rng.next_float(), r = std::sqrt(std::max(0.f, 1.f - z * z)), phi = 2.f * float(pi) * rng.next_float();
    return {r * std::cos(phi), r * std::sin(phi), z};
}
}  // namespace

TEST(SphericalHarmonics, ClosedFormsOfDegreesZeroAndOne) {
    Pcg32 rng(3);
    std::vector<double> y(static_cast<size_t>(sh_count(1)));
    for (int i = 0; i < 100; ++i) {
        const Vec3f w = uniform_sphere(rng);
        sh_evaluate(1, w, y.data());
        const double c0 = 0.5 / std::sqrt(pi), c1 = std::sqrt(3.0 / (4.0 * pi));
        EXPECT_NEAR(y[0], c0, 1e-12);
        EXPECT_NEAR(y[1], c1 * w.y, 1e-6);   // k = l² + l + m: (1, −1) ∝ sin φ
        EXPECT_NEAR(y[2], c1 * w.z, 1e-6);
        EXPECT_NEAR(y[3], c1 * w.x, 1e-6);
    }
}

// Σ_m Y_lm(w)² = (2l + 1)/(4π) at every w (the addition theorem at zero angle).
TEST(SphericalHarmonics, AdditionTheoremHoldsToDegreeTwelve) {
    Pcg32 rng(4);
    const int L = 12;
    std::vector<double> y(static_cast<size_t>(sh_count(L)));
    for (int i = 0; i < 200; ++i) {
        sh_evaluate(L, uniform_sphere(rng), y.data());
        for (int l = 0; l <= L; ++l) {
            double s = 0;
            for (int m = -l; m <= l; ++m) s += y[size_t(l * l + l + m)] * y[size_t(l * l + l + m)];
            EXPECT_NEAR(s, double(2 * l + 1) / (4.0 * pi), 1e-9) << "l " << l;
        }
    }
}

TEST(SphericalHarmonics, OrthonormalOverTheSphere) {
    const int L = 8, K = sh_count(L), nt = 200, np = 400;
    std::vector<double> gram(static_cast<size_t>(K * K), 0.0), y(static_cast<size_t>(K));
    for (int t = 0; t < nt; ++t)
        for (int p = 0; p < np; ++p) {
            const double th = (t + 0.5) * pi / nt, ph = (p + 0.5) * 2 * pi / np;
            const double dw = std::sin(th) * (pi / nt) * (2 * pi / np);
            sh_evaluate(L, Vec3f(float(std::sin(th) * std::cos(ph)), float(std::sin(th) * std::sin(ph)), float(std::cos(th))), y.data());
            for (int a = 0; a < K; ++a)
                for (int b = 0; b < K; ++b) gram[size_t(a * K + b)] += y[size_t(a)] * y[size_t(b)] * dw;
        }
    for (int a = 0; a < K; ++a)
        for (int b = 0; b < K; ++b) EXPECT_NEAR(gram[size_t(a * K + b)], a == b ? 1.0 : 0.0, 2e-3) << a << "," << b;
}

namespace {
// Bins of a function given as a callable, by a finer, independent cell average (12² points).
template <class F> std::vector<Vec3f> bins_of(int R, F f) {
    std::vector<Vec3f> out(static_cast<size_t>(R * R));
    for (int b = 0; b < R * R; ++b) {
        Vec3f s(0.f);
        for (int u = 0; u < 12; ++u)
            for (int v = 0; v < 12; ++v)
                s += f(square_to_direction({(float(b / R) + (u + 0.5f) / 12.f) / float(R), (float(b % R) + (v + 0.5f) / 12.f) / float(R)}));
        out[size_t(b)] = s / 144.f;
    }
    return out;
}
double sq_error(const std::vector<Vec3f> &a, const std::vector<Vec3f> &b) {
    double e = 0;
    for (size_t i = 0; i < a.size(); ++i)
        for (int c = 0; c < 3; ++c) e += double(a[i][c] - b[i][c]) * double(a[i][c] - b[i][c]);
    return e;
}
}  // namespace

// A radiance that is a degree-2 expansion (per channel) is fitted exactly from degree 2 on.
TEST(BinShFit, ExactOnItsOwnSpan) {
    const int R = 16;
    const BinShFit fit(R, 4);
    const auto bins = bins_of(R, [](Vec3f w) {
        std::vector<double> y(9);
        sh_evaluate(2, w, y.data());
        return Vec3f(float(1.0 + 0.5 * y[2] - 0.3 * y[6]), float(0.7 + 0.2 * y[3]), float(0.4 * y[8] + 0.5));
    });
    double norm = 0;
    for (const Vec3f &b : bins) norm += double(dot(b, b));
    EXPECT_GT(sq_error(fit.fit(bins, 1), bins), 1e-4 * norm);
    for (int l = 2; l <= 4; ++l) EXPECT_LT(sq_error(fit.fit(bins, l), bins), 1e-6 * norm) << l;
}

// A sharp lobe (one bright bin): the fit's error falls with the degree but stays large at 8
// (ringing), the failure the learned decoder is compared against.
TEST(BinShFit, ErrorNeverGrowsWithTheDegreeAndASharpLobeRings) {
    const int R = 32;
    const BinShFit fit(R, 8);
    std::vector<Vec3f> bins(size_t(R * R), Vec3f(0.1f));
    bins[size_t(20 * R + 13)] = Vec3f(50.f, 20.f, 5.f);
    double prev = 1e30;
    for (int l = 0; l <= 8; ++l) {
        const double e = sq_error(fit.fit(bins, l), bins);
        EXPECT_LE(e, prev * (1 + 1e-9)) << l;
        prev = e;
    }
    EXPECT_GT(prev, 0.5 * sq_error(fit.fit(bins, 0), bins));   // still most of the lobe's energy missing
    EXPECT_THROW(fit.fit(bins, 9), Error);
    EXPECT_THROW(fit.fit(std::vector<Vec3f>(10), 2), Error);
}
