// transport_prior_test.cpp: the visibility-free radiosity prior against the furnace's closed form,
// and its exact symmetries (emission linearity, unit and rotation invariance, channel independence),
// determinism and bad input.
#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
#include "ltm/core/sampling.h"
#include "ltm/transport/patch_form_factor.h"
#include "ltm/transport/transport_prior.h"
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

namespace {
// The prior's L⁺ over the R×R cell centres of each receiver's hemisphere (rows grouped by
// receiver, cells in order): [receivers × R² × 3].
std::vector<float> radiance_cells(const TransportPrior &t, const std::vector<Vec3f> &p, const std::vector<Vec3f> &n, int R,
                                  std::vector<Vec3f> *dirs = nullptr) {
    std::vector<float> pos, nrm, dir;
    for (size_t i = 0; i < p.size(); ++i) {
        const Frame frame(n[i]);
        for (int b = 0; b < R * R; ++b) {
            const Vec2f u{(float(b / R) + 0.5f) / float(R), (float(b % R) + 0.5f) / float(R)};
            const Vec3f w = normalize(frame.to_world(sample_cosine_hemisphere(u)));
            for (int c = 0; c < 3; ++c) pos.push_back(p[i][c]), nrm.push_back(n[i][c]), dir.push_back(w[c]);
            if (dirs) dirs->push_back(w);
        }
    }
    std::vector<float> out(pos.size());
    gather_transport_prior_radiance(t, pos.data(), nrm.data(), 3, dir.data(), 3, pos.size() / 3, R, out.data());
    return out;
}
}  // namespace

// L⁺ splits E⁺ by direction: its cosine integral over the cells is E⁺ exactly, light comes from
// where the lit wall is and from nowhere else, and a cell the wall fills holds its radiance 1/π.
TEST(TransportPrior, RadianceCellsSplitTheIrradianceByDirection) {
    const Nodes c = cube(12, 1.f, [](int) { return Vec3f(0.5f); }, [](int) { return Vec3f(0.f); });
    TransportPrior t = solve_transport_prior(c.p, c.n, c.rho, c.le, c.area, 1, {}, PriorBalance::per_channel, true);
    for (size_t j = 0; j < c.p.size(); ++j) t.exitance[j] = Vec3f(c.n[j].x > 0.5f ? 1.f : 0.f, 0.5f, 0.f);   // R: the wall x = 0
    const std::vector<Vec3f> p = {{0.05f, 0.f, 0.5f}, {0.5f, 0.f, 0.5f}, {0.9f, 0.f, 0.3f}, {0.4f, 0.6f, 1.f}};
    const std::vector<Vec3f> n = {{0.f, 1.f, 0.f}, {0.f, 1.f, 0.f}, {0.f, 1.f, 0.f}, {0.f, 0.f, -1.f}};
    const auto e = gather(t, p, n);
    for (int R : {1, 4, 8, 16}) {
        std::vector<Vec3f> dirs;
        const auto l = radiance_cells(t, p, n, R, &dirs);
        for (size_t i = 0; i < p.size(); ++i)
            for (int ch = 0; ch < 3; ++ch) {
                double sum = 0;
                for (int b = 0; b < R * R; ++b) sum += double(l[(i * size_t(R * R) + size_t(b)) * 3 + size_t(ch)]);
                EXPECT_NEAR(k_pi / double(R * R) * sum, double(e[i * 3 + size_t(ch)]), 1e-5 * (1.0 + double(e[i * 3 + size_t(ch)])))
                    << "R " << R << " receiver " << i << " channel " << ch;
                if (R == 1) { EXPECT_NEAR(l[i * 3 + size_t(ch)], e[i * 3 + size_t(ch)] / k_pi, 1e-6) << "one cell: uniform"; }
            }
        if (R != 8) continue;
        // Receiver 1, mid-floor: toward +x (away from the wall) the red channel is 0; toward the
        // wall (d.x < −0.8: cells wholly on it) it is the wall's radiance 1/π; green comes from all sides.
        double toward = 0;
        int n_toward = 0;
        for (int b = 0; b < 64; ++b) {
            const Vec3f d = dirs[64 + size_t(b)];
            const float red = l[(64 + size_t(b)) * 3], green = l[(64 + size_t(b)) * 3 + 1];
            if (d.x > 0.3f) { EXPECT_EQ(red, 0.f) << "cell " << b; }
            if (d.x < -0.8f) toward += red, ++n_toward;
            EXPECT_GT(green, 0.f) << "cell " << b;
        }
        ASSERT_GT(n_toward, 0);
        EXPECT_NEAR(toward / n_toward, 1.0 / k_pi, 0.2 / k_pi);
    }
    // Rows one at a time, and at 1 or 2 threads: the same bits as the grouped rows.
    const auto grouped = radiance_cells(t, p, n, 8);
    for (size_t i = 0; i < p.size(); ++i) {
        const auto single = radiance_cells(t, {p[i]}, {n[i]}, 8);
        for (size_t k = 0; k < single.size(); ++k) ASSERT_EQ(single[k], grouped[i * 64 * 3 + k]) << i << " " << k;
    }
    const int threads = num_threads();
    set_num_threads(1);
    const auto one = radiance_cells(t, p, n, 8);
    set_num_threads(threads);
    EXPECT_EQ(one, grouped);
    float dummy[3];
    EXPECT_THROW(gather_transport_prior_radiance(t, &p[0].x, &n[0].x, 3, &p[0].x, 3, 1, 0, dummy), Error);
    EXPECT_THROW(gather_transport_prior_radiance(t, &p[0].x, &n[0].x, 3, &p[0].x, 2, 1, 4, dummy), Error);
}
