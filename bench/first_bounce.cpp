// first_bounce.cpp: where the transport prior's first bounce goes wrong (issue #29). The prior's
// E⁺ with one bounce is a gather of B₁ = ρ c Ê_direct at its nodes; its error on a view splits into
//   (a) the nodes' direct light:  Ê_direct(j) of the row-normalised solve against the path tracer's
//       E_direct at the same node (shadow rays against the meshes), and
//   (b) the gather: the view gathered from the exact B₁ = ρ E_direct (the prior's own
//       normalisation, visibility and closure), against the path tracer's one-bounce E⁺.
// Per scene it prints the level (mean luminance ratio) of the prior's one-bounce view, of (b) and of
// the nodes' B₁ (a: power-weighted, i.e. Σ_j lum B̂₁ / Σ_j lum ρE_d, and its quartiles per node).
//   build/bench/first_bounce SCENES REF_CACHE [size=128] [ref_spp=1024] [direct_spp=64]
// FIRST_BOUNCE_PNG=DIR writes DIR/<scene>.png: reference | prior | gather of the exact B₁ (tone mapped
// by the reference, 3× enlarged); FIRST_BOUNCE_DUMP=DIR writes DIR/<scene>.txt, one line per node: its 12
// scene-point columns, the exact B₁ and the prior's B₁. SCENES: scene files and builtin:NAME, comma-separated. The one-bounce references are cached as
// `ltm eval`'s (max_depth 1 in the key; PRIOR_ABLATION_REF_DEPTH=1 of prior_ablation writes the same).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ltm/core/log.h"
#include "ltm/core/parallel.h"
#include "ltm/core/startup.h"
#include "ltm/core/tonemap.h"
#include "ltm/eval/image_grid.h"
#include "ltm/eval/eval_setup.h"
#include "ltm/eval/field_metrics.h"
#include "ltm/eval/metrics.h"
#include "ltm/eval/reference_cache.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/path_tracer.h"
#include "ltm/render/scene_points.h"
#include "ltm/scene/scene_loader.h"
#include "ltm/transport/transport_prior.h"
#include "scene_list.h"
#include "shipped_prior.h"

using namespace ltm;

namespace {
double lum(Vec3f c) { return double(luminance(c)); }

double mean_lum(const std::vector<Vec3f> &v) {
    double s = 0;
    for (const Vec3f &c : v) s += lum(c);
    return v.empty() ? 0.0 : s / double(v.size());
}

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}
}  // namespace

int main(int argc, char **argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s SCENES REF_CACHE [size=128] [ref_spp=1024] [direct_spp=64]\n", argv[0]);
        return 1;
    }
    configure_process();
    set_log_level(LogLevel::quiet);
    const std::vector<std::string> paths = bench::split_commas(argv[1]);
    const std::string cache = argv[2];
    const int size = argc > 3 ? std::atoi(argv[3]) : 128, ref_spp = argc > 4 ? std::atoi(argv[4]) : 1024;
    const int direct_spp = argc > 5 ? std::atoi(argv[5]) : 64;
    const std::vector<std::string> labels = scene_labels(paths);
    std::printf("| scene | prior view level | gather of exact B1: view level | nodes' B1 level (power) | per node B1 ratio q25 / q50 / q75 |\n|---|---|---|---|---|\n");
    try {
        for (size_t si = 0; si < paths.size(); ++si) {
            const Scene scene = load_scene(paths[si]);
            const EmbreeAccel accel(scene);
            const Camera cam = eval_view_camera(scene, 0, 1, size, size);
            PathTracerConfig cfg = eval_tracer_config(0, EvalRole::reference);
            cfg.max_depth = 1;
            const PathTracer pt(accel, cfg);
            const GBuffer gb = render_gbuffer(accel, cam);
            if (gb.n_hits() == 0) continue;
            const Image ref = reference_irradiance(cache, scene, cam, gb, pt, cfg, ref_spp, {{"scene", labels[si]}}).indirect;
            const std::vector<Vec3f> ref_hits = gather_hits(gb, ref);

            // The shipped prior's settings (v0.12: 1:1024:0:1:1:2:D:4:1:8 of prior_ablation), one bounce.
            const ScenePoints sp = sample_scene_points(accel, 8192, 0, true);
            const PointSet &pts = sp.points;
            const float spacing = float(std::sqrt(scene.total_area() / double(pts.size())));
            TransportPrior prior = solve_transport_prior(pts, spacing * spacing, 1, &sp.emission_scale, bench::shipped_visibility(), nullptr,
                                                         PriorBalance::none, true);   // dense rows, as v0.12
            std::vector<Vec3f> e(gb.n_hits());
            gather_transport_prior(prior, &gb.position[0].x, &gb.normal[0].x, 3, gb.n_hits(), &e[0].x);
            const double prior_level = mean_lum(e) / std::max(1e-30, mean_lum(ref_hits));

            // The nodes' exact B₁ = ρ E_direct (path-traced direct light at each node).
            const size_t m = pts.size();
            std::vector<Vec3f> exact(m);
            parallel_for(0, int64_t(m), 64, [&](int64_t b, int64_t e_) {
                for (int64_t j = b; j < e_; ++j) {
                    const Vec3f p = pts.vec3(j, 0), n = pts.vec3(j, 3), rho = pts.vec3(j, 6);
                    const Vec3f ed = pt.irradiance(p, n, uint64_t(j), direct_spp, /*with_indirect=*/false).direct;
                    exact[j] = Vec3f{rho.x * ed.x, rho.y * ed.y, rho.z * ed.z};
                }
            });
            double s_hat = 0, s_exact = 0;
            std::vector<double> ratios;
            const double mean_exact = mean_lum(exact);
            for (size_t j = 0; j < m; ++j) {
                s_hat += lum(prior.exitance[j]), s_exact += lum(exact[j]);
                if (lum(exact[j]) > 0.1 * mean_exact) ratios.push_back(lum(prior.exitance[j]) / lum(exact[j]));
            }
            const Image prior_img = scatter_to_image(gb, e);
            if (std::getenv("FIRST_BOUNCE_DUMP")) {   // every node: p, n, ρ, L, exact B₁, prior B₁
                FILE *f = std::fopen((std::string(std::getenv("FIRST_BOUNCE_DUMP")) + "/" + labels[si] + ".txt").c_str(), "w");
                for (size_t j = 0; j < m; ++j) {
                    for (int c = 0; c < 12; ++c) std::fprintf(f, "%g ", pts.at(j, size_t(c)));
                    std::fprintf(f, "%g %g %g %g %g %g\n", exact[j].x, exact[j].y, exact[j].z, prior.exitance[j].x,
                                 prior.exitance[j].y, prior.exitance[j].z);
                }
                std::fclose(f);
            }
            prior.exitance = exact;
            gather_transport_prior(prior, &gb.position[0].x, &gb.normal[0].x, 3, gb.n_hits(), &e[0].x);
            if (const char *dir = std::getenv("FIRST_BOUNCE_PNG")) {   // reference | prior | gather of exact B₁
                std::vector<Image> strip{ref, prior_img, scatter_to_image(gb, e)};
                const float scale = tonemap_scale(ref);
                for (Image &im : strip) im = resize_nearest(tonemap(im, scale), 3 * size, 3 * size);
                write_png(std::string(dir) + "/" + labels[si] + ".png", hconcat(strip));
            }
            const double gather_level = mean_lum(e) / std::max(1e-30, mean_lum(ref_hits));
            std::printf("| %s | %.3f | %.3f | %.3f | %.2f / %.2f / %.2f |\n", labels[si].c_str(), prior_level, gather_level,
                        s_hat / std::max(1e-30, s_exact), quantile(ratios, 0.25), quantile(ratios, 0.5), quantile(ratios, 0.75));
            std::fflush(stdout);
        }
    } catch (const std::exception &ex) {
        std::fprintf(stderr, "first_bounce: error: %s\n", ex.what());
        return 1;
    }
    return 0;
}
