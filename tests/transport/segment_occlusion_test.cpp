// segment_occlusion_test.cpp: the transport prior's visibility by rays (transport/segment_occlusion.h,
// PriorTree::set_rays) against scenes whose occlusion is known in closed form: rays that block nothing
// give the unoccluded tree to the bit; a wall between two rooms lets no light through and leaves the
// lit room as it is alone; the furnace stays exact; a receiver's closure under an open side is the
// form factor's complement; deterministic at any thread count; bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <utility>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
#include "ltm/transport/prior_hierarchy.h"
#include "ltm/transport/segment_occlusion.h"
#include "ltm/transport/transport_prior.h"
#include "point_rooms.h"

using namespace ltm;

namespace {
using test::Points;

// Nothing blocks; every ray meets a surface (a closed scene).
struct Clear final : SegmentOcclusion {
    bool blocked(Vec3f, Vec3f) const override { return false; }
    bool meets(Vec3f, Vec3f) const override { return true; }
};

// A solid wall filling the plane x = wall_x: a segment is blocked when it crosses it; rays meet
// the scene always (closed rooms).
struct Wall final : SegmentOcclusion {
    float x;
    explicit Wall(float wall_x) : x(wall_x) {}
    bool blocked(Vec3f a, Vec3f b) const override { return (a.x - x) * (b.x - x) < 0.f; }
    bool meets(Vec3f, Vec3f) const override { return true; }
};

// The unit cube [0, 1]³ without its top face: a ray from inside meets a surface unless it leaves
// through the square y = 1.
struct OpenTopBox final : SegmentOcclusion {
    bool blocked(Vec3f, Vec3f) const override { return false; }
    bool meets(Vec3f o, Vec3f d) const override {
        if (!(d.y > 0.f)) return true;
        const float t = (1.f - o.y) / d.y;
        const float x = o.x + t * d.x, z = o.z + t * d.z;
        return !(x > 0.f && x < 1.f && z > 0.f && z < 1.f);
    }
};

// Blocked where the segment ends beyond x = edge (a screen over the far side); rays meet the scene always.
struct Screen final : SegmentOcclusion {
    float edge;
    explicit Screen(float x) : edge(x) {}
    bool blocked(Vec3f, Vec3f b) const override { return b.x > edge; }
    bool meets(Vec3f, Vec3f) const override { return true; }
};

// An occluder that counts the segments asked of it (the rays a walk traces).
template <class Occlusion> struct Counting final : SegmentOcclusion {
    Occlusion inner;
    mutable std::atomic<uint64_t> segments{0};
    explicit Counting(Occlusion o) : inner(std::move(o)) {}
    bool blocked(Vec3f a, Vec3f b) const override { return ++segments, inner.blocked(a, b); }
    bool meets(Vec3f o, Vec3f d) const override { return inner.meets(o, d); }
};

// Two 3 m rooms side by side, a solid wall between them (at x = 3.1), light in the first; g×g points a face.
Points two_closed_rooms(int g, bool second) {
    Points pts;
    for (int room = 0; room < (second ? 2 : 1); ++room)
        test::for_each_face_cell(Vec3f(3.2f * float(room), 0.f, 0.f), Vec3f(3.f), g, test::no_jitter, [&](int f, Vec3f p, Vec3f n) {
            const bool panel = room == 0 && f == 3 && std::abs(p.x - 1.5f) < 0.5f && std::abs(p.z - 1.5f) < 0.5f;
            pts.p.push_back(p), pts.n.push_back(n), pts.rho.push_back(Vec3f(0.3f + 0.1f * float(f), 0.5f, 0.6f));
            pts.le.push_back(panel ? Vec3f(6.f, 5.f, 4.f) : Vec3f(0.f));
        });
    return pts;
}

TransportPrior solve(const Points &pts, float area, std::shared_ptr<const SegmentOcclusion> occ, int closure_rays = 4) {
    PriorRays rays;
    rays.occlusion = std::move(occ), rays.closure_rays = closure_rays;
    return solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, area, 5, {}, PriorBalance::none, true, 0.5f, k_prior_row_budget, rays);
}

// Receivers on the floors, walls and ceilings of the room(s), just off the surface.
void receivers(float x0, std::vector<Vec3f> &qp, std::vector<Vec3f> &qn) {
    for (float u : {0.4f, 1.5f, 2.6f})
        for (float v : {0.5f, 2.2f}) {
            qp.push_back({x0 + u, 0.001f, v}), qn.push_back({0, 1, 0});
            qp.push_back({x0 + u, 2.999f, v}), qn.push_back({0, -1, 0});
            qp.push_back({x0 + 0.001f, v, u}), qn.push_back({1, 0, 0});
        }
}
}  // namespace

// Rays that block nothing: each term passes, so a receiver's row through the tree is the one it
// gets without rays, bit for bit (the filter only drops terms). With emitters flagged exact, their
// subtrees are opened: more exact terms, the same den up to the aggregates' error.
TEST(PriorRays, ClearRaysAreTheUnoccludedTree) {
    const Points pts = two_closed_rooms(10, true);
    PriorTree tree(pts.p, pts.n, {}, 9.f / 100.f, true, 0.5f);
    std::vector<Vec3f> qp, qn;
    receivers(0.f, qp, qn), receivers(3.2f, qp, qn);
    PriorTree::Scratch scratch;
    std::vector<PriorTree::Row> plain(qp.size());
    for (size_t i = 0; i < qp.size(); ++i) tree.record(qp[i], qn[i], {}, plain[i], scratch);
    tree.set_rays(std::make_shared<Clear>());
    ASSERT_TRUE(tree.has_rays());
    for (size_t i = 0; i < qp.size(); ++i) {
        PriorTree::Row row;
        tree.record(qp[i], qn[i], {}, row, scratch);
        EXPECT_EQ(row.den, plain[i].den) << i;
        ASSERT_EQ(row.aggregates.size(), plain[i].aggregates.size()) << i;
        ASSERT_EQ(row.exact.size(), plain[i].exact.size()) << i;
        for (size_t k = 0; k < row.exact.size(); ++k)
            EXPECT_TRUE(row.exact[k].place == plain[i].exact[k].place && row.exact[k].coef == plain[i].exact[k].coef);
        for (size_t k = 0; k < row.aggregates.size(); ++k) EXPECT_EQ(row.aggregates[k].node, plain[i].aggregates[k].node);
    }
    std::vector<uint8_t> emitter(pts.p.size());
    size_t emitters = 0;
    for (size_t j = 0; j < pts.p.size(); ++j) emitters += emitter[j] = max_component(pts.le[j]) > 0.f;
    tree.set_rays(std::make_shared<Clear>(), emitter);
    size_t more = 0;
    for (size_t i = 0; i < qp.size(); ++i) {
        PriorTree::Row row;
        tree.record(qp[i], qn[i], {}, row, scratch);
        EXPECT_GE(row.exact.size(), plain[i].exact.size());
        more += row.exact.size() - plain[i].exact.size();
        EXPECT_NEAR(row.den, plain[i].den, 0.02 * plain[i].den) << i;
    }
    EXPECT_GT(emitters, 0u);
    EXPECT_GT(more, 0u);   // some receiver aggregated the lamp without the flags
    EXPECT_THROW(tree.set_rays(std::make_shared<Clear>(), std::vector<uint8_t>(3)), Error);
}

// Half of a floor hidden from a receiver above it (a screen over x > 1): the receiver's row through
// the tree at θ 0.5, where one aggregate would stand for the whole floor, keeps what the exact row
// (θ 0) keeps — the subtrees whose rays disagree are opened, not taken whole or dropped whole.
TEST(PriorRays, PartlyVisibleSubtreesAreOpened) {
    std::vector<Vec3f> p, n;
    for (int i = 0; i < 32; ++i)
        for (int k = 0; k < 32; ++k) p.push_back({(float(i) + 0.5f) / 16.f, 0.f, (float(k) + 0.5f) / 16.f}), n.push_back({0, 1, 0});
    const float area = 4.f / 1024.f;
    PriorTree coarse(p, n, {}, area, true, 0.5f), exact(p, n, {}, area, true, 0.f);
    const auto screen = std::make_shared<Screen>(1.f);
    coarse.set_rays(screen), exact.set_rays(screen);
    PriorTree::Scratch scratch;
    PriorTree::Row half, whole, plain;
    const Vec3f q(1.f, 6.f, 1.f), down(0.f, -1.f, 0.f);
    coarse.record(q, down, {}, half, scratch);
    exact.record(q, down, {}, whole, scratch);
    PriorTree(p, n, {}, area, true, 0.5f).record(q, down, {}, plain, scratch);
    EXPECT_FALSE(plain.aggregates.empty());   // without rays the far floor is aggregated
    EXPECT_NEAR(half.den, whole.den, 0.02 * whole.den);
    EXPECT_NEAR(whole.den, 0.5 * plain.den, 0.05 * plain.den);   // half the floor is seen
}

// Bumps far below a receiver (a 16 × 16 grid of small hemispheres, 16 points each): no subtree is
// flat enough to aggregate, so the walk sums their members exactly, leaf by leaf. A far leaf whose
// representative and ends agree is taken whole: with nothing in the way, far fewer rays than exact
// terms; with half the bumps screened, the row keeps what one ray per member keeps (leaves that
// straddle the screen's edge disagree and trace their members).
TEST(PriorRays, FarLeavesAreTestedWhole) {
    std::vector<Vec3f> p, n;
    const float r = 0.05f, golden = float(k_pi) * (3.f - std::sqrt(5.f));
    for (int i = 0; i < 16; ++i)
        for (int k = 0; k < 16; ++k)
            for (int j = 0; j < 16; ++j) {   // a Fibonacci hemisphere
                const float y = 1.f - (float(j) + 0.5f) / 16.f, s = std::sqrt(1.f - y * y), phi = golden * float(j);
                const Vec3f d(s * std::cos(phi), y, s * std::sin(phi));
                p.push_back(Vec3f((float(i) + 0.5f) / 8.f, r, (float(k) + 0.5f) / 8.f) + d * r), n.push_back(d);
            }
    const float area = 2.f * float(k_pi) * r * r / 16.f;
    const Vec3f q(1.f, 6.f, 1.f), down(0.f, -1.f, 0.f);
    PriorTree::Scratch scratch;
    PriorTree tree(p, n, {}, area, true, 0.5f);
    const auto clear = std::make_shared<Counting<Screen>>(Screen(1e30f));   // nothing blocks
    tree.set_rays(clear);
    PriorTree::Row row;
    tree.record(q, down, {}, row, scratch);
    ASSERT_GT(row.exact.size(), 10 * row.aggregates.size());   // summed exactly, leaf by leaf
    EXPECT_LT(clear->segments.load(), (row.exact.size() + 3 * row.aggregates.size()) * 6 / 10);   // 3 rays a whole leaf of ≤ 8
    // Half of it screened: per-member rays (θ 0: no aggregates, no whole leaves) against whole leaves.
    PriorTree exact(p, n, {}, area, true, 0.f);
    const auto screen = std::make_shared<Counting<Screen>>(Screen(1.f)), screen_exact = std::make_shared<Counting<Screen>>(Screen(1.f));
    tree.set_rays(screen), exact.set_rays(screen_exact);
    PriorTree::Row half, ref;
    tree.record(q, down, {}, half, scratch);
    exact.record(q, down, {}, ref, scratch);
    EXPECT_NEAR(half.den, ref.den, 0.02 * ref.den);
    EXPECT_NEAR(ref.den, 0.5 * row.den, 0.05 * row.den);
    EXPECT_LT(screen->segments.load(), screen_exact->segments.load() / 2);
}

// Walks that share a Scratch share their rays (PriorTree::RayShare): a run of neighbouring groups
// on a floor traces fewer rays with one Scratch than with a fresh one a group, and gets rows
// within the rays' own error of those; a Scratch used with other rays does not reuse their answers.
TEST(PriorRays, NeighbouringGroupsShareTheirRays) {
    const Points pts = two_closed_rooms(10, true);
    PriorTree tree(pts.p, pts.n, {}, 9.f / 100.f, true, 0.5f);
    std::vector<PriorTree::Receiver> floor;   // 16 groups of 8 receivers on the floor, 1 cm apart
    for (int i = 0; i < 128; ++i) floor.push_back({Vec3f(0.2f + 0.01f * float(i), 0.001f, 1.5f), Vec3f(0, 1, 0), {}});
    const auto occ = std::make_shared<Counting<Wall>>(Wall(1.7f));
    tree.set_rays(occ);
    PriorTree::Scratch together;
    std::vector<PriorTree::Row> shared(128), alone(128);
    for (int g = 0; g < 16; ++g) tree.record_group(&floor[size_t(g) * 8], 8, &shared[size_t(g) * 8], together);
    const uint64_t traced_shared = occ->segments.load();
    for (int g = 0; g < 16; ++g) {
        PriorTree::Scratch fresh;
        tree.record_group(&floor[size_t(g) * 8], 8, &alone[size_t(g) * 8], fresh);
    }
    const uint64_t traced_alone = occ->segments.load() - traced_shared;
    EXPECT_LT(traced_shared, traced_alone * 3 / 4);   // measured: 0.65 (a 3 m room: only terms beyond ~1.6 m are shared)
    for (size_t i = 0; i < 128; ++i) EXPECT_NEAR(shared[i].den, alone[i].den, 0.02 * alone[i].den) << i;
    // The same Scratch with other rays (nothing blocks): traced afresh, so the far room is seen.
    tree.set_rays(std::make_shared<Clear>());
    PriorTree::Row open[8];
    tree.record_group(&floor[0], 8, open, together);
    for (int l = 0; l < 8; ++l) EXPECT_GT(open[l].den, 1.2 * alone[size_t(l)].den) << l;
}

// A wall between the rooms: the dark room receives nothing, while the unoccluded prior sends it the
// lit room's light; the lit room gets what it gets alone (within the tree's own error, which differs
// with the other room's nodes in the tree).
TEST(PriorRays, AWallBetweenRoomsLetsNoLightThrough) {
    const Points both = two_closed_rooms(10, true), alone = two_closed_rooms(10, false);
    const float area = 9.f / 100.f;
    const TransportPrior walled = solve(both, area, std::make_shared<Wall>(3.1f));
    const TransportPrior open = solve_transport_prior(both.p, both.n, both.rho, both.le, area, 5, {}, PriorBalance::none, true, 0.5f);
    const TransportPrior single = solve(alone, area, std::make_shared<Clear>());
    std::vector<Vec3f> dark_p, dark_n, lit_p, lit_n;
    receivers(3.2f, dark_p, dark_n), receivers(0.f, lit_p, lit_n);
    const auto dark = test::gather(walled, dark_p, dark_n), leaked = test::gather(open, dark_p, dark_n);
    double leak = 0;
    for (size_t i = 0; i < dark.size(); ++i) {
        EXPECT_EQ(dark[i], 0.f) << i;
        leak += leaked[i];
    }
    EXPECT_GT(leak, 0.0);   // the test can fail: without the wall, light reaches the second room
    const auto lit = test::gather(walled, lit_p, lit_n), ref = test::gather(single, lit_p, lit_n);
    for (size_t i = 0; i < lit.size(); ++i) EXPECT_NEAR(lit[i], ref[i], 0.03 * ref[i] + 1e-6) << i;
}

// With rays the clusters' pairwise visibility and closure are read by the directional gather alone:
// built without them (VisibilityOptions::cluster_pairs false, a frame solved for its regather alone)
// the prior's nodes and gathers are the same bit for bit, and the clusters the same partition.
TEST(PriorRays, ClusterPairsAreNotNeededByTheRaysGather) {
    const Points both = two_closed_rooms(10, true);
    PointSet sp;
    sp.columns = scene_point_columns();
    for (size_t i = 0; i < both.p.size(); ++i)
        for (const Vec3f &v : {both.p[i], both.n[i], both.rho[i], both.le[i]}) sp.values.insert(sp.values.end(), {v.x, v.y, v.z});
    auto solved = [&](bool pairs) {
        VisibilityOptions vis;
        vis.voxel_spacings = 1.f, vis.disc_spacings = 1.f, vis.clusters = 32, vis.blend = 4, vis.open_rays = 4;
        vis.rays.occlusion = std::make_shared<Wall>(3.1f), vis.rays.closure_rays = 4;
        vis.cluster_pairs = pairs;
        return solve_transport_prior(sp, 9.f / 100.f, 5, nullptr, vis, nullptr, PriorBalance::none, true, 0.5f);
    };
    const TransportPrior with = solved(true), without = solved(false);
    ASSERT_EQ(with.visibility.node_cluster, without.visibility.node_cluster);
    EXPECT_FALSE(with.visibility.closure.empty());
    EXPECT_TRUE(without.visibility.closure.empty());
    EXPECT_NE(std::count(with.visibility.visible.begin(), with.visibility.visible.end(), 0), 0) << "the wall hides clusters";
    EXPECT_EQ(std::count(without.visibility.visible.begin(), without.visibility.visible.end(), 0), 0);
    ASSERT_EQ(with.exitance.size(), without.exitance.size());
    for (size_t j = 0; j < with.exitance.size(); ++j) ASSERT_EQ(with.exitance[j], without.exitance[j]) << j;
    std::vector<Vec3f> qp, qn;
    receivers(0.f, qp, qn), receivers(3.2f, qp, qn);
    EXPECT_EQ(test::gather(with, qp, qn), test::gather(without, qp, qn));
}

// The furnace (a closed box, uniform ρ and emission) with rays: every term is clear and every ray
// meets a wall, so E⁺ = π L Σ_{k=1..5} ρ^k exactly, as without occlusion.
TEST(PriorRays, FurnaceIsExact) {
    const Points pts = test::furnace_box();
    EXPECT_LE(test::furnace_error(solve(pts, 4.f / 256.f, std::make_shared<Clear>(), 8), pts), 1e-4);
}

// The centre of the floor of a unit cube without its top: the top square, side 1 at height 1, takes
// a form factor of 4 · (1/π) · X/√(1+X²) · atan(X/√(1+X²)) with X = 1/2 (a differential area to a
// parallel rectangle, by quarters) = 0.2394, so the closure is 0.7606.
TEST(PriorRays, ClosureIsTheFormFactorsComplement) {
    const double x = 0.5, s = std::sqrt(1 + x * x);
    const double open = 4 / k_pi * x / s * std::atan(x / s);
    const float c = ray_closure(OpenTopBox(), {0.5f, 0.f, 0.5f}, {0.f, 1.f, 0.f}, 1e-4f, 64);
    EXPECT_NEAR(c, 1.0 - open, 2e-3);
    // Many receivers at once: the same answer per receiver.
    const float pos[6] = {0.5f, 0.f, 0.5f, 0.5f, 0.5f, 0.f}, nrm[6] = {0, 1, 0, 0, 0, 1};
    float out[2];
    ray_closures(OpenTopBox(), pos, nrm, 3, 2, 1e-4f, 64, out);
    EXPECT_EQ(out[0], c);
    EXPECT_GT(out[1], 0.f);
    EXPECT_LT(out[1], 1.f);   // a wall's receiver sees the open top over part of its hemisphere
}

// An occluder whose answer is a hash of the segment's bits: any change in which receiver traced a
// shared answer changes the result, so the thread count may not change who shares with whom.
struct Hashed final : SegmentOcclusion {
    bool blocked(Vec3f a, Vec3f b) const override {
        uint64_t h = 1469598103934665603ull;
        for (float v : {a.x, a.y, a.z, b.x, b.y, b.z}) {
            uint32_t bits;
            std::memcpy(&bits, &v, 4);
            h = (h ^ bits) * 1099511628211ull;
        }
        return (h >> 29) % 5 == 0;   // a fifth of the segments
    }
    bool meets(Vec3f, Vec3f) const override { return true; }
};

TEST(PriorRays, SharedAnswersAreTheSameAtAnyThreadCount) {
    const Points pts = two_closed_rooms(12, true);
    std::vector<Vec3f> qp, qn;
    for (int i = 0; i < 400; ++i) qp.push_back({0.2f + 0.007f * float(i), 0.001f, 1.5f + 0.001f * float(i % 7)}), qn.push_back({0, 1, 0});
    const auto occ = std::make_shared<Hashed>();
    const TransportPrior many_prior = solve(pts, 9.f / 144.f, occ);
    const auto many = test::gather(many_prior, qp, qn);
    const int threads = num_threads();
    set_num_threads(1);
    const TransportPrior one_prior = solve(pts, 9.f / 144.f, occ);
    const auto one = test::gather(one_prior, qp, qn);
    set_num_threads(threads);
    EXPECT_EQ(one, many);
    for (size_t j = 0; j < one_prior.exitance.size(); ++j)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(one_prior.exitance[j][c], many_prior.exitance[j][c]) << j;
}

TEST(PriorRays, SameAtAnyThreadCount) {
    const Points pts = two_closed_rooms(10, true);
    std::vector<Vec3f> qp, qn;
    receivers(0.f, qp, qn), receivers(3.2f, qp, qn);
    const auto many = test::gather(solve(pts, 0.09f, std::make_shared<Wall>(1.7f)), qp, qn);
    const int threads = num_threads();
    set_num_threads(1);
    const auto one = test::gather(solve(pts, 0.09f, std::make_shared<Wall>(1.7f)), qp, qn);
    set_num_threads(threads);
    EXPECT_EQ(one, many);
}

// The paired gather (gather_transport_prior_pair: the prior and its regather, a copy with another
// exitance) gives each the bits its own gather gives — through the tree by rays (an occluder whose
// answers are a hash of the segment: any other sharing of answers changes them), through the tree by
// clusters and through the dense rows — and walks once: with rays it traces the segments of one
// gather, not two. A copy of another prior (another tree) is refused.
TEST(PriorRays, APairedGatherIsTwoGathersInOneWalk) {
    const Points pts = two_closed_rooms(10, true);
    std::vector<Vec3f> qp, qn;
    receivers(0.f, qp, qn), receivers(3.2f, qp, qn);
    for (int i = 0; i < 40; ++i) qp.push_back({0.2f + 0.07f * float(i), 0.001f, 1.5f}), qn.push_back({0, 1, 0});
    std::vector<float> pos, nrm;
    for (size_t i = 0; i < qp.size(); ++i)
        for (int c = 0; c < 3; ++c) pos.push_back(qp[i][c]), nrm.push_back(qn[i][c]);
    const size_t n = qp.size();
    const auto counting = std::make_shared<Counting<Hashed>>(Hashed{});
    const TransportPrior by_rays = solve(pts, 0.09f, counting);
    const TransportPrior dense = solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, 0.09f, 5, {}, PriorBalance::none, true, 0.f);
    const TransportPrior tree = solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, 0.09f, 5, {}, PriorBalance::none, true, 0.5f);
    for (const TransportPrior *prior : {&by_rays, &dense, &tree}) {
        TransportPrior also = *prior;   // another exitance on the same nodes: a hash of each node's index
        for (size_t j = 0; j < also.exitance.size(); ++j)
            also.exitance[j] = Vec3f(float(j % 7), float(j % 3) + 0.5f, float((j * 5) % 11)) * 0.1f;
        if (also.tree) also.tree_sums = std::make_shared<const PriorTree::Sums>(also.tree->sums(also.exitance));
        const uint64_t before = counting->segments.load();
        std::vector<float> a(3 * n, -1.f), b(3 * n, -1.f);
        gather_transport_prior_pair(*prior, also, pos.data(), nrm.data(), 3, n, a.data(), b.data());
        const uint64_t paired = counting->segments.load() - before;
        const auto alone = test::gather(*prior, qp, qn);
        const uint64_t single = counting->segments.load() - before - paired;
        EXPECT_EQ(a, alone);
        EXPECT_EQ(b, test::gather(also, qp, qn));
        double sum = 0;
        for (float v : b) sum += v;
        EXPECT_GT(sum, 0.0);   // the second exitance is gathered, not zero
        if (prior == &by_rays) {
            EXPECT_GT(single, 0u);
            EXPECT_EQ(paired, single) << "one walk's rays for both";
        }
    }
    // The same nodes, solved again: another tree.
    const TransportPrior other = solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, 0.09f, 5, {}, PriorBalance::none, true, 0.5f);
    std::vector<float> a(3 * n), b(3 * n);
    EXPECT_THROW(gather_transport_prior_pair(tree, other, pos.data(), nrm.data(), 3, n, a.data(), b.data()), Error);
    EXPECT_THROW(gather_transport_prior_pair(tree, dense, pos.data(), nrm.data(), 3, n, a.data(), b.data()), Error);
}

// Rows beyond the solve's budget are walked again at every bounce; with rays they replay their first
// walk's decisions (PriorTree::RayLog) instead of tracing again: no rows kept, or all, give the same
// exitance to the bit, and the replay traces nothing.
TEST(PriorRays, ReplayedRowsAreTheTracedOnes) {
    const Points pts = two_closed_rooms(8, true);
    auto solve_with = [&](size_t budget, const std::shared_ptr<Counting<Wall>> &occ) {
        PriorRays rays;
        rays.occlusion = occ, rays.closure_rays = 0;
        return solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, 9.f / 64.f, 5, {}, PriorBalance::none, true, 0.5f, budget, rays);
    };
    const auto kept = std::make_shared<Counting<Wall>>(Wall(3.1f)), walked = std::make_shared<Counting<Wall>>(Wall(3.1f));
    const TransportPrior a = solve_with(k_prior_row_budget, kept), b = solve_with(0, walked);
    for (size_t j = 0; j < a.exitance.size(); ++j)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(a.exitance[j][c], b.exitance[j][c]) << j;
    EXPECT_GT(kept->segments.load(), 0u);
    EXPECT_EQ(walked->segments.load(), kept->segments.load());   // the later bounces traced nothing
    // A budget that keeps some rows: which ones depends on the threads' timing, the answer does not.
    const size_t part = a.tree ? 64 * 1024 : 0;
    const TransportPrior many = solve_with(part, std::make_shared<Counting<Wall>>(Wall(3.1f)));
    const int threads = num_threads();
    set_num_threads(1);
    const TransportPrior one = solve_with(part, std::make_shared<Counting<Wall>>(Wall(3.1f)));
    set_num_threads(threads);
    for (size_t j = 0; j < a.exitance.size(); ++j)
        for (int c = 0; c < 3; ++c) {
            ASSERT_EQ(many.exitance[j][c], a.exitance[j][c]) << j;
            ASSERT_EQ(one.exitance[j][c], a.exitance[j][c]) << j;
        }
}

// An occluder that logs the segments asked of it, in order (one thread).
template <class Occlusion> struct Logging final : SegmentOcclusion {
    Occlusion inner;
    mutable std::vector<std::pair<Vec3f, Vec3f>> asked;
    explicit Logging(Occlusion o) : inner(std::move(o)) {}
    bool blocked(Vec3f a, Vec3f b) const override { return asked.push_back({a, b}), inner.blocked(a, b); }
    bool meets(Vec3f o, Vec3f d) const override { return inner.meets(o, d); }
};

// x moved by k ulps (k in −2 … 2, from a hash of i): the rounding a sampler's barycentric sums leave
// on the same point computed in another unit.
float nudged(float x, size_t i) {
    const int k = int(test::hash01(i, 7) * 5.f) - 2;
    for (int s = 0; s < std::abs(k); ++s) x = std::nextafter(x, k > 0 ? INFINITY : -INFINITY);
    return x;
}

// The same rooms in another unit (× 10, every coordinate rounded a few ulps either way, as a sampler
// leaves it): the tree's shape is the same and a walk traces the same segments × 10 to the same
// members with the same answers. Compared as floats, the grid's equal coordinates were ordered by
// their rounding, so splits, representatives and the rays' ends changed with the unit (a generated
// house: 1.1 % of E⁺ at × 10 with rays).
TEST(PriorRays, TheSameRaysInAnotherUnit) {
    const Points pts = two_closed_rooms(10, true);
    std::vector<Vec3f> twin = pts.p;
    for (size_t j = 0; j < twin.size(); ++j)
        for (int c = 0; c < 3; ++c) twin[j][c] = nudged(10.f * twin[j][c], 3 * j + size_t(c));
    PriorTree a(pts.p, pts.n, {}, 0.09f, true, 0.5f), b(twin, pts.n, {}, 9.f, true, 0.5f);
    ASSERT_EQ(a.place_nodes(), b.place_nodes());
    const auto la = std::make_shared<Logging<Wall>>(Wall(1.7f)), lb = std::make_shared<Logging<Wall>>(Wall(17.f));
    a.set_rays(la), b.set_rays(lb);
    std::vector<Vec3f> qp, qn;
    receivers(0.f, qp, qn), receivers(3.2f, qp, qn);
    for (size_t i = 0; i < qp.size(); ++i) {
        PriorTree::Scratch sa, sb;
        PriorTree::Row ra, rb;
        la->asked.clear(), lb->asked.clear();
        a.record(qp[i], qn[i], {}, ra, sa);
        b.record(qp[i] * 10.f, qn[i], {}, rb, sb);
        ASSERT_EQ(la->asked.size(), lb->asked.size()) << i;
        for (size_t k = 0; k < la->asked.size(); ++k) {
            EXPECT_LT(length(lb->asked[k].first / 10.f - la->asked[k].first), 1e-5f) << i << " " << k;
            EXPECT_LT(length(lb->asked[k].second / 10.f - la->asked[k].second), 1e-5f) << i << " " << k;
        }
        ASSERT_EQ(ra.exact.size(), rb.exact.size()) << i;
        for (size_t k = 0; k < ra.exact.size(); ++k) EXPECT_EQ(ra.exact[k].place, rb.exact[k].place) << i;
        ASSERT_EQ(ra.aggregates.size(), rb.aggregates.size()) << i;
        for (size_t k = 0; k < ra.aggregates.size(); ++k) EXPECT_EQ(ra.aggregates[k].node, rb.aggregates[k].node) << i;
        EXPECT_NEAR(100.0 * rb.den, ra.den, 1e-4 * ra.den) << i;   // den: per area
    }
}

TEST(PriorRays, BadInputIsAnError) {
    const Points pts = two_closed_rooms(4, false);
    PriorRays rays;
    rays.occlusion = std::make_shared<Clear>();
    // Rays test the tree's terms: the dense rows (θ = 0) have none.
    EXPECT_THROW(solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, 0.5f, 5, {}, PriorBalance::none, true, 0.f, k_prior_row_budget, rays),
                 Error);
    rays.closure_rays = 65;
    EXPECT_THROW(solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, 0.5f, 5, {}, PriorBalance::none, true, 0.5f, k_prior_row_budget, rays),
                 Error);
    EXPECT_THROW(ray_closure(OpenTopBox(), {0.5f, 0.f, 0.5f}, {0, 1, 0}, 1e-4f, 0), Error);
    EXPECT_THROW(FramedOcclusion(nullptr, Vec3f(0.f), 1.f), Error);
    EXPECT_THROW(FramedOcclusion(std::make_shared<Clear>(), Vec3f(0.f), 0.f), Error);
}

// The frame adapter: a point x of the prior's frame is centre + ℓ·x in the scene's.
TEST(PriorRays, FramedOcclusionMapsToTheScene) {
    const FramedOcclusion framed(std::make_shared<Wall>(5.f), Vec3f(1.f, 0.f, 0.f), 2.f);   // the wall at x = 2 in the frame
    EXPECT_TRUE(framed.blocked({1.9f, 0, 0}, {2.1f, 0, 0}));
    EXPECT_FALSE(framed.blocked({2.1f, 0, 0}, {3.f, 0, 0}));
}
