// guided_error.cpp: error against a reference vs samples per pixel for BSDF-sampled and guided
// path tracing (issue #11 item 5, paper Fig. 13), at equal spp and at equal time (the guide's
// prediction counted). The figures in docs/results.md come from:
//   build/bench/guided_error SCENE.json WEIGHTS.safetensors [ref_spp=512] [size=128] [guide_points=256] [guide_res=16] [oracle_emission=0]
// MSE and relMSE as `ltm eval` computes them (eval/metrics.h: tone-mapped with the reference's scale).
#include <cstdio>
#include <cstdlib>
#include <string>

#include "ltm/core/log.h"
#include "ltm/core/startup.h"
#include "ltm/eval/metrics.h"
#include "ltm/infer/guide_builder.h"
#include "ltm/infer/neural_renderer.h"
#include "ltm/nn/torch_runtime.h"
#include "ltm/render/image_renderer.h"
#include "ltm/scene/scene_loader.h"

using namespace ltm;

int main(int argc, char **argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s SCENE.json WEIGHTS.safetensors [ref_spp] [size] [guide_points] [guide_res] [oracle_emission]\n", argv[0]);
        return 1;
    }
    configure_process();
    configure_torch_threads(0);   // torch's and OpenBLAS's pools bounded to the cores, as the CLI does
    set_log_level(LogLevel::quiet);
    const int ref_spp = argc > 3 ? std::atoi(argv[3]) : 512, size = argc > 4 ? std::atoi(argv[4]) : 128;
    const int guide_points = argc > 5 ? std::atoi(argv[5]) : 256, guide_res = argc > 6 ? std::atoi(argv[6]) : 16;
    // oracle_emission = 1: the oracle's bins include the emitters seen directly (L_in, not L_in⁺).
    const bool oracle_emission = argc > 7 && std::atoi(argv[7]) != 0;
    try {
        const Scene scene = load_scene(argv[1]);
        Camera cam = scene.cameras.at(0);
        cam.width = cam.height = size;
        const EmbreeAccel accel(scene);
        PathTracerConfig cfg;
        cfg.seed = 1000;   // the reference's own seed, disjoint from the tested renders'
        const RenderedImage ref = render_pathtraced(PathTracer(accel, cfg), cam, ref_spp);
        LoadedModel m = load_model(argv[2]);
        GuideBuildOptions go;
        go.points = guide_points, go.resolution = guide_res;
        const GuideBuild guide = build_guide_cache(m.model, accel, go);
        // The oracle guide: path-traced L_in⁺ bins at the same points (what a perfect head would
        // predict, up to 16-spp noise per bin) — separates the guiding machinery from the head.
        std::vector<Vec3f> oracle_bins;
        {
            PathTracerConfig ocfg;
            ocfg.seed = 99;
            const PathTracer opt_pt(accel, ocfg);
            const auto &P = guide.cache.positions();
            const auto &N = guide.cache.normals();
            for (size_t c = 0; c < P.size(); ++c) {
                const auto b = opt_pt.incident_radiance_bins(P[c], N[c], c, guide_res, 16, /*with_emission=*/oracle_emission);
                oracle_bins.insert(oracle_bins.end(), b.begin(), b.end());
            }
        }
        const GuideCache oracle(guide_res, guide.cache.positions(), guide.cache.normals(), oracle_bins, guide.cache.radius());
        std::printf("scene %s, %dx%d, reference %d spp (%.1f s); guide: %d points × %d² bins, %.1f s to predict\n\n", argv[1], size, size,
                    ref_spp, ref.seconds, guide_points, guide_res, guide.seconds);
        std::printf("| spp | BSDF sampling MSE | relMSE | time | guided MSE | relMSE | render time | guided/BSDF MSE | oracle-guided MSE | oracle/BSDF |\n|---|---|---|---|---|---|---|---|---|---|\n");
        double pt_seconds_per_spp = 0;
        for (int spp : {1, 2, 4, 8, 16, 64}) {
            cfg.seed = 7;
            PathTracer pt(accel, cfg);
            const RenderedImage a = render_pathtraced(pt, cam, spp);
            pt.set_guide(&guide.cache, 0.25f);
            const RenderedImage g = render_pathtraced(pt, cam, spp);
            pt.set_guide(&oracle, 0.25f);
            const RenderedImage o = render_pathtraced(pt, cam, spp);
            const ImageMetrics ma = compare_images(a.color, ref.color), mg = compare_images(g.color, ref.color),
                               mo = compare_images(o.color, ref.color);
            pt_seconds_per_spp = std::max(pt_seconds_per_spp, a.seconds / spp);
            std::printf("| %d | %.5f | %.4f | %.2f s | %.5f | %.4f | %.2f s | %.2f | %.5f | %.2f |\n", spp, ma.mse, ma.rel_mse, a.seconds, mg.mse,
                        mg.rel_mse, g.seconds, mg.mse / ma.mse, mo.mse, mo.mse / ma.mse);
        }
        // Equal time: BSDF sampling given the guided render's time at 2 and 16 spp plus the guide's.
        std::printf("\nequal time (guide prediction counted):\n\n| guided spp | its total time | BSDF sampling spp in that time | BSDF MSE | guided MSE |\n|---|---|---|---|---|\n");
        for (int spp : {2, 16}) {
            cfg.seed = 7;
            PathTracer pt(accel, cfg);
            pt.set_guide(&guide.cache, 0.25f);
            const RenderedImage g = render_pathtraced(pt, cam, spp);
            const double total = guide.seconds + g.seconds;
            const int eq = std::max(1, int(total / pt_seconds_per_spp));
            pt.set_guide(nullptr);
            const RenderedImage a = render_pathtraced(pt, cam, eq);
            std::printf("| %d | %.1f s | %d | %.5f | %.5f |\n", spp, total, eq, compare_images(a.color, ref.color).mse,
                        compare_images(g.color, ref.color).mse);
        }
    } catch (const std::exception &e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
    return 0;
}
