// foundation_bench.cpp: generator, surface sampling, enclosure filter and Embree build timings.
//   build/bench/foundation_bench --benchmark_min_time=1
#include <benchmark/benchmark.h>

#include "ltm/core/parallel.h"
#include "ltm/core/startup.h"
#include "ltm/points/surface_sampler.h"
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

