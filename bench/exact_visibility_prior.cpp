// exact_visibility_prior.cpp: how much of the transport prior's error is its visibility? (issue #30's
// "what is left for a network", the real rooms' bias). The prior's point formula among M scene points
// with the visibility and closure taken exactly from the meshes instead of from the points:
//   G_ij = V_ij · max(0, n_i·w) · max(0, −n_j·w) / (r² + a/π),   V_ij = 1 when the segment between the
//          two points (each lifted off its surface) meets no triangle (an Embree occlusion ray),
//   rows normalised to the closure c_i (the share of k_closure_rays cosine-distributed rays from p_i
//          that meet any triangle), B_0 = π L, B_{k+1} = ρ ⊙ Ĝ B_k, E⁺(p) = c(p) Σ_j Ĝ_pj Σ_{k=1..D} B_k,
// the pixels' rows with the same rays. Dense, O(M²) rays for the solve and O(pixels · M) for the
// gather, so a bench, not a renderer: it bounds what better visibility could give the prior.
// Beside it the same formula without occlusion (V = 1, c = 1), the shipped prior (its settings and
// its cluster visibility from the points as discs) and the shipped prior with only its cluster
// visibility and closures taken from the meshes (the segment between two cluster centres by an
// Embree ray, each centre's closure by k_closure_rays rays): how much of the exact visibility's gain
// the prior's clusters can hold.
//   build/bench/exact_visibility_prior SCENES REF_CACHE [size=128] [ref_spp=1024] [M=4096] [bounces=5]
// EXACT_VIS_FG=N adds a final gather at the pixels: N cosine-distributed rays a pixel, each hit
// reading the solve's exitance Σ_k B_k from the nearest nodes on its surface (points/point_interpolation.h;
// where none qualifies, the prior's own gather at the hit), E⁺ = (1/N) Σ B(hit): the pixels' visibility
// from the meshes at a cost of N rays a pixel instead of one a pixel and node.
// EXACT_VIS_SOFT=R adds two cluster visibilities through the same formula (dense, exact closure), so
// only the visibility differs from the exact column: the shipped prior's clusters seeing each other
// or not (centre to centre against the points as discs), and the same clusters with a soft
// visibility, the share of R ray pairs between facing random members that no triangle blocks.
// EXACT_VIS_SOFT_BINARY=1 keeps the soft variant's clusters binary (with EXACT_VIS_EMITTERS_EXACT:
// only the emitters' pairs exact). EXACT_VIS_EMITTERS_EXACT=1 gives the soft variant's pairs that hold an emitter node their own ray
// (a light's cluster mixes it with the ceiling it hangs under). EXACT_VIS_NEAR=R adds the shipped
// solve gathered with rays to the nodes within R spacings of a pixel and the shipped clusters beyond.
// EXACT_VIS_CLUSTER_LIFT=x lifts the centre-to-centre rays x spacings off their surfaces (default
// 0.5). EXACT_VIS_SKIP=1 leaves out every dense part (only the shipped prior, its clusters from the
// meshes and the final gather: any M). EXACT_VIS_DEBUG=1 prints the emitters' clusters' visibility.
// The hybrids (exact solve with the clustered gather, the shipped solve gathered exactly) and these
// variants print to stderr. docs/results.md, "The prior's visibility is most of the real rooms' error".
// EXACT_VIS_REF_DEPTH=D compares against the reference with at most D scattering events (cached as
// prior_ablation's PRIOR_ABLATION_REF_DEPTH). SCENES: scene files and builtin:NAME, comma-separated,
// or a seed range A:B of generated houses.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ltm/core/log.h"
#include "ltm/core/parallel.h"
#include "ltm/core/rng.h"
#include "ltm/core/sampling.h"
#include "ltm/core/startup.h"
#include "ltm/eval/eval_setup.h"
#include "ltm/eval/field_metrics.h"
#include "ltm/eval/metrics.h"
#include "ltm/eval/reference_cache.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/scene_points.h"
#include "ltm/points/point_interpolation.h"
#include "ltm/scene/scene_loader.h"
#include "ltm/transport/transport_prior.h"
#include "bench_scenes.h"
#include "shipped_prior.h"

using namespace ltm;

namespace {
constexpr int k_closure_rays = 64;

struct Nodes {
    std::vector<Vec3f> p, n, rho, le;
};

/// Segment p -> q, each end lifted by eps along its normal, blocked by any triangle?
bool blocked(const EmbreeAccel &accel, Vec3f p, Vec3f np, Vec3f q, Vec3f nq, float eps) {
    Ray ray;
    ray.o = p + np * eps;
    ray.d = (q + nq * eps) - ray.o;
    ray.tmin = 1e-4f, ray.tmax = 1.f - 1e-4f;
    return accel.occluded(ray);
}

/// Share of cosine-distributed rays from (p, n) that meet a triangle (deterministic per index).
float closure(const EmbreeAccel &accel, Vec3f p, Vec3f n, float eps, uint64_t key) {
    const Frame f(n);
    Pcg32 rng(key);
    int hit = 0;
    for (int r = 0; r < k_closure_rays; ++r) {
        Ray ray;
        ray.o = p + n * eps;
        ray.d = f.to_world(sample_cosine_hemisphere(Vec2f{rng.next_float(), rng.next_float()}));
        ray.tmin = 1e-4f;
        hit += accel.occluded(ray);
    }
    return float(hit) / float(k_closure_rays);
}

float term(Vec3f p, Vec3f n, Vec3f q, Vec3f nq, float a) {
    const Vec3f d = q - p;
    const float r2 = dot(d, d);
    if (!(r2 > 0.f)) return 0.f;
    const Vec3f w = d * (1.f / std::sqrt(r2));
    const float c1 = dot(n, w), c2 = -dot(nq, w);
    if (c1 <= 0.f || c2 <= 0.f) return 0.f;
    return c1 * c2 / (r2 + a / float(k_pi));
}
}  // namespace

int main(int argc, char **argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s SCENES REF_CACHE [size=128] [ref_spp=1024] [M=4096] [bounces=5]\n", argv[0]);
        return 1;
    }
    configure_process();
    set_log_level(LogLevel::quiet);
    const std::string range = argv[1], cache = argv[2];
    const int size = argc > 3 ? std::atoi(argv[3]) : 128, ref_spp = argc > 4 ? std::atoi(argv[4]) : 1024;
    const int64_t m_req = argc > 5 ? std::atoll(argv[5]) : 4096;
    const int bounces = argc > 6 ? std::atoi(argv[6]) : 5;
    const std::vector<bench::BenchScene> scene_list = bench::bench_scenes(range);
    std::printf("| scene | M | reference depth | exact visibility: MSE (level) | no occlusion: MSE (level) | mean closure (nodes / pixels) | "
                "shipped prior: MSE (level) | its clusters from the meshes: MSE (level) |\n|---|---|---|---|---|---|---|---|\n");
    try {
        for (const bench::BenchScene &bs : scene_list) {
            const std::string &name = bs.name;
            const Scene scene = bench::load_bench_scene(bs);
            const EmbreeAccel accel(scene);
            const Camera cam = eval_view_camera(scene, 0, 1, size, size);
            PathTracerConfig cfg = eval_tracer_config(0, EvalRole::reference);
            if (const char *depth = std::getenv("EXACT_VIS_REF_DEPTH")) cfg.max_depth = std::atoi(depth);
            const PathTracer pt(accel, cfg);
            const GBuffer gb = render_gbuffer(accel, cam);
            if (gb.n_hits() == 0) continue;
            const Image ref = reference_irradiance(cache, scene, cam, gb, pt, cfg, ref_spp, {{"scene", name}}).indirect;
            const std::vector<Vec3f> ref_hits = gather_hits(gb, ref);

            const ScenePoints sp = sample_scene_points(accel, m_req, 0, true, k_buried_spacings);
            const size_t m = sp.points.size();
            const float a = float(scene.total_area() / double(m)), spacing = std::sqrt(a), eps = 1e-3f * spacing;
            Nodes nd;
            Vec3f mean_le{0.f, 0.f, 0.f};
            for (size_t j = 0; j < m; ++j) {
                nd.p.push_back(sp.points.vec3(j, 0)), nd.n.push_back(sp.points.vec3(j, 3));
                nd.rho.push_back(sp.points.vec3(j, 6)), nd.le.push_back(sp.points.vec3(j, 9));
                mean_le += nd.le.back() * (1.f / float(m));
            }
            // The prior's emission scale: π · mean L = S_c (exact from the meshes).
            for (Vec3f &l : nd.le)
                for (int c = 0; c < 3; ++c) l[c] = mean_le[c] > 0.f ? l[c] * sp.emission_scale[c] / (float(k_pi) * mean_le[c]) : 0.f;
            // Node rows, both variants, as dense M×M floats (row i: the receiver).
            // EXACT_VIS_SKIP=1: only the shipped prior and its clusters from the meshes (the dense per-pair
            // part holds 8·M² bytes and casts O(M² + pixels·M) rays: 4 096 points, not 32 768).
            const bool exact = std::getenv("EXACT_VIS_SKIP") == nullptr;
            std::vector<float> gv(exact ? m * m : 0, 0.f), g0(exact ? m * m : 0, 0.f), cl(m, 1.f);
            parallel_for(0, exact ? int64_t(m) : 0, 16, [&](int64_t b, int64_t e) {
                for (int64_t i = b; i < e; ++i) {
                    cl[size_t(i)] = closure(accel, nd.p[size_t(i)], nd.n[size_t(i)], eps, 0x9e3779b97f4a7c15ull ^ uint64_t(i));
                    for (size_t j = 0; j < m; ++j) {
                        const float t = term(nd.p[size_t(i)], nd.n[size_t(i)], nd.p[j], nd.n[j], a);
                        if (t <= 0.f) continue;
                        g0[size_t(i) * m + j] = t;
                        if (!blocked(accel, nd.p[size_t(i)], nd.n[size_t(i)], nd.p[j], nd.n[j], eps)) gv[size_t(i) * m + j] = t;
                    }
                }
            });
            auto normalise = [&](std::vector<float> &g, const std::vector<float> *c) {
                for (size_t i = 0; i < m; ++i) {
                    double s = 0;
                    for (size_t j = 0; j < m; ++j) s += g[i * m + j];
                    const float k = s > 0 ? float((c ? (*c)[i] : 1.f) / s) : 0.f;
                    for (size_t j = 0; j < m; ++j) g[i * m + j] *= k;
                }
            };
            if (exact) normalise(gv, &cl), normalise(g0, nullptr);
            auto solve = [&](const std::vector<float> &g) {
                std::vector<Vec3f> b(m), sum(m, Vec3f{0.f, 0.f, 0.f});
                for (size_t j = 0; j < m; ++j) b[j] = nd.le[j] * float(k_pi);
                for (int k = 1; k <= bounces; ++k) {
                    std::vector<Vec3f> nb(m);
                    parallel_for(0, int64_t(m), 64, [&](int64_t lo, int64_t hi) {
                        for (int64_t i = lo; i < hi; ++i) {
                            double acc[3] = {0, 0, 0};
                            for (size_t j = 0; j < m; ++j)
                                for (int c = 0; c < 3; ++c) acc[c] += double(g[size_t(i) * m + j]) * double(b[j][c]);
                            for (int c = 0; c < 3; ++c) nb[size_t(i)][c] = nd.rho[size_t(i)][c] * float(acc[c]);
                        }
                    });
                    b = nb;
                    for (size_t j = 0; j < m; ++j) sum[j] += b[j];
                }
                return sum;
            };
            const std::vector<Vec3f> sv = exact ? solve(gv) : std::vector<Vec3f>(m), s0 = exact ? solve(g0) : std::vector<Vec3f>(m);
            const size_t n = gb.n_hits();
            // The shipped prior (prior_features' settings), then its clusters' visibility from the meshes.
            const TransportPrior shipped = bench::solve_shipped_prior(sp, a, bounces);
            ClusterVisibility cv = shipped.visibility;
            // EXACT_VIS_CLUSTER_LIFT=x: the centres' segment ends lifted x spacings off their surfaces (default 0.5).
            const float lift = spacing * (std::getenv("EXACT_VIS_CLUSTER_LIFT") ? std::stof(std::getenv("EXACT_VIS_CLUSTER_LIFT")) : 0.5f);
            const size_t nc = cv.size();
            parallel_for(0, int64_t(nc), 8, [&](int64_t b, int64_t e) {
                for (int64_t c1 = b; c1 < e; ++c1) {
                    cv.closure[size_t(c1)] = closure(accel, cv.position[size_t(c1)], cv.normal[size_t(c1)], eps, 0xc1u ^ uint64_t(c1));
                    for (size_t c2 = size_t(c1) + 1; c2 < nc; ++c2) {
                        const bool see = !blocked(accel, cv.position[size_t(c1)], cv.normal[size_t(c1)], cv.position[c2], cv.normal[c2], lift);
                        cv.visible[size_t(c1) * nc + c2] = cv.visible[c2 * nc + size_t(c1)] = see;
                    }
                }
            });
            const TransportPrior meshed = solve_transport_prior(nd.p, nd.n, nd.rho, nd.le, a, bounces, cv, PriorBalance::none, true, 0.5f);
            std::vector<Vec3f> es(n), em(n);
            gather_transport_prior(shipped, &gb.position[0].x, &gb.normal[0].x, 3, n, &es[0].x);
            gather_transport_prior(meshed, &gb.position[0].x, &gb.normal[0].x, 3, n, &em[0].x);
            const ImageMetrics ms = compare_images(scatter_to_image(gb, es), ref), mm = compare_images(scatter_to_image(gb, em), ref);
            const FieldMetrics fs = compare_fields(es, ref_hits), fm = compare_fields(em, ref_hits);
            // EXACT_VIS_SOFT: cluster visibilities through the exact column's formula.
            const int soft_rays = exact && std::getenv("EXACT_VIS_SOFT") ? std::atoi(std::getenv("EXACT_VIS_SOFT")) : 0;
            const ClusterVisibility &sv_vis = shipped.visibility;
            const bool emitters_exact = std::getenv("EXACT_VIS_EMITTERS_EXACT") != nullptr;
            const bool soft_binary = std::getenv("EXACT_VIS_SOFT_BINARY") != nullptr;
            const size_t n_cl = sv_vis.size();
            std::vector<float> v_soft, v_bin;
            std::vector<Vec3f> s_soft, s_bin;
            if (soft_rays > 0) {
                std::vector<std::vector<uint32_t>> members(n_cl);
                for (size_t j = 0; j < m; ++j) members[sv_vis.node_cluster[j]].push_back(uint32_t(j));
                v_soft.assign(n_cl * n_cl, 1.f), v_bin.assign(n_cl * n_cl, 1.f);
                parallel_for(0, int64_t(n_cl), 4, [&](int64_t b, int64_t e) {
                    for (int64_t c1 = b; c1 < e; ++c1)
                        for (size_t c2 = size_t(c1) + 1; c2 < n_cl; ++c2) {
                            v_bin[size_t(c1) * n_cl + c2] = v_bin[c2 * n_cl + size_t(c1)] = float(sv_vis.visible[size_t(c1) * n_cl + c2]);
                            Pcg32 rng(uint64_t(c1) * 1000003ull + c2);
                            const auto &ma = members[size_t(c1)], &mb = members[c2];
                            int tried = 0, seen = 0, facing = 0;
                            while (facing < soft_rays && tried < 4 * soft_rays && !ma.empty() && !mb.empty()) {
                                ++tried;
                                const uint32_t i = ma[rng.next_u32() % ma.size()], j = mb[rng.next_u32() % mb.size()];
                                if (term(nd.p[i], nd.n[i], nd.p[j], nd.n[j], a) <= 0.f) continue;
                                ++facing;
                                seen += !blocked(accel, nd.p[i], nd.n[i], nd.p[j], nd.n[j], eps);
                            }
                            // EXACT_VIS_SOFT_BINARY=1: the soft variant keeps the binary clusters (to isolate EXACT_VIS_EMITTERS_EXACT).
                            const float v = facing > 0 && !soft_binary ? float(seen) / float(facing) : float(sv_vis.visible[size_t(c1) * n_cl + c2]);
                            v_soft[size_t(c1) * n_cl + c2] = v_soft[c2 * n_cl + size_t(c1)] = v;
                        }
                });
                if (std::getenv("EXACT_VIS_DEBUG")) {   // the emitters' clusters: soft against binary visibility
                    double sum_s = 0, sum_b = 0;
                    size_t cnt = 0;
                    for (size_t j = 0; j < m; ++j) {
                        if (!(nd.le[j][0] > 0.f)) continue;
                        const size_t c1 = sv_vis.node_cluster[j];
                        for (size_t c2 = 0; c2 < n_cl; ++c2) sum_s += v_soft[c1 * n_cl + c2], sum_b += v_bin[c1 * n_cl + c2], ++cnt;
                        std::fprintf(stderr, "emitter node %zu cluster %zu members %zu\n", j, c1, members[c1].size());
                    }
                    double all_s = 0, all_b = 0;
                    for (size_t i = 0; i < n_cl * n_cl; ++i) all_s += v_soft[i], all_b += v_bin[i];
                    std::fprintf(stderr, "emitters' clusters: mean soft V %.3f, binary %.3f; all clusters: soft %.3f, binary %.3f (%zu clusters)\n",
                                 sum_s / double(cnt ? cnt : 1), sum_b / double(cnt ? cnt : 1), all_s / double(n_cl * n_cl), all_b / double(n_cl * n_cl), n_cl);
                }
                for (const std::vector<float> *vv : {&v_soft, &v_bin}) {
                    std::vector<float> g(m * m, 0.f);
                    parallel_for(0, int64_t(m), 16, [&](int64_t b, int64_t e) {
                        for (int64_t i = b; i < e; ++i) {
                            const size_t ci = sv_vis.node_cluster[size_t(i)];
                            for (size_t j = 0; j < m; ++j)
                            {
                                if (!(g0[size_t(i) * m + j] > 0.f)) continue;
                                const bool with_emitter = emitters_exact && vv == &v_soft &&
                                                (nd.le[j][0] + nd.le[j][1] + nd.le[j][2] > 0.f || nd.le[size_t(i)][0] + nd.le[size_t(i)][1] + nd.le[size_t(i)][2] > 0.f);
                                const float v = with_emitter ? float(gv[size_t(i) * m + j] > 0.f) : (*vv)[ci * n_cl + sv_vis.node_cluster[j]];
                                g[size_t(i) * m + j] = term(nd.p[size_t(i)], nd.n[size_t(i)], nd.p[j], nd.n[j], a) * v;
                            }
                        }
                    });
                    normalise(g, &cl);
                    (vv == &v_soft ? s_soft : s_bin) = solve(g);
                }
            }
            // The pixels' gathers.
            std::vector<Vec3f> ev(n), e0(n), ex_sh(n);
            // EXACT_VIS_NEAR=R: also the shipped exitance with rays only to the nodes within R spacings of
            // the pixel and the shipped clusters' blended visibility beyond (near_sh).
            const float near_r = std::getenv("EXACT_VIS_NEAR") ? std::stof(std::getenv("EXACT_VIS_NEAR")) * spacing : -1.f;
            std::vector<Vec3f> near_sh(n), e_soft(n), e_bin(n);
            std::vector<double> near_rays(n, 0.0);   // ex_sh: the shipped solve's exitance, gathered exactly
            std::vector<float> pcl(n);
            parallel_for(0, exact ? int64_t(n) : 0, 16, [&](int64_t b, int64_t e) {
                for (int64_t h = b; h < e; ++h) {
                    const Vec3f p = gb.position[size_t(h)], nn = gb.normal[size_t(h)];
                    const float c = closure(accel, p, nn, eps, 0x51ed2701ull ^ uint64_t(h));
                    pcl[size_t(h)] = c;
                    double dv = 0, d0 = 0, av[3] = {0, 0, 0}, a0[3] = {0, 0, 0}, ah[3] = {0, 0, 0}, dn = 0, an[3] = {0, 0, 0};
                    std::vector<float> cw, cws(soft_rays > 0 ? n_cl : 0, 0.f), cwb(soft_rays > 0 ? n_cl : 0, 0.f);
                    double ds = 0, db = 0, as_[3] = {0, 0, 0}, ab[3] = {0, 0, 0};
                    if (soft_rays > 0) {
                        uint32_t ids[ClusterVisibility::k_candidates];
                        float w[ClusterVisibility::k_candidates];
                        const int kb = sv_vis.receiver_clusters(p, nn, ids, w);
                        for (int k = 0; k < kb; ++k)
                            for (size_t c2 = 0; c2 < n_cl; ++c2)
                                cws[c2] += w[k] * v_soft[size_t(ids[k]) * n_cl + c2], cwb[c2] += w[k] * v_bin[size_t(ids[k]) * n_cl + c2];
                    }
                    if (near_r > 0.f) {
                        const ClusterVisibility &vis = shipped.visibility;
                        uint32_t ids[ClusterVisibility::k_candidates];
                        float w[ClusterVisibility::k_candidates];
                        const int kb = vis.receiver_clusters(p, nn, ids, w);
                        cw.resize(vis.size());
                        vis.blend_rows(ids, w, kb, cw.data());
                    }
                    for (size_t j = 0; j < m; ++j) {
                        const float t = term(p, nn, nd.p[j], nd.n[j], a);
                        if (t <= 0.f) continue;
                        d0 += t;
                        const bool occluded = blocked(accel, p, nn, nd.p[j], nd.n[j], eps);
                        if (soft_rays > 0) {
                            // EXACT_VIS_EMITTERS_EXACT=1: pairs with an emitter node take the ray's answer.
                            const bool with_emitter = emitters_exact && nd.le[j][0] + nd.le[j][1] + nd.le[j][2] > 0.f;
                            const float vs = with_emitter ? float(!occluded) : cws[sv_vis.node_cluster[j]];
                            const float ws = t * vs, wb = t * cwb[sv_vis.node_cluster[j]];
                            ds += ws, db += wb;
                            for (int k = 0; k < 3; ++k) as_[k] += double(ws) * s_soft[j][k], ab[k] += double(wb) * s_bin[j][k];
                        }
                        for (int k = 0; k < 3; ++k) a0[k] += double(t) * s0[j][k];
                        if (near_r > 0.f) {
                            const Vec3f dd = nd.p[j] - p;
                            float wv;
                            if (dot(dd, dd) < near_r * near_r) wv = occluded ? 0.f : 1.f, near_rays[size_t(h)] += 1;
                            else wv = cw[shipped.visibility.node_cluster[j]];
                            dn += double(t * wv);
                            for (int k = 0; k < 3; ++k) an[k] += double(t * wv) * shipped.exitance[j][k];
                        }
                        if (occluded) continue;
                        dv += t;
                        for (int k = 0; k < 3; ++k) av[k] += double(t) * sv[j][k], ah[k] += double(t) * shipped.exitance[j][k];
                    }
                    for (int k = 0; k < 3; ++k) {
                        ev[size_t(h)][k] = dv > 0 ? float(c * av[k] / dv) : 0.f;
                        ex_sh[size_t(h)][k] = dv > 0 ? float(c * ah[k] / dv) : 0.f;
                        near_sh[size_t(h)][k] = dn > 0 ? float(c * an[k] / dn) : 0.f;
                        e_soft[size_t(h)][k] = ds > 0 ? float(c * as_[k] / ds) : 0.f;
                        e_bin[size_t(h)][k] = db > 0 ? float(c * ab[k] / db) : 0.f;
                        e0[size_t(h)][k] = d0 > 0 ? float(a0[k] / d0) : 0.f;
                    }
                }
            });
            if (const char *fg = std::getenv("EXACT_VIS_FG")) {
                const int rays = std::atoi(fg);
                const PointInterpolator interp(nd.p, nd.n, spacing);
                auto final_gather = [&](const std::vector<Vec3f> &exitance, const TransportPrior &fallback) {
                    std::vector<Vec3f> out(n, Vec3f{0.f, 0.f, 0.f});
                    std::vector<std::vector<std::pair<Vec3f, Vec3f>>> missed(n);   // hits no node serves
                    parallel_for(0, int64_t(n), 16, [&](int64_t b, int64_t e) {
                        for (int64_t h = b; h < e; ++h) {
                            const Vec3f p = gb.position[size_t(h)], nn = gb.normal[size_t(h)];
                            const Frame f(nn);
                            Pcg32 rng(0x7f4a7c15ull ^ uint64_t(h));
                            const int side = int(std::lround(std::sqrt(double(rays))));
                            Vec3f acc{0.f, 0.f, 0.f};
                            for (int r = 0; r < rays; ++r) {
                                // stratified on a side × side grid when rays is a square
                                const float u = side * side == rays ? (float(r % side) + rng.next_float()) / float(side) : rng.next_float();
                                const float v = side * side == rays ? (float(r / side) + rng.next_float()) / float(side) : rng.next_float();
                                Ray ray;
                                ray.o = p + nn * eps;
                                ray.d = f.to_world(sample_cosine_hemisphere(Vec2f{u, v}));
                                ray.tmin = 1e-4f;
                                const auto hit = accel.intersect(ray);
                                if (!hit) continue;
                                const Vec3f q = ray.o + ray.d * hit->t;
                                const Vec3f nq = dot(hit->n, ray.d) > 0.f ? hit->n * -1.f : hit->n;
                                Vec3f val;
                                if (interp.interpolate(q, nq, exitance.data(), val)) acc += val;
                                else missed[size_t(h)].emplace_back(q, nq);
                            }
                            out[size_t(h)] = acc * (1.f / float(rays));
                        }
                    });
                    // Hits no node serves: the prior's gather there is E⁺(q); its exitance is ρ(q)·E⁺(q) at
                    // best known, so take the nearest node's albedo-free share: E⁺(q) · mean albedo of the nodes.
                    std::vector<Vec3f> qp, qn;
                    for (const auto &v : missed)
                        for (const auto &[q, nq] : v) qp.push_back(q), qn.push_back(nq);
                    size_t missed_count = qp.size();
                    if (!qp.empty()) {
                        std::vector<Vec3f> eq(qp.size());
                        std::vector<float> flat(qp.size() * 6);
                        for (size_t i = 0; i < qp.size(); ++i)
                            for (int c = 0; c < 3; ++c) flat[6 * i + size_t(c)] = qp[i][c], flat[6 * i + 3 + size_t(c)] = qn[i][c];
                        gather_transport_prior(fallback, flat.data(), flat.data() + 3, 6, qp.size(), &eq[0].x);
                        Vec3f rho_mean{0.f, 0.f, 0.f};
                        for (const Vec3f &r : nd.rho) rho_mean += r * (1.f / float(m));
                        size_t i = 0;
                        for (size_t h = 0; h < n; ++h)
                            for (size_t k = 0; k < missed[h].size(); ++k, ++i) out[h] += eq[i] * rho_mean * (1.f / float(rays));
                    }
                    return std::make_pair(out, missed_count);
                };
                const auto [fs_img, fs_missed] = final_gather(shipped.exitance, shipped);
                const ImageMetrics mf = compare_images(scatter_to_image(gb, fs_img), ref);
                const FieldMetrics ff = compare_fields(fs_img, ref_hits);
                std::fprintf(stderr, "%s: shipped solve, final gather %d rays: %.4f (level %.3f), %zu hits served by the gather\n", name.c_str(), rays,
                             mf.mse, ff.level_ratio, fs_missed);
                if (exact) {
                    const auto [fe_img, fe_missed] = final_gather(sv, shipped);
                    const ImageMetrics me = compare_images(scatter_to_image(gb, fe_img), ref);
                    const FieldMetrics fe = compare_fields(fe_img, ref_hits);
                    std::fprintf(stderr, "%s: exact solve, final gather %d rays: %.4f (level %.3f)\n", name.c_str(), rays, me.mse, fe.level_ratio);
                }
            }
            // The exact solve's exitance through the shipped prior's clustered gather.
            TransportPrior hybrid = shipped;
            hybrid.exitance = sv, hybrid.tree_sums = nullptr;
            std::vector<Vec3f> eh(n);
            gather_transport_prior(hybrid, &gb.position[0].x, &gb.normal[0].x, 3, n, &eh[0].x);
            const ImageMetrics mh = compare_images(scatter_to_image(gb, eh), ref), mx = compare_images(scatter_to_image(gb, ex_sh), ref);
            const FieldMetrics fh = compare_fields(eh, ref_hits), fx = compare_fields(ex_sh, ref_hits);
            if (soft_rays > 0) {
                const ImageMetrics ms2 = compare_images(scatter_to_image(gb, e_soft), ref), mb2 = compare_images(scatter_to_image(gb, e_bin), ref);
                const FieldMetrics fs2 = compare_fields(e_soft, ref_hits), fb2 = compare_fields(e_bin, ref_hits);
                std::fprintf(stderr, "%s: same formula, shipped clusters' visibility %.4f (level %.3f); clusters' soft visibility from %d rays %.4f (level %.3f)\n",
                             name.c_str(), mb2.mse, fb2.level_ratio, soft_rays, ms2.mse, fs2.level_ratio);
            }
            if (exact && near_r > 0.f) {
                const ImageMetrics mn = compare_images(scatter_to_image(gb, near_sh), ref);
                const FieldMetrics fn = compare_fields(near_sh, ref_hits);
                double rays_mean = 0;
                for (double r : near_rays) rays_mean += r / double(n);
                std::fprintf(stderr, "%s: shipped solve, rays to nodes within %s spacings, clusters beyond: %.4f (level %.3f), %.0f rays a pixel\n",
                             name.c_str(), std::getenv("EXACT_VIS_NEAR"), mn.mse, fn.level_ratio, rays_mean);
            }
            if (exact)
                std::fprintf(stderr, "%s: exact solve, clustered gather %.4f (level %.3f); shipped solve, exact gather %.4f (level %.3f)\n",
                             name.c_str(), mh.mse, fh.level_ratio, mx.mse, fx.level_ratio);
            const ImageMetrics mv = compare_images(scatter_to_image(gb, ev), ref), m0 = compare_images(scatter_to_image(gb, e0), ref);
            const FieldMetrics fv = compare_fields(ev, ref_hits), f0 = compare_fields(e0, ref_hits);
            double cn = 0, cp = 0;
            for (float c : cl) cn += c / double(m);
            for (float c : pcl) cp += c / double(n);
            std::printf("| %s | %zu | %s | %.4f (%.3f) | %.4f (%.3f) | %.3f / %.3f | %.4f (%.3f) | %.4f (%.3f) |\n", name.c_str(), m,
                        std::getenv("EXACT_VIS_REF_DEPTH") ? std::getenv("EXACT_VIS_REF_DEPTH") : "all", mv.mse, fv.level_ratio, m0.mse,
                        f0.level_ratio, cn, cp, ms.mse, fs.level_ratio, mm.mse, fm.level_ratio);
            std::fflush(stdout);
        }
    } catch (const std::exception &ex) {
        std::fprintf(stderr, "exact_visibility_prior: error: %s\n", ex.what());
        return 1;
    }
    return 0;
}
