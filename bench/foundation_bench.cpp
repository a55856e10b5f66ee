// foundation_bench.cpp: generator, surface sampling, enclosure filter and Embree build timings.
//   build/bench/foundation_bench --benchmark_min_time=1
#include <benchmark/benchmark.h>

#include "ltm/core/parallel.h"
#include "ltm/core/startup.h"
#include "ltm/points/surface_sampler.h"
#include "ltm/transport/transport_prior.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/render/embree_accel.h"
#include "ltm/render/enclosure.h"

using namespace ltm;

// One generated scene per iteration, cycling seeds (scenes differ in size).
static void BM_GenerateIndoor(benchmark::State &state) {
    uint64_t seed = 0;
    for (auto _ : state) benchmark::DoNotOptimize(generate_indoor(GenConfig{}, seed++ % 64));
}
BENCHMARK(BM_GenerateIndoor)->Unit(benchmark::kMillisecond);

// 65 536 query points on a generated scene, at 1 and 2 threads: points/s.
static void BM_SampleSurface(benchmark::State &state) {
    set_num_threads(int(state.range(0)));
    const Scene s = generate_indoor(GenConfig{}, 42).scene;
    for (auto _ : state) benchmark::DoNotOptimize(sample_surface(s, 65536, 1, SampleStream::query_points));
    state.SetItemsProcessed(state.iterations() * 65536);
}
BENCHMARK(BM_SampleSurface)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// The same with --exclude-enclosed (32 rays per candidate): points/s and rays/s.
static void BM_SampleSurfaceExcludeEnclosed(benchmark::State &state) {
    set_num_threads(int(state.range(0)));
    const Scene s = generate_indoor(GenConfig{}, 42).scene;
    const EmbreeAccel accel(s);
    for (auto _ : state)
        benchmark::DoNotOptimize(sample_surface(s, 65536, 1, SampleStream::query_points, enclosed_filter(accel)));
    state.SetItemsProcessed(state.iterations() * 65536);
}
BENCHMARK(BM_SampleSurfaceExcludeEnclosed)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

static void BM_EmbreeBuild(benchmark::State &state) {
    set_num_threads(2);
    const Scene s = generate_indoor(GenConfig{}, 42).scene;
    for (auto _ : state) EmbreeAccel accel(s);
    state.counters["triangles"] = double(s.n_triangles());
}
BENCHMARK(BM_EmbreeBuild)->Unit(benchmark::kMillisecond);


// The transport prior (transport/transport_prior.h) on a generated house: solve among m nodes (the
// model's anchors: m = 4 096, D = 8) and gather at 65 536 receivers (a 512² frame at GI stride 2).
static PointSet transport_nodes(int64_t m) {
    const Scene s = generate_indoor(GenConfig{}, 42).scene;
    return to_scene_points(sample_surface(s, size_t(m), 1, SampleStream::scene_points));
}
static void BM_TransportPriorSolve(benchmark::State &state) {
    set_num_threads(1);
    const PointSet sp = transport_nodes(state.range(0));
    for (auto _ : state) benchmark::DoNotOptimize(solve_transport_prior(sp, 0.01f, 8));
    state.SetItemsProcessed(state.iterations() * state.range(0) * state.range(0));
}
BENCHMARK(BM_TransportPriorSolve)->Arg(4096)->Unit(benchmark::kMillisecond);

static void BM_TransportPriorGather(benchmark::State &state) {
    set_num_threads(1);
    const TransportPrior t = solve_transport_prior(transport_nodes(4096), 0.01f, 8);
    const PointSet q = to_query_points(sample_surface(generate_indoor(GenConfig{}, 42).scene, 8192, 2, SampleStream::query_points));
    std::vector<float> out(3 * q.size());
    for (auto _ : state) gather_transport_prior(t, &q.values[0], &q.values[3], 9, q.size(), out.data());
    state.SetItemsProcessed(state.iterations() * int64_t(q.size()) * 4096);
}
BENCHMARK(BM_TransportPriorGather)->Unit(benchmark::kMillisecond);
