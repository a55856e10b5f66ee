// prior_features.cpp: does the transport prior know where it errs? (issue #30, deliverable 1 and 4)
// For every view `ltm eval` scores, writes one row per hit pixel: the path-traced reference E⁺, the
// shipped prior's Ê⁺ (its settings and its auto point count), and quantities the prior computes on
// the way that a network could be given as inputs:
//   e1     the prior's Ê⁺ with one bounce (its first bounce; the rest is inter-reflection),
//   closure c(p), the share of the receiver's hemisphere that meets a disc (1 − its open share),
//   eu     the same exitance gathered without occlusion (Ê⁺ unoccluded, closure 1): where occlusion
//          changes the answer most is where the prior's visibility, blended from clusters, decides,
//   albedo at the receiver,
//   ef     the part of Ê⁺ that came through the tree's aggregates (far subtrees; the rest from nodes
//          summed exactly: the near field): how much of a receiver's light the prior carries from far,
// and per view the normaliser of the prior inputs (S_c Σ_{k=1..D} ρ̄_c^k) and the tone-mapping scale
// of the view metric (eval/metrics.h), so scripts/analysis/prior_error_features.py can fit the
// prior's log error on some views and score the corrected views on others with the eval's MSE.
//   build/bench/prior_features SCENES REF_CACHE OUT.tsv [size=96] [ref_spp=1024]
// SCENES: a seed range A:B of generated houses (GenConfig{}) or scene files / builtin:NAME,
// comma-separated. References come from (and go to) the cache `ltm eval --ref-cache` uses.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ltm/core/log.h"
#include "ltm/core/startup.h"
#include "ltm/core/tonemap.h"
#include "ltm/eval/eval_setup.h"
#include "ltm/eval/metrics.h"
#include "ltm/eval/reference_cache.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/scene_points.h"
#include "ltm/scene/scene_loader.h"
#include "ltm/transport/transport_prior.h"
#include "bench_scenes.h"
#include "shipped_prior.h"

using namespace ltm;

namespace {
constexpr int k_bounces = 5;   // the shipped prior's D

std::vector<Vec3f> gather(const TransportPrior &prior, const GBuffer &gb, std::vector<Vec3f> *far = nullptr) {
    std::vector<Vec3f> out(gb.n_hits());
    if (far) far->assign(gb.n_hits(), Vec3f(0.f));
    gather_transport_prior(prior, &gb.position[0].x, &gb.normal[0].x, 3, gb.n_hits(), &out[0].x, far ? &(*far)[0].x : nullptr);
    return out;
}
}  // namespace

int main(int argc, char **argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: %s SCENES REF_CACHE OUT.tsv [size=96] [ref_spp=1024]\n", argv[0]);
        return 1;
    }
    configure_process();
    set_log_level(LogLevel::quiet);
    const std::string range = argv[1], cache = argv[2], out_path = argv[3];
    const int size = argc > 4 ? std::atoi(argv[4]) : 96, ref_spp = argc > 5 ? std::atoi(argv[5]) : 1024;
    const std::vector<bench::BenchScene> scene_list = bench::bench_scenes(range);
    FILE *out = std::fopen((out_path + ".tmp").c_str(), "w");
    if (!out) {
        std::fprintf(stderr, "prior_features: cannot write %s.tmp\n", out_path.c_str());
        return 1;
    }
    // Per view a line "# view NAME pixels W*H scale S norm r g b", then one line per hit.
    std::fprintf(out, "# columns: pixel ref_r ref_g ref_b e_r e_g e_b e1_r e1_g e1_b eu_r eu_g eu_b closure alb_r alb_g alb_b ef_r ef_g ef_b\n");
    try {
        for (const bench::BenchScene &bs : scene_list) {
            const std::string &name = bs.name;
            const Scene scene = bench::load_bench_scene(bs);
            const EmbreeAccel accel(scene);
            const Camera cam = eval_view_camera(scene, 0, 1, size, size);
            const PathTracerConfig cfg = eval_tracer_config(0, EvalRole::reference);
            const PathTracer pt(accel, cfg);
            const GBuffer gb = render_gbuffer(accel, cam);
            if (gb.n_hits() == 0) continue;
            const Image ref = reference_irradiance(cache, scene, cam, gb, pt, cfg, ref_spp, {{"scene", name}}).indirect;
            const std::vector<Vec3f> ref_hits = gather_hits(gb, ref);
            const ScenePoints sp = sample_scene_points(accel, auto_scene_points(scene), 0, true, k_buried_spacings);
            const size_t m = sp.points.size();
            const float spacing = float(std::sqrt(scene.total_area() / double(m)));
            const TransportPrior prior = bench::solve_shipped_prior(sp, spacing * spacing, k_bounces);
            std::vector<Vec3f> ef;
            const std::vector<Vec3f> e = gather(prior, gb, &ef);
            const std::vector<Vec3f> e1 = gather(bench::solve_shipped_prior(sp, spacing * spacing, 1), gb);
            TransportPrior ones = prior;   // exitance 1 everywhere: the gather returns the closure c(p)
            ones.exitance.assign(m, Vec3f{1.f, 1.f, 1.f});
            ones.tree_sums = nullptr;
            const std::vector<Vec3f> closure = gather(ones, gb);
            TransportPrior open = prior;   // the same exitance, no occlusion and closure 1, dense rows
            open.visibility = ClusterVisibility{};
            open.tree = nullptr, open.tree_sums = nullptr;
            const std::vector<Vec3f> eu = gather(open, gb);
            // The prior inputs' normaliser S_c Σ_{k=1..D} ρ̄_c^k (ρ̄: the points' mean albedo).
            Vec3f rho{0.f, 0.f, 0.f};
            for (size_t j = 0; j < m; ++j)
                for (int c = 0; c < 3; ++c) rho[c] += sp.points.at(j, 6 + c) / float(m);
            Vec3f norm;
            for (int c = 0; c < 3; ++c) {
                double s = 0, p = 1;
                for (int k = 1; k <= k_bounces; ++k) p *= rho[c], s += p;
                norm[c] = float(double(sp.emission_scale[c]) * s);
            }
            std::fprintf(out, "# view %s pixels %d scale %.9g norm %.9g %.9g %.9g points %zu\n", name.c_str(), size * size,
                         double(tonemap_scale(ref)), double(norm[0]), double(norm[1]), double(norm[2]), m);
            for (size_t h = 0; h < gb.n_hits(); ++h) {
                const Vec3f &r = ref_hits[h], &a = gb.albedo[h];
                std::fprintf(out, "%lld %.6g %.6g %.6g %.6g %.6g %.6g %.6g %.6g %.6g %.6g %.6g %.6g %.5f %.4f %.4f %.4f %.6g %.6g %.6g\n",
                             (long long)gb.hit_pixels[h], double(r.x), double(r.y), double(r.z), double(e[h].x), double(e[h].y),
                             double(e[h].z), double(e1[h].x), double(e1[h].y), double(e1[h].z), double(eu[h].x), double(eu[h].y),
                             double(eu[h].z), double(closure[h].x), double(a.x), double(a.y), double(a.z), double(ef[h].x),
                             double(ef[h].y), double(ef[h].z));
            }
            std::fprintf(stderr, "%s: %zu hits, %zu points\n", name.c_str(), gb.n_hits(), m);
        }
    } catch (const std::exception &ex) {
        std::fclose(out);
        std::remove((out_path + ".tmp").c_str());
        std::fprintf(stderr, "prior_features: error: %s\n", ex.what());
        return 1;
    }
    std::fclose(out);
    std::rename((out_path + ".tmp").c_str(), out_path.c_str());
    return 0;
}
