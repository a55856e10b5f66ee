// neural_renderer.cpp: encode once, decode the G-buffer, add direct light, compose.
#include "ltm/infer/neural_renderer.h"

#include <chrono>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/core/parallel.h"
#include "ltm/core/rng.h"
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
            {"knn_s", knn},         {"decode_s", decode}, {"direct_s", direct},     {"glossy_s", glossy},
            {"model_s", model()},   {"total_s", total}};
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

namespace {
// Conductor pixels with the directional head: L = Le + L_direct (NEE + BSDF sampling, MIS: the
// path tracer with one scattering event) + (1/K) Σ_k f cos / pdf · L̂⁺(p, ω_k), ω_k ~ GGX.
void shade_conductors(LtmModel &model, const EncodedScene &enc, const PathTracer &pt, const Camera &camera, const GBuffer &gb,
                      const NeuralRenderOptions &opt, RenderedImage &image) {
    const Scene &scene = pt.accel().scene();
    std::vector<size_t> hits;
    for (size_t k = 0; k < gb.n_hits(); ++k)
        if (!gb.diffuse[k]) hits.push_back(k);
    if (hits.empty()) return;
    const int K = opt.glossy_samples;
    std::vector<Vec3f> direct(hits.size()), weight(hits.size() * size_t(K), Vec3f(0.f));
    std::vector<float> qrows(hits.size() * size_t(K) * 9), dirs(hits.size() * size_t(K) * 3);
    parallel_for(0, int64_t(hits.size()), 16, [&](int64_t b, int64_t e) {
        for (int64_t h = b; h < e; ++h) {
            const size_t k = hits[size_t(h)];
            const int64_t pixel = gb.hit_pixels[k];
            const Ray ray{camera.eye, camera.ray_direction(float(pixel % gb.width) + 0.5f, float(pixel / gb.width) + 0.5f)};
            const auto hit = pt.accel().intersect(ray);
            if (!hit) continue;   // the G-buffer's own ray: it hits
            const SurfaceInteraction si = make_interaction(scene, ray, *hit);
            Vec3f d(0.f);
            for (int s = 0; s < opt.direct_spp; ++s) {
                Pcg32 rng(pt.stream_key(0x6c055ull << 40 | uint64_t(pixel), uint64_t(s)));
                d += pt.reflected_radiance(si, -ray.d, 1, rng);
            }
            direct[size_t(h)] = d / float(opt.direct_spp);
            const Frame frame(si.front ? si.n : -si.n);
            const Vec3f wo = frame.to_local(-ray.d);
            const Bsdf bsdf = si.bsdf();
            Pcg32 rng(pt.stream_key(0x9105ull << 40 | uint64_t(pixel), 0));
            for (int j = 0; j < K; ++j) {
                const size_t row = size_t(h) * size_t(K) + size_t(j);
                const BsdfSample bs = bsdf.sample(wo, {rng.next_float(), rng.next_float()});
                Vec3f w = frame.n;   // a failed sample: any valid direction, weight 0
                if (bs.pdf > 0.f && bs.wi.z > 0.f) w = normalize(frame.to_world(bs.wi)), weight[row] = bs.weight;
                const float q[9] = {gb.position[k].x, gb.position[k].y, gb.position[k].z, frame.n.x, frame.n.y, frame.n.z,
                                    gb.albedo[k].x,   gb.albedo[k].y,   gb.albedo[k].z};
                std::copy(q, q + 9, qrows.begin() + std::ptrdiff_t(row * 9));
                dirs[row * 3] = w.x, dirs[row * 3 + 1] = w.y, dirs[row * 3 + 2] = w.z;
            }
        }
    });
    const auto l = model->predict_radiance(rows_tensor(qrows, 9), rows_tensor(dirs, 3), enc.latents).contiguous();
    const Vec3f *lp = reinterpret_cast<const Vec3f *>(l.data_ptr<float>());
    for (size_t h = 0; h < hits.size(); ++h) {
        Vec3f ind(0.f);
        for (int j = 0; j < K; ++j) ind += weight[h * size_t(K) + size_t(j)] * lp[h * size_t(K) + size_t(j)];
        const size_t k = hits[h];
        image.color.pixels[size_t(gb.hit_pixels[k])] = gb.emitted[k] + direct[h] + ind / float(K);
    }
}
}  // namespace

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
    if (model->directional && r.n_conductor > 0) {
        if (opt.glossy_samples < 1) LTM_THROW("neural render: glossy samples per pixel must be >= 1, got ", opt.glossy_samples);
        const auto tg = Clock::now();
        shade_conductors(model, enc, pt, camera, gb, opt, r.image);
        r.glossy_from_head = true;
        r.timings.glossy = seconds_since(tg);
    }
    r.timings.total = seconds_since(t0);
    r.image.seconds = r.timings.total;
    r.n_queries = int64_t(gb.n_hits());
    r.n_scene_points = enc.n_scene_points;
    return r;
}

}  // namespace ltm
