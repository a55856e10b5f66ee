// transport_prior_test.cpp: the visibility-free radiosity prior against the furnace's closed form,
// and its exact symmetries (emission linearity, unit and rotation invariance, channel independence),
// determinism and bad input.
#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
#include "ltm/points/patch_form_factor.h"
#include "ltm/points/transport_prior.h"
#include "point_rooms.h"

using namespace ltm;

namespace {
// Nodes on a g×g grid per face of the cube [0, s]³, normals pointing inward; per-face albedo and
// radiance from the callbacks (face index 0..5).
struct Nodes {
    std::vector<Vec3f> p, n, rho, le;
    float area = 0.f;
};
template <class Rho, class Le> Nodes cube(int g, float side, Rho rho, Le le) {
    Nodes out;
    test::for_each_face_cell(Vec3f(0.f), Vec3f(side), g, test::no_jitter, [&](int f, Vec3f p, Vec3f n) {
        out.p.push_back(p), out.n.push_back(n), out.rho.push_back(rho(f)), out.le.push_back(le(f));
    });
    out.area = side * side / float(g * g);
    return out;
}

using test::gather;

TransportPrior solve(const Nodes &c, int bounces) { return solve_transport_prior(c.p, c.n, c.rho, c.le, c.area, bounces); }
}  // namespace

// A closed box of uniform albedo ρ and emitted radiance L: every bounce spreads evenly, so
// E⁺ = π L Σ_{k=1..D} ρ^k at every inward-facing receiver, per channel.
TEST(TransportPrior, FurnaceBoxMatchesClosedForm) {
    const Vec3f rho(0.5f, 0.8f, 0.2f), le(1.f, 2.f, 3.f);
    const Nodes c = cube(8, 2.f, [&](int) { return rho; }, [&](int) { return le; });
    const int d = 5;
    const TransportPrior t = solve(c, d);
    const auto e = gather(t, {{1.f, 0.01f, 1.f}, {0.3f, 1.2f, 1.99f}, {1.7f, 0.5f, 0.8f}},
                          {{0, 1, 0}, {0, 0, -1}, {-0.6f, 0.8f, 0.f}});
    for (int c3 = 0; c3 < 3; ++c3) {
        double series = 0, term = 1;
        for (int k = 0; k < d; ++k) series += (term *= double(rho[c3]));
        const double expect = k_pi * double(le[c3]) * series;
        for (size_t q = 0; q < 3; ++q) EXPECT_NEAR(e[3 * q + size_t(c3)], expect, 1e-4 * expect) << "channel " << c3;
    }
}

// Only the floor emits, the walls are coloured: exact symmetries of light transport hold bit for
// bit or to float rounding — linear in emission, independent of the unit of length, of a rotation
// of the scene, and each channel depends only on its own albedo and emission.
TEST(TransportPrior, ExactSymmetries) {
    const Nodes c = cube(6, 3.f, [](int f) { return f == 0 ? Vec3f(0.2f, 0.3f, 0.4f) : Vec3f(0.7f, 0.1f * float(f), 0.5f); },
                         [](int f) { return f == 2 ? Vec3f(5.f, 4.f, 3.f) : Vec3f(0.f); });
    const std::vector<Vec3f> qp{{1.5f, 0.2f, 1.5f}, {2.9f, 1.f, 0.4f}, {0.7f, 2.5f, 2.2f}};
    const std::vector<Vec3f> qn{{0, 1, 0}, {-1, 0, 0}, {0.f, -0.6f, -0.8f}};
    const auto base = gather(solve(c, 4), qp, qn);
    for (float v : base) EXPECT_GT(v, 0.f);

    Nodes x4 = c;   // emission ×4 (a power of two: exact in float)
    for (auto &l : x4.le) l = l * 4.f;
    const auto e4 = gather(solve(x4, 4), qp, qn);
    for (size_t i = 0; i < base.size(); ++i) EXPECT_EQ(e4[i], 4.f * base[i]);

    Nodes cm = c;   // the same box in centimetres
    for (auto &p : cm.p) p = p * 100.f;
    cm.area *= 1e4f;
    std::vector<Vec3f> qcm;
    for (const auto &p : qp) qcm.push_back(p * 100.f);
    const auto ecm = gather(solve(cm, 4), qcm, qn);
    for (size_t i = 0; i < base.size(); ++i) EXPECT_NEAR(ecm[i], base[i], 1e-4f * base[i]);

    Nodes rot = c;   // a quarter turn about y: (x, y, z) -> (z, y, −x)
    auto turn = [](Vec3f v) { return Vec3f(v.z, v.y, -v.x); };
    for (auto &p : rot.p) p = turn(p);
    for (auto &n : rot.n) n = turn(n);
    std::vector<Vec3f> qr, nr;
    for (size_t i = 0; i < qp.size(); ++i) qr.push_back(turn(qp[i])), nr.push_back(turn(qn[i]));
    const auto erot = gather(solve(rot, 4), qr, nr);
    for (size_t i = 0; i < base.size(); ++i) EXPECT_NEAR(erot[i], base[i], 1e-4f * base[i]);

    Nodes green = c;   // another green albedo everywhere: red and blue unchanged
    for (auto &r : green.rho) r.y = 0.9f;
    const auto eg = gather(solve(green, 4), qp, qn);
    for (size_t q = 0; q < qp.size(); ++q) {
        EXPECT_EQ(eg[3 * q], base[3 * q]);
        EXPECT_EQ(eg[3 * q + 2], base[3 * q + 2]);
        EXPECT_NE(eg[3 * q + 1], base[3 * q + 1]);
    }
}

// More bounces add light (ρ > 0), zero bounces give nothing, a receiver facing away from every
// node gets 0, and the result does not depend on the thread count.
TEST(TransportPrior, BouncesFacingAndThreads) {
    const Nodes c = cube(6, 2.f, [](int) { return Vec3f(0.6f); }, [](int f) { return f == 3 ? Vec3f(2.f) : Vec3f(0.f); });
    const std::vector<Vec3f> qp{{1.f, 0.1f, 1.f}, {1.f, 1.f, -5.f}}, qn{{0, 1, 0}, {0, 0, -1}};
    const auto e1 = gather(solve(c, 1), qp, qn), e3 = gather(solve(c, 3), qp, qn), e0 = gather(solve(c, 0), qp, qn);
    EXPECT_GT(e3[0], e1[0]);
    EXPECT_GT(e1[0], 0.f);
    EXPECT_EQ(e0[0], 0.f);
    EXPECT_EQ(e3[3], 0.f) << "outside the box, facing away from it";
    const int threads = num_threads();
    set_num_threads(1);
    const auto one = gather(solve(c, 3), qp, qn);
    set_num_threads(threads);
    EXPECT_EQ(one, e3);
}

TEST(TransportPrior, BadInputIsAnError) {
    const Nodes c = cube(2, 1.f, [](int) { return Vec3f(0.5f); }, [](int) { return Vec3f(1.f); });
    EXPECT_THROW(solve_transport_prior({}, {}, {}, {}, 1.f, 2), Error);
    EXPECT_THROW(solve_transport_prior(c.p, c.n, c.rho, {}, c.area, 2), Error);
    EXPECT_THROW(solve_transport_prior(c.p, c.n, c.rho, c.le, 0.f, 2), Error);
    EXPECT_THROW(solve_transport_prior(c.p, c.n, c.rho, c.le, c.area, -1), Error);
}

// The near field (patches): in a closed unit cube whose wall x = 0 alone has exitance 1, the
// gather at a floor point is that wall's share of the receiver's hemisphere — its form factor,
// exactly (a closed box's form factors sum to 1). Approaching the concave edge the wall fills half
// the hemisphere; the point formula at the nodes' centres misses the elements within the nodes'
// spacing of the edge, the square patches do not. Far from the edge both agree with the exact value.
TEST(TransportPrior, PatchesGiveTheNearFieldOfAConcaveEdge) {
    const Nodes c = cube(12, 1.f, [](int) { return Vec3f(0.5f); }, [](int) { return Vec3f(0.f); });
    auto prior = [&](bool patches) {
        TransportPrior t = solve_transport_prior(c.p, c.n, c.rho, c.le, c.area, 1, {}, PriorBalance::per_channel, patches);
        for (size_t j = 0; j < c.p.size(); ++j) t.exitance[j] = Vec3f(c.n[j].x > 0.5f ? 1.f : 0.f);   // the wall x = 0
        return t;
    };
    const TransportPrior point = prior(false), patch = prior(true);
    EXPECT_TRUE(patch.patches);
    const Vec3f up(0.f, 1.f, 0.f);
    for (float x : {0.004f, 0.02f, 0.05f, 0.3f}) {
        const Vec3f p(x, 0.f, 0.5f);
        const double exact = patch_form_factor(p, up, Vec3f(0.f, 0.5f, 0.5f), Vec3f(1.f, 0.f, 0.f), 1.f);
        const double e_point = gather(point, {p}, {up})[0], e_patch = gather(patch, {p}, {up})[0];
        // measured: exact 0.497 / 0.484 / 0.461 / 0.287, patches 0.497 / 0.482 / 0.455 / 0.287,
        // point formula 0.103 / 0.333 / 0.434 / 0.287
        EXPECT_NEAR(e_patch, exact, 0.01) << "x " << x;
        if (x <= 0.02f) {
            EXPECT_GT(exact - e_point, 0.1) << "the point formula misses the edge, x " << x;
        }
        if (x >= 0.3f) {
            EXPECT_NEAR(e_point, exact, 0.01) << "far from the edge the point formula holds";
        }
    }
}
