// field_render.cpp: G-buffer, Ê⁺ from the source on a lattice, direct light, compose, conductors.
#include "ltm/infer/field_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/core/parallel.h"
#include "ltm/core/progress.h"
#include "ltm/core/rng.h"
#include "ltm/render/direct_light.h"
#include "ltm/render/image_renderer.h"
#include "ltm/render/interaction.h"

namespace ltm {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

std::vector<float> gbuffer_query_rows(const GBuffer &gb, const std::vector<size_t> *hits) {
    const size_t n = hits ? hits->size() : gb.n_hits();
    std::vector<float> q(n * 9);
    for (size_t k = 0; k < n; ++k) {
        const size_t h = hits ? (*hits)[k] : k;
        write_query_row(&q[k * 9], gb.position[h], gb.normal[h], gb.albedo[h]);
    }
    return q;
}

std::vector<Vec3f> decode_gbuffer(const IrradianceDecoder &decode, const GBuffer &gb, const std::vector<size_t> *hits) {
    const size_t n = hits ? hits->size() : gb.n_hits();
    if (n == 0) return {};
    std::vector<Vec3f> e = decode(gbuffer_query_rows(gb, hits));
    if (e.size() != n) LTM_THROW("neural render: the decoder returned ", e.size(), " values for ", n, " pixels");
    return e;
}

std::vector<Vec3f> decode_gbuffer_upsampled(const IrradianceDecoder &decode, const GBuffer &gb, const Camera &camera,
                                            const GiUpsampleOptions &opt, int64_t *n_decoded) {
    if (opt.stride == 1 && opt.levels == 1) {
        if (n_decoded) *n_decoded = int64_t(gb.n_hits());
        return decode_gbuffer(decode, gb);
    }
    GiUpsampled r = upsample_gi(gb, camera, opt, [&](const std::vector<size_t> &hits) { return decode_gbuffer(decode, gb, &hits); });
    if (n_decoded) *n_decoded = r.decoded;
    return std::move(r.values);
}

OrderedJson NeuralTimings::to_json() const {
    return {{"gbuffer_s", gbuffer}, {"sample_s", sample}, {"geometry_s", geometry}, {"encode_s", encode},
            {"prior_solve_s", prior_solve}, {"trace_s", trace}, {"knn_s", knn}, {"decode_s", decode}, {"direct_s", direct}, {"glossy_s", glossy},
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
std::vector<Vec3f> head_radiance(const GiSource &src, const GBuffer &gb, const ConductorSamples &c) {
    const size_t K = size_t(c.K), rows = c.hits.size() * K;
    std::vector<float> q(rows * 9), d(rows * 3);
    for (size_t row = 0; row < rows; ++row) {
        const size_t k = c.hits[row / K];
        write_query_row(&q[row * 9], gb.position[k], gb.normal[k], gb.albedo[k]);
        for (int a = 0; a < 3; ++a) d[row * 3 + size_t(a)] = c.dir[row][a];
    }
    std::vector<Vec3f> l = src.head(q, d);
    if (l.size() != rows) LTM_THROW("neural render: the directional head returned ", l.size(), " values for ", rows, " rows");
    return l;
}

// One traced bounce (GlossyShading::trace) along every row with a sample.  -> [H·K]
std::vector<Vec3f> traced_radiance(const IrradianceDecoder &decode, const GiSource &src, const PathTracer &pt, const GBuffer &gb,
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
        nodes = decode_node_irradiance(decode, *src.points, src.spacing);
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

NeuralRender render_with_gi(const GiSource &src, const PathTracer &pt, const Camera &camera, const NeuralRenderOptions &opt) {
    if (opt.direct_spp <= 0) LTM_THROW("neural render: direct-light samples per pixel must be > 0, got ", opt.direct_spp);
    if (opt.glossy_samples < 0) LTM_THROW("neural render: glossy samples per pixel must be >= 0 (0: automatic), got ", opt.glossy_samples);
    if (!src.irradiance || !src.points) LTM_THROW("neural render: no Ê⁺ field to render from");
    if (opt.glossy == GlossyShading::head && opt.prior_only)
        LTM_THROW("neural render: the prior alone has no directional head (use --glossy trace or diffuse)");
    if (opt.glossy == GlossyShading::head && !src.head)
        LTM_THROW("neural render: --glossy head needs a directional head, and these weights have none (use trace or diffuse)");
    NeuralRender r;
    const auto t0 = Clock::now();
    r.timings.sample = src.sample_seconds, r.timings.geometry = src.geometry_seconds, r.timings.encode = src.encode_seconds;
    r.timings.prior_solve = src.prior_solve_seconds;
    r.timings.trace = src.trace_seconds;
    auto t = Clock::now();
    const GBuffer gb = render_gbuffer(pt.accel(), camera);
    r.timings.gbuffer = seconds_since(t);
    const DecodeTimings before = src.timings ? *src.timings : DecodeTimings{};
    const Image indirect = scatter_to_image(gb, decode_gbuffer_upsampled(src.irradiance, gb, camera, opt.gi, &r.n_decoded));
    if (src.timings) r.timings.knn = src.timings->knn - before.knn, r.timings.decode = src.timings->decode - before.decode;
    r.direct = opt.direct;
    if (r.direct == DirectEstimator::automatic)
        r.direct = RatioDirectLight::supports(pt.accel().scene()) ? DirectEstimator::ratio : DirectEstimator::mis;
    std::optional<RatioDirectLight> ratio;
    if (r.direct == DirectEstimator::ratio) ratio.emplace(pt.accel(), opt.seed);
    const IrradianceImages direct = ratio ? direct_images_ratio(*ratio, gb, opt.direct_spp)
                                          : irradiance_images(pt, gb, opt.direct_spp, /*with_indirect=*/false);
    r.timings.direct = direct.seconds;
    r.image = compose_image(gb, direct.direct, indirect, &r.n_conductor);
    const GlossyShading glossy = opt.glossy == GlossyShading::automatic ? GlossyShading::trace : opt.glossy;
    if (r.n_conductor > 0 && glossy != GlossyShading::diffuse) {
        // 0: 64 traced samples (cheap: a ray, light samples, one fused Ê⁺ decode each), 16 through the
        // head (a libtorch decode each, ~10× a traced sample).
        const int K = opt.glossy_samples > 0 ? opt.glossy_samples : glossy == GlossyShading::head ? 16 : 64;
        const auto tg = Clock::now();
        const ConductorSamples c = sample_conductors(pt, camera, gb, opt, K);
        r.glossy_samples = K;
        if (glossy == GlossyShading::head) {
            compose_conductors(gb, c, head_radiance(src, gb, c), r.image);
        } else {
            // Light samples per bounce hit: the pixel's budget spread over its K samples.
            const int spp = (opt.direct_spp + K - 1) / K;
            r.bounce = opt.bounce;
            if (r.bounce == BounceIrradiance::automatic)
                r.bounce = int64_t(c.hits.size()) * K >= k_bounce_nodes_per_point * src.n_scene_points ? BounceIrradiance::nodes
                                                                                                        : BounceIrradiance::decode;
            compose_conductors(gb, c, traced_radiance(src.irradiance, src, pt, gb, c, direct_irradiance_fn(pt, ratio ? &*ratio : nullptr, spp),
                                               r.bounce),
                               r.image);
        }
        r.timings.glossy = seconds_since(tg);
    }
    r.glossy = r.n_conductor > 0 ? glossy : GlossyShading::diffuse;
    r.timings.total = seconds_since(t0);
    r.image.seconds = r.timings.total;
    r.n_queries = int64_t(gb.n_hits());
    r.n_scene_points = src.n_scene_points;
    return r;
}

}  // namespace ltm
