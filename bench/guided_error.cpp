// guided_error.cpp: error against a reference vs samples per pixel for BSDF-sampled and guided
// path tracing (issue #11 item 5, paper Fig. 13), at equal spp and at equal time (the guide's
// prediction counted). The figures in docs/results.md come from:
//   build/bench/guided_error SCENE.json WEIGHTS.safetensors [ref_spp=512] [size=128] [guide_points=256] [guide_res=16] [oracle_emission=0]
// MSE and relMSE as `ltm eval` computes them (eval/metrics.h: tone-mapped with the reference's scale).
#include <cstdio>
#include <cstdlib>
#include <string>

#include "ltm/core/log.h"
#include "ltm/core/parallel.h"
#include "ltm/core/rng.h"
#include "ltm/core/startup.h"
#include "ltm/eval/metrics.h"
#include "ltm/infer/guide_builder.h"
#include "ltm/infer/neural_renderer.h"
#include "ltm/nn/torch_runtime.h"
#include "ltm/render/image_renderer.h"
#include "ltm/render/interaction.h"
#include "ltm/scene/scene_loader.h"

using namespace ltm;

namespace {
// Direct light only, as render_pathtraced draws it (jittered pixel samples; diffuse: Le +
// ρ/π·E_direct by NEE + cosine sampling with MIS; conductor: Le + one scattering event).
Image render_direct_only(const PathTracer &pt, const Camera &cam, int spp) {
    const Scene &scene = pt.accel().scene();
    Image out(cam.width, cam.height);
    parallel_for(0, cam.height, 1, [&](int64_t y0, int64_t y1) {
        for (int64_t y = y0; y < y1; ++y)
            for (int x = 0; x < cam.width; ++x) {
                const uint64_t pixel = uint64_t(y) * uint64_t(cam.width) + uint64_t(x);
                Vec3f color(0.f);
                for (int s = 0; s < spp; ++s) {
                    const uint64_t key = pt.stream_key(0xd1ec7ull << 40 | pixel, uint64_t(s));
                    Pcg32 rng(key ^ 0x9e3779b97f4a7c15ull);   // not irradiance_sample's own stream: jitter and light samples independent
                    const float jx = spp == 1 ? 0.5f : rng.next_float(), jy = spp == 1 ? 0.5f : rng.next_float();
                    const Ray ray{cam.eye, cam.ray_direction(float(x) + jx, float(y) + jy)};
                    const auto hit = pt.accel().intersect(ray);
                    if (!hit) continue;
                    const SurfaceInteraction si = make_interaction(scene, ray, *hit);
                    color += si.emitted();
                    if (si.material->bsdf == BsdfKind::diffuse)
                        color += si.albedo() * k_inv_pi * pt.irradiance_sample(si.p, si.front ? si.n : -si.n, key, s, spp, false).direct;
                    else
                        color += pt.reflected_radiance(si, -ray.d, 1, rng);
                }
                out.pixels[size_t(pixel)] = color / float(spp);
            }
    });
    return out;
}
}  // namespace

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
        // The point count `ltm render --method guided` would use (the model's own, or the scene's auto).
        if (apply_point_options(m.model, 0, -1) == k_scene_points_auto) set_auto_scene_points(m.model, scene, false);
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
        // A floor for any guide of the indirect part: an image whose indirect light is exact (the
        // reference's, full minus direct-only at ref_spp) and whose direct light is rendered at the
        // same spp (NEE + BSDF sampling with MIS at the first vertex only).
        const Image ref_direct = render_direct_only(PathTracer(accel, cfg), cam, ref_spp);
        std::printf("scene %s, %dx%d, reference %d spp (%.1f s); guide: %d points × %d² bins, %.1f s to predict\n\n", argv[1], size, size,
                    ref_spp, ref.seconds, guide_points, guide_res, guide.seconds);
        std::printf("| spp | BSDF sampling MSE | relMSE | time | guided MSE | relMSE | render time | guided/BSDF MSE | oracle-guided MSE | oracle/BSDF | exact indirect/BSDF |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
        double pt_seconds_per_spp = 0;
        for (int spp : {1, 2, 4, 8, 16, 64}) {
            cfg.seed = 7;
            PathTracer pt(accel, cfg);
            const RenderedImage a = render_pathtraced(pt, cam, spp);
            pt.set_guide(&guide.cache, 0.25f);
            const RenderedImage g = render_pathtraced(pt, cam, spp);
            pt.set_guide(&oracle, 0.25f);
            const RenderedImage o = render_pathtraced(pt, cam, spp);
            pt.set_guide(nullptr);
            Image exact_indirect = render_direct_only(pt, cam, spp);
            for (size_t i = 0; i < exact_indirect.pixels.size(); ++i)
                exact_indirect.pixels[i] += ref.color.pixels[i] - ref_direct.pixels[i];
            const ImageMetrics ma = compare_images(a.color, ref.color), mg = compare_images(g.color, ref.color),
                               mo = compare_images(o.color, ref.color), me = compare_images(exact_indirect, ref.color);
            pt_seconds_per_spp = std::max(pt_seconds_per_spp, a.seconds / spp);
            std::printf("| %d | %.5f | %.4f | %.2f s | %.5f | %.4f | %.2f s | %.2f | %.5f | %.2f | %.2f |\n", spp, ma.mse, ma.rel_mse, a.seconds,
                        mg.mse, mg.rel_mse, g.seconds, mg.mse / ma.mse, mo.mse, mo.mse / ma.mse, me.mse / ma.mse);
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
