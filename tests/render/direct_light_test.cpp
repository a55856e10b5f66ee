// direct_light_test.cpp: the analytic unshadowed irradiance and the ratio estimator against the
// path tracer's unbiased MIS estimator of E_direct (the ground truth, tested against closed forms).
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "ltm/core/error.h"
#include "ltm/core/rng.h"
#include "ltm/render/direct_light.h"
#include "ltm/render/path_tracer.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/mesh_builder.h"

namespace ltm {
namespace {

// A black emitter of constant radiance: a lamp's material, which scatters nothing back.
Material emitter(const std::string &name, Vec3f radiance) {
    Material m;
    m.name = name;
    m.albedo = Texture::constant(Vec3f(0.f));
    m.emission = Texture::constant(radiance);
    return m;
}

// A 1 m × 0.5 m light at y = 2 facing down (radiance (4, 2, 1)), and a small occluder plate at
// y = 1 under part of it; nothing else, so points away from the plate see the light unshadowed.
Scene lamp_scene(bool with_plate) {
    Scene s;
    s.name = "lamp";
    Material plate;
    plate.name = "plate";
    plate.albedo = Texture::constant(Vec3f(0.f));   // black: no light scattered back
    s.add_material(emitter("light", Vec3f(4.f, 2.f, 1.f)));
    s.add_material(plate);
    TriangleMesh lamp, occ;
    lamp.name = "light", lamp.material = 0;
    add_quad_facing(lamp, {-0.5f, 2, -0.25f}, {0.5f, 2, -0.25f}, {0.5f, 2, 0.25f}, {-0.5f, 2, 0.25f}, {0, -1, 0});
    s.meshes = {lamp};
    if (with_plate) {
        occ.name = "plate", occ.material = 1;
        add_quad_facing(occ, {0.f, 1, -0.6f}, {1.f, 1, -0.6f}, {1.f, 1, 0.6f}, {0.f, 1, 0.6f}, {0, 1, 0});
        s.meshes.push_back(occ);
    }
    return s;
}

struct Probe {
    Vec3f p, n;
};
// Below the light, tilted so that the light straddles the horizon, grazing, and above (behind) it.
const std::vector<Probe> k_probes = {
    {{0.f, 0.f, 0.f}, {0, 1, 0}},          {{0.3f, 1.5f, 0.1f}, {0, 1, 0}},
    {{-0.2f, 1.8f, 0.f}, normalize(Vec3f(1, 0.2f, 0))},   // light partly below this point's horizon
    {{0.4f, 1.9f, 0.3f}, normalize(Vec3f(-1, 0.5f, -0.3f))},
    {{2.f, 0.5f, 1.f}, normalize(Vec3f(-1, 1, -0.5f))},   {{0.f, 2.5f, 0.f}, {0, 1, 0}},
};

TEST(DirectLight, AnalyticUnshadowedEqualsThePathTracerEstimate) {
    const Scene s = lamp_scene(false);
    const EmbreeAccel accel(s);
    const PathTracer pt(accel, {});
    const RatioDirectLight light(accel, 0);
    for (size_t i = 0; i < k_probes.size(); ++i) {
        const Vec3f e = light.unoccluded(k_probes[i].p, k_probes[i].n);
        const Vec3f ref = pt.irradiance(k_probes[i].p, k_probes[i].n, i, 65536, false).direct;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(e[c], ref[c], 0.01f * std::max(ref[c], 0.05f)) << "probe " << i << " channel " << c;
    }
    EXPECT_EQ(max_component(light.unoccluded({0.f, 2.5f, 0.f}, {0, -1, 0})), 0.f) << "behind a one-sided emitter";
}

TEST(DirectLight, TriangleIrradianceKnownValues) {
    // A huge triangle covering the whole upper hemisphere of a receiver gives π (Le = 1): the
    // furnace value; a far-away small triangle gives A·cosθ/d².
    const float big = triangle_irradiance({0, 0, 0}, {0, 1, 0}, {-1e4f, 1e-3f, 1e4f}, {0, 1e-3f, -1e4f}, {1e4f, 1e-3f, 1e4f});
    EXPECT_NEAR(big, k_pi, 0.01f);
    const float small = triangle_irradiance({0, 0, 0}, {0, 1, 0}, {0, 10, 0}, {0.01f, 10, 0}, {0.01f, 10, 0.01f});
    EXPECT_NEAR(small, 0.5f * 0.01f * 0.01f / 100.f, 2e-8f);   // facing down (winding), area 5e-5 m²
    EXPECT_EQ(triangle_irradiance({0, 0, 0}, {0, 1, 0}, {0, 10, 0}, {0.01f, 10, 0.01f}, {0.01f, 10, 0}), 0.f)
        << "the same triangle facing up emits away from the receiver";
    EXPECT_EQ(triangle_irradiance({0, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, -1, 1}, {1, -1, 0}), 0.f)
        << "facing the receiver's side but below its horizon";
}

// Lambert's formula for one triangle in double precision, clipped to the hemisphere as
// triangle_irradiance clips it: the reference for sums over many small triangles, whose float terms
// lose digits to cancellation.
double triangle_irradiance_double(Vec3f pf, Vec3f nf, Vec3f v0, Vec3f v1, Vec3f v2) {
    using D3 = std::array<double, 3>;
    auto sub = [](Vec3f a, Vec3f b) { return D3{double(a.x) - b.x, double(a.y) - b.y, double(a.z) - b.z}; };
    auto dotd = [](const D3 &a, const D3 &b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    auto crossd = [](const D3 &a, const D3 &b) { return D3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; };
    const D3 n{nf.x, nf.y, nf.z};
    if (!(dotd(crossd(sub(v1, v0), sub(v2, v0)), sub(pf, v0)) > 0.0)) return 0.0;
    const D3 in[3] = {sub(v0, pf), sub(v1, pf), sub(v2, pf)};
    D3 poly[4];
    int m = 0;
    for (int i = 0; i < 3; ++i) {
        const D3 a = in[i], b = in[(i + 1) % 3];
        const double da = dotd(n, a), db = dotd(n, b);
        if (da >= 0.0) poly[m++] = a;
        if ((da >= 0.0) != (db >= 0.0)) {
            const double t = da / (da - db);
            poly[m++] = D3{a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t};
        }
    }
    double sum = 0.0;
    for (int i = 0; i < m && m >= 3; ++i) {
        D3 a = poly[i], b = poly[(i + 1) % m];
        const double la = std::sqrt(dotd(a, a)), lb = std::sqrt(dotd(b, b));
        for (int k = 0; k < 3; ++k) a[k] /= la, b[k] /= lb;
        const D3 c = crossd(a, b);
        const double len = std::sqrt(dotd(c, c));
        if (len > 0.0) sum += std::atan2(len, dotd(a, b)) * dotd(n, c) / len;
    }
    return std::abs(0.5 * sum);
}

// Lamps as real files bring them: a sphere tessellated 48 × 24 (as the pbrt reader does, its seam's
// vertices repeated), a box whose faces repeat their corners (a triangle soup), one face wound the
// other way and one missing.
Scene sphere_and_box_lamps() {
    Scene s;
    s.name = "lamps";
    s.add_material(emitter("light", Vec3f(3.f, 2.f, 1.f)));
    TriangleMesh sphere;
    sphere.name = "sphere", sphere.material = 0;
    const int nu = 48, nv = 24;
    const float r = 0.2f;
    const Vec3f c(0.3f, 1.8f, -0.2f);
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
            const float th = k_pi * float(j) / float(nv), ph = 2.f * k_pi * float(i) / float(nu);
            sphere.positions.push_back(c + Vec3f(r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th)));
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const uint32_t a = uint32_t(j * (nu + 1) + i), b = a + 1, cc = a + uint32_t(nu + 1), e = cc + 1;
            if (j > 0) sphere.indices.insert(sphere.indices.end(), {a, cc, b});
            if (j < nv - 1) sphere.indices.insert(sphere.indices.end(), {b, cc, e});
        }
    TriangleMesh box;
    box.name = "box", box.material = 0;
    const Vec3f lo(-0.6f, 1.2f, 0.2f), hi(-0.2f, 1.5f, 0.5f);
    auto corner = [&](int x, int y, int z) { return Vec3f(x ? hi.x : lo.x, y ? hi.y : lo.y, z ? hi.z : lo.z); };
    add_quad_facing(box, corner(0, 0, 0), corner(1, 0, 0), corner(1, 0, 1), corner(0, 0, 1), {0, -1, 0});
    add_quad_facing(box, corner(0, 0, 0), corner(0, 1, 0), corner(0, 1, 1), corner(0, 0, 1), {-1, 0, 0});
    add_quad_facing(box, corner(1, 0, 0), corner(1, 1, 0), corner(1, 1, 1), corner(1, 0, 1), {1, 0, 0});
    add_quad_facing(box, corner(0, 0, 1), corner(1, 0, 1), corner(1, 1, 1), corner(0, 1, 1), {0, 0, 1});
    add_quad_facing(box, corner(0, 1, 0), corner(1, 1, 0), corner(1, 1, 1), corner(0, 1, 1), {0, -1, 0});   // wound inwards
    s.meshes = {sphere, box};
    return s;
}

// E_unocc, summed over the outline of what is in view, equals the sum of every triangle's own clipped
// formula (in double) — for receivers that see the lamps whole, cut by their horizon, grazing and
// inside the open box.
TEST(DirectLight, OutlineSumEqualsTheTrianglesSum) {
    const Scene s = sphere_and_box_lamps();
    const EmbreeAccel accel(s);
    const RatioDirectLight lamps(accel, 0);
    Pcg32 rng(7);
    int cut = 0;
    for (int k = 0; k < 400; ++k) {
        const Vec3f p(rng.next_float() * 3.f - 1.5f, rng.next_float() * 3.f, rng.next_float() * 3.f - 1.5f);
        const Vec3f n = normalize(Vec3f(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
        double want = 0.0;
        for (const TriangleMesh &m : s.meshes)
            for (size_t t = 0; t < m.n_triangles(); ++t) {
                if (!(m.area(t) > 0.f)) continue;
                want += triangle_irradiance_double(p, n, m.vertex(t, 0), m.vertex(t, 1), m.vertex(t, 2));
                if (dot(n, m.vertex(t, 0) - p) * dot(n, m.vertex(t, 1) - p) < 0.f) ++cut;
            }
        const Vec3f e = lamps.unoccluded(p, n);
        EXPECT_NEAR(e.x, 3.0 * want, 1e-5 * 3.0 * want + 1e-9) << "receiver " << k;
        EXPECT_NEAR(e.z, want, 1e-5 * want + 1e-9) << "receiver " << k;
    }
    EXPECT_GT(cut, 100) << "receivers whose horizon cuts a lamp";
}

// Where nothing occludes, every light that a receiver sees analytically must get samples, whether
// its share came from the exact sum (near it, or cut by the horizon) or from the small-source
// approximation (far and wholly in view), and every seen light adds its exact E_unocc: the ratio
// estimate is the analytic sum (but for slivers above the horizon that no sample of 4 096 hits). A
// light dropped from the share — ruled out as below the horizon or turned away when part of it is
// not — shows here. The lamps lie on a shell of radius 5 around the receivers, apart, so that none
// hides another: 24 small quads tilted up to 70° off the centre (some turned away from part of the
// ball, many straddling a receiver's horizon) and kept clear of the other two, a 3 m quad (half the
// receivers within 3 of its radii) and a tessellated sphere, each of its own colour.
TEST(DirectLight, RatioEstimatorSharesTheSamplesWithoutDroppingALight) {
    Scene s;
    s.name = "shell";
    Pcg32 rng(11);
    // Each lamp its own colour: a lamp dropped or counted twice shows in the channels' ratios too.
    const auto lamp_material = [&](int i) {
        return s.add_material(emitter("light" + std::to_string(i), Vec3f(1.f + float(i % 3), 1.f + float(i % 5), 1.f + float(i % 7))));
    };
    int n_lamps = 0;
    const auto quad = [&](Vec3f centre, Vec3f facing, float half, const std::string &name) {
        const Frame f(facing);
        TriangleMesh m;
        m.name = name, m.material = lamp_material(n_lamps++);
        const Vec3f u = f.s * half, v = f.t * half;
        add_quad_facing(m, centre - u - v, centre + u - v, centre + u + v, centre - u + v, facing);
        s.meshes.push_back(m);
    };
    const int n_small = 24;
    const Vec3f sphere_dir = normalize(Vec3f(0.f, 1.f, 0.5f));
    for (int i = 0; i < n_small; ++i) {
        // Fibonacci directions: well apart on the sphere.
        const float z = 1.f - 2.f * (float(i) + 0.5f) / float(n_small), r = std::sqrt(1.f - z * z), ph = 2.39996323f * float(i);
        const Vec3f dir(r * std::cos(ph), z, r * std::sin(ph));
        if (dir.z < -0.6f || dot(dir, sphere_dir) > 0.9f) continue;   // keep clear of the large quad and the sphere
        const Vec3f tilt = normalize(Vec3f(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
        const Vec3f facing = normalize(-dir + 2.7f * rng.next_float() * normalize(tilt - dot(tilt, dir) * dir));
        quad(5.f * dir, facing, 0.25f, "small" + std::to_string(i));
    }
    quad({0.f, 0.f, -6.f}, {0, 0, 1}, 1.5f, "large");
    TriangleMesh sphere = sphere_and_box_lamps().meshes[0];
    sphere.material = lamp_material(n_lamps++);
    for (Vec3f &v : sphere.positions) v += 4.f * sphere_dir - Vec3f(0.3f, 1.8f, -0.2f);   // its centre to 4 · sphere_dir
    s.meshes.push_back(sphere);
    const EmbreeAccel accel(s);
    const RatioDirectLight lamps(accel, 0);
    int lit = 0, near_large = 0, off = 0;
    for (int k = 0; k < 300; ++k) {
        Vec3f p;
        do p = Vec3f(rng.next_float(), rng.next_float(), rng.next_float()) * 2.f - Vec3f(1.f);
        while (dot(p, p) > 1.f);
        p.z -= 2.f * float(k % 2);   // every other receiver nearer the large quad
        near_large += length(p - Vec3f(0.f, 0.f, -6.f)) <= 3.f * 1.5f * std::sqrt(2.f);   // within 3 of its radii
        const Vec3f n = normalize(Vec3f(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
        const Vec3f want = lamps.unoccluded(p, n);
        const Vec3f e = lamps.irradiance(p, n, uint64_t(k), 4096);
        if (want.z > 0.f) ++lit;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(e[c], want[c], 0.02f * want[c] + 1e-9f) << "receiver " << k << " channel " << c;
        off += std::abs(e.x - want.x) > 2e-3f * want.x || std::abs(e.z - want.z) > 2e-3f * want.z;
    }
    EXPECT_GT(lit, 290);
    // Slivers: a lamp the horizon cuts, with a few samples of its own, may get none above it (then 0,
    // as the estimator's comment says); a lamp dropped from the share would move far more receivers.
    EXPECT_LE(off, 10) << "receivers off by more than 0.2 %";
    EXPECT_GT(near_large, 100);
}

// Unshadowed: the ratio is 1, so any sample count gives the analytic value exactly.
TEST(DirectLight, RatioEstimatorIsExactWithoutOcclusion) {
    const Scene s = lamp_scene(false);
    const EmbreeAccel accel(s);
    const RatioDirectLight light(accel, 0);
    for (size_t i = 0; i < k_probes.size(); ++i)
        for (int spp : {1, 4}) {
            const Vec3f e = light.irradiance(k_probes[i].p, k_probes[i].n, i, spp), u = light.unoccluded(k_probes[i].p, k_probes[i].n);
            for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(e[c], u[c]) << "probe " << i;
        }
}

// Shadowed and penumbra points: the ratio estimate converges to the path tracer's E_direct.
TEST(DirectLight, RatioEstimatorMatchesThePathTracerInShadow) {
    const Scene s = lamp_scene(true);
    const EmbreeAccel accel(s);
    const PathTracer pt(accel, {});
    const RatioDirectLight light(accel, 0);
    // Under the plate (umbra), at its edge (penumbra), and clear of it.
    const std::vector<Vec3f> points = {{0.5f, 0.f, 0.f}, {0.f, 0.f, 0.f}, {-0.2f, 0.3f, 0.1f}, {0.2f, 0.5f, 0.f}, {-1.f, 0.f, 0.f}};
    for (size_t i = 0; i < points.size(); ++i) {
        const Vec3f e = light.irradiance(points[i], {0, 1, 0}, i, 65536);
        const Vec3f ref = pt.irradiance(points[i], {0, 1, 0}, i, 65536, false).direct;
        // Tolerance: 3% of the value, or of a tenth of the unshadowed level in deep penumbra
        // (there both estimates carry ~1.5% noise from the few visible samples).
        const float scale = std::max(ref.x, 0.1f * light.unoccluded(points[i], {0, 1, 0}).x);
        EXPECT_NEAR(e.x, ref.x, 0.03f * scale) << "point " << i << " unoccluded " << light.unoccluded(points[i], {0, 1, 0}).x;
        EXPECT_NEAR(e.z / std::max(e.x, 1e-6f), ref.z / std::max(ref.x, 1e-6f), 0.02f) << "colour of the light";
    }
}

// A second light behind a wall (another room): analytically unoccluded, in fact hidden. Per-light
// ratios make the estimate exact at any sample count: the seen light's E_unocc, nothing else.
TEST(DirectLight, LightBehindAWallAddsNoNoise) {
    Scene s = lamp_scene(false);
    TriangleMesh lamp2, wall;
    lamp2.name = "light2", lamp2.material = 0;
    add_quad_facing(lamp2, {4.5f, 2, -0.25f}, {5.5f, 2, -0.25f}, {5.5f, 2, 0.25f}, {4.5f, 2, 0.25f}, {0, -1, 0});
    wall.name = "wall", wall.material = s.add_material([] {
        Material m;
        m.name = "wall";
        m.albedo = Texture::constant(Vec3f(0.f));
        return m;
    }());
    add_quad_facing(wall, {2.5f, -1, -5}, {2.5f, 3, -5}, {2.5f, 3, 5}, {2.5f, -1, 5}, {-1, 0, 0});
    s.meshes.push_back(lamp2);
    s.meshes.push_back(wall);
    const EmbreeAccel accel(s);
    const RatioDirectLight both(accel, 0);
    const Scene alone = lamp_scene(false);
    const EmbreeAccel accel_alone(alone);
    const RatioDirectLight one(accel_alone, 0);
    for (const Vec3f p : {Vec3f{0.f, 0.f, 0.f}, Vec3f{1.f, 0.5f, 0.5f}, Vec3f{-1.f, 0.f, -1.f}}) {
        EXPECT_GT(both.unoccluded(p, {0, 1, 0}).x, one.unoccluded(p, {0, 1, 0}).x) << "the hidden light counts analytically";
        for (int spp : {2, 4, 16}) {
            const Vec3f e = both.irradiance(p, {0, 1, 0}, 7, spp), want = one.unoccluded(p, {0, 1, 0});
            EXPECT_FLOAT_EQ(e.x, want.x) << "spp " << spp;
        }
    }
}

TEST(DirectLight, TexturedEmissionIsRejected) {
    Scene s = lamp_scene(false);
    s.materials[0].emission.kind = TextureKind::checker;
    EXPECT_FALSE(RatioDirectLight::supports(s));
    const EmbreeAccel accel(s);
    EXPECT_THROW(RatioDirectLight(accel, 0), Error);
    EXPECT_TRUE(RatioDirectLight::supports(cornell_box()));
}

}  // namespace
}  // namespace ltm
