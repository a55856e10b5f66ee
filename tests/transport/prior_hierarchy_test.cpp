// prior_hierarchy_test.cpp: the transport prior through its cluster tree against the dense rows —
// identical up to rounding at θ = 0 (solve and gather), close at θ = 0.5 with a fraction of the
// work, the furnace exact at any θ; deterministic at any thread count; bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <tuple>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
#include "ltm/transport/point_visibility.h"
#include "ltm/transport/prior_hierarchy.h"
#include "ltm/transport/transport_prior.h"
#include "point_rooms.h"

using namespace ltm;

namespace {
using test::Points;

// Two rooms side by side, [0, 3]³ and [3.2, 6.2] × [0, 3]², with a door through the wall between
// them; g×g jittered points per face; coloured walls; a ceiling panel in the first room emits.
Points two_rooms(int g) {
    Points pts;
    const Vec3f origin(0.0137f, 0.0071f, 0.0029f);
    for (int room = 0; room < 2; ++room) {
        const Vec3f lo = origin + Vec3f(3.2f * float(room), 0.f, 0.f);
        test::for_each_face_cell(lo, Vec3f(3.f), g, test::jitter_by_count(pts, 0.3f), [&](int f, Vec3f p, Vec3f n) {
            const bool in_wall = p.x > 2.9f && p.x < 3.3f;
            if (in_wall && p.y < 2.f && std::abs(p.z - 1.5f) < 0.5f) return;   // the door
            const bool panel = room == 0 && f == 3 && std::abs(p.x - 1.5f) < 0.5f && std::abs(p.z - 1.5f) < 0.5f;
            pts.p.push_back(p), pts.n.push_back(n);
            pts.rho.push_back(Vec3f(0.3f + 0.1f * float(f), 0.5f, 0.7f - 0.08f * float(f)));
            pts.le.push_back(panel ? Vec3f(6.f, 5.f, 4.f) : Vec3f(0.f));
        });
    }
    return pts;
}

TransportPrior solve(const Points &pts, float area, float theta, bool visibility, bool patches, int blend = 1) {
    ClusterVisibility v;
    if (visibility) {
        v = cluster_visibility(pts.p, pts.n, VoxelOccupancy(pts.p, pts.n, 2.f * std::sqrt(area)), 128);
        v.blend = blend;
    }
    return solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, area, 5, std::move(v), PriorBalance::per_channel, patches, theta);
}

// Receivers: points of the rooms' surfaces, off the nodes, and a few inside the air facing up.
void receivers(const Points &pts, std::vector<Vec3f> &qp, std::vector<Vec3f> &qn) {
    for (size_t i = 0; i < pts.p.size(); i += 7) qp.push_back(pts.p[i] + pts.n[i] * 0.01f), qn.push_back(pts.n[i]);
    qp.push_back({1.5f, 1.f, 1.5f}), qn.push_back({0.f, 1.f, 0.f});
    qp.push_back({4.7f, 1.f, 1.5f}), qn.push_back({0.f, 1.f, 0.f});
}

// √(mean (a − b)²) / √(mean b²) over every channel.
double relative_rms(const std::vector<float> &a, const std::vector<float> &b) {
    double num = 0, den = 0;
    for (size_t i = 0; i < a.size(); ++i) num += double(a[i] - b[i]) * double(a[i] - b[i]), den += double(b[i]) * double(b[i]);
    return std::sqrt(num / den);
}

std::vector<float> flat(const std::vector<Vec3f> &v) {
    std::vector<float> out;
    for (const Vec3f &x : v) out.insert(out.end(), {x.x, x.y, x.z});
    return out;
}
}  // namespace

// θ = 0 never aggregates: the tree visits every node the dense row sums, with the same terms (the
// point formula, the patches, the clusters' weights), so the solve and the gather agree to rounding.
TEST(PriorHierarchy, ThetaZeroIsTheDenseRows) {
    const Points pts = two_rooms(10);
    const float area = 9.f / 100.f;
    std::vector<Vec3f> qp, qn;
    receivers(pts, qp, qn);
    for (const auto &[vis, patches, blend] : {std::tuple{false, false, 1}, std::tuple{true, false, 1}, std::tuple{true, true, 1},
                                              std::tuple{true, true, 4}}) {
        const TransportPrior dense = solve(pts, area, 0.f, vis, patches, blend);
        const TransportPrior tree = solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, area, 5, dense.visibility,
                                                          PriorBalance::per_channel, patches, 1e-30f);
        ASSERT_TRUE(tree.tree);
        EXPECT_LT(relative_rms(flat(tree.exitance), flat(dense.exitance)), 1e-5) << vis << patches << blend;
        EXPECT_LT(relative_rms(test::gather(tree, qp, qn), test::gather(dense, qp, qn)), 1e-5) << vis << patches << blend;
    }
}

// At θ = 0.5 the far light comes from aggregates: the solve and the gather stay within a few
// per cent of the dense rows, and a receiver's row visits a fraction of the nodes.
TEST(PriorHierarchy, ApproximatesTheDenseRowsWithLessWork) {
    const Points pts = two_rooms(24);   // 6 670 nodes
    const float area = 9.f / 576.f;
    std::vector<Vec3f> qp, qn;
    receivers(pts, qp, qn);
    const TransportPrior dense = solve(pts, area, 0.f, true, true, 4);
    const TransportPrior tree = solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, area, 5, dense.visibility,
                                                      PriorBalance::per_channel, true, 0.5f);
    const double ex = relative_rms(flat(tree.exitance), flat(dense.exitance));
    const double e = relative_rms(test::gather(tree, qp, qn), test::gather(dense, qp, qn));
    EXPECT_LT(ex, 0.025);   // measured 0.014 (0.026 without the second-order terms)
    EXPECT_LT(e, 0.01);     // measured 0.0033
    // Work at a receiver in the middle of the lit room's floor: aggregates and exactly summed nodes.
    PriorTree::Scratch scratch;
    uint32_t ids[ClusterVisibility::k_candidates];
    float w[ClusterVisibility::k_candidates];
    const Vec3f p(1.5f, 0.0171f, 1.2f), n(0.f, 1.f, 0.f);
    const int K = dense.visibility.receiver_clusters(p, n, ids, w);
    const PriorTree::Work work = tree.tree->count(p, n, {ids, w, K}, scratch);
    EXPECT_GT(work.aggregates, 0u);
    EXPECT_LT(double(work.aggregates + work.exact), 0.1 * double(pts.p.size())) << work.aggregates << " + " << work.exact;   // measured 4.4 %
}

// The gather's far part (gather_transport_prior's `far`): asking for it leaves E⁺ the same bits; it
// is 0 where nothing is aggregated (θ = 1e-30: only a subtree of radius 0 could be, and this
// fixture's leaves all hold points apart), and at θ = 0.5 it is the light of the far subtrees: a
// share of E⁺, larger where the receiver is far from its room's walls, never more than E⁺ itself
// (and written for every receiver: the −1 it starts at never stays).
TEST(PriorHierarchy, FarPartIsTheAggregatesShare) {
    const Points pts = two_rooms(24);
    const float area = 9.f / 576.f;
    std::vector<Vec3f> qp, qn;
    receivers(pts, qp, qn);
    const size_t n = qp.size();
    const TransportPrior dense = solve(pts, area, 0.f, true, true, 4);
    for (const float theta : {1e-30f, 0.5f}) {
        const TransportPrior tree = solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, area, 5, dense.visibility,
                                                          PriorBalance::per_channel, true, theta);
        std::vector<float> far(3 * n, -1.f);
        const std::vector<float> e = test::gather(tree, qp, qn), e2 = test::gather(tree, qp, qn, &far);
        EXPECT_EQ(std::memcmp(e.data(), e2.data(), e.size() * sizeof(float)), 0) << theta;
        double share = 0;   // the far part's mean share of E⁺
        for (size_t i = 0; i < 3 * n; ++i) {
            if (theta < 1e-20f) ASSERT_EQ(far[i], 0.f) << i;
            EXPECT_LE(far[i], e[i] * (1 + 1e-5f) + 1e-9f) << i;
            EXPECT_GT(far[i], -0.01f * e[i] - 1e-9f) << i;
            share += far[i] / std::max(1e-12, double(e[i])) / double(3 * n);
        }
        if (theta > 0.1f) {
            EXPECT_GT(share, 0.05) << "the far subtrees carry part of the light";
            EXPECT_LT(share, 0.95);
            // Mid-air in the lit room (the second-to-last receiver) sees every wall from ≥ 1 m: more
            // of its light comes from aggregates than on average.
            const size_t mid = n - 2;
            EXPECT_GT(far[3 * mid + 1] / e[3 * mid + 1], share);
        }
    }
    std::vector<float> far;
    EXPECT_THROW(test::gather(dense, qp, qn, &far), Error);
}

// Receivers that walk the tree together (record_group, gather_group) get the rows each gets alone,
// bit for bit (memcmp of every value): neighbours on one wall, receivers far apart and facing every
// way, views that repeat, the solve's own-cluster views over consecutive places (lanes with equal
// views at different points: one lane's weights serve another that a subtree keeps descending),
// without occlusion (K = 0), partial groups and an empty one. The gather's one-pass sum equals
// record + apply. (record() is the walk of one; what this holds is that lanes never mix.)
TEST(PriorHierarchy, AGroupWalksAsEachReceiverAlone) {
    const Points pts = two_rooms(16);
    const float area = 9.f / 256.f;
    auto bits_equal = [](const auto &a, const auto &b) { return std::memcmp(&a, &b, sizeof(a)) == 0; };
    auto same_row = [&](const PriorTree::Row &a, const PriorTree::Row &b) {
        if (!bits_equal(a.den, b.den) || a.aggregates.size() != b.aggregates.size() || a.exact.size() != b.exact.size()) return false;
        for (size_t i = 0; i < a.aggregates.size(); ++i) {
            const auto &x = a.aggregates[i], &y = b.aggregates[i];
            if (x.node != y.node || !bits_equal(x.along, y.along) || !bits_equal(x.grad, y.grad)) return false;
        }
        for (size_t i = 0; i < a.exact.size(); ++i)
            if (a.exact[i].place != b.exact[i].place || !bits_equal(a.exact[i].coef, b.exact[i].coef)) return false;
        return true;
    };
    // Receivers with their own views' storage; walks them in groups of k_group as listed.
    struct Receivers {
        std::vector<PriorTree::Receiver> rc;
        std::vector<std::array<uint32_t, ClusterVisibility::k_candidates>> ids;
        std::vector<std::array<float, ClusterVisibility::k_candidates>> w;
    };
    size_t rows = 0, aggregates = 0, copies = 0;
    auto check = [&](const PriorTree &tree, const PriorTree::Sums &sums, Receivers r, const char *what) {
        for (size_t i = 0; i < r.rc.size(); ++i) r.rc[i].view.ids = r.ids[i].data(), r.rc[i].view.w = r.w[i].data();
        PriorTree::Scratch scratch, alone;
        PriorTree::Row one;
        for (size_t first = 0; first < r.rc.size(); first += PriorTree::k_group) {
            const int count = int(std::min<size_t>(PriorTree::k_group, r.rc.size() - first));
            const PriorTree::Receiver *rc = &r.rc[first];
            tree.record_group(rc, count, scratch.rows, scratch);
            double den[PriorTree::k_group], num[PriorTree::k_group][3];
            tree.gather_group(rc, count, sums, den, num, scratch);
            for (int l = 0; l < count; ++l) {
                tree.record(rc[l].p, rc[l].n, rc[l].view, one, alone);
                EXPECT_TRUE(same_row(scratch.rows[l], one)) << what << ": receiver " << first + size_t(l) << " lane " << l;
                double applied[3];
                tree.apply(one, sums, applied);
                EXPECT_TRUE(bits_equal(den[l], one.den)) << what;
                for (int c = 0; c < 3; ++c) EXPECT_TRUE(bits_equal(num[l][c], applied[c])) << what << " channel " << c;
                ++rows, aggregates += one.aggregates.size();
                for (int j = 0; j < l; ++j)
                    copies += rc[j].view.K == rc[l].view.K && rc[l].view.K > 0 && r.ids[first + size_t(j)] == r.ids[first + size_t(l)] &&
                              r.w[first + size_t(j)] == r.w[first + size_t(l)] && !(rc[j].p == rc[l].p);
            }
        }
    };
    std::vector<Vec3f> qp, qn;
    receivers(pts, qp, qn);
    for (const bool occlusion : {true, false}) {
        const TransportPrior t = solve(pts, area, 0.5f, occlusion, true, 4);
        ASSERT_TRUE(t.tree);
        const PriorTree &tree = *t.tree;
        const ClusterVisibility &vis = t.visibility;
        const PriorTree::Sums sums = tree.sums(t.exitance);
        // As listed (neighbours), shuffled (far apart), one receiver repeated around another.
        std::vector<size_t> order(qp.size()), shuffled(qp.size()), repeated(11, qp.size() / 3);
        for (size_t i = 0; i < order.size(); ++i) order[i] = shuffled[i] = i;
        for (size_t i = 0; i < shuffled.size(); ++i) std::swap(shuffled[i], shuffled[(i * 7919 + 13) % shuffled.size()]);
        repeated[4] = 0;
        for (const std::vector<size_t> *list : {&order, &shuffled, &repeated}) {
            Receivers r;
            for (size_t q : *list) {
                r.ids.emplace_back(), r.w.emplace_back();
                const int K = occlusion ? vis.receiver_clusters(qp[q], qn[q], r.ids.back().data(), r.w.back().data()) : 0;
                r.rc.push_back({qp[q], qn[q], {nullptr, nullptr, K}});
            }
            check(tree, sums, r, occlusion ? "blended views" : "no occlusion");
        }
        if (!occlusion) continue;
        // The solve's receivers: the nodes in place order, each seeing from its own cluster (K 1).
        Receivers r;
        for (uint32_t j : tree.place_nodes()) {
            r.ids.push_back({vis.node_cluster[j]}), r.w.push_back({1.f});
            r.rc.push_back({pts.p[j], pts.n[j], {nullptr, nullptr, 1}});
        }
        check(tree, sums, r, "own clusters");
        PriorTree::Scratch scratch;
        tree.record_group(r.rc.data(), 0, scratch.rows, scratch);   // an empty group: nothing to do
        EXPECT_THROW(tree.record_group(r.rc.data(), PriorTree::k_group + 1, scratch.rows, scratch), Error);
    }
    EXPECT_GT(aggregates, rows);   // the rows do use aggregates (θ 0.5), not only exact nodes
    EXPECT_GT(copies, rows / 4);   // and lanes with equal views at different points were common
    // The gather's order is a permutation that puts receivers facing one way together.
    std::vector<float> pos, nrm;
    for (size_t i = 0; i < qp.size(); ++i) pos.insert(pos.end(), {qp[i].x, qp[i].y, qp[i].z}), nrm.insert(nrm.end(), {qn[i].x, qn[i].y, qn[i].z});
    const std::vector<uint32_t> go = PriorTree::group_order(pos.data(), nrm.data(), 3, qp.size());
    std::vector<uint32_t> sorted = go;
    std::sort(sorted.begin(), sorted.end());
    for (size_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], uint32_t(i));
    size_t changes = 0;
    for (size_t i = 1; i < go.size(); ++i) changes += !(qn[go[i]] == qn[go[i - 1]]);
    EXPECT_EQ(changes, 5u);   // six facings: one run each
}

// A closed box of uniform albedo and emission: every value is the same, so a row's aggregates give
// num/den = that value whatever they approximate — exact at any θ, as the dense rows.
TEST(PriorHierarchy, FurnaceIsExactAtAnyTheta) {
    const Points pts = test::furnace_box();
    const TransportPrior t = solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, 4.f / 256.f, 5, {}, PriorBalance::per_channel, true, 0.8f);
    EXPECT_LE(test::furnace_error(t, pts), 1e-4);
}

TEST(PriorHierarchy, SameAtAnyThreadCount) {
    const Points pts = two_rooms(12);
    std::vector<Vec3f> qp, qn;
    receivers(pts, qp, qn);
    const auto many = test::gather(solve(pts, 9.f / 144.f, 0.5f, true, true, 4), qp, qn);
    const int threads = num_threads();
    set_num_threads(1);
    const auto one = test::gather(solve(pts, 9.f / 144.f, 0.5f, true, true, 4), qp, qn);
    set_num_threads(threads);
    EXPECT_EQ(one, many);
}

// The tree solve records each node's row for the later bounces while the rows fit its budget and
// walks the tree again beyond it (k_prior_row_budget): no rows kept, some, or all give the same
// exitance to the bit, and so the same gather.
TEST(PriorHierarchy, RowBudgetBoundsMemoryNotTheAnswer) {
    const Points pts = two_rooms(12);
    const float area = 9.f / 144.f;
    std::vector<Vec3f> qp, qn;
    receivers(pts, qp, qn);
    const TransportPrior dense = solve(pts, area, 0.f, true, true, 4);
    auto tree = [&](size_t budget) {
        return solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, area, 5, dense.visibility, PriorBalance::per_channel, true,
                                     0.5f, budget);
    };
    const TransportPrior all = tree(k_prior_row_budget), none = tree(0), some = tree(size_t(64) << 10);
    EXPECT_EQ(flat(none.exitance), flat(all.exitance));
    EXPECT_EQ(flat(some.exitance), flat(all.exitance));
    EXPECT_EQ(test::gather(none, qp, qn), test::gather(all, qp, qn));
    // And it is still the prior: within the θ 0.5 bound of the dense rows.
    EXPECT_LT(relative_rms(flat(none.exitance), flat(dense.exitance)), 0.025);
}

TEST(PriorHierarchy, BadInputIsAnError) {
    const Points pts = two_rooms(4);
    EXPECT_THROW(solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, 0.1f, 5, {}, PriorBalance::per_channel, false, -0.1f), Error);
    EXPECT_THROW(solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, 0.1f, 5, {}, PriorBalance::per_channel, false, 1.5f), Error);
    EXPECT_THROW(solve_transport_prior(pts.p, pts.n, pts.rho, pts.le, 0.1f, 5, {}, PriorBalance::per_channel, false, NAN), Error);
    EXPECT_THROW(PriorTree(pts.p, {}, {}, 0.1f, false, 0.5f), Error);
}
