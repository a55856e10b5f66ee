// neural_renderer.cpp: a tensor model as infer/field_render.h's Ê⁺ field.
#include "ltm/infer/neural_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/nn/checkpoint.h"
#include "ltm/nn/point_tensor.h"
#include "ltm/render/scene_points.h"

namespace ltm {

namespace {
using Clock = std::chrono::steady_clock;

// Rows of an [n, 3] irradiance tensor (any device) as Vec3f.
std::vector<Vec3f> rows_of(const torch::Tensor &e, int64_t n, const char *what) {
    TORCH_CHECK(e.sizes() == torch::IntArrayRef({n, 3}), what, ": returned ", e.sizes());
    const auto c = e.to(torch::kCPU, torch::kFloat32).contiguous();
    const Vec3f *ep = reinterpret_cast<const Vec3f *>(c.data_ptr<float>());
    return std::vector<Vec3f>(ep, ep + n);
}
}  // namespace

LoadedModel load_model(const std::string &path) {
    LoadedModel m;
    m.path = path;
    m.model = load_weights(path, &m.metadata);
    m.model->eval();
    return m;
}

EncodedScene encode_scene(LtmModel &model, const EmbreeAccel &accel, uint64_t seed, bool exclude_enclosed) {
    EncodedScene enc;
    auto t = Clock::now();
    ScenePoints sampled = sample_scene_points(accel, model->cfg.scene_points, seed, exclude_enclosed);
    const auto points = point_tensor(sampled.points);
    enc.spacing = nominal_spacing(accel.scene(), int64_t(sampled.points.size()));
    enc.points = std::move(sampled.points);   // the tensor holds its own copy
    const Vec3f s = sampled.emission_scale;
    const auto emission_scale = torch::tensor({s.x, s.y, s.z});
    enc.n_scene_points = points.size(0);
    enc.sample_seconds = seconds_since(t);
    t = Clock::now();
    const SceneGeometry g = model->scene_geometry(points);
    enc.geometry_seconds = seconds_since(t);
    t = Clock::now();
    {
        torch::NoGradGuard no_grad;
        model->eval();
        // physics.prior_rays: the prior's visibility by rays against this scene's meshes; traced_inputs:
        // a few paths per scene point through this scene (counted in the encode's time).
        enc.latents = model->encode(points, g, emission_scale, nullptr, prior_occlusion(model->cfg, accel),
                                    traced_inputs_tracer(model->cfg, accel, std::move(sampled.ids)));
    }
    enc.encode_seconds = seconds_since(t);
    const SceneNormalization &n = enc.latents.norm;
    log_debug("scene frame: length unit ℓ = ", n.length.item<float>(), ", emission scale S = (", n.emission[0].item<float>(), ", ",
              n.emission[1].item<float>(), ", ", n.emission[2].item<float>(), "), output scale = (", n.output[0].item<float>(), ", ",
              n.output[1].item<float>(), ", ", n.output[2].item<float>(), ")");
    return enc;
}

// By value: a module holder and tensors are cheap to copy, and the decoder may outlive its arguments.
IrradianceDecoder model_irradiance(LtmModel &model, const SceneLatents &latents, DecodeTimings *timings) {
    return [model, latents, timings](const std::vector<float> &rows) mutable {
        const int64_t n = int64_t(rows.size() / 9);
        if (n == 0) return std::vector<Vec3f>{};
        PredictTimings t;
        const auto e = model->predict_irradiance(rows_tensor(rows, 9), latents, int64_t(k_decode_chunk), &t);
        if (timings) timings->knn += t.knn, timings->decode += t.decode;
        return rows_of(e, n, "model decoder");
    };
}

IrradianceDecoder model_prior_irradiance(const SceneLatents &latents, DecodeTimings *timings) {
    return [latents, timings](const std::vector<float> &rows) {
        const int64_t n = int64_t(rows.size() / 9);
        if (n == 0) return std::vector<Vec3f>{};
        const auto t = Clock::now();
        std::vector<Vec3f> e = rows_of(prior_irradiance(rows_tensor(rows, 9), latents.norm), n, "model prior");
        if (timings) timings->decode += seconds_since(t);
        return e;
    };
}

std::vector<Vec3f> predict_gbuffer_prior(const EncodedScene &enc, const GBuffer &gb) {
    return decode_gbuffer(model_prior_irradiance(enc.latents), gb);
}

std::vector<Vec3f> predict_gbuffer(LtmModel &model, const EncodedScene &enc, const GBuffer &gb, PredictTimings *timings) {
    DecodeTimings t;
    std::vector<Vec3f> e = decode_gbuffer(model_irradiance(model, enc.latents, &t), gb);
    if (timings) timings->knn = t.knn, timings->decode = t.decode;
    return e;
}

std::vector<Vec3f> predict_gbuffer_upsampled(LtmModel &model, const EncodedScene &enc, const GBuffer &gb,
                                             const Camera &camera, const GiUpsampleOptions &opt, PredictTimings *timings,
                                             int64_t *n_decoded, bool prior_only) {
    DecodeTimings t;
    const IrradianceDecoder decode = prior_only ? model_prior_irradiance(enc.latents) : model_irradiance(model, enc.latents, &t);
    std::vector<Vec3f> e = decode_gbuffer_upsampled(decode, gb, camera, opt, n_decoded);
    if (timings) timings->knn = t.knn, timings->decode = t.decode;
    return e;
}

NeuralRender render_neural(LtmModel &model, const PathTracer &pt, const Camera &camera, const NeuralRenderOptions &opt) {
    const auto t0 = Clock::now();
    const EncodedScene enc = encode_scene(model, pt.accel(), opt.seed, opt.exclude_enclosed);
    DecodeTimings timings;
    GiSource src;
    src.irradiance = opt.prior_only ? model_prior_irradiance(enc.latents, &timings) : model_irradiance(model, enc.latents, &timings);
    src.timings = &timings;
    if (model->directional && !opt.prior_only)
        src.head = [&model, &enc](const std::vector<float> &rows, const std::vector<float> &dirs) {
            const int64_t n = int64_t(rows.size() / 9);
            return rows_of(model->predict_radiance(rows_tensor(rows, 9), rows_tensor(dirs, 3), enc.latents), n, "directional head");
        };
    src.points = &enc.points, src.spacing = enc.spacing, src.n_scene_points = enc.n_scene_points;
    src.sample_seconds = enc.sample_seconds, src.geometry_seconds = enc.geometry_seconds, src.encode_seconds = enc.encode_seconds;
    src.prior_solve_seconds = enc.latents.norm.solve_seconds;
    src.trace_seconds = enc.latents.norm.trace_seconds;
    NeuralRender r = render_with_gi(src, pt, camera, opt);
    r.timings.total = seconds_since(t0);   // the encode included
    r.image.seconds = r.timings.total;
    return r;
}

}  // namespace ltm
