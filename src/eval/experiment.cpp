// experiment.cpp: scenes × views × methods → metrics, grids, report.
#include "ltm/eval/experiment.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/core/tonemap.h"
#include "ltm/eval/image_grid.h"
#include "ltm/eval/reference_cache.h"
#include "ltm/infer/field_render.h"
#include "ltm/infer/neural_renderer.h"
#include "ltm/infer/prior_model.h"
#include "ltm/nn/scene_frame.h"
#include "ltm/transport/power_balance.h"
#include "ltm/transport/transport_prior.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/scene_points.h"

namespace ltm {

namespace {

struct Stats {
    double mean = 0, std = 0;
};
Stats stats(const std::vector<double> &v) {
    Stats s;
    if (v.empty()) return s;
    for (double x : v) s.mean += x;
    s.mean /= double(v.size());
    for (double x : v) s.std += (x - s.mean) * (x - s.mean);
    s.std = v.size() > 1 ? std::sqrt(s.std / double(v.size() - 1)) : 0.0;
    return s;
}

OrderedJson metrics_json(const MethodResult &r) {
    const ImageMetrics &m = r.metrics;
    return {{"mse", m.mse}, {"psnr", std::isfinite(m.psnr) ? OrderedJson(m.psnr) : OrderedJson("inf")},
            {"ssim", m.ssim}, {"rel_mse", m.rel_mse}, {"level_ratio", r.field.level_ratio},
            {"chroma_error", r.field.chroma_error}, {"luminance_correlation", r.field.luminance_correlation}};
}

// The flat oracle's tone-mapped MSE in the view (NaN if it was not evaluated).
double flat_oracle_mse(const ViewResult &v) {
    for (const auto &m : v.methods)
        if (m.method == "flat-oracle") return m.metrics.mse;
    return NAN;
}

std::vector<std::string> method_order(const EvalReport &r) {
    std::vector<std::string> out;
    for (const auto &v : r.views)
        for (const auto &m : v.methods)
            if (std::find(out.begin(), out.end(), m.method) == out.end()) out.push_back(m.method);
    return out;
}

// A reference render of one view at opt.ref_spp with `pt`'s streams (cached when opt.ref_cache_dir
// is set); `role` names any render other than the reference itself in the cache's provenance.
CachedReference view_reference(const EvalScene &es, const Camera &cam, const GBuffer &gb, const PathTracer &pt,
                               const PathTracerConfig &cfg, const EvalOptions &opt, const std::string &role = "",
                               bool *from_cache = nullptr) {
    OrderedJson provenance{{"scene", es.name}, {"view", cam.name}, {"width", cam.width}, {"height", cam.height}, {"spp", opt.ref_spp}};
    if (!role.empty()) provenance["role"] = role;
    return reference_irradiance(opt.ref_cache_dir, es.scene, cam, gb, pt, cfg, opt.ref_spp, provenance, from_cache);
}

// The reference E⁺ of one view.
Image reference_image(const EvalScene &es, const Camera &cam, const GBuffer &gb, const PathTracer &pt,
                      const PathTracerConfig &cfg, const EvalOptions &opt, ViewResult *vr) {
    CachedReference ref = view_reference(es, cam, gb, pt, cfg, opt, "", &vr->reference_cached);
    vr->reference_seconds = ref.seconds;
    return std::move(ref.indirect);
}

// ViewResult::reference_noise_mse: against a twin of the reference (its spp, its own streams;
// cached like it).
double view_reference_noise(const EvalScene &es, const EmbreeAccel &accel, const Camera &cam, const GBuffer &gb,
                            const Image &ref, const EvalOptions &opt) {
    const PathTracerConfig cfg = eval_tracer_config(opt.seed, EvalRole::reference_twin);
    return reference_noise_mse(ref, view_reference(es, cam, gb, PathTracer(accel, cfg), cfg, opt, "reference twin").indirect);
}

}  // namespace

void EvalModel::enable_auto_scene_points(bool theta_was_given) {
    auto_scene_points = true, theta_given = theta_was_given;
    fixed = {model->cfg.scene_points, model->cfg.physics.prior_theta};
}

int64_t EvalModel::fit_scene_points(const Scene &scene) {
    if (auto_scene_points) {
        model->cfg.scene_points = fixed.scene_points, model->cfg.physics.prior_theta = fixed.prior_theta;
        set_auto_scene_points(model, scene, theta_given);
    }
    return model->cfg.scene_points;
}

namespace {
// A silent body whose skip reads its regather R alone (nn/scene_frame.h skip_reads_regather_alone),
// which `ltm render` solves without the prior's bounces.
bool folds_to_regather(LtmModel &m) {
    if (!m->fold_prior || !m->cfg.traced_queries || !m->decoder->body_silent()) return false;
    const auto w = m->decoder->skip.detach().to(torch::kCPU, torch::kFloat32).contiguous();
    return skip_reads_regather_alone(Vec3f(w[0].item<float>(), w[1].item<float>(), w[2].item<float>()));
}
}  // namespace

EvalReport run_evaluation(const std::vector<EvalScene> &scenes, std::vector<EvalModel> &models, const EvalOptions &opt) {
    if (opt.views < 1) LTM_THROW("eval: views must be >= 1, got ", opt.views);
    if (opt.ref_spp < 1 || opt.baseline_spp < 1) LTM_THROW("eval: samples per pixel must be >= 1");
    if (opt.gi_stride < 1) LTM_THROW("eval: GI stride must be >= 1, got ", opt.gi_stride);
    using Clock = std::chrono::steady_clock;
    EvalReport report;
    report.options = opt;
    for (const auto &m : models) report.models.push_back(m.name);
    if (!opt.out_dir.empty()) create_directories(opt.out_dir);
    for (size_t si = 0; si < scenes.size(); ++si) {
        const EvalScene &es = scenes[si];
        const EmbreeAccel accel(es.scene);
        auto tracer_config = [&](EvalRole role) { return eval_tracer_config(opt.seed, role); };
        const PathTracer pt_ref(accel, tracer_config(EvalRole::reference)), pt_64(accel, tracer_config(EvalRole::baseline)),
            pt_eq(accel, tracer_config(EvalRole::equal_time));
        for (auto &m : models) m.fit_scene_points(es.scene);
        // The closed-form rows below solve densely: at the first model's M, or with auto at the M it
        // was loaded with (auto's M goes through the tree), and at most k_dense_rows_points (dense
        // rows at 32 768 hold ~4 GB and took 7 s a view beside v0.16, which samples 32 768 everywhere).
        constexpr int64_t k_dense_rows_points = 16384;
        const int64_t n_points = std::min(k_dense_rows_points, models.empty()                      ? 8192
                                                               : models.front().auto_scene_points ? models.front().fixed.scene_points
                                                                                                  : models.front().model->cfg.scene_points);
        const auto t_prior = Clock::now();
        const ScenePoints sampled = sample_scene_points(accel, n_points, opt.seed, opt.exclude_enclosed);
        const auto prior = power_balance_irradiance(sampled.points, PathTracerConfig{}.max_depth, &sampled.emission_scale);
        const double prior_seconds = seconds_since(t_prior);
        // The visibility-free radiosity prior (transport/transport_prior.h) with every scene point a
        // node and D = 8, as configs/model/cpu-tp.json: its level per point, no network.
        const auto t_transport = Clock::now();
        const TransportPrior transport = solve_transport_prior(
            sampled.points, float(es.scene.total_area() / double(sampled.points.size())), 8, &sampled.emission_scale);
        const double transport_seconds = seconds_since(t_transport);
        // With occlusion from the points alone (transport/point_visibility.h) as configs/model/cpu-tp.json
        // since v0.9: 1 024 clusters, segments tested against the points as discs of one spacing,
        // no power balance, D = 5 as the references (bench/prior_ablation.cpp compares the settings);
        // since v0.10 each receiver blends the visibility of its 4 nearest visible clusters and the
        // near field is by square patches.
        const auto t_vis = Clock::now();
        const float spacing = nominal_spacing(es.scene, int64_t(sampled.points.size()));
        VisibilityOptions vis;
        vis.voxel_spacings = 1.f, vis.disc_spacings = 1.f, vis.blend = 4;
        const TransportPrior transport_vis = solve_transport_prior(
            sampled.points, spacing * spacing, PathTracerConfig{}.max_depth, &sampled.emission_scale, vis, nullptr, PriorBalance::none,
            true);
        const double transport_vis_seconds = seconds_since(t_vis);
        // A model that folds to its regather R (a silent body, the skip at 1) is made and timed as the
        // renderer makes it, without libtorch (infer/prior_model.h: the same points, tracer and R to
        // float rounding): R from a frame solved for it alone, its model-prior row from a frame solved
        // for the prior alone (untraced) — the tensor model's encode would trace the scene a second time
        // for neither. Any other model encodes as the tensor model.
        // encode_s: what a single frame pays before it decodes (sampling, geometry, the encode);
        // prior_s: the same for the model-prior row; points: the scene points sampled.
        std::vector<EncodedScene> encoded(models.size());
        std::vector<IrradianceDecoder> regather(models.size()), prior_only(models.size());
        std::vector<double> encode_s(models.size()), prior_s(models.size());
        std::vector<int64_t> points(models.size());
        for (size_t mi = 0; mi < models.size(); ++mi) {
            if (!folds_to_regather(models[mi].model)) {
                const EncodedScene &e = encoded[mi] = encode_scene(models[mi].model, accel, opt.seed, opt.exclude_enclosed);
                encode_s[mi] = e.sample_seconds + e.geometry_seconds + e.encode_seconds;
                prior_s[mi] = e.sample_seconds + e.geometry_seconds + e.latents.norm.solve_seconds;
                points[mi] = e.n_scene_points;
                continue;
            }
            const ModelConfig &cfg = models[mi].model->cfg;
            // One sample of the scene points for both frames (the same points either way: both
            // would draw them from opt.seed); each frame's time counts the sampling.
            auto t = Clock::now();
            ScenePoints drawn = sample_scene_points(accel, cfg.scene_points, opt.seed, opt.exclude_enclosed);
            const double sample_s = seconds_since(t);
            ScenePoints for_prior{drawn.points, drawn.emission_scale, {}};   // the prior alone traces nothing: no ids
            t = Clock::now();
            PriorScene r = encode_prior_scene(cfg, accel, std::move(drawn), Vec3f(1.f), sample_s);
            encode_s[mi] = sample_s + seconds_since(t), points[mi] = r.n_scene_points;
            regather[mi] = prior_decoder(std::make_shared<const SceneFrame>(std::move(r.frame)), nullptr, Vec3f(1.f));   // it holds the frame
            t = Clock::now();
            PriorScene p = encode_prior_scene(cfg, accel, std::move(for_prior), Vec3f(0.f), sample_s);
            prior_s[mi] = sample_s + seconds_since(t);
            prior_only[mi] = prior_decoder(std::make_shared<const SceneFrame>(std::move(p.frame)), nullptr);
        }
        for (int v = 0; v < opt.views; ++v) {
            const auto view = eval_view(accel, es.name, v, opt.views, opt.width, opt.height);
            if (!view) continue;
            const Camera &cam = view->camera;
            const GBuffer &gb = view->gbuffer;
            ViewResult vr;
            vr.scene = es.name, vr.view = cam.name, vr.pixels = int64_t(gb.n_hits());
            log_info("eval: ", es.name, " / ", cam.name, " (", si + 1, "/", scenes.size(), ")");
            const Image ref = reference_image(es, cam, gb, pt_ref, tracer_config(EvalRole::reference), opt, &vr);
            if (opt.reference_noise) vr.reference_noise_mse = view_reference_noise(es, accel, cam, gb, ref, opt);
            const std::vector<Vec3f> ref_hits = gather_hits(gb, ref);
            auto add = [&](const std::string &method, const Image &img, double secs, int spp, int64_t n_points = 0) {
                vr.methods.push_back({method, compare_images(img, ref), secs, spp, compare_fields(gather_hits(gb, img), ref_hits), n_points});
            };
            std::vector<Image> model_images;
            double first_model_seconds = 0;
            for (size_t mi = 0; mi < models.size(); ++mi) {
                const auto t0 = Clock::now();
                PredictTimings pt;
                const Image pred = scatter_to_image(gb, regather[mi] ? decode_gbuffer(regather[mi], gb)
                                                                     : predict_gbuffer(models[mi].model, encoded[mi], gb, &pt));
                const double decode_s = seconds_since(t0);
                const EncodedScene &e = encoded[mi];
                // A single frame pays the encoder too: the model's time is encode + kNN + decode.
                const double secs = encode_s[mi] + decode_s;
                if (mi == 0) first_model_seconds = secs;
                add("model:" + models[mi].name, pred, secs, 0, points[mi]);
                model_images.push_back(pred);
                // The model's own prior, the network silenced: what the network adds is the row above against this.
                const auto t_prior_row = Clock::now();
                const Image prior_img = scatter_to_image(gb, prior_only[mi] ? decode_gbuffer(prior_only[mi], gb) : predict_gbuffer_prior(e, gb));
                add("model-prior:" + models[mi].name, prior_img, prior_s[mi] + seconds_since(t_prior_row), 0, points[mi]);
                const int gi_levels = opt.gi_levels > 0 ? opt.gi_levels : auto_gi_levels(opt.gi_stride, cam.width, cam.height);
                if (opt.gi_stride > 1 || gi_levels > 1) {
                    GiUpsampleOptions gi;
                    gi.stride = opt.gi_stride, gi.levels = gi_levels, gi.contrast = opt.gi_contrast;
                    const auto t1 = Clock::now();
                    const Image up = scatter_to_image(gb, regather[mi] ? decode_gbuffer_upsampled(regather[mi], gb, cam, gi)
                                                                       : predict_gbuffer_upsampled(models[mi].model, e, gb, cam, gi));
                    const double up_s = encode_s[mi] + seconds_since(t1);
                    add("model:" + models[mi].name + "/gi" + std::to_string(opt.gi_stride) +
                            (gi_levels > 1 ? "-L" + std::to_string(gi_levels) : ""),
                        up, up_s, 0, points[mi]);
                }
            }
            const IrradianceImages b64 = irradiance_images(pt_64, gb, opt.baseline_spp, true);
            add("pt" + std::to_string(opt.baseline_spp), b64.indirect, b64.seconds, opt.baseline_spp);
            Image eq_img;
            if (!models.empty()) {
                // PT at the model's wall time: spp scaled from the 64-spp run's measured rate.
                const int spp_eq = std::max(1, int(std::lround(double(opt.baseline_spp) * first_model_seconds / b64.seconds)));
                const IrradianceImages eq = irradiance_images(pt_eq, gb, spp_eq, true);
                add("pt-equal-time", eq.indirect, eq.seconds, spp_eq);
                eq_img = eq.indirect;
            }
            auto flat = [&](const std::array<double, 3> &c) {
                return scatter_to_image(gb, std::vector<Vec3f>(gb.n_hits(), Vec3f{float(c[0]), float(c[1]), float(c[2])}));
            };
            // The floor: every pixel the reference's own mean colour (eval/field_metrics.h).
            add("flat-oracle", flat(mean_color(ref_hits)), 0.0, 0);
            // The closed-form power-balance level from the scene points alone (transport/power_balance.h):
            // what the model's prior gives before the network adds anything.
            add("flat-prior", flat(prior), prior_seconds, 0);
            {
                static_assert(sizeof(Vec3f) == 3 * sizeof(float), "Vec3f rows are read as float triples");
                std::vector<Vec3f> e(gb.n_hits());
                gather_transport_prior(transport, &gb.position[0].x, &gb.normal[0].x, 3, gb.n_hits(), &e[0].x);
                add("transport-prior", scatter_to_image(gb, e), transport_seconds, 0);
                gather_transport_prior(transport_vis, &gb.position[0].x, &gb.normal[0].x, 3, gb.n_hits(), &e[0].x);
                add("transport-prior-vis", scatter_to_image(gb, e), transport_vis_seconds, 0);
            }
            if (!opt.out_dir.empty()) {
                // albedo | reference | model | PT 64 | PT equal time | |model − reference|
                const float scale = tonemap_scale(ref);
                std::vector<Image> tiles{scatter_to_image(gb, gb.albedo), tonemap(ref, scale)};
                if (!model_images.empty()) tiles.push_back(tonemap(model_images[0], scale));
                tiles.push_back(tonemap(b64.indirect, scale));
                if (!model_images.empty()) {
                    tiles.push_back(tonemap(eq_img, scale));
                    tiles.push_back(error_map(model_images[0], ref, scale));
                }
                write_png(opt.out_dir + "/" + es.name + "_" + cam.name + ".png", hconcat(tiles), 1.f);
            }
            report.views.push_back(std::move(vr));
        }
    }
    return report;
}

OrderedJson EvalReport::to_json() const {
    OrderedJson j;
    j["options"] = {{"width", options.width},       {"height", options.height},
                    {"views", options.views},       {"ref_spp", options.ref_spp},
                    {"baseline_spp", options.baseline_spp}, {"seed", options.seed},
                    {"metric_definition",
                     quantity + "; MSE/PSNR/SSIM after dividing both images by the reference's 99th-percentile "
                     "luminance and clamping to [0,1] (SSIM: Gaussian 11x11, sigma 1.5, K1 0.01, K2 0.03, mean over "
                     "RGB); relMSE = mean (x-ref)^2/(ref^2+0.01) on linear HDR"}};
    j["models"] = models;
    OrderedJson summary = OrderedJson::object();
    for (const auto &method : method_order(*this)) {
        std::vector<double> mse, ssim, psnr, rel, secs, chroma, corr, log_level;
        int beats_flat = 0, level_in_band = 0;
        for (const auto &v : views)
            for (const auto &m : v.methods)
                if (m.method == method) {
                    mse.push_back(m.metrics.mse), rel.push_back(m.metrics.rel_mse);
                    if (std::isfinite(m.metrics.ssim)) ssim.push_back(m.metrics.ssim);   // NaN: a region too near the border
                    secs.push_back(m.seconds);
                    if (std::isfinite(m.metrics.psnr)) psnr.push_back(m.metrics.psnr);
                    chroma.push_back(m.field.chroma_error), corr.push_back(m.field.luminance_correlation);
                    log_level.push_back(std::log(std::max(m.field.level_ratio, 1e-30)));
                    beats_flat += m.metrics.mse < flat_oracle_mse(v);
                    level_in_band += m.field.level_in_band();
                }
        auto ms = [](const std::vector<double> &x) {
            const Stats s = stats(x);
            return OrderedJson{{"mean", s.mean}, {"std", s.std}};
        };
        summary[method] = {{"views", mse.size()}, {"mse", ms(mse)}, {"ssim", ms(ssim)}, {"psnr", ms(psnr)},
                           {"rel_mse", ms(rel)}, {"seconds", ms(secs)},
                           {"level_ratio_geomean", std::exp(stats(log_level).mean)}, {"level_in_band", level_in_band},
                           {"chroma_error", ms(chroma)}, {"luminance_correlation", ms(corr)}, {"beats_flat_oracle", beats_flat}};
    }
    j["summary"] = summary;
    std::vector<double> noise;
    for (const auto &v : views)
        if (std::isfinite(v.reference_noise_mse)) noise.push_back(v.reference_noise_mse);
    if (!noise.empty()) {
        const Stats s = stats(noise);
        j["reference_noise_mse"] = {{"views", noise.size()}, {"mean", s.mean}, {"std", s.std}};
    }
    OrderedJson vs = OrderedJson::array();
    for (const auto &v : views) {
        OrderedJson mj = OrderedJson::array();
        for (const auto &m : v.methods) {
            OrderedJson row{{"method", m.method}, {"metrics", metrics_json(m)}, {"seconds", m.seconds}, {"spp", m.spp}};
            if (m.scene_points > 0) row["scene_points"] = m.scene_points;
            mj.push_back(std::move(row));
        }
        vs.push_back({{"scene", v.scene}, {"view", v.view}, {"pixels", v.pixels},
                      {"reference_seconds", v.reference_seconds}, {"reference_cached", v.reference_cached},
                      {"reference_noise_mse", std::isfinite(v.reference_noise_mse) ? OrderedJson(v.reference_noise_mse) : OrderedJson(nullptr)},
                      {"methods", mj}});
    }
    j["views"] = vs;
    return j;
}

std::string EvalReport::table_markdown() const {
    std::ostringstream o;
    const OrderedJson j = to_json();
    o << "| method | views | MSE ↓ | SSIM ↑ | PSNR (dB) ↑ | relMSE ↓ | time (s) | beats flat | level ratio (in band) | chroma err ↓ "
         "| lum. corr ↑ |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    char buf[512];
    for (const auto &[method, s] : j["summary"].items()) {
        auto f = [&](const char *k, const char *fmt) {
            std::snprintf(buf, sizeof buf, fmt, s[k]["mean"].get<double>(), s[k]["std"].get<double>());
            return std::string(buf);
        };
        o << "| " << method << " | " << s["views"].get<size_t>() << " | " << f("mse", "%.4f ± %.4f") << " | "
          << f("ssim", "%.3f ± %.3f") << " | " << f("psnr", "%.2f ± %.2f") << " | " << f("rel_mse", "%.3f ± %.3f")
          << " | " << f("seconds", "%.2f ± %.2f") << " | " << s["beats_flat_oracle"].get<int>() << " | ";
        std::snprintf(buf, sizeof buf, "%.2f (%d)", s["level_ratio_geomean"].get<double>(), s["level_in_band"].get<int>());
        o << buf << " | " << f("chroma_error", "%.3f ± %.3f") << " | " << f("luminance_correlation", "%.2f ± %.2f") << " |\n";
    }
    o << "\n" << quantity << ", " << options.width << "×" << options.height
      << ", reference " << options.ref_spp << " spp. MSE/PSNR/SSIM on images divided by the reference's "
      << "99th-percentile luminance and clamped to [0, 1]; relMSE on linear HDR. mean ± std over views. "
      << "beats flat: views where the MSE is below the flat oracle's (every pixel the reference's mean colour). "
      << "level ratio: geometric mean over views of mean Y(method)/mean Y(reference), in band: views within "
      << "[0.8, 1.25]. chroma err: RMS of centred log channel means against the reference. lum. corr: Pearson "
      << "correlation of per-pixel luminance (eval/field_metrics.h).\n";
    if (j.contains("reference_noise_mse")) {
        const auto &n = j["reference_noise_mse"];
        std::snprintf(buf, sizeof buf, "%.4f ± %.4f", n["mean"].get<double>(), n["std"].get<double>());
        o << "\nReference noise: " << buf << " — the MSE the exact E⁺ would have against these references (from an independent "
          << "twin of each; no method can go below it), over " << n["views"].get<size_t>() << " views.\n";
    }
    return o.str();
}

}  // namespace ltm
