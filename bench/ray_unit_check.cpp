// ray_unit_check.cpp: where the ray prior's unit error comes from (issue #31; `--prior-rays` moves
// E⁺ by up to 1.25 % under a change of unit, the points' visibility by < 0.1 %). Per scene: the scene
// and its twin with every length × f, each with its own Embree BVH and its own scene points (same
// seed); the prior (θ 0.5, patches, D 5, the shipped settings) solved with visibility by rays in
// both, and the relative L1 difference mean|Ê_f − Ê| / mean Ê at the first eval view's G-buffer and
// at the nodes — with every ray (full), with the terms' rays only (every closure ray meets a surface)
// and with the closures' rays only (every term's segment clear). Also how far the twin's points are
// from f × the scene's (largest distance over f, in spacings).
//   build/bench/ray_unit_check SCENES [M=16384] [f=10] [size=64]
// Modes: RAY_UNIT_TRACE=N (per receiver, where the two walks first part: the rows' first differing
// term and the first ray answered differently); RAY_UNIT_POINTS=1 (the points' visibility, no rays:
// how many nodes join another cluster, how many tree places move, and its relative L1;
// RAY_UNIT_POINTS_DEBUG=1 lists each moved node's distances to both clusters' centres).
// Session 30: 900100 at × 10, rays 1.08 % → 0.01 %, points 0.03 % → 0 (same clusters, same tree).
// SCENES: scene files, builtin:NAME or generated seeds as seed:N, comma-separated.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "ltm/core/log.h"
#include "ltm/core/startup.h"
#include "ltm/eval/eval_setup.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/mesh_occlusion.h"
#include "ltm/render/scene_points.h"
#include "ltm/scene/scene_loader.h"
#include "ltm/scene/scene_transform.h"
#include "ltm/transport/prior_hierarchy.h"
#include "ltm/transport/transport_prior.h"
#include "scene_list.h"

using namespace ltm;

namespace {
double relative_l1(const std::vector<Vec3f> &a, const std::vector<Vec3f> &b) {
    double num = 0, den = 0;
    for (size_t q = 0; q < a.size(); ++q)
        for (int c = 0; c < 3; ++c) num += std::abs(double(a[q][c]) - double(b[q][c])), den += std::abs(double(b[q][c]));
    return num / std::max(den, 1e-30);
}

// The meshes' rays with one kind switched off.
struct Partial final : SegmentOcclusion {
    std::shared_ptr<const SegmentOcclusion> inner;
    bool terms, closures;
    bool blocked(Vec3f a, Vec3f b) const override { return terms && inner->blocked(a, b); }
    bool meets(Vec3f o, Vec3f d) const override { return !closures || inner->meets(o, d); }
};

// Every segment asked, in order, with its answer (one thread: the trace mode).
struct Logging final : SegmentOcclusion {
    std::shared_ptr<const SegmentOcclusion> inner;
    mutable std::vector<std::pair<Vec3f, Vec3f>> asked;
    mutable std::vector<uint8_t> answers;
    bool blocked(Vec3f a, Vec3f b) const override {
        const bool r = inner->blocked(a, b);
        asked.push_back({a, b}), answers.push_back(r);
        return r;
    }
    bool meets(Vec3f o, Vec3f d) const override { return inner->meets(o, d); }
};

// RAY_UNIT_TRACE=N: for N receivers (every M/N-th node), the first ray whose answer differs between
// the units, with what it hits.
void trace(const EmbreeAccel &a, const EmbreeAccel &b, const ScenePoints &sa, const ScenePoints &sb, float f, int n) {
    auto tree_of = [](const ScenePoints &sp, float area) {
        std::vector<Vec3f> p, nn;
        for (size_t j = 0; j < sp.points.size(); ++j) p.push_back(sp.points.vec3(j, 0)), nn.push_back(sp.points.vec3(j, 3));
        return std::make_pair(PriorTree(p, nn, {}, area, true, 0.5f), std::make_pair(p, nn));
    };
    const float sp2 = float(a.scene().total_area() / double(sa.points.size()));
    auto [ta, pa] = tree_of(sa, sp2);
    auto [tb, pb] = tree_of(sb, sp2 * f * f);
    size_t moved_places = 0;   // the trees' shapes: which node sits at each place
    for (size_t k = 0; k < ta.nodes(); ++k) moved_places += ta.place_nodes()[k] != tb.place_nodes()[k];
    std::printf("the trees differ at %zu of %zu places\n", moved_places, ta.nodes());
    auto la = std::make_shared<Logging>(), lb = std::make_shared<Logging>();
    la->inner = std::make_shared<MeshOcclusion>(a), lb->inner = std::make_shared<MeshOcclusion>(b);
    ta.set_rays(la), tb.set_rays(lb);
    const size_t m = pa.first.size(), step = std::max<size_t>(1, m / size_t(n));
    int differing = 0;
    for (size_t j = 0; j < m; j += step) {
        la->asked.clear(), la->answers.clear(), lb->asked.clear(), lb->answers.clear();
        PriorTree::Scratch s1, s2;
        PriorTree::Row r1, r2;
        ta.record(pa.first[j], pa.second[j], {}, r1, s1);
        tb.record(pb.first[j], pb.second[j], {}, r2, s2);
        {   // the first term the two rows disagree on
            size_t e = 0, g = 0;
            while (e < std::min(r1.exact.size(), r2.exact.size()) && r1.exact[e].place == r2.exact[e].place) ++e;
            while (g < std::min(r1.aggregates.size(), r2.aggregates.size()) && r1.aggregates[g].node == r2.aggregates[g].node) ++g;
            if (e < r1.exact.size() || e < r2.exact.size() || g < r1.aggregates.size() || g < r2.aggregates.size())
                std::printf("receiver %zu at (%.5f %.5f %.5f): exact %zu/%zu agree to %zu (place %u vs %u), aggregates %zu/%zu agree to %zu (node %u vs %u)\n", j,
                            pa.first[j].x, pa.first[j].y, pa.first[j].z, r1.exact.size(), r2.exact.size(), e,
                            e < r1.exact.size() ? r1.exact[e].place : 0u, e < r2.exact.size() ? r2.exact[e].place : 0u, r1.aggregates.size(),
                            r2.aggregates.size(), g, g < r1.aggregates.size() ? r1.aggregates[g].node : 0u, g < r2.aggregates.size() ? r2.aggregates[g].node : 0u);
            if (e < r1.exact.size() && e < r2.exact.size()) {
                const Vec3f x1 = pa.first[ta.place_nodes()[r1.exact[e].place]], x2 = pa.first[ta.place_nodes()[r2.exact[e].place]];
                std::printf("   places at (%.5f %.5f %.5f) and (%.5f %.5f %.5f)\n", x1.x, x1.y, x1.z, x2.x, x2.y, x2.z);
            }
        }
        const size_t k_max = std::min(la->answers.size(), lb->answers.size());
        size_t k = 0;
        while (k < k_max && la->answers[k] == lb->answers[k]) ++k;
        if (k == k_max && la->answers.size() == lb->answers.size()) continue;
        ++differing;
        if (k == k_max) {
            std::printf("receiver %zu: %zu rays against %zu, the same answers as far as both go\n", j, la->answers.size(), lb->answers.size());
            continue;
        }
        const auto [a0, a1] = la->asked[k];
        const auto [b0, b1] = lb->asked[k];
        std::printf("  unit f's ray %zu / f: (%.5f %.5f %.5f) -> (%.5f %.5f %.5f)\n", k, b0.x / f, b0.y / f, b0.z / f, b1.x / f, b1.y / f, b1.z / f);
        const auto hit_a = a.intersect(Ray{a0, a1 - a0, 1e-4f, 1.f - 1e-4f}), hit_b = b.intersect(Ray{b0, b1 - b0, 1e-4f, 1.f - 1e-4f});
        const auto hit = hit_a ? hit_a : hit_b;
        const bool in_a = bool(hit_a);
        std::printf("receiver %zu (n %.2f %.2f %.2f): ray %zu of %zu: (%.5f %.5f %.5f) -> (%.5f %.5f %.5f), length %.4f, unit 1 %s, unit f %s; "
                    "hit t %.6f mesh %u '%s' triangle %u, its normal %.2f %.2f %.2f, b %.4f %.4f\n",
                    j, pa.second[j].x, pa.second[j].y, pa.second[j].z, k, la->answers.size(), a0.x, a0.y, a0.z, a1.x, a1.y, a1.z, length(a1 - a0),
                    la->answers[k] ? "blocked" : "clear", lb->answers[k] ? "blocked" : "clear", hit ? hit->t : -1.f, hit ? hit->mesh : 0u,
                    hit ? (in_a ? a : b).scene().meshes[hit->mesh].name.c_str() : "", hit ? hit->triangle : 0u, hit ? hit->n.x : 0.f,
                    hit ? hit->n.y : 0.f, hit ? hit->n.z : 0.f, hit ? hit->b1 : 0.f, hit ? hit->b2 : 0.f);
    }
    std::printf("%d of %d receivers trace a ray whose answer differs\n", differing, int((m + step - 1) / step));
}

struct Solved {
    std::vector<Vec3f> view, nodes;
};

// rays false: the points' visibility (the default prior), with its clusters.
TransportPrior solve_prior(const EmbreeAccel &accel, const ScenePoints &sp, bool rays, bool terms, bool closures) {
    const float spacing = float(std::sqrt(accel.scene().total_area() / double(sp.points.size())));
    VisibilityOptions vis;
    vis.voxel_spacings = 1.f, vis.clusters = 1024, vis.disc_spacings = 1.f, vis.blend = 4, vis.open_rays = 8;
    if (rays) {
        auto occ = std::make_shared<Partial>();
        occ->inner = std::make_shared<MeshOcclusion>(accel), occ->terms = terms, occ->closures = closures;
        vis.rays.occlusion = occ, vis.rays.closure_rays = 8;
    }
    return solve_transport_prior(sp.points, spacing * spacing, 5, &sp.emission_scale, vis, nullptr, PriorBalance::none, true, 0.5f);
}

Solved solve(const EmbreeAccel &accel, const ScenePoints &sp, const GBuffer &gb, bool terms, bool closures, bool rays = true) {
    const TransportPrior prior = solve_prior(accel, sp, rays, terms, closures);
    Solved s;
    s.view.resize(gb.n_hits());
    gather_transport_prior(prior, &gb.position[0].x, &gb.normal[0].x, 3, gb.n_hits(), &s.view[0].x);
    s.nodes = prior.exitance;
    return s;
}
}  // namespace

int main(int argc, char **argv) {
    configure_process();
    if (argc < 2) {
        std::fprintf(stderr, "usage: ray_unit_check SCENES [M=16384] [f=10] [size=64]\n");
        return 1;
    }
    set_log_level(LogLevel::quiet);
    const std::vector<std::string> scenes = bench::split_commas(argv[1]);
    const int64_t M = argc > 2 ? std::atoll(argv[2]) : 16384;
    const float f = argc > 3 ? std::stof(argv[3]) : 10.f;
    const int size = argc > 4 ? std::atoi(argv[4]) : 64;
    std::printf("| scene | points moved (largest, spacings) | full: view / nodes | terms' rays only | closures' rays only |\n|---|---|---|---|---|\n");
    try {
        for (const std::string &name : scenes) {
            const bool seed = name.rfind("seed:", 0) == 0;
            const Scene scene = seed ? generate_indoor(GenConfig{}, std::stoull(name.substr(5))).scene : load_scene(name);
            Scene twin = scene;
            scale_lengths(twin, f);
            const EmbreeAccel a(scene), b(twin);
            const GBuffer ga = render_gbuffer(a, eval_view_camera(scene, 0, 1, size, size));
            GBuffer gb = ga;   // the same surface points in the new unit
            for (Vec3f &p : gb.position) p = p * f;
            const ScenePoints sa = sample_scene_points(a, M, 0, true), sb = sample_scene_points(b, M, 0, true);
            const float spacing = float(std::sqrt(scene.total_area() / double(sa.points.size())));
            double moved = sa.points.size() == sb.points.size() ? 0.0 : INFINITY;
            for (size_t j = 0; j < sa.points.size() && std::isfinite(moved); ++j) {
                const Vec3f pa = sa.points.vec3(j, 0), pb = sb.points.vec3(j, 0);
                moved = std::max(moved, double(length(pb / f - pa)) / double(spacing));
            }
            if (std::getenv("RAY_UNIT_POINTS")) {   // the points' visibility: its clusters and tree in both units
                const TransportPrior x = solve_prior(a, sa, false, true, true), y = solve_prior(b, sb, false, true, true);
                size_t cl = 0, places = 0;
                for (size_t j = 0; j < x.visibility.node_cluster.size(); ++j) cl += x.visibility.node_cluster[j] != y.visibility.node_cluster[j];
                for (size_t k = 0; k < x.tree->nodes(); ++k) places += x.tree->place_nodes()[k] != y.tree->place_nodes()[k];
                if (std::getenv("RAY_UNIT_POINTS_DEBUG"))
                    for (size_t k = 0; k < x.tree->nodes(); ++k)
                        if (x.tree->place_nodes()[k] != y.tree->place_nodes()[k]) {
                            const uint32_t ja = x.tree->place_nodes()[k], jb = y.tree->place_nodes()[k];
                            const uint32_t ca = x.visibility.node_cluster[ja], cb = x.visibility.node_cluster[jb];
                            Vec3f na(0.f), nb(0.f);
                            for (size_t j = 0; j < x.position.size(); ++j) {
                                if (x.visibility.node_cluster[j] == ca) na += x.normal[j];
                                if (x.visibility.node_cluster[j] == cb) nb += x.normal[j];
                            }
                            std::printf("first moved place %zu: node %u (cluster %u, normal sum %.4f %.4f %.4f) vs node %u (cluster %u, normal sum %.4f %.4f %.4f)\n", k, ja,
                                        ca, na.x, na.y, na.z, jb, cb, nb.x, nb.y, nb.z);
                            // Both clusters' centroids on the tree's key grid, in both units.
                            for (const TransportPrior *t : {&x, &y}) {
                                const KeyGrid &grid = t->tree->key_grid();
                                for (uint32_t c : {ca, cb}) {
                                    Vec3f cp(0.f);
                                    size_t count = 0;
                                    for (size_t j = 0; j < t->position.size(); ++j) count += x.visibility.node_cluster[j] == c;
                                    for (size_t j = 0; j < t->position.size(); ++j)
                                        if (x.visibility.node_cluster[j] == c) cp += t->position[j] / float(count);
                                    std::printf("  %s cluster %u: centroid / unit %.7f %.7f %.7f, keys %lld %lld %lld, fractions %.5f %.5f %.5f\n", t == &x ? "unit 1" : "unit f", c,
                                                cp.x / (t == &x ? 1.f : f), cp.y / (t == &x ? 1.f : f), cp.z / (t == &x ? 1.f : f), (long long)grid.key(cp.x, 0),
                                                (long long)grid.key(cp.y, 1), (long long)grid.key(cp.z, 2),
                                                (double(cp.x) - grid.origin.x) / grid.step - double(grid.key(cp.x, 0)),
                                                (double(cp.y) - grid.origin.y) / grid.step - double(grid.key(cp.y, 1)),
                                                (double(cp.z) - grid.origin.z) / grid.step - double(grid.key(cp.z, 2)));
                                }
                            }
                            break;
                        }
                if (std::getenv("RAY_UNIT_POINTS_DEBUG"))
                    for (size_t j = 0; j < x.visibility.node_cluster.size(); ++j) {
                        const uint32_t cx = x.visibility.node_cluster[j], cy = y.visibility.node_cluster[j];
                        if (cx == cy) continue;
                        const ClusterVisibility &vx = x.visibility, &vy = y.visibility;
                        const Vec3f p = x.position[j], q = y.position[j];
                        std::printf("node %zu: cluster %u / %u; d(cx) %.6f / %.6f, d(cy) %.6f / %.6f; blocked(cx) %d / %d, blocked(cy) %d / %d\n", j, cx, cy,
                                    length(vx.position[cx] - p), length(vy.position[cx] - q) / f, length(vx.position[cy] - p), length(vy.position[cy] - q) / f,
                                    int(vx.blocked(p, x.normal[j], vx.position[cx], vx.normal[cx])), int(vy.blocked(q, y.normal[j], vy.position[cx], vy.normal[cx])),
                                    int(vx.blocked(p, x.normal[j], vx.position[cy], vx.normal[cy])), int(vy.blocked(q, y.normal[j], vy.position[cy], vy.normal[cy])));
                    }
                const Solved sx = solve(a, sa, ga, true, true, false), sy = solve(b, sb, gb, true, true, false);
                std::printf("%s: clusters %zu / %zu, nodes in another cluster %zu, tree places moved %zu; view / nodes %.4f / %.4f\n", name.c_str(),
                            x.visibility.size(), y.visibility.size(), cl, places, relative_l1(sy.view, sx.view), relative_l1(sy.nodes, sx.nodes));
                continue;
            }
            if (const char *t = std::getenv("RAY_UNIT_TRACE")) {
                trace(a, b, sa, sb, f, std::atoi(t));
                continue;
            }
            std::string cells[3];
            const bool variants[3][2] = {{true, true}, {true, false}, {false, true}};
            for (int v = 0; v < 3; ++v) {
                const Solved x = solve(a, sa, ga, variants[v][0], variants[v][1]), y = solve(b, sb, gb, variants[v][0], variants[v][1]);
                char buf[64];
                std::snprintf(buf, sizeof buf, "%.4f / %.4f", relative_l1(y.view, x.view), relative_l1(y.nodes, x.nodes));
                cells[v] = buf;
            }
            std::printf("| %s | %.2g | %s | %s | %s |\n", name.c_str(), moved, cells[0].c_str(), cells[1].c_str(), cells[2].c_str());
            std::fflush(stdout);
        }
    } catch (const std::exception &e) {
        std::fprintf(stderr, "ray_unit_check: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
