// metrics_test.cpp: SSIM against closed forms, a naive windowed reference and scikit-image;
// MSE / PSNR / relMSE known values; the tone-mapping protocol; error images; bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "ltm/core/color.h"
#include "ltm/core/error.h"
#include "ltm/core/rng.h"
#include "ltm/eval/metrics.h"
#include "test_util.h"

using namespace ltm;

namespace {

constexpr double k_c1 = 0.01 * 0.01, k_c2 = 0.03 * 0.03;
constexpr int k_radius = 5;   // 11×11 window

Image constant_image(int w, int h, Vec3f v) {
    Image img(w, h);
    std::fill(img.pixels.begin(), img.pixels.end(), v);
    return img;
}

Image random_image(int w, int h, uint64_t seed) {
    Image img(w, h);
    Pcg32 rng(seed);
    for (Vec3f &p : img.pixels) p = {rng.next_float(), rng.next_float(), rng.next_float()};
    return img;
}

// Direct 2-D Gaussian window weights w(i, j) ∝ exp(−(i² + j²) / 2σ²), summing to 1
// (not factored into 1-D passes, so it checks the separable filter independently).
std::vector<double> window_weights() {
    std::vector<double> wgt;
    double sum = 0;
    for (int j = -k_radius; j <= k_radius; ++j)
        for (int i = -k_radius; i <= k_radius; ++i) {
            wgt.push_back(std::exp(-(i * i + j * j) / (2 * 1.5 * 1.5)));
            sum += wgt.back();
        }
    for (double &v : wgt) v /= sum;
    return wgt;
}

// Gaussian-weighted mean of channel c in the window centred on (cx, cy).
double window_mean(const Image &img, int cx, int cy, int c, const std::vector<double> &wgt) {
    double mu = 0;
    size_t k = 0;
    for (int j = -k_radius; j <= k_radius; ++j)
        for (int i = -k_radius; i <= k_radius; ++i) mu += wgt[k++] * img.at(cx + i, cy + j)[c];
    return mu;
}

// Textbook SSIM: per valid pixel, direct window sums with centred (population) moments.
double naive_ssim(const Image &a, const Image &b) {
    const std::vector<double> wgt = window_weights();
    double total = 0;
    for (int c = 0; c < 3; ++c) {
        double channel = 0;
        int n = 0;
        for (int cy = k_radius; cy < a.height - k_radius; ++cy)
            for (int cx = k_radius; cx < a.width - k_radius; ++cx) {
                const double mx = window_mean(a, cx, cy, c, wgt), my = window_mean(b, cx, cy, c, wgt);
                double vx = 0, vy = 0, vxy = 0;
                size_t k = 0;
                for (int j = -k_radius; j <= k_radius; ++j)
                    for (int i = -k_radius; i <= k_radius; ++i, ++k) {
                        const double dx = a.at(cx + i, cy + j)[c] - mx;
                        const double dy = b.at(cx + i, cy + j)[c] - my;
                        vx += wgt[k] * dx * dx;
                        vy += wgt[k] * dy * dy;
                        vxy += wgt[k] * dx * dy;
                    }
                channel += (2 * mx * my + k_c1) * (2 * vxy + k_c2) /
                           ((mx * mx + my * my + k_c1) * (vx + vy + k_c2));
                ++n;
            }
        total += channel / n;
    }
    return total / 3;
}

std::string error_message(const std::function<void()> &f) {
    try {
        f();
    } catch (const Error &e) {
        return e.what();
    }
    return "(no ltm::Error thrown)";
}

}  // namespace

// ---- SSIM --------------------------------------------------------------------------------------

TEST(Metrics, SsimOfIdenticalImagesIsOne) {
    const Image x = random_image(40, 33, /*seed=*/1);
    EXPECT_NEAR(ssim(x, x), 1.0, 1e-12);
}

TEST(Metrics, SsimIsSymmetric) {
    const Image a = random_image(30, 24, /*seed=*/2), b = random_image(30, 24, /*seed=*/3);
    EXPECT_NEAR(ssim(a, b), ssim(b, a), 1e-15);
    EXPECT_LT(ssim(a, b), 0.2);   // independent noise is structurally dissimilar
}

// Constant images: σ terms vanish, so SSIM = (2 c1 c2 + C1) / (c1² + c2² + C1) per channel.
TEST(Metrics, SsimOfConstantImagesMatchesClosedForm) {
    const Vec3f c1(0.2f, 0.5f, 0.9f), c2(0.7f, 0.5f, 0.1f);
    double expected = 0;
    for (int c = 0; c < 3; ++c) {
        const double u = c1[c], v = c2[c];
        expected += (2 * u * v + k_c1) / (u * u + v * v + k_c1) / 3;
    }
    EXPECT_NEAR(ssim(constant_image(16, 12, c1), constant_image(16, 12, c2)), expected, 1e-9);
}

// y = x + d leaves σx² = σy² = σxy, so SSIM = mean of (2 μx (μx + d) + C1) / (μx² + (μx + d)² + C1).
// Values are dyadic so x + d is exact in float and the identity holds bit for bit.
TEST(Metrics, SsimOfOffsetImageIsTheLuminanceTerm) {
    const int w = 27, h = 21;
    const float d = 0.375f;
    Image x(w, h), y(w, h);
    Pcg32 rng(/*seed=*/4);
    for (size_t i = 0; i < x.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            x.pixels[i][c] = float(rng.next_below(512)) / 1024.f;   // [0, 0.5)
            y.pixels[i][c] = x.pixels[i][c] + d;                    // no clamping needed
        }
    const std::vector<double> wgt = window_weights();
    double expected = 0;
    const int n_valid = (w - 2 * k_radius) * (h - 2 * k_radius);
    for (int c = 0; c < 3; ++c)
        for (int cy = k_radius; cy < h - k_radius; ++cy)
            for (int cx = k_radius; cx < w - k_radius; ++cx) {
                const double mx = window_mean(x, cx, cy, c, wgt), my = mx + d;
                expected += (2 * mx * my + k_c1) / (mx * mx + my * my + k_c1) / (3 * n_valid);
            }
    EXPECT_NEAR(ssim(x, y), expected, 1e-9);
    EXPECT_LT(expected, 0.99);   // the offset is visible, so the check is not vacuous
}

TEST(Metrics, SsimMatchesNaiveWindowedReferenceOnNoisyPair) {
    const int w = 37, h = 29;
    const Image a = random_image(w, h, /*seed=*/5);
    Image b = a;
    Pcg32 rng(/*seed=*/6);
    for (Vec3f &p : b.pixels)
        for (int c = 0; c < 3; ++c) p[c] = clamp(p[c] + rng.uniform(-0.2f, 0.2f), 0.f, 1.f);
    const double s = ssim(a, b);
    EXPECT_NEAR(s, naive_ssim(a, b), 1e-9);
    EXPECT_GT(s, 0.3);
    EXPECT_LT(s, 0.95);
}

// Expected value from scikit-image 0.19.3 (float64 copies of the same float32 images):
//   structural_similarity(a, b, gaussian_weights=True, sigma=1.5, use_sample_covariance=False,
//                         data_range=1.0, channel_axis=-1)
// with a = 0.5 + 0.4 sin(0.31x + 0.17y + 1.3c), b = a + 0.15 cos(0.23x − 0.41y + 0.7c), 23×19.
TEST(Metrics, SsimMatchesScikitImage) {
    const int w = 23, h = 19;
    Image a(w, h), b(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                a.at(x, y)[c] = float(0.5 + 0.4 * std::sin(0.31 * x + 0.17 * y + 1.3 * c));
                b.at(x, y)[c] = float(double(a.at(x, y)[c]) +
                                      0.15 * std::cos(0.23 * x - 0.41 * y + 0.7 * c));
            }
    EXPECT_NEAR(ssim(a, b), 0.8395220021052925, 1e-9);
}

TEST(Metrics, SsimMapCoversTheValidRegionAndAveragesToSsim) {
    const Image a = random_image(25, 18, /*seed=*/7), b = random_image(25, 18, /*seed=*/8);
    const Image map = ssim_map(a, b);
    ASSERT_EQ(map.width, 15);
    ASSERT_EQ(map.height, 8);
    double mean = 0;
    for (const Vec3f &p : map.pixels) mean += (double(p.x) + p.y + p.z) / (3.0 * map.pixels.size());
    EXPECT_NEAR(mean, ssim(a, b), 1e-6);   // the map is stored in float
}

TEST(Metrics, SsimRejectsImagesSmallerThanTheWindow) {
    EXPECT_THROW(ssim(random_image(10, 20, 1), random_image(10, 20, 2)), Error);
    EXPECT_THROW(ssim(random_image(20, 10, 1), random_image(20, 10, 2)), Error);
    EXPECT_THROW(ssim_map(random_image(10, 10, 1), random_image(10, 10, 2)), Error);
    EXPECT_EQ(ssim_map(random_image(11, 11, 1), random_image(11, 11, 2)).pixels.size(), 1u);
}

// ---- pixel-wise errors -------------------------------------------------------------------------

TEST(Metrics, MseAndPsnrOfUniformOffset) {
    const Image a = constant_image(8, 5, Vec3f(0.6f)), b = constant_image(8, 5, Vec3f(0.5f));
    EXPECT_NEAR(mse(a, b), 0.01, 1e-8);   // 0.6f − 0.5f = 0.1 up to float rounding
    EXPECT_NEAR(psnr(a, b), 20.0, 1e-5);
    // Exactly representable: d = 1/4 → mse = 1/16, psnr = 10 log10(16); peak 2 adds 20 log10 2.
    const Image c = constant_image(8, 5, Vec3f(0.75f));
    EXPECT_EQ(mse(c, b), 0.0625);
    EXPECT_NEAR(psnr(c, b), 10 * std::log10(16.0), 1e-12);
    EXPECT_NEAR(psnr(c, b, /*peak=*/2.0), 10 * std::log10(64.0), 1e-12);
}

TEST(Metrics, MseAveragesOverPixelsAndChannels) {
    Image a = constant_image(2, 2, Vec3f(0.f)), b = a;
    b.at(1, 0) = {0.5f, 0.f, 0.f};   // one channel of one of 4 pixels: 0.25 / 12
    EXPECT_NEAR(mse(a, b), 0.25 / 12, 1e-15);
    EXPECT_EQ(mse(a, b), mse(b, a));
}

TEST(Metrics, PsnrOfIdenticalImagesIsInfinite) {
    const Image a = random_image(4, 4, 9);
    EXPECT_EQ(psnr(a, a), std::numeric_limits<double>::infinity());
}

// relMSE = mean (t − r)² / (r² + eps) on linear values: bright pixels are judged relatively,
// black ones by (t − r)² / eps.
TEST(Metrics, RelMseMatchesClosedForm) {
    Image ref(2, 1), test(2, 1);
    ref.at(0, 0) = Vec3f(2.f), test.at(0, 0) = Vec3f(3.f);          // 1 / (4 + 0.01)
    ref.at(1, 0) = Vec3f(0.f), test.at(1, 0) = Vec3f(0.125f);       // 0.015625 / 0.01
    EXPECT_NEAR(rel_mse(test, ref), (1.0 / 4.01 + 1.5625) / 2, 1e-12);
    EXPECT_NEAR(rel_mse(test, ref, /*eps=*/1.0), (1.0 / 5 + 0.015625) / 2, 1e-12);
    EXPECT_EQ(rel_mse(ref, ref), 0.0);
    // Linear HDR, no tone mapping: a 50 % error on a bright pixel costs ≈ 0.25 at any exposure.
    const Image r1 = constant_image(1, 1, Vec3f(200.f)), t1 = constant_image(1, 1, Vec3f(300.f));
    EXPECT_NEAR(rel_mse(t1, r1), 1e4 / (4e4 + 0.01), 1e-12);
}

// ---- tone mapping ------------------------------------------------------------------------------

TEST(Metrics, TonemapScaleIsInverse99thPercentileLuminance) {
    // Grey values 1..100 in scrambled order: k = ⌊0.99 · 99⌋ = 98, the 99th smallest = 99.
    Image img(10, 10);
    for (int i = 0; i < 100; ++i) img.pixels[size_t((i * 37) % 100)] = Vec3f(float(i + 1));
    EXPECT_NEAR(tonemap_scale(img), 1.f / 99.f, 1e-6f);
    // Rec. 709 weights: a pure-green reference has Y = 0.7152 · 2.
    EXPECT_NEAR(tonemap_scale(constant_image(3, 3, {0.f, 2.f, 0.f})), 1.f / (0.7152f * 2.f), 1e-6f);
    EXPECT_NEAR(tonemap_scale(constant_image(3, 3, {0.f, 0.f, 1.f})), 1.f / 0.0722f, 1e-3f);
}

TEST(Metrics, TonemapScaleOfBlackImageIsOne) {
    EXPECT_EQ(tonemap_scale(constant_image(4, 4, Vec3f(0.f))), 1.f);
    EXPECT_EQ(tonemap_scale(constant_image(4, 4, Vec3f(-1.f))), 1.f);
}

TEST(Metrics, TonemapScalesAndClampsEachChannel) {
    Image img(2, 1);
    img.at(0, 0) = {0.25f, 1.f, -0.5f};
    img.at(1, 0) = {4.f, 0.f, 0.5f};
    const Image t = tonemap(img, 2.f);
    EXPECT_EQ(t.at(0, 0), Vec3f(0.5f, 1.f, 0.f));
    EXPECT_EQ(t.at(1, 0), Vec3f(1.f, 0.f, 1.f));
}

// Reference 2, test 1: s = 1/2 maps them to 1 and 0.5. Swapped: s = 1, test clamps to 1 = ref.
TEST(Metrics, CompareImagesUsesTheReferenceScale) {
    const Image one = constant_image(16, 16, Vec3f(1.f)), two = constant_image(16, 16, Vec3f(2.f));
    const ImageMetrics m = compare_images(/*test=*/one, /*reference=*/two);
    EXPECT_NEAR(m.mse, 0.25, 1e-12);
    EXPECT_NEAR(m.psnr, 10 * std::log10(4.0), 1e-9);
    EXPECT_NEAR(m.ssim, (2 * 0.5 * 1 + k_c1) / (0.25 + 1 + k_c1), 1e-9);
    EXPECT_NEAR(m.rel_mse, 1.0 / 4.01, 1e-12);

    const ImageMetrics swapped = compare_images(/*test=*/two, /*reference=*/one);
    EXPECT_EQ(swapped.mse, 0.0);
    EXPECT_EQ(swapped.psnr, std::numeric_limits<double>::infinity());
    EXPECT_NEAR(swapped.ssim, 1.0, 1e-12);
    EXPECT_NEAR(swapped.rel_mse, 1.0 / 1.01, 1e-12);   // linear values: no clamping
}

// ---- bad input ---------------------------------------------------------------------------------

TEST(Metrics, SizeMismatchThrowsNamingBothSizes) {
    const Image test = random_image(32, 32, 1), ref = random_image(64, 64, 2);
    EXPECT_THROW(mse(test, ref), Error);
    EXPECT_THROW(psnr(test, ref), Error);
    EXPECT_THROW(rel_mse(test, ref), Error);
    EXPECT_THROW(ssim(test, ref), Error);
    EXPECT_THROW(error_map(test, ref, 1.f), Error);
    const std::string msg = error_message([&] { compare_images(test, ref); });
    EXPECT_NE(msg.find("reference is 64x64, test image is 32x32"), std::string::npos) << msg;
}

TEST(Metrics, NonFinitePixelThrowsNamingTheImage) {
    Image test = random_image(16, 16, 1), ref = random_image(16, 16, 2);
    test.at(3, 4).y = std::numeric_limits<float>::quiet_NaN();
    std::string msg = error_message([&] { compare_images(test, ref); });
    EXPECT_NE(msg.find("test image has a non-finite pixel at (3, 4)"), std::string::npos) << msg;
    EXPECT_THROW(ssim(ref, test), Error);
    EXPECT_THROW(tonemap(test, 1.f), Error);

    test = random_image(16, 16, 1);
    ref.at(7, 2).z = std::numeric_limits<float>::infinity();
    msg = error_message([&] { mse(test, ref); });
    EXPECT_NE(msg.find("reference has a non-finite pixel at (7, 2)"), std::string::npos) << msg;
    EXPECT_THROW(tonemap_scale(ref), Error);
    EXPECT_THROW(error_map(test, ref, 1.f), Error);
}

TEST(Metrics, EmptyImagesThrow) {
    EXPECT_THROW(mse(Image(), Image()), Error);
    EXPECT_THROW(tonemap_scale(Image()), Error);
}

// ---- error images ------------------------------------------------------------------------------

TEST(Metrics, ErrorMapOfIdenticalImagesIsTheZeroColour) {
    const Image a = random_image(9, 7, 3);
    const Image e = error_map(a, a, tonemap_scale(a));
    ASSERT_EQ(e.width, 9);
    ASSERT_EQ(e.height, 7);
    EXPECT_EQ(error_ramp(0.f), Vec3f(0.f));
    for (const Vec3f &p : e.pixels) EXPECT_EQ(p, error_ramp(0.f));
}

TEST(Metrics, ErrorRampPassesThroughItsStops) {
    EXPECT_EQ(error_ramp(0.25f), Vec3f(0.f, 0.f, 1.f));   // blue
    EXPECT_EQ(error_ramp(0.5f), Vec3f(1.f, 0.f, 0.f));    // red
    EXPECT_EQ(error_ramp(0.75f), Vec3f(1.f, 1.f, 0.f));   // yellow
    EXPECT_EQ(error_ramp(1.f), Vec3f(1.f));               // white
    EXPECT_EQ(error_ramp(7.f), Vec3f(1.f));               // clamped
    EXPECT_EQ(error_ramp(-1.f), Vec3f(0.f));
    // Between stops the ramp is linear in display space: t = 3/8 is half blue, half red.
    const Vec3f mid = error_ramp(0.375f);
    EXPECT_NEAR(linear_to_srgb(mid.x), 0.5f, 1e-5f);
    EXPECT_NEAR(linear_to_srgb(mid.z), 0.5f, 1e-5f);
    EXPECT_EQ(mid.y, 0.f);
}

// error = Y(|test − ref|) · scale; written as PNG, the 8-bit values are the display-space ramp.
TEST(Metrics, ErrorMapFollowsTheRampThroughWritePng) {
    test::TempDir dir;
    const Image ref = constant_image(5, 1, Vec3f(1.f));
    Image test = ref;
    const float errors[5] = {0.f, 0.5f, 1.f, 1.5f, 2.f};   // luminance of |test − ref|
    for (int x = 0; x < 5; ++x) test.at(x, 0) = Vec3f(1.f + errors[x]);
    const Image e = error_map(test, ref, /*scale=*/0.5f);   // t = 0, 1/4, 1/2, 3/4, 1
    for (int x = 0; x < 5; ++x) {
        const Vec3f want = error_ramp(errors[x] * 0.5f);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(e.at(x, 0)[c], want[c], 1e-6f) << x;
    }
    write_png(dir.path("err.png"), e);
    const Image png = read_image(dir.path("err.png"), /*srgb=*/false);   // 8-bit codes / 255
    const Vec3f stops[5] = {Vec3f(0.f), {0, 0, 1}, {1, 0, 0}, {1, 1, 0}, Vec3f(1.f)};
    for (int x = 0; x < 5; ++x)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(png.at(x, 0)[c], stops[x][c], 1e-6f) << x;
}

// A region's metrics: the whole image as the region is compare_images; a region is the same sums
// taken over its pixels only (tone-mapped with the whole reference's scale); bad masks are refused.
TEST(Metrics, MaskedComparisonIsTheFullOneRestrictedToTheRegion) {
    const Image ref = random_image(24, 20, 11), test = random_image(24, 20, 12);
    const ImageMetrics full = compare_images(test, ref);
    const ImageMetrics all = compare_images_masked(test, ref, std::vector<uint8_t>(ref.pixels.size(), 1));
    EXPECT_NEAR(all.mse, full.mse, 1e-12);
    EXPECT_NEAR(all.rel_mse, full.rel_mse, 1e-12);
    EXPECT_NEAR(all.ssim, full.ssim, 1e-6);   // the map is float, ssim() sums in double
    // A region: pixel sums by hand, with the reference's own scale.
    std::vector<uint8_t> mask(ref.pixels.size(), 0);
    for (int x = 3; x < 20; ++x) mask[size_t(9 * 24 + x)] = 1;   // row 9, x in [3, 20)
    const float s = tonemap_scale(ref);
    double se = 0, rel = 0;
    for (int x = 3; x < 20; ++x)
        for (int c = 0; c < 3; ++c) {
            const double t = test.at(x, 9)[c], r = ref.at(x, 9)[c];
            const double d = std::min(1.0, std::max(0.0, double(float(t) * s))) - std::min(1.0, std::max(0.0, double(float(r) * s)));
            se += d * d, rel += (t - r) * (t - r) / (r * r + 1e-2);
        }
    const ImageMetrics m = compare_images_masked(test, ref, mask);
    EXPECT_NEAR(m.mse, se / (3 * 17), 1e-7);
    EXPECT_NEAR(m.rel_mse, rel / (3 * 17), 1e-9);
    // SSIM: the mean of the map over windows centred on region pixels (x in [5, 19) of row 9).
    const Image map = ssim_map(tonemap(test, s), tonemap(ref, s));
    double ss = 0;
    for (int x = 5; x < 19; ++x) ss += (double(map.at(x - 5, 4).x) + map.at(x - 5, 4).y + map.at(x - 5, 4).z) / 3.0;
    EXPECT_NEAR(m.ssim, ss / 14, 1e-9);
    // A region wholly within the border has no SSIM window: NaN, the other metrics stay defined.
    std::vector<uint8_t> corner(ref.pixels.size(), 0);
    corner[0] = 1;
    const ImageMetrics c = compare_images_masked(test, ref, corner);
    EXPECT_TRUE(std::isnan(c.ssim));
    EXPECT_TRUE(std::isfinite(c.mse));
    EXPECT_THROW(compare_images_masked(test, ref, std::vector<uint8_t>(ref.pixels.size(), 0)), Error);
    EXPECT_THROW(compare_images_masked(test, ref, std::vector<uint8_t>(7, 1)), Error);
}
