// neural_renderer.cpp: encode once, decode the G-buffer, add direct light, compose.
#include "ltm/infer/neural_renderer.h"

#include <chrono>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/nn/checkpoint.h"
#include "ltm/nn/point_tensor.h"
#include "ltm/render/direct_light.h"
#include "ltm/render/scene_points.h"

namespace ltm {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
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
    const ScenePoints sampled = sample_scene_points(accel, model->cfg.scene_points, seed, exclude_enclosed);
    const auto points = point_tensor(sampled.points);
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
        enc.latents = model->encode(points, g, emission_scale);
    }
    enc.encode_seconds = seconds_since(t);
    const SceneNormalization &n = enc.latents.norm;
    log_debug("scene frame: length unit ℓ = ", n.length.item<float>(), ", emission scale S = (", n.emission[0].item<float>(), ", ",
              n.emission[1].item<float>(), ", ", n.emission[2].item<float>(), "), output scale = (", n.output[0].item<float>(), ", ",
              n.output[1].item<float>(), ", ", n.output[2].item<float>(), ")");
    return enc;
}

namespace {
// Ê⁺ at the G-buffer hits listed in `hits` (all hits if null), in that order.
std::vector<Vec3f> predict_hits(LtmModel &model, const EncodedScene &enc, const GBuffer &gb,
                                const std::vector<size_t> *hits, PredictTimings *timings) {
    const int64_t n = hits ? int64_t(hits->size()) : int64_t(gb.n_hits());
    std::vector<Vec3f> out(static_cast<size_t>(n));
    if (n == 0) return out;
    // Query points [n, 9]: p, n (facing the eye), albedo, as in the dataset's query_point_columns().
    auto q = torch::empty({n, 9});
    float *qp = q.data_ptr<float>();
    for (int64_t k = 0; k < n; ++k) {
        const size_t h = hits ? (*hits)[size_t(k)] : size_t(k);
        const Vec3f *cols[3] = {&gb.position[h], &gb.normal[h], &gb.albedo[h]};
        for (int c = 0; c < 3; ++c) {
            qp[k * 9 + c * 3 + 0] = cols[c]->x;
            qp[k * 9 + c * 3 + 1] = cols[c]->y;
            qp[k * 9 + c * 3 + 2] = cols[c]->z;
        }
    }
    PredictTimings t;
    const auto e = model->predict_irradiance(q, enc.latents, 16384, &t).contiguous();
    TORCH_CHECK(e.sizes() == torch::IntArrayRef({n, 3}), "predict_gbuffer: model returned ", e.sizes());
    if (timings) timings->knn += t.knn, timings->decode += t.decode;
    const float *ep = e.data_ptr<float>();
    for (int64_t k = 0; k < n; ++k) out[size_t(k)] = {ep[k * 3], ep[k * 3 + 1], ep[k * 3 + 2]};
    return out;
}
}  // namespace

std::vector<Vec3f> predict_gbuffer(LtmModel &model, const EncodedScene &enc, const GBuffer &gb, PredictTimings *timings) {
    if (timings) *timings = {};
    return predict_hits(model, enc, gb, nullptr, timings);
}

std::vector<Vec3f> predict_gbuffer_upsampled(LtmModel &model, const EncodedScene &enc, const GBuffer &gb,
                                             const Camera &camera, const GiUpsampleOptions &opt, PredictTimings *timings,
                                             int64_t *n_decoded) {
    if (opt.stride == 1) {
        if (n_decoded) *n_decoded = int64_t(gb.n_hits());
        return predict_gbuffer(model, enc, gb, timings);
    }
    if (timings) *timings = {};
    const std::vector<size_t> lattice = lattice_hits(gb, opt.stride);
    GiInterpolation r = interpolate_from_lattice(gb, camera, predict_hits(model, enc, gb, &lattice, timings), opt);
    const std::vector<Vec3f> own = predict_hits(model, enc, gb, &r.needs_decode, timings);
    for (size_t k = 0; k < own.size(); ++k) r.values[r.needs_decode[k]] = own[k];
    if (n_decoded) *n_decoded = int64_t(lattice.size() + r.needs_decode.size());
    return std::move(r.values);
}

OrderedJson NeuralTimings::to_json() const {
    return {{"gbuffer_s", gbuffer}, {"sample_s", sample}, {"geometry_s", geometry}, {"encode_s", encode},
            {"knn_s", knn},         {"decode_s", decode}, {"direct_s", direct},     {"model_s", model()},
            {"total_s", total}};
}

DirectEstimator parse_direct_estimator(const std::string &name) {
    if (name == "mis") return DirectEstimator::mis;
    if (name == "ratio") return DirectEstimator::ratio;
    if (name == "auto") return DirectEstimator::automatic;
    LTM_THROW("direct-light estimator '", name, "': expected mis, ratio or auto");
}

const char *direct_estimator_name(DirectEstimator e) {
    switch (e) {
        case DirectEstimator::mis: return "mis";
        case DirectEstimator::ratio: return "ratio";
        case DirectEstimator::automatic: return "auto";
    }
    return "?";
}

NeuralRender render_neural(LtmModel &model, const PathTracer &pt, const Camera &camera, const NeuralRenderOptions &opt) {
    if (opt.direct_spp <= 0) LTM_THROW("neural render: direct-light samples per pixel must be > 0, got ", opt.direct_spp);
    NeuralRender r;
    const auto t0 = Clock::now();
    const EncodedScene enc = encode_scene(model, pt.accel(), opt.seed, opt.exclude_enclosed);
    r.timings.sample = enc.sample_seconds, r.timings.geometry = enc.geometry_seconds, r.timings.encode = enc.encode_seconds;
    const auto t = Clock::now();
    const GBuffer gb = render_gbuffer(pt.accel(), camera);
    r.timings.gbuffer = seconds_since(t);
    PredictTimings pt_times;
    const Image indirect =
        scatter_to_image(gb, predict_gbuffer_upsampled(model, enc, gb, camera, opt.gi, &pt_times, &r.n_decoded));
    r.timings.knn = pt_times.knn, r.timings.decode = pt_times.decode;
    r.direct = opt.direct;
    if (r.direct == DirectEstimator::automatic)
        r.direct = RatioDirectLight::supports(pt.accel().scene()) ? DirectEstimator::ratio : DirectEstimator::mis;
    const IrradianceImages direct = r.direct == DirectEstimator::ratio
                                        ? direct_images_ratio(RatioDirectLight(pt.accel(), opt.seed), gb, opt.direct_spp)
                                        : irradiance_images(pt, gb, opt.direct_spp, /*with_indirect=*/false);
    r.timings.direct = direct.seconds;
    r.image = compose_image(gb, direct.direct, indirect, &r.n_conductor);
    r.timings.total = seconds_since(t0);
    r.image.seconds = r.timings.total;
    r.n_queries = int64_t(gb.n_hits());
    r.n_scene_points = enc.n_scene_points;
    return r;
}

}  // namespace ltm
