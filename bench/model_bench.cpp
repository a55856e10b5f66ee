// model_bench.cpp: model timings on CPU beside the machine's GEMM rate measured in the same run.
//   build/bench/model_bench [--benchmark_filter=...]
// Scene: 8192 (or 20000) points on the walls, floor and furniture of a generated indoor scene;
// 8192 queries. Forward = encode + decode; step = forward + backward + AdamW.
#include <benchmark/benchmark.h>

#include <malloc.h>

#include <chrono>

#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/core/startup.h"
#include "ltm/nn/fused_decoder.h"
#include "ltm/nn/knn.h"
#include "ltm/nn/point_tensor.h"
#include "ltm/nn/ltm_model.h"
#include "ltm/points/surface_sampler.h"
#include "ltm/procgen/indoor_generator.h"

using namespace ltm;

namespace {
torch::Tensor points(int64_t n, SampleStream stream, bool scene) {
    static const Scene s = generate_indoor(GenConfig{}, 7).scene;
    const auto x = sample_surface(s, n, 1, stream);
    const PointSet p = scene ? to_scene_points(x) : to_query_points(x);
    return point_tensor(p);
}
ModelConfig preset(const std::string &name) { return ModelConfig::from_file(std::string(LTM_SOURCE_DIR) + "/configs/model/" + name + ".json"); }
double mb(size_t bytes) { return double(bytes) / double(1 << 20); }

// A `cpu` model (random weights, eval mode) with one encoded scene and 65536 normalised queries;
// autograd is off while it lives (the decode benchmarks run in its scope).
struct EncodedScene {
    torch::NoGradGuard no_grad;   // first: also covers the members' construction
    LtmModel model{preset("cpu")};
    torch::Tensor query_points;   // [65536, 9] raw
    torch::Tensor query;          // [65536, 9] normalised
    SceneLatents latents;
    EncodedScene() {
        torch::manual_seed(0);
        model->eval();
        const auto sp = points(8192, SampleStream::scene_points, true);
        query_points = points(65536, SampleStream::query_points, false);
        latents = model->encode(sp, model->scene_geometry(sp));
        query = normalize_query_points(query_points, latents.norm);
    }
};
}  // namespace

// 1024² float GEMM: the machine's attainable FLOP rate in this run.
static void BM_Gemm1024(benchmark::State &state) {
    const auto a = torch::randn({1024, 1024}), b = torch::randn({1024, 1024});
    auto c = torch::empty({1024, 1024});
    for (auto _ : state) torch::mm_out(c, a, b);
    state.counters["GFLOP/s"] = benchmark::Counter(2.0 * 1024 * 1024 * 1024 * 1e-9 * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Gemm1024)->Unit(benchmark::kMillisecond)->UseRealTime();

// Encoder (embedding + PTv3) at M scene points; arg0 = M, arg1 = preset (0 cpu, 1 paper).
static void BM_Encode(benchmark::State &state) {
    torch::manual_seed(0);
    ModelConfig cfg = preset(state.range(1) ? "paper" : "cpu");
    cfg.scene_points = int(state.range(0));
    LtmModel model(cfg);
    model->eval();
    torch::NoGradGuard ng;
    const auto sp = points(state.range(0), SampleStream::scene_points, true);
    const SceneGeometry g = model->scene_geometry(sp);
    for (auto _ : state) benchmark::DoNotOptimize(model->features(model->encode(sp, g)).data_ptr());
}
BENCHMARK(BM_Encode)->Args({8192, 0})->Args({20000, 0})->Args({20000, 1})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// FPS + kNN once per scene (cached in training and rendering).
static void BM_SceneGeometry(benchmark::State &state) {
    LtmModel model(preset("cpu"));
    const auto sp = points(state.range(0), SampleStream::scene_points, true);
    for (auto _ : state) benchmark::DoNotOptimize(model->scene_geometry(sp).groups.data_ptr());
}
BENCHMARK(BM_SceneGeometry)->Arg(8192)->Arg(20000)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// Decoder throughput (queries/s) incl. the kNN among anchors, 65536 queries per call.
static void BM_DecodeQueries(benchmark::State &state) {
    EncodedScene e;
    for (auto _ : state) benchmark::DoNotOptimize(e.model->predict_irradiance(e.query_points, e.latents, state.range(0)).data_ptr());
    state.SetItemsProcessed(state.iterations() * 65536);
}
// arg = queries per chunk
BENCHMARK(BM_DecodeQueries)->Arg(1024)->Arg(4096)->Arg(16384)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// The same with the libtorch modules instead of FusedDecoder (the path before the fused kernel).
static void BM_DecodeQueriesLibtorch(benchmark::State &state) {
    EncodedScene e;
    e.model->fused_inference = false;
    for (auto _ : state) benchmark::DoNotOptimize(e.model->predict_irradiance(e.query_points, e.latents, state.range(0)).data_ptr());
    state.SetItemsProcessed(state.iterations() * 65536);
}
BENCHMARK(BM_DecodeQueriesLibtorch)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// Decoder alone (kNN precomputed), 65536 queries: arg 0 = QueryDecoder::forward in chunks of 1024,
// arg 1 = FusedDecoder::forward in one call (its build + prepare excluded, reported as build_ms).
static void BM_DecodeKernel(benchmark::State &state) {
    EncodedScene e;
    LtmModel &model = e.model;
    const SceneLatents &lat = e.latents;
    const auto &q = e.query;
    const auto idx = knn(q.slice(1, 0, 3).contiguous(), lat.anchors.contiguous(), model->cfg.decoder.n_neighbors);
    const auto t0 = std::chrono::steady_clock::now();
    FusedDecoder fused(*model->decoder);
    fused.prepare(model->features(lat));
    state.counters["build_ms"] = 1e3 * seconds_since(t0);
    for (auto _ : state) {
        if (state.range(0) == 1) {
            benchmark::DoNotOptimize(fused.forward(q, lat.anchors, idx).data_ptr());
            continue;
        }
        for (int64_t s = 0; s < q.size(0); s += 1024)
            benchmark::DoNotOptimize(model->decoder->forward(q.slice(0, s, s + 1024), model->features(lat), lat.anchors,
                                                             idx.slice(0, s, s + 1024)).data_ptr());
    }
    state.SetItemsProcessed(state.iterations() * 65536);
}
BENCHMARK(BM_DecodeKernel)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// kNN among anchors alone, 65536 queries in chunks of 1024 (as predict_irradiance).
static void BM_DecodeKnn(benchmark::State &state) {
    EncodedScene e;
    const auto &q = e.query;
    for (auto _ : state)
        for (int64_t s = 0; s < q.size(0); s += 1024)
            benchmark::DoNotOptimize(knn(q.slice(0, s, s + 1024).slice(1, 0, 3).contiguous(), e.latents.anchors.contiguous(),
                                         e.model->cfg.decoder.n_neighbors).data_ptr());
    state.SetItemsProcessed(state.iterations() * 65536);
}
BENCHMARK(BM_DecodeKnn)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// One training step of a preset: encode + decode N queries + loss + backward + AdamW. As the trainer
// does, the scene's frame (with prior inputs: the prior at every scene point) and the queries' output
// scale are computed once, outside the step. Args: preset (k_step_presets), queries per step.
const char *const k_step_presets[] = {"cpu", "paper", "tiny-pi", "small-pi", "cpu-pi"};
static void BM_TrainStep(benchmark::State &state) {
    torch::manual_seed(0);
    const ModelConfig cfg = preset(k_step_presets[state.range(0)]);
    state.SetLabel(cfg.name);
    LtmModel model(cfg);
    torch::optim::AdamW opt(model->parameters(), torch::optim::AdamWOptions(1e-4));
    const auto sp = points(cfg.scene_points, SampleStream::scene_points, true);
    const auto qp = points(state.range(1), SampleStream::query_points, false);
    const auto target = torch::rand({state.range(1), 3});
    const SceneGeometry g = model->scene_geometry(sp);
    const SceneNormalization frame = model->scene_frame(sp, g);
    const torch::Tensor scale = output_scale(qp, frame);
    double fwd = 0;
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        opt.zero_grad();
        const auto loss = relative_l2_log_loss(model->decode(qp, model->encode(sp, g, {}, &frame), scale), target);
        fwd += seconds_since(t0);
        loss.backward();
        opt.step();
    }
    state.counters["forward_ms"] = 1e3 * fwd / double(state.iterations());
    state.counters["params_M"] = double(model->n_parameters()) * 1e-6;
    const struct mallinfo2 mi = mallinfo2();
    state.counters["heap_MB"] = mb(mi.arena + mi.hblkhd);
}
BENCHMARK(BM_TrainStep)->Args({0, 8192})->Args({1, 8192})->Args({2, 4096})->Args({3, 4096})->Args({4, 4096})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

