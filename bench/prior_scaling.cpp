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
// PRIOR_SCALING_NODE_INTERP=1 also prints, per row, what the traced bounce's cheaper Ê⁺ at its hits
// costs in accuracy: the gather at the M nodes themselves, then each G-buffer query's E⁺ interpolated
// from them (PointInterpolator: the K nearest nodes on its surface); its time and its relative RMS
// difference to the query's own gather, beside the same difference between two point sets (seeds 0
// and 1: the prior's own sampling noise, the scale the interpolation's error is to be read against).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/core/parallel.h"
#include "ltm/core/startup.h"
#include "ltm/eval/eval_setup.h"
#include "ltm/points/point_interpolation.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/scene_points.h"
#include "ltm/scene/scene_loader.h"
#include "ltm/transport/transport_prior.h"
#include "scene_list.h"

using namespace ltm;

namespace {
// √(Σ (a − b)²) / √(Σ b²) over every channel.
double relative_rms(const std::vector<Vec3f> &a, const std::vector<Vec3f> &b) {
    double num = 0, den = 0;
    for (size_t q = 0; q < a.size(); ++q)
        for (int c = 0; c < 3; ++c) {
            const double x = a[q][c], y = b[q][c];
            num += (x - y) * (x - y), den += y * y;
        }
    return std::sqrt(num / std::max(den, 1e-30));
}

// E⁺ at each query interpolated from the nodes (PointInterpolator, as the renderer's traced bounce
// does); a query that no node serves keeps its own gather, as the renderer decodes it. -> values, misses
std::pair<std::vector<Vec3f>, size_t> interpolate_nodes(const TransportPrior &prior, const std::vector<Vec3f> &node_e, const GBuffer &gb,
                                                        const std::vector<Vec3f> &gathered, float spacing) {
    const PointInterpolator interp(prior.position, prior.normal, spacing);
    std::vector<Vec3f> out(gathered);
    std::vector<uint8_t> miss(gb.n_hits(), 0);
    parallel_for(0, int64_t(gb.n_hits()), 256, [&](int64_t b, int64_t e) {
        for (int64_t q = b; q < e; ++q) miss[size_t(q)] = !interp.interpolate(gb.position[size_t(q)], gb.normal[size_t(q)], node_e.data(), out[size_t(q)]);
    });
    return {out, size_t(std::count(miss.begin(), miss.end(), uint8_t(1)))};
}
}  // namespace

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
    const char *interp_env = std::getenv("PRIOR_SCALING_NODE_INTERP");
    const bool interp_nodes = interp_env && std::atoi(interp_env) > 0;
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
                        diff = std::to_string(relative_rms(e, dense_e)).substr(0, 6);
                    }
                    std::printf("| %s | %lld | %.2f | %.2f (sample %.2f) | %.2f | %.2f | %.0f / %.0f / %.0f | %.1f | %s |\n", name.c_str(),
                                (long long)M, double(theta), vis_s, sample_s, solve_all - vis_s, gather_s, visited, aggregates, exact, mb,
                                diff.c_str());
                    if (interp_nodes) {
                        const auto tn = std::chrono::steady_clock::now();
                        std::vector<Vec3f> node_e(prior.position.size());
                        gather_transport_prior(prior, &prior.position[0].x, &prior.normal[0].x, 3, node_e.size(), &node_e[0].x);
                        const double node_s = seconds_since(tn);
                        const auto ti = std::chrono::steady_clock::now();
                        const auto [interp, misses] = interpolate_nodes(prior, node_e, gb, e, spacing);
                        const double interp_s = seconds_since(ti);
                        const ScenePoints sp1 = sample_scene_points(accel, M, 1, true);
                        const float spacing1 = float(std::sqrt(scene.total_area() / double(sp1.points.size())));
                        const TransportPrior prior1 = solve_transport_prior(sp1.points, spacing1 * spacing1, 5, &sp1.emission_scale, vis,
                                                                            nullptr, PriorBalance::none, true, theta);
                        std::vector<Vec3f> e1(gb.n_hits());
                        gather_transport_prior(prior1, &gb.position[0].x, &gb.normal[0].x, 3, gb.n_hits(), &e1[0].x);
                        std::printf("|   nodes interpolated | | | gather at the nodes %.2f s | interpolation %.3f s (%.1f %% of queries gathered) "
                                    "| rel. RMS to the gather %.4f | two point sets' gathers: rel. RMS %.4f | | |\n",
                                    node_s, interp_s, 100.0 * double(misses) / double(std::max<size_t>(1, gb.n_hits())),
                                    relative_rms(interp, e), relative_rms(e1, e));
                        std::fflush(stdout);
                    }
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
