// path_tracer_test.cpp: the ground truth against closed forms (furnace, Lambert's polygon
// formula), energy conservation of GGX, bins vs irradiance, and seed stability of images.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "ltm/core/rng.h"
#include "ltm/core/sampling.h"
#include "ltm/render/hemisphere_bins.h"
#include "ltm/render/image_renderer.h"
#include "ltm/render/path_tracer.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/mesh_builder.h"

using namespace ltm;

namespace {
// Average of E over points on the furnace floor (a wall like any other).
IrradianceEstimate furnace_irradiance(float rho, int max_depth, int spp, int n_points) {
    const Scene s = furnace_box(rho, 1.f);
    const EmbreeAccel accel(s);
    PathTracerConfig cfg;
    cfg.seed = 1;
    cfg.max_depth = max_depth;
    const PathTracer pt(accel, cfg);
    IrradianceEstimate sum;
    for (int i = 0; i < n_points; ++i) {
        const Vec3f p{0.1f + 0.8f * float(i % 4) / 3.f, 0.f, 0.1f + 0.8f * float(i / 4) / 3.f};
        const IrradianceEstimate e = pt.irradiance(p, {0, 1, 0}, uint64_t(i), spp);
        sum.direct += e.direct / float(n_points);
        sum.indirect += e.indirect / float(n_points);
    }
    return sum;
}

// Lambert's formula for a polygon light of radiance L seen from (p, n):
// E = L/2 · Σ_i θ_i · n·(r_i × r_{i+1})/|r_i × r_{i+1}|, r_i unit vectors to the vertices.
float polygon_irradiance(Vec3f p, Vec3f n, const std::vector<Vec3f> &poly, float radiance) {
    double sum = 0;
    for (size_t i = 0; i < poly.size(); ++i) {
        const Vec3f a = normalize(poly[i] - p), b = normalize(poly[(i + 1) % poly.size()] - p);
        const Vec3f c = cross(a, b);
        const double theta = std::acos(std::clamp(double(dot(a, b)), -1.0, 1.0));
        sum += theta * double(dot(n, c)) / double(length(c));
    }
    return float(std::abs(0.5 * sum) * double(radiance));
}

Scene quad_over_plane(Vec3f light_lo, Vec3f light_hi, float radiance) {
    Scene s;
    s.name = "quad-over-plane";
    Material plane, light;
    plane.name = "plane";
    plane.albedo = Texture::constant(Vec3f(0.5f));
    light.name = "light";
    light.albedo = Texture::constant(Vec3f(0.f));
    light.emission = Texture::constant(Vec3f(radiance));
    s.add_material(plane);
    s.add_material(light);
    TriangleMesh floor, lamp;
    floor.name = "plane", floor.material = 0;
    lamp.name = "light", lamp.material = 1;
    add_quad_facing(floor, {-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}, {0, 1, 0});
    add_quad_facing(lamp, {light_lo.x, light_lo.y, light_lo.z}, {light_hi.x, light_lo.y, light_lo.z},
                    {light_hi.x, light_lo.y, light_hi.z}, {light_lo.x, light_lo.y, light_hi.z}, {0, -10, 0});
    s.meshes = {floor, lamp};
    return s;
}
}  // namespace

// Closed box, albedo ρ, emission Le = 1 everywhere: E_direct = π·Le and, for depth D,
// E⁺ = π·Le·(ρ + ρ² + … + ρ^D); for D → ∞ the total is π·Le/(1−ρ).
TEST(PathTracer, FurnaceDepthTruncatedSeriesMatchesClosedForm) {
    for (float rho : {0.3f, 0.8f}) {
        const IrradianceEstimate e = furnace_irradiance(rho, /*max_depth=*/5, /*spp=*/1024, /*points=*/16);
        double series = 0, r = 1;
        for (int k = 1; k <= 5; ++k) series += (r *= rho);
        EXPECT_NEAR(e.direct.x, k_pi, 0.01 * k_pi) << rho;
        EXPECT_NEAR(e.indirect.x, k_pi * series, 0.01 * k_pi * series) << rho;
        EXPECT_EQ(e.indirect.x, e.indirect.y);   // grey scene, same paths for every channel
    }
}

TEST(PathTracer, FurnaceInfiniteDepthMatchesClosedForm) {
    for (float rho : {0.3f, 0.8f}) {
        const IrradianceEstimate e = furnace_irradiance(rho, /*max_depth=*/1000, /*spp=*/8192, /*points=*/16);
        const double expected = k_pi / (1.0 - rho);
        EXPECT_NEAR(e.direct.x + e.indirect.x, expected, 0.01 * expected) << rho;
    }
}

// trace_irradiance runs point i on stream keys[i] (without keys: on stream i): rows and keys permuted
// together give the outputs permuted, bit for bit, and keys 0 … n−1 are the keyless numbers — so a
// scene point keeps its paths wherever it lands in the list (ScenePoints::ids).
TEST(PathTracer, TracedIrradianceFollowsItsKeysNotItsRows) {
    const Scene s = builtin_scene("cornell-box");
    const EmbreeAccel accel(s);
    PathTracerConfig cfg;
    cfg.seed = 7;
    const PathTracer pt(accel, cfg);
    const size_t n = 6;
    std::vector<float> rows;
    for (size_t i = 0; i < n; ++i) rows.insert(rows.end(), {0.05f + 0.08f * float(i), 0.f, 0.3f, 0.f, 1.f, 0.f});
    const std::vector<uint64_t> keys{11, 3, 900, 42, 7, 1 << 20}, counting{0, 1, 2, 3, 4, 5};
    std::vector<Vec3f> d(n), e(n), dk(n), ek(n), d0(n), e0(n), dp(n), ep(n);
    trace_irradiance(pt, rows.data(), 6, n, 4, d.data(), e.data());
    trace_irradiance(pt, rows.data(), 6, n, 4, d0.data(), e0.data(), counting.data());
    trace_irradiance(pt, rows.data(), 6, n, 4, dk.data(), ek.data(), keys.data());
    for (size_t i = 0; i < n; ++i) EXPECT_TRUE(d0[i] == d[i] && e0[i] == e[i]) << i;
    const size_t order[n] = {4, 0, 5, 2, 1, 3};   // row i of the permuted table is row order[i]
    std::vector<float> prow;
    std::vector<uint64_t> pkeys;
    for (size_t i : order) prow.insert(prow.end(), rows.begin() + ptrdiff_t(i * 6), rows.begin() + ptrdiff_t(i * 6 + 6)), pkeys.push_back(keys[i]);
    trace_irradiance(pt, prow.data(), 6, n, 4, dp.data(), ep.data(), pkeys.data());
    bool moved = false;
    for (size_t i = 0; i < n; ++i) {
        EXPECT_TRUE(dp[i] == dk[order[i]] && ep[i] == ek[order[i]]) << i;
        moved |= !(ek[i] == e[i]);
    }
    EXPECT_TRUE(moved) << "other keys, other paths";
}

// The camera image inside the furnace: every pixel sees L = Le/(1−ρ) (up to depth truncation).
TEST(PathTracer, FurnaceImageRadianceMatchesClosedForm) {
    const Scene s = furnace_box(0.5f, 1.f);
    const EmbreeAccel accel(s);
    PathTracerConfig cfg;
    cfg.max_depth = 1000;
    const PathTracer pt(accel, cfg);
    Camera cam = s.cameras[0];
    cam.width = cam.height = 16;
    const RenderedImage img = render_pathtraced(pt, cam, 64);
    double mean = 0;
    for (const Vec3f &c : img.color.pixels) mean += double(c.x) / double(img.color.pixels.size());
    EXPECT_NEAR(mean, 2.0, 0.02);
    EXPECT_EQ(img.hit_fraction, 1.f);
}

// A 1 m × 1 m light 1 m above a plane: E_direct equals Lambert's polygon formula within 1%,
// and E⁺ is exactly 0 (the plane's light escapes or hits the black light).
TEST(PathTracer, QuadLightDirectIrradianceMatchesLambert) {
    const Vec3f lo{-0.5f, 1.f, -0.5f}, hi{0.5f, 1.f, 0.5f};
    const Scene s = quad_over_plane(lo, hi, 10.f);
    const EmbreeAccel accel(s);
    PathTracerConfig cfg;
    cfg.seed = 3;
    const PathTracer pt(accel, cfg);
    const std::vector<Vec3f> poly = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, lo.y, hi.z}, {lo.x, lo.y, hi.z}};
    const Vec3f points[] = {{0, 0, 0}, {0.3f, 0, 0.2f}, {1.2f, 0, -0.4f}, {-2.f, 0, 1.5f}, {0.5f, 0, 0.5f}};
    for (size_t i = 0; i < std::size(points); ++i) {
        const float expected = polygon_irradiance(points[i], {0, 1, 0}, poly, 10.f);
        const IrradianceEstimate e = pt.irradiance(points[i], {0, 1, 0}, i, 65536);
        EXPECT_NEAR(e.direct.x, expected, 0.01f * expected) << "point " << i;
        EXPECT_EQ(e.indirect.x, 0.f);
    }
    // Facing away from the light: nothing arrives.
    EXPECT_EQ(pt.irradiance({0, 0.5f, 0}, {0, -1, 0}, 99, 256).direct.x, 0.f);
}

// GGX with F0 = 1: the directional albedo ∫ f cosθ dω ≤ 1 (single scattering loses energy,
// more at high roughness), and BSDF sampling agrees with uniform hemisphere sampling.
TEST(Bsdf, GgxWhiteFurnaceConservesEnergy) {
    for (float alpha : {0.05f, 0.3f, 0.7f, 1.0f})
        for (float cos_o : {1.0f, 0.5f, 0.15f}) {
            Bsdf b;
            b.kind = BsdfKind::conductor;
            b.f0 = Vec3f(1.f);
            b.alpha = alpha;
            const Vec3f wo{std::sqrt(1.f - cos_o * cos_o), 0.f, cos_o};
            Pcg32 rng(7);
            double imp = 0, uni = 0;
            const int n = 200000;
            for (int i = 0; i < n; ++i) {
                const BsdfSample s = b.sample(wo, {rng.next_float(), rng.next_float()});
                if (s.pdf > 0.f) {
                    imp += s.weight.x;
                    EXPECT_NEAR(s.pdf, b.pdf(wo, s.wi), 1e-3f * s.pdf + 1e-6f);
                }
                const float z = rng.next_float(), phi = 2.f * k_pi * rng.next_float();   // uniform hemisphere
                const float r = std::sqrt(std::max(0.f, 1.f - z * z));
                const Vec3f wi{r * std::cos(phi), r * std::sin(phi), z};
                uni += double(b.eval(wo, wi).x * wi.z) * 2.0 * k_pi;
            }
            imp /= n, uni /= n;
            EXPECT_LE(imp, 1.0 + 1e-3) << alpha << " " << cos_o;
            EXPECT_NEAR(imp, uni, 0.02 + (alpha < 0.1f ? 0.2 : 0.0)) << alpha << " " << cos_o;
            if (alpha <= 0.05f && cos_o >= 0.5f) {   // near-mirror: almost no masking loss
                EXPECT_GT(imp, 0.99);
            }
            if (alpha >= 1.0f && cos_o == 1.0f) {
                // α = 1: D = 1/π, and at normal incidence only half-vectors with θh < 45° reflect
                // above the horizon: ∫ D cosθh dω_h = sin²45° = 0.5 bounds the albedo; masking takes more.
                EXPECT_LT(imp, 0.5);
                EXPECT_GT(imp, 0.25);
            }
        }
}

// The 32×32 (here 8×8) bins integrate with the cosine to the irradiance: E = π/R²·Σ L̄_bin.
TEST(PathTracer, BinsIntegrateToIrradiance) {
    const Scene s = cornell_box();
    const EmbreeAccel accel(s);
    const PathTracer pt(accel, PathTracerConfig{});
    const Vec3f p{0.2f, 0.f, 0.2f}, n{0, 1, 0};
    const int res = 8;
    const auto bins = pt.incident_radiance_bins(p, n, 0, res, 64);
    Vec3f from_bins(0.f);
    for (const Vec3f &b : bins) from_bins += b * (k_pi / float(res * res));
    const IrradianceEstimate e = pt.irradiance(p, n, 1, 16384);
    const Vec3f total = e.direct + e.indirect;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(from_bins[c], total[c], 0.04f * total[c]) << c;
}

// Paper §7's ground truth against a closed form: a point under one rectangular light of radiance L
// (nothing else in the scene). Bins whose every sub-direction sees the light hold exactly L, bins
// that see none of it hold 0, and Σ (π/R²)·L̄_bin = π L F, F the point-to-parallel-rectangle view
// factor (four corner rectangles of sides a, b at height h: F = Σ (1/2π)[X/√(1+X²) atan(Y/√(1+X²))
// + Y/√(1+Y²) atan(X/√(1+Y²))], X = a/h, Y = b/h).
TEST(HemisphereBins, QuadLightCoversItsBinsExactly) {
    const float a = 0.6f, b = 0.4f, h = 1.f, le = 2.f;
    Scene s;
    Material m;
    m.name = "light";
    m.albedo = Texture::constant(Vec3f(0.f));
    m.emission = Texture::constant(Vec3f(le));
    s.add_material(m);
    TriangleMesh q;
    q.name = "light";
    q.material = 0;
    add_quad_facing(q, {-a, h, -b}, {a, h, -b}, {a, h, b}, {-a, h, b}, {0.f, 0.f, 0.f});
    s.meshes.push_back(q);
    const EmbreeAccel accel(s);
    const PathTracer pt(accel, PathTracerConfig{});
    const int res = 16;
    const Vec3f p{0.f, 0.f, 0.f}, n{0.f, 1.f, 0.f};
    const auto bins = pt.incident_radiance_bins(p, n, 0, res, 64);
    ASSERT_EQ(bins.size(), size_t(res * res));
    // Local frame of the bins: z = n (the tracer's frame for n = +y).
    auto sees_light = [&](Vec3f local) {   // world direction from the tracer's own frame
        const Frame f(n);
        const Vec3f d = f.to_world(local);
        if (d.y <= 0.f) return false;
        const float t = h / d.y;
        return std::abs(d.x * t) < a && std::abs(d.z * t) < b;
    };
    int full = 0, empty = 0;
    double sum = 0;
    for (int i = 0; i < res; ++i)
        for (int j = 0; j < res; ++j) {
            int hit = 0;
            const int sub = 12;
            for (int u = 0; u <= sub; ++u)
                for (int v = 0; v <= sub; ++v)
                    hit += sees_light(square_to_direction({(float(i) + float(u) / sub) / res, (float(j) + float(v) / sub) / res}));
            const float l = bins[size_t(i * res + j)].y;
            if (hit == (sub + 1) * (sub + 1)) {
                ++full;
                EXPECT_NEAR(l, le, 1e-5f) << i << "," << j;
            }
            if (hit == 0) {
                ++empty;
                EXPECT_EQ(l, 0.f) << i << "," << j;
            }
            sum += double(l) * k_pi / double(res * res);
        }
    EXPECT_GT(full, 10);
    EXPECT_GT(empty, 10);
    auto corner = [](double x, double y) {
        return (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) + y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) /
               (2 * k_pi);
    };
    const double f = 4 * corner(a / h, b / h);
    EXPECT_NEAR(sum, k_pi * le * f, 0.01 * k_pi * le * f) << "view factor " << f;
    // L_in⁺ (no emitter seen directly): nothing else in the scene scatters, so every bin is 0.
    for (const Vec3f &l : pt.incident_radiance_bins(p, n, 0, res, 4, /*with_emission=*/false)) EXPECT_EQ(l, Vec3f(0.f));
}

TEST(HemisphereBins, MappingIsInvertible) {
    Pcg32 rng(5);
    for (int i = 0; i < 10000; ++i) {
        const Vec2f u{rng.next_float(), rng.next_float()};
        const Vec2f back = direction_to_square(square_to_direction(u));
        EXPECT_NEAR(back.x, u.x, 2e-4f);
        EXPECT_NEAR(back.y, u.y, 2e-4f);
    }
    EXPECT_EQ(direction_to_bin(square_to_direction({0.51f, 0.26f}), 32), 16 * 32 + 8);
}

namespace {
// Reference path tracer with no light sampling and no MIS: cosine directions only, emission
// counted where a path hits it. Independent of PathTracer's NEE/MIS bookkeeping.
Vec3f naive_radiance(const EmbreeAccel &accel, const Ray &ray, int scatter_left, Pcg32 &rng, bool count_emission) {
    const auto hit = accel.intersect(ray);
    if (!hit) return Vec3f(0.f);
    const SurfaceInteraction si = make_interaction(accel.scene(), ray, *hit);
    Vec3f L = count_emission ? si.emitted() : Vec3f(0.f);
    if (scatter_left == 0) return L;
    const Frame frame(si.front ? si.n : -si.n);
    const Vec3f wi = frame.to_world(sample_cosine_hemisphere({rng.next_float(), rng.next_float()}));
    return L + si.albedo() * naive_radiance(accel, {offset_ray_origin(si.p, frame.n, wi), wi}, scatter_left - 1, rng, true);
}
}  // namespace

// The Cornell box image: its mean luminance is stable across seeds and equals an independent
// estimator's — naive path tracing (cosine directions only, emission counted where a path hits it,
// no NEE/MIS), up to max_depth + 1 scattering events as the image's diffuse first hit allows —
// within 4 standard errors of the two estimates (issue #14 item 10: the value is no longer one the
// tracer itself produced).
TEST(PathTracer, CornellImageMatchesNaivePathTracing) {
    const Scene s = cornell_box();
    const EmbreeAccel accel(s);
    Camera cam = s.cameras[0];
    cam.width = cam.height = 32;
    std::vector<double> means;
    for (uint64_t seed : {1, 2, 3}) {
        PathTracerConfig cfg;
        cfg.seed = seed;
        const PathTracer pt(accel, cfg);
        const RenderedImage img = render_pathtraced(pt, cam, 64);
        double m = 0;
        for (const Vec3f &c : img.color.pixels) m += double(luminance(c)) / double(img.color.pixels.size());
        means.push_back(m);
    }
    for (double m : means) EXPECT_NEAR(m, means[0], 0.02 * means[0]);
    // The naive estimate of the same image mean: per path, the luminance of one jittered pixel sample.
    Pcg32 rng(77);
    const int per_pixel = 768;
    double sum = 0, sum2 = 0;
    int64_t n = 0;
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x)
            for (int k = 0; k < per_pixel; ++k) {
                const Ray ray{cam.eye, cam.ray_direction(float(x) + rng.next_float(), float(y) + rng.next_float())};
                const double l = luminance(naive_radiance(accel, ray, PathTracerConfig{}.max_depth + 1, rng, true));
                sum += l, sum2 += l * l, ++n;
            }
    const double naive = sum / double(n), se_naive = std::sqrt((sum2 / double(n) - naive * naive) / double(n));
    const double pt_mean = (means[0] + means[1] + means[2]) / 3.0;
    const double spread = std::abs(means[0] - means[2]) + 0.002 * pt_mean;   // the seeds' own spread bounds the PT error
    std::printf("Cornell mean luminance: path tracer %.5f (seeds 1-3), naive %.5f ± %.5f\n", pt_mean, naive, se_naive);
    EXPECT_NEAR(pt_mean, naive, 4.0 * se_naive + spread);
    EXPECT_LT(se_naive, 0.015 * naive) << "the naive estimate must be tight enough to mean something";
}

// E_direct and E⁺ with NEE+MIS equal the naive estimator's (π·first-hit emission, π·the rest).
TEST(PathTracer, NeeMisMatchesNaivePathTracing) {
    const Scene s = quad_light_room();
    const EmbreeAccel accel(s);
    const PathTracer pt(accel, PathTracerConfig{});
    const Vec3f p{1.5f, 0.f, 2.5f}, n{0, 1, 0};
    const IrradianceEstimate e = pt.irradiance(p, n, 0, 65536);
    Pcg32 rng(11);
    double direct = 0, indirect = 0;
    const int N = 400000;
    for (int i = 0; i < N; ++i) {
        const Vec3f wi = Frame(n).to_world(sample_cosine_hemisphere({rng.next_float(), rng.next_float()}));
        const Ray ray{offset_ray_origin(p, n, wi), wi};
        if (const auto hit = accel.intersect(ray)) direct += k_pi * make_interaction(s, ray, *hit).emitted().x;
        indirect += k_pi * naive_radiance(accel, ray, /*scatter_left=*/5, rng, /*count_emission=*/false).x;
    }
    direct /= N, indirect /= N;
    EXPECT_NEAR(e.direct.x, direct, 0.02 * direct);
    EXPECT_NEAR(e.indirect.x, indirect, 0.02 * indirect);
}
