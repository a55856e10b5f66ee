// traced_correction.cpp: how much of the prior's view error do a few traced paths per scene point
// remove? (issue #30: what an input to the network could carry that the prior cannot know.)
// Per view `ltm eval` scores: the prior's Ê⁺ at the hit pixels, the same prior gathered at its own
// scene points P_j, and path-traced irradiance at those points with N strata each (the references'
// tracer, another seed). Two corrections of the prior from them:
//   local gain   Ê⁺_c(h) = Ê⁺(h) · Σ_{j∈K(h)} lum T_j / Σ_{j∈K(h)} lum P_j  (T_j: traced E⁺), K(h) the k
//                nearest probes facing the same way (n_j·n_h > 0.5) that any light reaches (T_j > 0:
//                points hidden in a gap read T = 0 where the prior gives them light); a ratio of
//                sums, so the noise averages over k points before it divides. k = "all": one gain
//                per view (the level alone).
//   regather     the prior's nodes re-emit ρ_j ⊙ (traced E_dir + E⁺ at node j) and are gathered once
//                more at the hits: the last bounce by the prior's gather, the rest traced (E⁺ to the
//                references' depth 5, so 1 … 6 events; the model's traced inputs stop at D − 1).
// Prior: the shipped one (bench/shipped_prior.h, the auto point count) or, with MODEL_CONFIG=path,
// the prior of that model config exactly as `ltm eval`'s model-prior row solves it (its points, its
// visibility by rays). Writes the eval's MSE (compare_images) per variant, its ratio to the prior,
// views better and the tracing time; TSV=path the per-pixel table that
// scripts/analysis/traced_probe_features.py fits. Diagnostics: PROBES=1 (probes from an independent
// point draw), KEEP_DARK, MEDIAN, NO_EMITTERS, PROBE_DEBUG, DUMP=dir (PNGs), REGATHER_DEPTH.
//   build/bench/traced_correction SCENES REF_CACHE [size=96] [ref_spp=1024] [spp list=4,16,64] [k list=16,64,256,0]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "ltm/core/color.h"
#include "ltm/core/image.h"
#include "ltm/core/tonemap.h"
#include "ltm/core/log.h"
#include "ltm/core/parallel.h"
#include "ltm/core/startup.h"
#include "ltm/eval/eval_setup.h"
#include "ltm/eval/metrics.h"
#include "ltm/eval/reference_cache.h"
#include "ltm/infer/prior_model.h"
#include "ltm/nn/scene_frame.h"
#include "ltm/points/knn_points.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/scene_points.h"
#include "ltm/transport/transport_prior.h"
#include "bench_scenes.h"
#include "shipped_prior.h"

using namespace ltm;

namespace {
constexpr int k_bounces = 5;

std::vector<int> parse_list(const std::string &s) {
    std::vector<int> v;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) v.push_back(std::atoi(item.c_str()));
    return v;
}

float lum(Vec3f c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
}  // namespace

int main(int argc, char **argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s SCENES REF_CACHE [size=96] [ref_spp=1024] [spp=4,16,64] [k=16,64,256,0]\n", argv[0]);
        return 1;
    }
    configure_process();
    set_log_level(LogLevel::quiet);
    const std::string range = argv[1], cache = argv[2];
    const int size = argc > 3 ? std::atoi(argv[3]) : 96, ref_spp = argc > 4 ? std::atoi(argv[4]) : 1024;
    const std::vector<int> spps = parse_list(argc > 5 ? argv[5] : "4,16,64");
    const std::vector<int> ks = parse_list(argc > 6 ? argv[6] : "16,64,256,0");
    const std::vector<bench::BenchScene> scene_list = bench::bench_scenes(range);
    const size_t n_var = spps.size() * ks.size();
    std::vector<double> sum(n_var, 0.0), trace_s(spps.size(), 0.0);
    std::vector<int> better(n_var, 0), regather_better(spps.size(), 0);
    std::vector<double> regather_mse(spps.size(), 0.0);
    double sum_prior = 0.0;
    // TSV=path: per hit pixel ref, prior, regather and each k's gain, for scripts/analysis fits.
    FILE *tsv = std::getenv("TSV") ? std::fopen(std::getenv("TSV"), "w") : nullptr;
    int views = 0;
    for (const bench::BenchScene &bs : scene_list) {
        const Scene scene = bench::load_bench_scene(bs);
        const EmbreeAccel accel(scene);
        const Camera cam = eval_view_camera(scene, 0, 1, size, size);
        const PathTracerConfig cfg = eval_tracer_config(0, EvalRole::reference);
        const PathTracer pt(accel, cfg);
        const GBuffer gb = render_gbuffer(accel, cam);
        if (gb.n_hits() == 0) continue;
        const Image ref = reference_irradiance(cache, scene, cam, gb, pt, cfg, ref_spp, {{"scene", bs.name}}).indirect;
        // The prior: the shipped one (bench/shipped_prior.h, the auto point count), or with
        // MODEL_CONFIG=path the prior of that model config as `ltm eval`'s model-prior row solves it
        // (infer/prior_model.h: its point count, its visibility, rays included). Both give Ê⁺ in W/m²
        // at world rows; `regather` gathers the same nodes with their exitance replaced.
        const char *model_config = std::getenv("MODEL_CONFIG");
        ScenePoints sp;
        std::function<void(const float *, size_t, size_t, Vec3f *)> prior_at;   // rows (p, n; stride floats) -> Ê⁺
        std::function<std::vector<Vec3f>(const std::vector<Vec3f> &)> regather;  // node exitance -> Ê⁺ at the hits
        std::shared_ptr<PriorScene> ps;
        std::shared_ptr<TransportPrior> shipped;
        if (model_config) {
            ps = std::make_shared<PriorScene>(encode_prior_scene(ModelConfig::from_file(model_config), accel, 0, true));
            sp.points = ps->points;
            if (ps->frame.transport->position.size() != sp.points.size()) throw std::runtime_error("MODEL_CONFIG: nodes are not the scene points");
            const auto as_rows = [](const float *rows, size_t stride, size_t n) {
                std::vector<float> r(n * 9, 0.f);
                for (size_t i = 0; i < n; ++i)
                    for (size_t a = 0; a < 6; ++a) r[i * 9 + a] = rows[i * stride + a];
                return r;
            };
            prior_at = [ps, as_rows](const float *rows, size_t stride, size_t n, Vec3f *out) {
                const std::vector<float> r = as_rows(rows, stride, n);
                prior_irradiance(ps->frame, r.data(), n, out);
            };
            regather = [ps, as_rows, &gb](const std::vector<Vec3f> &ex) {
                auto t = std::make_shared<TransportPrior>(*ps->frame.transport);
                t->exitance = ex;
                if (t->tree) t->tree_sums = std::make_shared<const PriorTree::Sums>(t->tree->sums(t->exitance));
                SceneFrame f = ps->frame;
                f.transport = t;
                std::vector<Vec3f> pn(gb.n_hits() * 2);
                for (size_t h = 0; h < gb.n_hits(); ++h) pn[2 * h] = gb.position[h], pn[2 * h + 1] = gb.normal[h];
                const std::vector<float> r = as_rows(&pn[0].x, 6, gb.n_hits());
                std::vector<Vec3f> out(gb.n_hits());
                prior_irradiance(f, r.data(), gb.n_hits(), out.data());
                return out;
            };
        } else {
            sp = sample_scene_points(accel, auto_scene_points(scene), 0, true, k_buried_spacings);
            const float spacing = float(std::sqrt(scene.total_area() / double(sp.points.size())));
            shipped = std::make_shared<TransportPrior>(bench::solve_shipped_prior(sp, spacing * spacing, k_bounces));
            prior_at = [shipped](const float *rows, size_t stride, size_t n, Vec3f *out) {
                gather_transport_prior(*shipped, rows, rows + 3, stride, n, &out[0].x);
            };
            regather = [shipped, &gb](const std::vector<Vec3f> &ex) {
                TransportPrior t = *shipped;
                t.exitance = ex;
                if (t.tree) t.tree_sums = std::make_shared<const PriorTree::Sums>(t.tree->sums(t.exitance));
                std::vector<Vec3f> out(gb.n_hits());
                gather_transport_prior(t, &gb.position[0].x, &gb.normal[0].x, 3, gb.n_hits(), &out[0].x);
                return out;
            };
        }
        const size_t m = sp.points.size();
        // The probes: the prior's own nodes (PROBES unset) or an independent draw of as many points
        // (PROBES=1, sampling seed 1), where the gather meets no node at distance 0.
        const bool own = !std::getenv("PROBES");
        const bool skip_dark = std::getenv("KEEP_DARK") == nullptr;
        const bool median = std::getenv("MEDIAN") != nullptr;   // exp median log(T/P) instead of ΣT/ΣP
        const bool skip_emitters = std::getenv("NO_EMITTERS") != nullptr;   // probes on lights left out
        const ScenePoints probes = own ? sp : sample_scene_points(accel, m, 1, true, k_buried_spacings);
        const PointSet &pp = probes.points;
        const size_t nc = pp.columns.size();
        std::vector<Vec3f> e(gb.n_hits()), ep(pp.size());
        {
            std::vector<Vec3f> pn(gb.n_hits() * 2);
            for (size_t h = 0; h < gb.n_hits(); ++h) pn[2 * h] = gb.position[h], pn[2 * h + 1] = gb.normal[h];
            prior_at(&pn[0].x, 6, gb.n_hits(), e.data());
        }
        prior_at(&pp.values[0], nc, pp.size(), ep.data());
        const double mse_prior = compare_images(scatter_to_image(gb, e), ref).mse;
        sum_prior += mse_prior;
        const size_t np = pp.size();
        std::vector<float> pts(np * 3);
        for (size_t j = 0; j < np; ++j)
            for (int a = 0; a < 3; ++a) pts[j * 3 + a] = pp.at(j, a);
        const int kmax_cap = 1024;
        const int64_t kq = int64_t(std::min<size_t>(np, size_t(kmax_cap)));
        const std::vector<int64_t> nn = knn_points(&gb.position[0].x, gb.n_hits(), pts.data(), np, kq);
        PathTracerConfig tcfg = cfg;
        tcfg.seed = cfg.seed + 7919;   // independent of the reference's paths
        const PathTracer tracer(accel, tcfg);
        // REGATHER_DEPTH=D: the regather's E⁺ to D scattering events (default the references' 5;
        // the model's traced inputs use prior_bounces − 1 = 4).
        PathTracerConfig rcfg = tcfg;
        if (const char *d = std::getenv("REGATHER_DEPTH")) rcfg.max_depth = rcfg.rr_depth = std::max(1, std::atoi(d));
        const PathTracer regather_tracer(accel, rcfg);
        std::printf("%-28s prior %.5f |", bs.name.c_str(), mse_prior);
        std::vector<Vec3f> rg_first;
        std::vector<std::vector<Vec3f>> corrected_first;
        for (size_t si = 0; si < spps.size(); ++si) {
            const int spp = spps[si];
            std::vector<Vec3f> t(np);
            const auto t0 = std::chrono::steady_clock::now();
            parallel_for(0, int64_t(np), 64, [&](int64_t b, int64_t en) {
                for (int64_t j = b; j < en; ++j)
                    t[size_t(j)] = tracer.irradiance(pp.vec3(size_t(j), 0), pp.vec3(size_t(j), 3), uint64_t(j), spp).indirect;
            });
            trace_s[si] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            {   // regather: the prior's nodes re-emit ρ_j ⊙ (traced E_j + E⁺_j), gathered once more at the hits
                std::vector<Vec3f> ex(m);
                parallel_for(0, int64_t(m), 64, [&](int64_t b, int64_t en) {
                    for (int64_t j = b; j < en; ++j) {
                        const size_t i = size_t(j);
                        const IrradianceEstimate est = regather_tracer.irradiance(sp.points.vec3(i, 0), sp.points.vec3(i, 3), uint64_t(j) + 1000000007ull, spp);
                        ex[i] = sp.points.vec3(i, 6) * (est.direct + est.indirect);
                    }
                });
                const std::vector<Vec3f> c = regather(ex);
                if (si == 0) rg_first = c;
                const double mse = compare_images(scatter_to_image(gb, c), ref).mse;
                regather_mse[si] += mse;
                regather_better[si] += mse < mse_prior;
                std::printf(" rg%d %.5f", spp, mse);
                if (const char *dump = std::getenv("DUMP")) {
                    const float s = 1.f / tonemap_scale(ref);
                    write_png(std::string(dump) + "/" + bs.name + "-rg" + std::to_string(spp) + ".png", scatter_to_image(gb, c), s);
                }
            }
            for (size_t ki = 0; ki < ks.size(); ++ki) {
                const int k = ks[ki];
                std::vector<Vec3f> c(gb.n_hits());
                if (k == 0) {   // one factor per view
                    double st = 0, spr = 0;
                    for (size_t j = 0; j < np; ++j) st += lum(t[j]), spr += lum(ep[j]);
                    const float g = spr > 0 ? float(st / spr) : 1.f;
                    for (size_t h = 0; h < gb.n_hits(); ++h) c[h] = e[h] * g;
                } else {
                    for (size_t h = 0; h < gb.n_hits(); ++h) {
                        double st = 0, spr = 0;
                        int used = 0;
                        std::vector<float> lr;
                        for (int64_t r = 0; r < kq && used < k; ++r) {
                            const size_t j = size_t(nn[h * size_t(kq) + size_t(r)]);
                            if (dot(pp.vec3(j, 3), gb.normal[h]) < 0.5f) continue;
                            if (skip_emitters && lum(pp.vec3(j, 9)) > 0.f) continue;
                            if (skip_dark && !(lum(t[j]) > 0.f)) continue;   // no light reaches it: hidden in a gap
                            st += lum(t[j]), spr += lum(ep[j]), ++used;
                            lr.push_back(std::log((lum(t[j]) + 1e-6f) / (lum(ep[j]) + 1e-6f)));
                        }
                        float g = spr > 0 ? float(st / spr) : 1.f;
                        if (median && !lr.empty()) {
                            std::nth_element(lr.begin(), lr.begin() + long(lr.size() / 2), lr.end());
                            g = std::exp(lr[lr.size() / 2]);
                        }
                        c[h] = e[h] * g;
                    }
                }
                const double mse = compare_images(scatter_to_image(gb, c), ref).mse;
                if (si == 0) corrected_first.push_back(c);
                if (std::getenv("PROBE_DEBUG") && k > 0) {   // the worst-corrected pixel and its probes
                    const std::vector<Vec3f> rh = gather_hits(gb, ref);
                    size_t worst = 0;
                    float wv = 0.f;
                    for (size_t h = 0; h < gb.n_hits(); ++h) {
                        const float d = std::fabs(lum(c[h]) - lum(rh[h]));
                        if (d > wv) wv = d, worst = h;
                    }
                    const Vec3f &q = gb.position[worst], &qn = gb.normal[worst];
                    std::printf("\nworst pixel %lld p (%.3f %.3f %.3f) n (%.2f %.2f %.2f) ref %.4g prior %.4g corrected %.4g\n",
                                (long long)gb.hit_pixels[worst], q.x, q.y, q.z, qn.x, qn.y, qn.z, lum(rh[worst]), lum(e[worst]), lum(c[worst]));
                    for (int r = 0, used = 0; r < int(kq) && used < k; ++r) {
                        const size_t j = size_t(nn[worst * size_t(kq) + size_t(r)]);
                        if (dot(pp.vec3(j, 3), qn) < 0.5f) continue;
                        ++used;
                        if (lum(ep[j]) < 5.f && lum(t[j]) < 5.f && lum(t[j]) > 1.f) continue;
                        const Vec3f pj = pp.vec3(j, 0), nj = pp.vec3(j, 3);
                        std::printf("  probe %zu d %.4f n (%.2f %.2f %.2f) T %.4g P %.4g em %.3g\n", j, length(pj - q), nj.x, nj.y, nj.z,
                                    lum(t[j]), lum(ep[j]), lum(pp.vec3(j, 9)));
                    }
                }
                if (const char *dump = std::getenv("DUMP")) {   // DUMP=dir: the view's images at its tone-mapping scale
                    const float s = 1.f / tonemap_scale(ref);
                    const std::string base = std::string(dump) + "/" + bs.name;
                    write_png(base + "-ref.png", ref, s);
                    write_png(base + "-prior.png", scatter_to_image(gb, e), s);
                    write_png(base + "-c" + std::to_string(spp) + "-" + std::to_string(k) + ".png", scatter_to_image(gb, c), s);
                    std::vector<Vec3f> g(gb.n_hits());
                    for (size_t h = 0; h < gb.n_hits(); ++h) g[h] = Vec3f(0.5f * lum(c[h]) / std::max(lum(e[h]), 1e-12f));
                    write_png(base + "-g" + std::to_string(spp) + "-" + std::to_string(k) + ".png", scatter_to_image(gb, g), 1.f);
                    std::vector<Vec3f> gr(gb.n_hits());
                    const std::vector<Vec3f> rh = gather_hits(gb, ref);
                    for (size_t h = 0; h < gb.n_hits(); ++h) gr[h] = Vec3f(0.5f * lum(rh[h]) / std::max(lum(e[h]), 1e-12f));
                    write_png(base + "-gref.png", scatter_to_image(gb, gr), 1.f);
                }
                sum[si * ks.size() + ki] += mse;
                better[si * ks.size() + ki] += mse < mse_prior;
                std::printf(" %d/%d %.5f", spp, k, mse);
            }
        }
        std::printf("\n");
        std::fflush(stdout);
        if (tsv) {   // per hit: ref, prior, regather (first spp), then each k's corrected luminance / prior's
            const std::vector<Vec3f> rh = gather_hits(gb, ref);
            std::fprintf(tsv, "# view %s pixels %d scale %.9g\n", bs.name.c_str(), size * size, double(tonemap_scale(ref)));
            for (size_t h = 0; h < gb.n_hits(); ++h) {
                std::fprintf(tsv, "%lld %.6g %.6g %.6g %.6g %.6g %.6g %.6g %.6g %.6g", (long long)gb.hit_pixels[h], double(rh[h].x),
                             double(rh[h].y), double(rh[h].z), double(e[h].x), double(e[h].y), double(e[h].z), double(rg_first[h].x),
                             double(rg_first[h].y), double(rg_first[h].z));
                for (const std::vector<Vec3f> &c : corrected_first) std::fprintf(tsv, " %.6g", double(lum(c[h]) / std::max(lum(e[h]), 1e-12f)));
                std::fprintf(tsv, "\n");
            }
        }
        ++views;
    }
    if (tsv) std::fclose(tsv);
    if (views == 0) return 1;
    std::printf("\n| variant (spp per point / k) | MSE | / prior | views better | tracing s per view |\n|---|---|---|---|---|\n");
    std::printf("| prior | %.5f | 1 | | |\n", sum_prior / views);
    for (size_t si = 0; si < spps.size(); ++si)
        std::printf("| %d / regather | %.5f | %.3f | %d/%d | |\n", spps[si], regather_mse[si] / views, regather_mse[si] / sum_prior,
                    regather_better[si], views);
    for (size_t si = 0; si < spps.size(); ++si)
        for (size_t ki = 0; ki < ks.size(); ++ki) {
            const size_t v = si * ks.size() + ki;
            std::printf("| %d / %s | %.5f | %.3f | %d/%d | %.2f |\n", spps[si], ks[ki] ? std::to_string(ks[ki]).c_str() : "all",
                        sum[v] / views, sum[v] / sum_prior, better[v], views, trace_s[si] / views);
        }
    return 0;
}
