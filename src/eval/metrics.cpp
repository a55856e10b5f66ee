// metrics.cpp: MSE / PSNR / relMSE, SSIM (Wang et al. 2004) and error images; see metrics.h.
#include "ltm/eval/metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "ltm/core/color.h"
#include "ltm/core/error.h"

namespace ltm {

namespace {

// ---- input validation --------------------------------------------------------------------------

void check_image(const Image &img, const char *fn, const char *name) {
    if (img.width <= 0 || img.height <= 0)
        LTM_THROW(fn, "(): ", name, " is empty (", img.width, "x", img.height, ")");
    LTM_CHECK_EQ(img.pixels.size(), size_t(img.width) * size_t(img.height));
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (!is_finite(img.at(x, y)))
                LTM_THROW(fn, "(): ", name, " has a non-finite pixel at (", x, ", ", y, ")");
}

void check_pair(const Image &test, const Image &reference, const char *fn) {
    if (test.width != reference.width || test.height != reference.height)
        LTM_THROW(fn, "(): reference is ", reference.width, "x", reference.height,
                  ", test image is ", test.width, "x", test.height);
    check_image(test, fn, "test image");
    check_image(reference, fn, "reference");
}

double psnr_from_mse(double err, double peak) {
    if (err == 0) return std::numeric_limits<double>::infinity();
    return 10.0 * std::log10(peak * peak / err);
}

// ---- SSIM --------------------------------------------------------------------------------------

constexpr int k_ssim_win = 11;               // window side, 2·radius + 1
constexpr int k_ssim_radius = k_ssim_win / 2;
constexpr double k_ssim_sigma = 1.5;         // px
constexpr double k_ssim_c1 = 0.01 * 0.01;    // (K1 L)², L = 1
constexpr double k_ssim_c2 = 0.03 * 0.03;    // (K2 L)²

// 1-D Gaussian taps g_k ∝ exp(−(k − 5)² / 2σ²), Σ g_k = 1; the 2-D window is g_i g_j.
const std::array<double, k_ssim_win> &gaussian_taps() {
    static const std::array<double, k_ssim_win> taps = [] {
        std::array<double, k_ssim_win> g{};
        double sum = 0;
        for (int k = 0; k < k_ssim_win; ++k) {
            const double d = k - k_ssim_radius;
            g[size_t(k)] = std::exp(-d * d / (2 * k_ssim_sigma * k_ssim_sigma));
            sum += g[size_t(k)];
        }
        for (double &v : g) v /= sum;
        return g;
    }();
    return taps;
}

// Valid-region Gaussian filter, separable: out(x, y) = Σ_i Σ_j g_i g_j src(x + i, y + j),
// for 0 ≤ x < w − 10, 0 ≤ y < h − 10 (no boundary handling is ever needed).
std::vector<double> filter_valid(const std::vector<double> &src, int w, int h) {
    const auto &g = gaussian_taps();
    const int wo = w - k_ssim_win + 1, ho = h - k_ssim_win + 1;
    std::vector<double> rows(size_t(wo) * size_t(h)), out(size_t(wo) * size_t(ho));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < wo; ++x) {
            const double *s = &src[size_t(y) * size_t(w) + size_t(x)];
            double acc = 0;
            for (int k = 0; k < k_ssim_win; ++k) acc += g[size_t(k)] * s[k];
            rows[size_t(y) * size_t(wo) + size_t(x)] = acc;
        }
    for (int y = 0; y < ho; ++y)
        for (int x = 0; x < wo; ++x) {
            double acc = 0;
            for (int k = 0; k < k_ssim_win; ++k)
                acc += g[size_t(k)] * rows[size_t(y + k) * size_t(wo) + size_t(x)];
            out[size_t(y) * size_t(wo) + size_t(x)] = acc;
        }
    return out;
}

// SSIM map of channel c over the valid region, (w − 10)·(h − 10) values, row-major.
std::vector<double> ssim_channel_map(const Image &a, const Image &b, int c) {
    const size_t n = a.pixels.size();
    std::vector<double> x(n), y(n), xx(n), yy(n), xy(n);
    for (size_t i = 0; i < n; ++i) {
        x[i] = a.pixels[i][c];
        y[i] = b.pixels[i][c];
        xx[i] = x[i] * x[i];
        yy[i] = y[i] * y[i];
        xy[i] = x[i] * y[i];
    }
    const int w = a.width, h = a.height;
    const std::vector<double> mu_x = filter_valid(x, w, h), mu_y = filter_valid(y, w, h);
    const std::vector<double> e_xx = filter_valid(xx, w, h), e_yy = filter_valid(yy, w, h);
    const std::vector<double> e_xy = filter_valid(xy, w, h);
    std::vector<double> s(mu_x.size());
    for (size_t i = 0; i < s.size(); ++i) {
        const double mx = mu_x[i], my = mu_y[i];
        // Population moments: σ² = E_w[x²] − μ² (weights sum to 1, no n/(n−1) factor).
        const double vx = e_xx[i] - mx * mx, vy = e_yy[i] - my * my, vxy = e_xy[i] - mx * my;
        s[i] = ((2 * mx * my + k_ssim_c1) * (2 * vxy + k_ssim_c2)) /
               ((mx * mx + my * my + k_ssim_c1) * (vx + vy + k_ssim_c2));
    }
    return s;
}

void check_ssim_inputs(const Image &test, const Image &reference, const char *fn) {
    check_pair(test, reference, fn);
    if (test.width < k_ssim_win || test.height < k_ssim_win)
        LTM_THROW(fn, "(): images are ", test.width, "x", test.height, ", SSIM needs at least ",
                  k_ssim_win, "x", k_ssim_win, " (its window size)");
}

}  // namespace

// ---- pixel-wise errors -------------------------------------------------------------------------

double mse(const Image &test, const Image &reference) {
    check_pair(test, reference, "mse");
    double sum = 0;
    for (size_t i = 0; i < test.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double d = double(test.pixels[i][c]) - double(reference.pixels[i][c]);
            sum += d * d;
        }
    return sum / (3.0 * double(test.pixels.size()));
}

double psnr(const Image &test, const Image &reference, double peak) {
    if (!(std::isfinite(peak) && peak > 0)) LTM_THROW("psnr(): peak must be > 0, got ", peak);
    return psnr_from_mse(mse(test, reference), peak);
}

double rel_mse(const Image &test, const Image &reference, double eps) {
    if (!(std::isfinite(eps) && eps > 0)) LTM_THROW("rel_mse(): eps must be > 0, got ", eps);
    check_pair(test, reference, "rel_mse");
    double sum = 0;
    for (size_t i = 0; i < test.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double t = test.pixels[i][c], r = reference.pixels[i][c];
            sum += (t - r) * (t - r) / (r * r + eps);
        }
    return sum / (3.0 * double(test.pixels.size()));
}

// ---- structural similarity ---------------------------------------------------------------------

double ssim(const Image &test, const Image &reference) {
    check_ssim_inputs(test, reference, "ssim");
    // Mean of the per-channel means (as scikit-image); all channels share one valid region.
    double sum = 0;
    for (int c = 0; c < 3; ++c) {
        const std::vector<double> s = ssim_channel_map(test, reference, c);
        double channel_sum = 0;
        for (double v : s) channel_sum += v;
        sum += channel_sum / double(s.size());
    }
    return sum / 3.0;
}

Image ssim_map(const Image &test, const Image &reference) {
    check_ssim_inputs(test, reference, "ssim_map");
    Image out(test.width - k_ssim_win + 1, test.height - k_ssim_win + 1);
    for (int c = 0; c < 3; ++c) {
        const std::vector<double> s = ssim_channel_map(test, reference, c);
        for (size_t i = 0; i < s.size(); ++i) out.pixels[i][c] = float(s[i]);
    }
    return out;
}

// ---- the evaluation protocol -------------------------------------------------------------------

ImageMetrics compare_images(const Image &test, const Image &reference) {
    check_pair(test, reference, "compare_images");
    const float scale = tonemap_scale(reference);
    const Image test_ldr = tonemap(test, scale), reference_ldr = tonemap(reference, scale);
    ImageMetrics m;
    m.mse = mse(test_ldr, reference_ldr);
    m.psnr = psnr_from_mse(m.mse, /*peak=*/1.0);
    m.ssim = ssim(test_ldr, reference_ldr);
    m.rel_mse = rel_mse(test, reference);
    return m;
}

double reference_noise_mse(const Image &reference, const Image &twin) {
    check_pair(twin, reference, "reference_noise_mse");
    const float scale = tonemap_scale(reference);
    return 0.5 * mse(tonemap(twin, scale), tonemap(reference, scale));
}

ImageMetrics compare_images_masked(const Image &test, const Image &reference, const std::vector<uint8_t> &mask) {
    check_pair(test, reference, "compare_images_masked");
    if (mask.size() != reference.pixels.size())
        LTM_THROW("compare_images_masked(): mask has ", mask.size(), " entries, the images ", reference.pixels.size(), " pixels");
    const float scale = tonemap_scale(reference);
    const Image test_ldr = tonemap(test, scale), reference_ldr = tonemap(reference, scale);
    double se = 0, rel = 0;
    size_t n = 0;
    for (size_t i = 0; i < mask.size(); ++i) {
        if (!mask[i]) continue;
        ++n;
        for (int c = 0; c < 3; ++c) {
            const double d = double(test_ldr.pixels[i][c]) - double(reference_ldr.pixels[i][c]);
            const double r = double(reference.pixels[i][c]), dl = double(test.pixels[i][c]) - r;
            se += d * d, rel += dl * dl / (r * r + k_rel_mse_eps);
        }
    }
    if (n == 0) LTM_THROW("compare_images_masked(): the mask selects no pixel");
    ImageMetrics m;
    m.mse = se / double(3 * n);
    m.psnr = psnr_from_mse(m.mse, /*peak=*/1.0);
    m.rel_mse = rel / double(3 * n);
    // SSIM over the windows centred on region pixels: map pixel (x, y) is the window at (x + r, y + r).
    double s = 0;
    size_t windows = 0;
    if (reference.width >= k_ssim_win && reference.height >= k_ssim_win) {
        const Image map = ssim_map(test_ldr, reference_ldr);
        for (int y = 0; y < map.height; ++y)
            for (int x = 0; x < map.width; ++x)
                if (mask[size_t(y + k_ssim_radius) * size_t(reference.width) + size_t(x + k_ssim_radius)]) {
                    const Vec3f &v = map.at(x, y);
                    s += (double(v.x) + double(v.y) + double(v.z)) / 3.0, ++windows;
                }
    }
    m.ssim = windows > 0 ? s / double(windows) : std::numeric_limits<double>::quiet_NaN();
    return m;
}

// ---- visualisation -----------------------------------------------------------------------------

Vec3f error_ramp(float t) {
    // Display-space (sRGB-encoded) stops at t = 0, 1/4, 1/2, 3/4, 1.
    static constexpr std::array<Vec3f, 5> k_stops = {
        Vec3f(0, 0, 0), Vec3f(0, 0, 1), Vec3f(1, 0, 0), Vec3f(1, 1, 0), Vec3f(1, 1, 1)};
    if (!(t > 0)) t = 0;   // also maps NaN to the zero colour
    t = std::min(t, 1.f);
    const float u = t * float(k_stops.size() - 1);
    const size_t i = std::min(size_t(u), k_stops.size() - 2);
    const float f = u - float(i);
    const Vec3f display = k_stops[i] * (1.f - f) + k_stops[i + 1] * f;
    return srgb_to_linear(display);
}

Image error_map(const Image &test, const Image &reference, float scale) {
    check_pair(test, reference, "error_map");
    if (!(std::isfinite(scale) && scale >= 0))
        LTM_THROW("error_map(): scale must be finite and >= 0, got ", scale);
    Image out(test.width, test.height);
    for (size_t i = 0; i < test.pixels.size(); ++i) {
        const Vec3f d = test.pixels[i] - reference.pixels[i];
        const Vec3f abs_d(std::abs(d.x), std::abs(d.y), std::abs(d.z));
        out.pixels[i] = error_ramp(luminance(abs_d) * scale);
    }
    return out;
}

}  // namespace ltm
