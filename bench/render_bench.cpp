// render_bench.cpp: ground-truth throughput on a generated indoor scene (seed 42):
//   incoherent rays (Mrays/s), irradiance points/s at 1024 spp, 512² image at 64 spp.
//   build/bench/render_bench
#include <benchmark/benchmark.h>

#include "ltm/core/log.h"
#include "ltm/core/parallel.h"
#include "ltm/core/rng.h"
#include "ltm/core/sampling.h"
#include "ltm/core/startup.h"
#include "ltm/points/surface_sampler.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/render/image_renderer.h"

using namespace ltm;

namespace {
const Scene &bench_scene() {
    static const Scene s = generate_indoor(GenConfig{}, 42).scene;
    return s;
}
}  // namespace

// Closest-hit queries from random surface points in cosine directions (the bake's ray mix).
// Arg = threads; items = rays.
static void BM_IncoherentRays(benchmark::State &state) {
    set_num_threads(int(state.range(0)));
    const Scene &s = bench_scene();
    const EmbreeAccel accel(s);
    const auto pts = sample_surface(s, 1 << 16, 1, SampleStream::query_points);
    const int64_t n_rays = 1 << 20;
    for (auto _ : state) {
        parallel_for(0, n_rays, 4096, [&](int64_t i0, int64_t i1) {
            Pcg32 rng{static_cast<uint64_t>(i0)};
            int64_t hits = 0;
            for (int64_t i = i0; i < i1; ++i) {
                const SurfaceSample &x = pts[size_t(i) & 0xffff];
                const Vec3f d = Frame(x.n).to_world(sample_cosine_hemisphere({rng.next_float(), rng.next_float()}));
                hits += accel.intersect({offset_ray_origin(x.p, x.n, d), d}).has_value();
            }
            benchmark::DoNotOptimize(hits);
        });
    }
    state.SetItemsProcessed(state.iterations() * n_rays);
    state.counters["Mrays/s"] = benchmark::Counter(double(n_rays) * 1e-6 * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_IncoherentRays)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// E_direct + E⁺ at 1024 spp, depth 5, for 256 query points (2 threads). Items = points.
static void BM_IrradiancePoints1024spp(benchmark::State &state) {
    set_num_threads(2);
    const Scene &s = bench_scene();
    const EmbreeAccel accel(s);
    const PathTracer pt(accel, PathTracerConfig{});
    const auto pts = sample_surface(s, 256, 2, SampleStream::query_points);
    for (auto _ : state) {
        std::vector<IrradianceEstimate> out(pts.size());
        parallel_for(0, int64_t(pts.size()), 4, [&](int64_t i0, int64_t i1) {
            for (int64_t i = i0; i < i1; ++i) out[size_t(i)] = pt.irradiance(pts[size_t(i)].p, pts[size_t(i)].n, uint64_t(i), 1024);
        });
        benchmark::DoNotOptimize(out.data());
    }
    state.SetItemsProcessed(state.iterations() * int64_t(pts.size()));
}
BENCHMARK(BM_IrradiancePoints1024spp)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

// The scene camera at 512×512, 64 spp (2 threads).
static void BM_Image512At64spp(benchmark::State &state) {
    set_num_threads(2);
    const Scene &s = bench_scene();
    const EmbreeAccel accel(s);
    const PathTracer pt(accel, PathTracerConfig{});
    Camera cam = s.cameras.at(0);
    cam.width = cam.height = 512;
    for (auto _ : state) benchmark::DoNotOptimize(render_pathtraced(pt, cam, 64).color.pixels.data());
}
BENCHMARK(BM_Image512At64spp)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

