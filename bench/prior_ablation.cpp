// prior_ablation.cpp: the transport prior's occlusion settings against path-traced E⁺ on the
// validation views `ltm eval` uses (issue #10: the shipped model's Ê⁺ is this prior). For each
// setting: MSE and SSIM of the views (eval/metrics.h, as `ltm eval` computes them), views that
// beat the flat oracle, level ratios in [0.8, 1.25], and the solve time. References come from the
// same cache as `ltm eval --ref-cache` (identical key: scene, camera, spp and tracer seed), so
//   build/bench/prior_ablation 100000:100032 refs-val [size=64] [ref_spp=256] [H:C[:S[:F[:D[:B[:K[:L[:P[:O[:T]]]]]]]]]] ...]
// (or scene files and builtin:NAME, comma-separated, in place of the seed range)
// reuses `ltm eval --scenes 100000:100032 --width 64 --height 64 --ref-spp 256 --ref-cache refs-val`.
// PRIOR_ABLATION_M=M samples M scene points (default 8 192), PRIOR_ABLATION_POINT_SEED=S with seed S. PRIOR_ABLATION_REF_DEPTH=D traces the reference with max_depth D (E⁺ from bounces 1 … D).
// PRIOR_ABLATION_POINT_SETS=K (default 1) solves each setting on K independent point sets (seeds
// S … S+K−1) and scores their average: the prior's view error then splits into the references' own
// noise (PRIOR_ABLATION_REF_NOISE=1: the twin `ltm eval --ref-noise` caches), the point set's variance
// and what stays in the average over infinitely many sets (its bias), the part that neither more
// point sets nor more points of the same kind remove (see the table's columns).
// With PRIOR_ABLATION_PNG=DIR set, each view is also written as DIR/seed-N.png: reference | each
// setting, tone mapped by the reference (eval/metrics.h) and enlarged 3×.
#include <chrono>
#include <cmath>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/core/startup.h"
#include "ltm/core/tonemap.h"
#include "ltm/eval/eval_setup.h"
#include "ltm/eval/field_metrics.h"
#include "ltm/eval/image_grid.h"
#include "ltm/eval/metrics.h"
#include "ltm/eval/reference_cache.h"
#include "ltm/transport/transport_prior.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/scene/scene_loader.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/scene_points.h"
#include "bench_scenes.h"

using namespace ltm;

namespace {
struct Setting {
    std::string name;   ///< "H:C[:S[:F[:D[:B[:K[:L[:P[:O[:T]]]]]]]]]"; "0:0" = no occlusion
    float voxel_spacings;
    int clusters;
    float splat_spacings;   ///< VisibilityOptions::splat_spacings
    float area_factor;      ///< node area = factor · A / M
    float disc_spacings;    ///< VisibilityOptions::disc_spacings
    PriorBalance balance;   ///< 0 per channel, 1 grey, 2 none
    int bounces;            ///< D (default 8, as cpu-tp.json until v0.8; v0.9 uses 5)
    int blend;              ///< VisibilityOptions::blend (default 1)
    bool patches;           ///< the near field by square patches (solve_transport_prior's `patches`)
    int open_rays;          ///< VisibilityOptions::open_rays (rays per side; 0 = closed rows)
    float theta;            ///< the cluster tree's opening bound (transport/prior_hierarchy.h; 0 = dense rows)
};
struct Sums {
    double mse = 0, ssim = 0, seconds = 0;
    double mse_single = 0;   ///< mean over the K point sets of each one's own MSE
    int beats_flat = 0, in_band = 0, views = 0;
};
}  // namespace

int main(int argc, char **argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s A:B REF_CACHE_DIR [size=64] [ref_spp=256] [H:C[:S[:F[:D[:B[:K[:L[:P[:O[:T]]]]]]]]]] ...]\n", argv[0]);
        return 1;
    }
    configure_process();
    set_log_level(LogLevel::quiet);
    const std::string range = argv[1];
    // Scenes: a seed range A:B of generated houses, or scene files (and builtin:NAME) separated by commas.
    const std::vector<bench::BenchScene> scene_list = bench::bench_scenes(range);
    const std::string cache = argv[2];
    const int size = argc > 3 ? std::atoi(argv[3]) : 64, ref_spp = argc > 4 ? std::atoi(argv[4]) : 256;
    // Settings from the command line (fields below), else a default sweep.
    std::vector<Setting> settings;
    std::vector<std::string> names;
    for (int i = 5; i < argc; ++i) names.push_back(argv[i]);
    if (names.empty()) names = {"0:0", "2:1024", "2:2048", "2:4096", "1.5:2048", "3:2048"};
    for (const std::string &n : names) {
        // Fields H:C[:S[:F[:D[:B[:K[:L[:P[:O[:T]]]]]]]]]: voxel edge, clusters, then optional the tangent splat, a
        // factor on the node area a (with rows normalised, a only sets the near-field term a/π and, with P, the patches' side and reach), a
        // disc radius (transport/disc_occluder.h; 0 = voxels), lengths in spacings; the power balance
        // B (PriorBalance: 0 per channel, 1 grey, 2 none), the bounces K (0 = 8) and the clusters a
        // receiver's visibility blends L (VisibilityOptions::blend; 0 = 1); P = 1: the near field
        // by square patches (transport/patch_form_factor.h); O > 0: rows sum to each receiver's closure
        // from O × O rays per cluster centre (VisibilityOptions::open_rays); T > 0: through the cluster
        // tree with opening bound T (transport/prior_hierarchy.h).
        std::vector<float> f;
        for (size_t b = 0; b <= n.size();) {
            const size_t e = std::min(n.find(':', b), n.size());
            f.push_back(std::stof(n.substr(b, e - b)));
            b = e + 1;
        }
        if (f.size() < 2 || f.size() > 11 || (f.size() > 5 && !(f[5] == 0.f || f[5] == 1.f || f[5] == 2.f))) {
            std::fprintf(stderr, "prior_ablation: setting '%s': expected H:C[:S[:F[:D[:B[:K[:L[:P[:O[:T]]]]]]]]]\n", n.c_str());
            return 1;
        }
        f.resize(11, 0.f);
        settings.push_back({n, f[0], int(f[1]), f[2], f[3] > 0.f ? f[3] : 1.f, f[4], PriorBalance(int(f[5])), f[6] > 0.f ? int(f[6]) : 8,
                            f[7] > 0.f ? int(f[7]) : 1, f[8] > 0.f, int(f[9]), f[10]});
    }
    std::vector<Sums> sums(settings.size());
    const int point_sets = std::getenv("PRIOR_ABLATION_POINT_SETS") ? std::atoi(std::getenv("PRIOR_ABLATION_POINT_SETS")) : 1;
    if (point_sets < 1) {
        std::fprintf(stderr, "prior_ablation: PRIOR_ABLATION_POINT_SETS must be >= 1\n");
        return 1;
    }
    // PRIOR_ABLATION_POINT_SEED=S: the (first) scene points' sampling seed (default 0, as `ltm eval`).
    const uint64_t point_seed = std::getenv("PRIOR_ABLATION_POINT_SEED") ? std::stoull(std::getenv("PRIOR_ABLATION_POINT_SEED")) : 0;
    const bool ref_noise = std::getenv("PRIOR_ABLATION_REF_NOISE") != nullptr;
    double floor_sum = 0;   // Σ over views of the references' own noise (ref_noise)
    int floor_views = 0;
    try {
        for (const bench::BenchScene &bs : scene_list) {
            const std::string &name = bs.name;
            Scene scene = bench::load_bench_scene(bs);
            // PRIOR_ABLATION_CONDUCTOR_ALBEDO=1: conductors' scene points carry their F0 as albedo
            // (else the material's unused diffuse albedo, 0.8 by default). The reference is
            // unchanged: the path tracer reads only a conductor's F0 and roughness.
            if (std::getenv("PRIOR_ABLATION_CONDUCTOR_ALBEDO"))
                for (Material &mat : scene.materials)
                    if (mat.bsdf == BsdfKind::conductor) mat.albedo = Texture::constant(mat.specular);
            const EmbreeAccel accel(scene);
            // The eval's camera and reference tracer (eval/experiment.cpp: view 0 of 1, role 1).
            const Camera cam = eval_view_camera(scene, 0, 1, size, size);
            PathTracerConfig cfg = eval_tracer_config(0, EvalRole::reference);
            // PRIOR_ABLATION_REF_DEPTH=D: the reference's E⁺ with at most D scattering events (its
            // bounces 1 … D, against the prior's D bounces); the cache key includes the depth.
            if (const char *depth = std::getenv("PRIOR_ABLATION_REF_DEPTH")) cfg.max_depth = std::atoi(depth);
            const PathTracer pt(accel, cfg);
            const GBuffer gb = render_gbuffer(accel, cam);
            if (gb.n_hits() == 0) continue;
            bool cached = false;
            const Image ref = reference_irradiance(cache, scene, cam, gb, pt, cfg, ref_spp, {{"scene", name}}, &cached)
                                  .indirect;
            const std::vector<Vec3f> ref_hits = gather_hits(gb, ref);
            const Color3d mc = mean_color(ref_hits);
            const Image flat = scatter_to_image(gb, std::vector<Vec3f>(gb.n_hits(), Vec3f{float(mc[0]), float(mc[1]), float(mc[2])}));
            const double flat_mse = compare_images(flat, ref).mse;
            if (ref_noise) {   // as `ltm eval --ref-noise`: against the reference's twin
                PathTracerConfig twin_cfg = eval_tracer_config(0, EvalRole::reference_twin);
                twin_cfg.max_depth = cfg.max_depth;   // the reference's depth (PRIOR_ABLATION_REF_DEPTH)
                const Image twin = reference_irradiance(cache, scene, cam, gb, PathTracer(accel, twin_cfg), twin_cfg, ref_spp,
                                                        {{"scene", name}, {"role", "reference twin"}})
                                       .indirect;
                floor_sum += reference_noise_mse(ref, twin), ++floor_views;
            }
            // PRIOR_ABLATION_BURIED=x: scene points buried within x nominal spacings count as enclosed.
            const char *buried = std::getenv("PRIOR_ABLATION_BURIED");
            // PRIOR_ABLATION_M=M: M scene points instead of the shipped 8 192.
            const int64_t n_points = std::getenv("PRIOR_ABLATION_M") ? std::atoll(std::getenv("PRIOR_ABLATION_M")) : 8192;
            std::vector<ScenePoints> point_set;
            for (int k = 0; k < point_sets; ++k)
                point_set.push_back(sample_scene_points(accel, n_points, point_seed + uint64_t(k), true, buried ? std::stof(buried) : k_buried_spacings));
            std::string per_setting;   // this view's MSE per setting, for the log
            std::vector<Image> strip{ref};   // PRIOR_ABLATION_PNG=dir: reference | each setting, per view
            for (size_t s = 0; s < settings.size(); ++s) {
                const auto t0 = std::chrono::steady_clock::now();
                VisibilityOptions vis;
                vis.voxel_spacings = settings[s].voxel_spacings;
                if (settings[s].clusters > 0) vis.clusters = settings[s].clusters;
                vis.splat_spacings = settings[s].splat_spacings;
                vis.disc_spacings = settings[s].disc_spacings;
                vis.blend = settings[s].blend;
                vis.open_rays = settings[s].open_rays;
                // Ê⁺ of each point set, and their mean.
                std::vector<Vec3f> e(gb.n_hits(), Vec3f{0.f, 0.f, 0.f});
                double single = 0, scoring = 0;   // scoring: each set's own MSE, not part of the timed solve + gather
                for (const ScenePoints &sp : point_set) {
                    const float spacing = float(std::sqrt(scene.total_area() / double(sp.points.size())));
                    const TransportPrior prior =
                        solve_transport_prior(sp.points, settings[s].area_factor * spacing * spacing, settings[s].bounces, &sp.emission_scale,
                                              vis, nullptr, settings[s].balance, settings[s].patches, settings[s].theta);
                    std::vector<Vec3f> ek(gb.n_hits());
                    gather_transport_prior(prior, &gb.position[0].x, &gb.normal[0].x, 3, gb.n_hits(), &ek[0].x);
                    if (point_sets > 1) {
                        const auto ts = std::chrono::steady_clock::now();
                        single += compare_images(scatter_to_image(gb, ek), ref).mse;
                        scoring += seconds_since(ts);
                    }
                    for (size_t h = 0; h < e.size(); ++h) e[h] += ek[h] * (1.f / float(point_sets));
                }
                const double secs = (seconds_since(t0) - scoring) / point_sets;
                const ImageMetrics m = compare_images(scatter_to_image(gb, e), ref);
                sums[s].mse_single += point_sets > 1 ? single / point_sets : m.mse;
                const FieldMetrics f = compare_fields(e, ref_hits);
                Sums &x = sums[s];
                x.mse += m.mse, x.ssim += m.ssim, x.seconds += secs, ++x.views;
                x.beats_flat += m.mse < flat_mse, x.in_band += f.level_in_band();
                per_setting += " " + std::to_string(m.mse) + " (level " + std::to_string(f.level_ratio).substr(0, 5) + ", chroma " +
                               std::to_string(f.chroma_error).substr(0, 5) + ")";
                strip.push_back(scatter_to_image(gb, e));
            }
            if (const char *dir = std::getenv("PRIOR_ABLATION_PNG")) {
                const float scale = tonemap_scale(ref);
                for (Image &im : strip) im = resize_nearest(tonemap(im, scale), 3 * size, 3 * size);
                write_png(std::string(dir) + "/" + name + ".png", hconcat(strip));
            }
            std::fprintf(stderr, "%s%s: flat %.4f, MSE%s\n", name.c_str(), cached ? " (cached reference)" : "", flat_mse, per_setting.c_str());
        }
        if (point_sets > 1)
            std::printf("%d point sets per view (seeds %llu … %llu): MSE is their average's. Split of one set's MSE: its variance "
                        "V = (one set's − the average's) · K/(K−1), the infinite average's B = average's − V/K%s.\n\n",
                        point_sets, (unsigned long long)point_seed, (unsigned long long)(point_seed + point_sets - 1),
                        ref_noise ? ", of which the references' noise F" : "");
        std::printf("| occlusion H:C[:S[:F[:D[:B[:K[:L[:P[:O[:T]]]]]]]]] (voxel edge in point spacings : clusters : tangent splat in spacings : node-area factor : disc radius in spacings : balance 0 per channel, 1 grey, 2 none : bounces : blended clusters : patches : open rays : tree opening bound) | views | MSE | SSIM | beats flat | level in band | solve + gather (s) |%s\n|---|---|---|---|---|---|---|%s\n",
                    point_sets > 1 ? " one set's MSE | V | B |" : "", point_sets > 1 ? "---|---|---|" : "");
        for (size_t s = 0; s < settings.size(); ++s) {
            const Sums &x = sums[s];
            const double n = std::max(1, x.views);
            std::printf("| %s | %d | %.4f | %.3f | %d | %d | %.2f |", settings[s].name.c_str(), x.views, x.mse / n, x.ssim / n, x.beats_flat,
                        x.in_band, x.seconds / n);
            if (point_sets > 1) {
                const double one = x.mse_single / n, avg = x.mse / n;
                const double v = (one - avg) * point_sets / (point_sets - 1), b = avg - v / point_sets;
                std::printf(" %.4f | %.4f | %.4f |", one, v, b);
            }
            std::printf("\n");
        }
        if (ref_noise) std::printf("\nThe references' own noise F (mean over views): %.4f\n", floor_sum / std::max(1, floor_views));
    } catch (const std::exception &e) {
        std::fprintf(stderr, "prior_ablation: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
