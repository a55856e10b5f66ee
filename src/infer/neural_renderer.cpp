// neural_renderer.cpp: encode once, decode the G-buffer, add direct light, compose.
#include "ltm/infer/neural_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/core/parallel.h"
#include "ltm/core/progress.h"
#include "ltm/core/rng.h"
#include "ltm/infer/traced_bounce.h"
#include "ltm/nn/checkpoint.h"
#include "ltm/nn/point_tensor.h"
#include "ltm/render/direct_light.h"
#include "ltm/render/mesh_occlusion.h"
#include "ltm/render/scene_points.h"

namespace ltm {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

LoadedModel load_model(const std::string &path) {
    LoadedModel m;
    m.path = path;
    m.model = load_weights(path, &m.metadata);
    m.model->eval();
    return m;
}

std::shared_ptr<const SegmentOcclusion> prior_occlusion(const LtmModel &model, const EmbreeAccel &accel) {
    if (!model->cfg.physics.prior_rays) return nullptr;
    return std::make_shared<MeshOcclusion>(accel);
}

EncodedScene encode_scene(LtmModel &model, const EmbreeAccel &accel, uint64_t seed, bool exclude_enclosed) {
    EncodedScene enc;
    auto t = Clock::now();
    ScenePoints sampled = sample_scene_points(accel, model->cfg.scene_points, seed, exclude_enclosed);
    const auto points = point_tensor(sampled.points);
    enc.spacing = float(std::sqrt(accel.scene().total_area() / double(std::max<size_t>(1, sampled.points.size()))));
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
        // physics.prior_rays: the prior's visibility by rays against this scene's meshes.
        enc.latents = model->encode(points, g, emission_scale, nullptr, prior_occlusion(model, accel));
    }
    enc.encode_seconds = seconds_since(t);
    const SceneNormalization &n = enc.latents.norm;
    log_debug("scene frame: length unit ℓ = ", n.length.item<float>(), ", emission scale S = (", n.emission[0].item<float>(), ", ",
              n.emission[1].item<float>(), ", ", n.emission[2].item<float>(), "), output scale = (", n.output[0].item<float>(), ", ",
              n.output[1].item<float>(), ", ", n.output[2].item<float>(), ")");
    return enc;
}

namespace {
// Query points [n, 9] of the G-buffer hits listed in `hits` (all hits if null), in that order:
// p, n (facing the eye), albedo, as in the dataset's query_point_columns().
torch::Tensor gbuffer_queries(const GBuffer &gb, const std::vector<size_t> *hits) {
    const int64_t n = hits ? int64_t(hits->size()) : int64_t(gb.n_hits());
    auto q = torch::empty({n, 9});
    float *qp = q.data_ptr<float>();
    for (int64_t k = 0; k < n; ++k) {
        const size_t h = hits ? (*hits)[size_t(k)] : size_t(k);
        write_query_row(qp + k * 9, gb.position[h], gb.normal[h], gb.albedo[h]);
    }
    return q;
}

// Rows of an [n, 3] irradiance tensor (any device) as Vec3f.
std::vector<Vec3f> rows_of(const torch::Tensor &e, int64_t n, const char *what) {
    TORCH_CHECK(e.sizes() == torch::IntArrayRef({n, 3}), what, ": returned ", e.sizes());
    const auto c = e.to(torch::kCPU, torch::kFloat32).contiguous();
    const float *ep = c.data_ptr<float>();
    std::vector<Vec3f> out(static_cast<size_t>(n));
    for (int64_t k = 0; k < n; ++k) out[size_t(k)] = {ep[k * 3], ep[k * 3 + 1], ep[k * 3 + 2]};
    return out;
}

// The model's prior, the network silenced, at the G-buffer hits listed in `hits` (all if null).
std::vector<Vec3f> prior_hits(const EncodedScene &enc, const GBuffer &gb, const std::vector<size_t> *hits) {
    const int64_t n = hits ? int64_t(hits->size()) : int64_t(gb.n_hits());
    if (n == 0) return {};
    return rows_of(model_prior_irradiance(enc.latents)(gbuffer_queries(gb, hits)), n, "predict_gbuffer_prior: prior");
}

// Ê⁺ at the G-buffer hits listed in `hits` (all hits if null), in that order.
// prior_only: the model's prior instead (prior_hits; no timings: not the decoder's).
std::vector<Vec3f> predict_hits(LtmModel &model, const EncodedScene &enc, const GBuffer &gb,
                                const std::vector<size_t> *hits, PredictTimings *timings, bool prior_only = false) {
    if (prior_only) return prior_hits(enc, gb, hits);
    const int64_t n = hits ? int64_t(hits->size()) : int64_t(gb.n_hits());
    if (n == 0) return {};
    PredictTimings t;
    const auto e = model->predict_irradiance(gbuffer_queries(gb, hits), enc.latents, 16384, &t);
    if (timings) timings->knn += t.knn, timings->decode += t.decode;
    return rows_of(e, n, "predict_gbuffer: model");
}
}  // namespace

std::vector<Vec3f> predict_gbuffer_prior(const EncodedScene &enc, const GBuffer &gb) { return prior_hits(enc, gb, nullptr); }

std::vector<Vec3f> predict_gbuffer(LtmModel &model, const EncodedScene &enc, const GBuffer &gb, PredictTimings *timings) {
    if (timings) *timings = {};
    return predict_hits(model, enc, gb, nullptr, timings);
}

std::vector<Vec3f> predict_gbuffer_upsampled(LtmModel &model, const EncodedScene &enc, const GBuffer &gb,
                                             const Camera &camera, const GiUpsampleOptions &opt, PredictTimings *timings,
                                             int64_t *n_decoded, bool prior_only) {
    if (timings) *timings = {};
    if (opt.stride == 1 && opt.levels == 1) {
        if (n_decoded) *n_decoded = int64_t(gb.n_hits());
        return predict_hits(model, enc, gb, nullptr, timings, prior_only);
    }
    GiUpsampled r = upsample_gi(gb, camera, opt, [&](const std::vector<size_t> &hits) {
        return predict_hits(model, enc, gb, &hits, timings, prior_only);
    });
    if (n_decoded) *n_decoded = r.decoded;
    return std::move(r.values);
}

OrderedJson NeuralTimings::to_json() const {
    return {{"gbuffer_s", gbuffer}, {"sample_s", sample}, {"geometry_s", geometry}, {"encode_s", encode},
            {"prior_solve_s", prior_solve}, {"knn_s", knn}, {"decode_s", decode}, {"direct_s", direct}, {"glossy_s", glossy},
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

GlossyShading parse_glossy_shading(const std::string &name) {
    if (name == "auto") return GlossyShading::automatic;
    if (name == "trace") return GlossyShading::trace;
    if (name == "head") return GlossyShading::head;
    if (name == "diffuse") return GlossyShading::diffuse;
    LTM_THROW("glossy shading '", name, "': expected auto, trace, head or diffuse");
}

BounceIrradiance parse_bounce_irradiance(const std::string &name) {
    if (name == "auto") return BounceIrradiance::automatic;
    if (name == "nodes") return BounceIrradiance::nodes;
    if (name == "decode") return BounceIrradiance::decode;
    LTM_THROW("bounce irradiance '", name, "': expected auto, nodes or decode");
}

const char *bounce_irradiance_name(BounceIrradiance b) {
    switch (b) {
        case BounceIrradiance::automatic: return "auto";
        case BounceIrradiance::nodes: return "nodes";
        case BounceIrradiance::decode: return "decode";
    }
    return "?";
}

const char *glossy_shading_name(GlossyShading g) {
    switch (g) {
        case GlossyShading::automatic: return "auto";
        case GlossyShading::trace: return "trace";
        case GlossyShading::head: return "head";
        case GlossyShading::diffuse: return "diffuse";
    }
    return "?";
}

namespace {
// Stream domains of the conductor pass (disjoint from the G-buffer's and the points').
constexpr uint64_t k_conductor_direct = 0x6c055ull << 40, k_conductor_lobe = 0x9105ull << 40,
                   k_conductor_bounce = 0x7ace5ull << 40;

// Conductor pixels' GGX samples: rows h·K + j for conductor hit h (G-buffer hit c.hits[h]) and sample j.
struct ConductorSamples {
    int K = 0;
    std::vector<size_t> hits;    // [H] G-buffer hits on conductors
    std::vector<Vec3f> direct;   // [H] L_direct: NEE + BSDF sampling, MIS (one scattering event)
    std::vector<Vec3f> weight;   // [H·K] f cos / pdf (0: a failed sample)
    std::vector<Vec3f> dir;      // [H·K] ω_k, world space, on the facing normal's side
};

ConductorSamples sample_conductors(const PathTracer &pt, const Camera &camera, const GBuffer &gb, const NeuralRenderOptions &opt, int samples) {
    const Scene &scene = pt.accel().scene();
    ConductorSamples c;
    c.K = samples;
    for (size_t k = 0; k < gb.n_hits(); ++k)
        if (!gb.diffuse[k]) c.hits.push_back(k);
    const size_t K = size_t(c.K);
    c.direct.assign(c.hits.size(), Vec3f(0.f));
    c.weight.assign(c.hits.size() * K, Vec3f(0.f));
    c.dir.assign(c.hits.size() * K, Vec3f(0.f));
    parallel_for(0, int64_t(c.hits.size()), 16, [&](int64_t b, int64_t e) {
        for (int64_t h = b; h < e; ++h) {
            const size_t k = c.hits[size_t(h)];
            const int64_t pixel = gb.hit_pixels[k];
            const Ray ray{camera.eye, camera.ray_direction(float(pixel % gb.width) + 0.5f, float(pixel / gb.width) + 0.5f)};
            const auto hit = pt.accel().intersect(ray);
            if (!hit) continue;   // the G-buffer's own ray: it hits
            const SurfaceInteraction si = make_interaction(scene, ray, *hit);
            Vec3f d(0.f);
            for (int s = 0; s < opt.direct_spp; ++s) {
                Pcg32 rng(pt.stream_key(k_conductor_direct | uint64_t(pixel), uint64_t(s)));
                d += pt.reflected_radiance(si, -ray.d, 1, rng);
            }
            c.direct[size_t(h)] = d / float(opt.direct_spp);
            const Frame frame(gb.normal[k]);
            const Vec3f wo = frame.to_local(-ray.d);
            const Bsdf bsdf = si.bsdf();
            Pcg32 rng(pt.stream_key(k_conductor_lobe | uint64_t(pixel), 0));
            for (size_t j = 0; j < K; ++j) {
                const size_t row = size_t(h) * K + j;
                const BsdfSample bs = bsdf.sample(wo, {rng.next_float(), rng.next_float()});
                c.dir[row] = frame.n;   // a failed sample: any valid direction, weight 0
                if (bs.pdf > 0.f && bs.wi.z > 0.f) c.dir[row] = normalize(frame.to_world(bs.wi)), c.weight[row] = bs.weight;
            }
        }
    });
    return c;
}

// L̂⁺ of the directional head at every row.  -> [H·K]
std::vector<Vec3f> head_radiance(LtmModel &model, const EncodedScene &enc, const GBuffer &gb, const ConductorSamples &c) {
    const size_t K = size_t(c.K), rows = c.hits.size() * K;
    std::vector<float> q(rows * 9), d(rows * 3);
    for (size_t row = 0; row < rows; ++row) {
        const size_t k = c.hits[row / K];
        write_query_row(&q[row * 9], gb.position[k], gb.normal[k], gb.albedo[k]);
        for (int a = 0; a < 3; ++a) d[row * 3 + size_t(a)] = c.dir[row][a];
    }
    const auto l = model->predict_radiance(rows_tensor(q, 9), rows_tensor(d, 3), enc.latents).contiguous();
    const Vec3f *lp = reinterpret_cast<const Vec3f *>(l.data_ptr<float>());
    return std::vector<Vec3f>(lp, lp + rows);
}

// One traced bounce (GlossyShading::trace) along every row with a sample.  -> [H·K]
std::vector<Vec3f> traced_radiance(const IrradianceDecoder &decode, const EncodedScene &enc, const PathTracer &pt, const GBuffer &gb,
                                   const ConductorSamples &c, const DirectIrradianceFn &direct, BounceIrradiance bounce) {
    const size_t K = size_t(c.K), rows = c.hits.size() * K;
    std::vector<Ray> rays(rows, Ray{Vec3f(0.f), Vec3f(0.f)});   // zero direction: a failed sample, skipped
    std::vector<uint64_t> keys(rows);
    for (size_t row = 0; row < rows; ++row) {
        const size_t k = c.hits[row / K];
        keys[row] = hash_keys({k_conductor_bounce, uint64_t(gb.hit_pixels[k]), uint64_t(row % K)});
        if (c.weight[row] != Vec3f(0.f)) rays[row] = Ray{offset_ray_origin(gb.position[k], gb.normal[k], c.dir[row]), c.dir[row]};
    }
    std::optional<NodeIrradiance> nodes;
    if (bounce == BounceIrradiance::nodes) {
        nodes = decode_node_irradiance(decode, enc.points, enc.spacing);
        log_debug("traced bounce: Ê⁺ at the ", nodes->irradiance.size(), " scene points in ", nodes->seconds, " s");
    }
    return traced_bounce_radiance(decode, pt, rays, keys, direct, /*with_emission=*/false, nodes ? &*nodes : nullptr);
}

// Writes Le + L_direct + (1/K) Σ weight · L⁺ at the conductor pixels.
void compose_conductors(const GBuffer &gb, const ConductorSamples &c, const std::vector<Vec3f> &radiance, RenderedImage &image) {
    const size_t K = size_t(c.K);
    for (size_t h = 0; h < c.hits.size(); ++h) {
        Vec3f ind(0.f);
        for (size_t j = 0; j < K; ++j) ind += c.weight[h * K + j] * radiance[h * K + j];
        const size_t k = c.hits[h];
        image.color.pixels[size_t(gb.hit_pixels[k])] = gb.emitted[k] + c.direct[h] + ind / float(K);
    }
}
}  // namespace

NeuralRender render_neural(LtmModel &model, const PathTracer &pt, const Camera &camera, const NeuralRenderOptions &opt) {
    if (opt.direct_spp <= 0) LTM_THROW("neural render: direct-light samples per pixel must be > 0, got ", opt.direct_spp);
    if (opt.glossy_samples < 0) LTM_THROW("neural render: glossy samples per pixel must be >= 0 (0: automatic), got ", opt.glossy_samples);
    NeuralRender r;
    const auto t0 = Clock::now();
    const EncodedScene enc = encode_scene(model, pt.accel(), opt.seed, opt.exclude_enclosed);
    r.timings.sample = enc.sample_seconds, r.timings.geometry = enc.geometry_seconds, r.timings.encode = enc.encode_seconds;
    r.timings.prior_solve = enc.latents.norm.solve_seconds;
    const auto t = Clock::now();
    const GBuffer gb = render_gbuffer(pt.accel(), camera);
    r.timings.gbuffer = seconds_since(t);
    PredictTimings pt_times;
    const Image indirect =
        scatter_to_image(gb, predict_gbuffer_upsampled(model, enc, gb, camera, opt.gi, &pt_times, &r.n_decoded, opt.prior_only));
    r.timings.knn = pt_times.knn, r.timings.decode = pt_times.decode;
    r.direct = opt.direct;
    if (r.direct == DirectEstimator::automatic)
        r.direct = RatioDirectLight::supports(pt.accel().scene()) ? DirectEstimator::ratio : DirectEstimator::mis;
    std::optional<RatioDirectLight> ratio;
    if (r.direct == DirectEstimator::ratio) ratio.emplace(pt.accel(), opt.seed);
    const IrradianceImages direct = ratio ? direct_images_ratio(*ratio, gb, opt.direct_spp)
                                          : irradiance_images(pt, gb, opt.direct_spp, /*with_indirect=*/false);
    r.timings.direct = direct.seconds;
    r.image = compose_image(gb, direct.direct, indirect, &r.n_conductor);
    GlossyShading glossy = opt.glossy == GlossyShading::automatic ? GlossyShading::trace : opt.glossy;
    if (glossy == GlossyShading::head && !model->directional)
        LTM_THROW("neural render: --glossy head needs a directional head, and these weights have none (use trace or diffuse)");
    if (glossy == GlossyShading::head && opt.prior_only)
        LTM_THROW("neural render: the prior alone has no directional head (use --glossy trace or diffuse)");
    if (r.n_conductor > 0 && glossy != GlossyShading::diffuse) {
        // 0: 64 traced samples (cheap: a ray, light samples, one fused Ê⁺ decode each), 16 through the
        // head (a libtorch decode each, ~10× a traced sample).
        const int K = opt.glossy_samples > 0 ? opt.glossy_samples : glossy == GlossyShading::head ? 16 : 64;
        const auto tg = Clock::now();
        const ConductorSamples c = sample_conductors(pt, camera, gb, opt, K);
        r.glossy_samples = K;
        if (glossy == GlossyShading::head) {
            compose_conductors(gb, c, head_radiance(model, enc, gb, c), r.image);
        } else {
            // Light samples per bounce hit: the pixel's budget spread over its K samples.
            const int spp = (opt.direct_spp + K - 1) / K;
            r.bounce = opt.bounce;
            if (r.bounce == BounceIrradiance::automatic)
                r.bounce = int64_t(c.hits.size()) * K >= k_bounce_nodes_per_point * enc.n_scene_points ? BounceIrradiance::nodes
                                                                                                        : BounceIrradiance::decode;
            const IrradianceDecoder decode = opt.prior_only ? model_prior_irradiance(enc.latents) : model_irradiance(model, enc.latents);
            compose_conductors(gb, c, traced_radiance(decode, enc, pt, gb, c, direct_irradiance_fn(pt, ratio ? &*ratio : nullptr, spp),
                                               r.bounce),
                               r.image);
        }
        r.timings.glossy = seconds_since(tg);
    }
    r.glossy = r.n_conductor > 0 ? glossy : GlossyShading::diffuse;
    r.timings.total = seconds_since(t0);
    r.image.seconds = r.timings.total;
    r.n_queries = int64_t(gb.n_hits());
    r.n_scene_points = enc.n_scene_points;
    return r;
}

void set_scene_points(LtmModel &model, int64_t n) {
    if (n < k_min_scene_points)
        LTM_THROW("--scene-points ", n, ": below the minimum of ", k_min_scene_points, " (the decoder's neighbourhoods need more points)");
    const bool tree = model->cfg.physics.prior_theta > 0.f;
    if (tree && n > k_max_scene_points_tree)
        LTM_THROW("--scene-points ", n, ": above the limit of ", k_max_scene_points_tree, " with the prior's tree (~1 KB per point: ",
                  double(n) * 1024.0 / double(1 << 30), " GiB here)");
    if (!tree && n > k_max_scene_points)
        LTM_THROW("--scene-points ", n, ": above the limit of ", k_max_scene_points, " (the transport prior's dense solve holds ~4·M² bytes: ",
                  double(n) * double(n) * 4.0 / double(1 << 30), " GiB here; --prior-theta 0.5 solves through a tree up to ",
                  k_max_scene_points_tree, ")");
    model->cfg.scene_points = int(n);
}

void set_auto_scene_points(LtmModel &model, const Scene &scene, bool theta_given) {
    const int64_t m = auto_scene_points(scene);
    const bool tree = !theta_given && m > model->cfg.scene_points && model->cfg.physics.prior_field == "transport";
    if (tree) set_prior_theta(model, 0.5);
    set_scene_points(model, m);
    log_info("--scene-points auto: ", m, " scene points for ", scene.n_triangles(), " triangles", tree ? ", the prior through its tree (θ 0.5)" : "");
}

int apply_point_options(LtmModel &model, int given, double prior_theta, bool prior_rays) {
    const int n = given != 0 ? given : model->cfg.auto_scene_points ? int(k_scene_points_auto) : 0;
    if (prior_rays) set_prior_rays(model);
    if (prior_theta >= 0) set_prior_theta(model, prior_theta);
    if (model->cfg.physics.prior_rays && !(model->cfg.physics.prior_theta > 0.f))
        LTM_THROW("--prior-rays (physics.prior_rays) needs --prior-theta > 0 (physics.prior_theta): the rays test the terms of the "
                  "prior's cluster tree (the dense rows have none)");
    if (n > 0) set_scene_points(model, n);
    return n;
}

void set_prior_theta(LtmModel &model, double theta) {
    if (!(theta >= 0.0 && theta <= 1.0)) LTM_THROW("--prior-theta ", theta, ": must be in [0, 1] (0: the dense rows)");
    if (model->cfg.physics.prior_field != "transport")
        LTM_THROW("--prior-theta: the model's prior is \"", model->cfg.physics.prior_field, "\", not the transport prior");
    model->cfg.physics.prior_theta = float(theta);
}

void set_prior_rays(LtmModel &model) {
    if (model->cfg.physics.prior_field != "transport")
        LTM_THROW("--prior-rays: the model's prior is \"", model->cfg.physics.prior_field, "\", not the transport prior");
    model->cfg.physics.prior_rays = true;
    if (!(model->cfg.physics.prior_theta > 0.f)) model->cfg.physics.prior_theta = 0.5f;   // rays test the tree's terms
}

}  // namespace ltm
