// prior_scaling.cpp: how the transport prior's cost grows with the scene points M, dense rows
// against the cluster tree (issue #31; transport/prior_hierarchy.h). Per scene, M and θ, with the
// shipped prior's settings (configs/model/cpu-tp-open.json: occlusion by discs of one spacing, 1 024
// clusters, blend 4, patches, open rays 8, no balance, D = 5): the seconds of sampling, clusters and
// visibility, the solve and the gather at the G-buffer of the eval's first view (size²), the tree's
// mean work per receiver (tree nodes visited, aggregates, nodes summed exactly), the tree's bytes,
// and the relative RMS difference of the gathered E⁺ to the dense rows' at the same M (where the
// dense rows are run: θ list containing 0). Peak memory is the process's: run one M per process
// (`/usr/bin/time -f %M`) for it.
//   build/bench/prior_scaling SCENES M1,M2,... THETA1,THETA2,... [size=128] [clusters=1024]
// SCENES: scene files, builtin:NAME or generated seeds as seed:N, comma-separated.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/core/startup.h"
#include "ltm/eval/eval_setup.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/scene_points.h"
#include "ltm/scene/scene_loader.h"
#include "ltm/transport/transport_prior.h"
#include "scene_list.h"

using namespace ltm;

int main(int argc, char **argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: %s SCENES M1,M2,... THETA1,THETA2,... [size=128] [clusters=1024]\n", argv[0]);
        return 1;
    }
    configure_process();
    set_log_level(LogLevel::quiet);
    const std::vector<std::string> scenes = bench::split_commas(argv[1]);
    std::vector<int64_t> counts;
    std::vector<float> thetas;
    for (const std::string &m : bench::split_commas(argv[2])) counts.push_back(std::atoll(m.c_str()));
    for (const std::string &t : bench::split_commas(argv[3])) thetas.push_back(std::stof(t));
    const int size = argc > 4 ? std::atoi(argv[4]) : 128, clusters = argc > 5 ? std::atoi(argv[5]) : 1024;
    std::printf("| scene | M | θ | clusters + visibility (s) | solve (s) | gather %d² (s) | visited / aggregates / exact per receiver | tree MB | E⁺ vs dense (rel. RMS) |\n"
                "|---|---|---|---|---|---|---|---|---|\n",
                size);
    try {
        for (const std::string &name : scenes) {
            const bool seed = name.rfind("seed:", 0) == 0;
            const Scene scene = seed ? generate_indoor(GenConfig{}, std::stoull(name.substr(5))).scene : load_scene(name);
            const EmbreeAccel accel(scene);
            const GBuffer gb = render_gbuffer(accel, eval_view_camera(scene, 0, 1, size, size));
            for (int64_t M : counts) {
                const auto ts = std::chrono::steady_clock::now();
                const ScenePoints sp = sample_scene_points(accel, M, 0, true);
                const double sample_s = seconds_since(ts);
                const float spacing = float(std::sqrt(scene.total_area() / double(sp.points.size())));
                std::vector<Vec3f> dense_e;
                for (float theta : thetas) {
                    VisibilityOptions vis;
                    vis.voxel_spacings = 1.f, vis.clusters = clusters, vis.disc_spacings = 1.f, vis.blend = 4, vis.open_rays = 8;
                    const auto t0 = std::chrono::steady_clock::now();
                    const TransportPrior prior = solve_transport_prior(sp.points, spacing * spacing, 5, &sp.emission_scale, vis, nullptr,
                                                                       PriorBalance::none, true, theta);
                    const double solve_all = seconds_since(t0);
                    // The visibility alone (the same call without bounces), to split the solve's time.
                    const auto tv = std::chrono::steady_clock::now();
                    solve_transport_prior(sp.points, spacing * spacing, 0, &sp.emission_scale, vis, nullptr, PriorBalance::none, true, 0.f);
                    const double vis_s = seconds_since(tv);
                    const auto tg = std::chrono::steady_clock::now();
                    std::vector<Vec3f> e(gb.n_hits());
                    gather_transport_prior(prior, &gb.position[0].x, &gb.normal[0].x, 3, gb.n_hits(), &e[0].x);
                    const double gather_s = seconds_since(tg);
                    double visited = 0, aggregates = 0, exact = 0, mb = 0;
                    if (prior.tree) {
                        PriorTree::Scratch scratch;
                        const size_t step = std::max<size_t>(1, gb.n_hits() / 512);
                        size_t n = 0;
                        for (size_t q = 0; q < gb.n_hits(); q += step, ++n) {
                            uint32_t ids[ClusterVisibility::k_candidates];
                            float w[ClusterVisibility::k_candidates];
                            const int K = prior.visibility.receiver_clusters(gb.position[q], gb.normal[q], ids, w);
                            const PriorTree::Work work = prior.tree->count(gb.position[q], gb.normal[q], {ids, w, K}, scratch);
                            visited += double(work.visited), aggregates += double(work.aggregates), exact += double(work.exact);
                        }
                        visited /= double(n), aggregates /= double(n), exact /= double(n);
                        mb = double(prior.tree->bytes()) / 1e6;
                    }
                    std::string diff = "—";
                    if (theta == 0.f) {
                        dense_e = e;
                    } else if (!dense_e.empty()) {
                        double num = 0, den = 0;
                        for (size_t q = 0; q < e.size(); ++q)
                            for (int c = 0; c < 3; ++c) {
                                const double a = e[q][c], b = dense_e[q][c];
                                num += (a - b) * (a - b), den += b * b;
                            }
                        diff = std::to_string(std::sqrt(num / std::max(den, 1e-30))).substr(0, 6);
                    }
                    std::printf("| %s | %lld | %.2f | %.2f (sample %.2f) | %.2f | %.2f | %.0f / %.0f / %.0f | %.1f | %s |\n", name.c_str(),
                                (long long)M, double(theta), vis_s, sample_s, solve_all - vis_s, gather_s, visited, aggregates, exact, mb,
                                diff.c_str());
                    std::fflush(stdout);
                }
            }
        }
    } catch (const std::exception &e) {
        std::fprintf(stderr, "prior_scaling: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
