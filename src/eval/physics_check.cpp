// physics_check.cpp: the model under exact transformations of its input scene.
#include "ltm/eval/physics_check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/core/rng.h"
#include "ltm/eval/reference_cache.h"
#include "ltm/infer/neural_renderer.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/scene_transform.h"

namespace ltm {

namespace {

Camera check_camera(const Scene &scene, const PhysicsCheckOptions &opt) {
    if (scene.cameras.empty()) LTM_THROW("physics check: scene '", scene.name, "' has no camera");
    Camera cam = scene.cameras.front();
    cam.width = opt.width, cam.height = opt.height;
    return cam;
}

// Ê⁺ at the G-buffer points, the scene points sampled from `scene` as the dataset does: [0] the
// model's, [1] its own prior's (the network silenced; one encode serves both).
std::array<std::vector<Vec3f>, 2> predict(LtmModel &model, const Scene &scene, const GBuffer &gb, const PhysicsCheckOptions &opt) {
    const EmbreeAccel accel(scene);
    const EncodedScene enc = encode_scene(model, accel, opt.seed, opt.exclude_enclosed);
    return {predict_gbuffer(model, enc, gb), predict_gbuffer_prior(enc, gb)};
}

// mean_k |a_k − f·b_k| / mean_k |f·b_k| over all channels.
double relative_difference(const std::vector<Vec3f> &a, const std::vector<Vec3f> &b, float f) {
    double num = 0, den = 0;
    for (size_t k = 0; k < a.size(); ++k) {
        const Vec3f d = a[k] - b[k] * f;
        num += double(std::abs(d.x)) + double(std::abs(d.y)) + double(std::abs(d.z));
        den += double(std::abs(b[k].x * f)) + double(std::abs(b[k].y * f)) + double(std::abs(b[k].z * f));
    }
    return den > 0 ? num / den : (num > 0 ? INFINITY : 0.0);
}

// RMS over channels of (shift of a) − (shift of b), shift = clr(after) − clr(before).
double shift_error(const Color3d &a0, const Color3d &a1, const Color3d &b0, const Color3d &b1) {
    const Color3d la0 = centred_log(a0), la1 = centred_log(a1), lb0 = centred_log(b0), lb1 = centred_log(b1);
    double s = 0;
    for (size_t i = 0; i < 3; ++i) {
        const double d = (la1[i] - la0[i]) - (lb1[i] - lb0[i]);
        s += d * d;
    }
    return std::sqrt(s / 3.0);
}

std::string factor_key(float f) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", double(f));
    return b;
}

OrderedJson color_json(const Color3d &c) { return OrderedJson::array({c[0], c[1], c[2]}); }

}  // namespace

PhysicsReport run_physics_checks(const std::vector<EvalScene> &scenes, std::vector<EvalModel> &models,
                                 const PhysicsCheckOptions &opt) {
    PhysicsReport report;
    report.options = opt;
    PathTracerConfig tracer;
    tracer.seed = hash_keys({opt.seed, 0x9b751c5ull});
    for (size_t si = 0; si < scenes.size(); ++si) {
        const EvalScene &es = scenes[si];
        log_info("physics check: ", es.name, " (", si + 1, "/", scenes.size(), ")");
        const Camera cam = check_camera(es.scene, opt);
        const EmbreeAccel accel(es.scene);
        const GBuffer gb = render_gbuffer(accel, cam);
        if (gb.n_hits() == 0) {
            log_warn("physics check: ", es.name, " camera sees nothing; skipped");
            continue;
        }
        // The recoloured twin and both references (same G-buffer: geometry is unchanged).
        Scene recolored = es.scene;
        const int n_recolored = recolor_meshes(recolored, is_room_shell_mesh, opt.recolor, "physics_recolor");
        auto reference = [&](const Scene &s, const std::string &tag) {
            const EmbreeAccel a(s);
            const PathTracer pt(a, tracer);
            const CachedReference ref = reference_irradiance(opt.ref_cache_dir, s, cam, gb, pt, tracer, opt.ref_spp,
                                                             {{"scene", es.name + tag}, {"view", cam.name}, {"width", cam.width},
                                                              {"height", cam.height}, {"spp", opt.ref_spp}});
            return mean_color(gather_hits(gb, ref.indirect));
        };
        const Color3d ref_base = reference(es.scene, ""), ref_recolored = n_recolored > 0 ? reference(recolored, "-recolored") : ref_base;
        for (auto &m : models) {
            m.fit_scene_points(es.scene);   // scaled twins keep its triangles, so its M
            // Every prediction once; the model's checks read [0], its prior's (`model-prior:NAME`) [1].
            const auto base = predict(m.model, es.scene, gb, opt);
            std::vector<std::array<std::vector<Vec3f>, 2>> emitted, scaled;
            for (float k : opt.emission_factors) {
                Scene s = es.scene;
                scale_emission(s, k);
                emitted.push_back(predict(m.model, s, gb, opt));
            }
            for (float f : opt.length_factors) {
                Scene s = es.scene;
                scale_lengths(s, f);
                GBuffer g = gb;   // the same surface points in the new unit
                for (Vec3f &p : g.position) p = p * f;
                scaled.push_back(predict(m.model, s, g, opt));
            }
            const auto recolored_prediction = n_recolored > 0 ? predict(m.model, recolored, gb, opt) : base;
            for (size_t w = 0; w < 2; ++w) {
                SceneCheck c;
                c.scene = es.name, c.model = w == 0 ? m.name : "model-prior:" + m.name, c.recolored_meshes = n_recolored;
                for (size_t i = 0; i < emitted.size(); ++i)
                    c.emission_error.emplace_back(opt.emission_factors[i], relative_difference(emitted[i][w], base[w], opt.emission_factors[i]));
                for (size_t i = 0; i < scaled.size(); ++i)
                    c.length_error.emplace_back(opt.length_factors[i], relative_difference(scaled[i][w], base[w], 1.f));
                c.model_base = mean_color(base[w]);
                c.model_recolored = mean_color(recolored_prediction[w]);
                c.ref_base = ref_base, c.ref_recolored = ref_recolored;
                c.recolor_chroma_error = chroma_error(c.model_recolored, c.ref_recolored);
                c.response_error = shift_error(c.model_base, c.model_recolored, c.ref_base, c.ref_recolored);
                c.blue_share_model = blue_share(c.model_recolored), c.blue_share_ref = blue_share(c.ref_recolored);
                report.scenes.push_back(std::move(c));
            }
        }
    }
    // Furnace: every point sees E⁺ = π·Le·Σ_{k=1..D} ρ^k (render/path_tracer.h's depth convention).
    const Scene furnace = furnace_box(opt.furnace_albedo, 1.f);
    const Camera fcam = check_camera(furnace, opt);
    const EmbreeAccel faccel(furnace);
    const GBuffer fgb = render_gbuffer(faccel, fcam);
    double series = 0, term = 1;
    for (int k = 1; k <= opt.furnace_bounces; ++k) series += (term *= double(opt.furnace_albedo));
    for (auto &m : models) {
        m.fit_scene_points(furnace);
        const auto e = predict(m.model, furnace, fgb, opt);
        report.furnace.push_back({m.name, luminance(mean_color(e[0])), double(k_pi) * series});
        report.furnace.push_back({"model-prior:" + m.name, luminance(mean_color(e[1])), double(k_pi) * series});
    }
    return report;
}

OrderedJson PhysicsReport::to_json() const {
    OrderedJson j;
    j["options"] = {{"width", options.width}, {"height", options.height}, {"ref_spp", options.ref_spp},
                    {"seed", options.seed}, {"emission_factors", options.emission_factors},
                    {"length_factors", options.length_factors},
                    {"recolor", OrderedJson::array({options.recolor.x, options.recolor.y, options.recolor.z})},
                    {"furnace_albedo", options.furnace_albedo}, {"furnace_bounces", options.furnace_bounces}};
    OrderedJson sj = OrderedJson::array();
    for (const auto &c : scenes) {
        OrderedJson e = OrderedJson::object(), l = OrderedJson::object();
        for (const auto &[k, err] : c.emission_error) e[factor_key(k)] = err;
        for (const auto &[s, err] : c.length_error) l[factor_key(s)] = err;
        sj.push_back({{"scene", c.scene}, {"model", c.model}, {"emission_error", e}, {"length_error", l},
                      {"recolored_meshes", c.recolored_meshes}, {"model_base", color_json(c.model_base)},
                      {"model_recolored", color_json(c.model_recolored)}, {"ref_base", color_json(c.ref_base)},
                      {"ref_recolored", color_json(c.ref_recolored)}, {"recolor_chroma_error", c.recolor_chroma_error},
                      {"response_error", c.response_error}, {"blue_share_model", c.blue_share_model},
                      {"blue_share_ref", c.blue_share_ref}});
    }
    j["scenes"] = sj;
    OrderedJson fj = OrderedJson::array();
    for (const auto &f : furnace)
        fj.push_back({{"model", f.model}, {"predicted", f.predicted}, {"closed_form", f.closed_form},
                      {"ratio", f.predicted / f.closed_form}});
    j["furnace"] = fj;
    return j;
}

std::string PhysicsReport::table_markdown() const {
    struct Acc {
        double emission_max = 0, length_mean = 0, length_max = 0, recolor_chroma = 0, response = 0, blue_gap = 0,
               blue_gap_max = 0;
        int n = 0, blue_within = 0;
    };
    std::vector<std::string> order;
    std::map<std::string, Acc> acc;
    for (const auto &c : scenes) {
        if (!acc.count(c.model)) order.push_back(c.model);
        Acc &a = acc[c.model];
        for (const auto &e : c.emission_error) a.emission_max = std::max(a.emission_max, e.second);
        for (const auto &e : c.length_error) {
            a.length_mean += e.second / double(c.length_error.size());
            a.length_max = std::max(a.length_max, e.second);
        }
        const double gap = std::abs(c.blue_share_model - c.blue_share_ref);
        a.recolor_chroma += c.recolor_chroma_error, a.response += c.response_error, a.blue_gap += gap;
        a.blue_gap_max = std::max(a.blue_gap_max, gap);
        a.blue_within += gap <= 0.08;
        ++a.n;
    }
    std::ostringstream o;
    char buf[512];
    o << "| model | scenes | emission ×k error (max) | unit ×s error (mean / max) | recoloured chroma err | "
         "colour response err | blue-share gap (mean / max) | ≤ 0.08 | furnace Ê⁺ / closed form |\n"
         "|---|---|---|---|---|---|---|---|---|\n";
    for (const auto &name : order) {
        const Acc &a = acc[name];
        double furnace_ratio = NAN;
        for (const auto &f : furnace)
            if (f.model == name) furnace_ratio = f.predicted / f.closed_form;
        std::snprintf(buf, sizeof buf, "| %s | %d | %.2e | %.2e / %.2e | %.3f | %.3f | %.3f / %.3f | %d | %.3f |\n", name.c_str(),
                      a.n, a.emission_max, a.length_mean / a.n, a.length_max, a.recolor_chroma / a.n, a.response / a.n,
                      a.blue_gap / a.n, a.blue_gap_max, a.blue_within, furnace_ratio);
        o << buf;
    }
    o << "\nAt the G-buffer points of each scene's first camera (" << options.width << "×" << options.height
      << "), references " << options.ref_spp << " spp. Emission ×k (k in {";
    for (size_t i = 0; i < options.emission_factors.size(); ++i) o << (i ? ", " : "") << options.emission_factors[i];
    o << "}): mean|Ê(k·Le) − k·Ê(Le)| / mean k·Ê. Unit ×s (s in {";
    for (size_t i = 0; i < options.length_factors.size(); ++i) o << (i ? ", " : "") << options.length_factors[i];
    o << "}): mean|Ê(s·x) − Ê(x)| / mean Ê. Recolouring: room walls, floors and ceilings set to albedo ("
      << options.recolor.x << ", " << options.recolor.y << ", " << options.recolor.z
      << "); chroma errors are RMS differences of centred log channel means (eval/field_metrics.h); the response "
         "error compares the chroma shift the recolouring causes in the model and in the path tracer. Furnace: "
         "closed box, ρ = "
      << options.furnace_albedo << ", Le = 1, E⁺ = π·Σ_{k=1.." << options.furnace_bounces << "} ρ^k.\n";
    return o.str();
}

}  // namespace ltm
