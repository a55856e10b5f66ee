// cmd_eval.cpp: `ltm eval --model M --scenes 900000:900050 --views 2 -o DIR` → report.json,
// table.md and one PNG grid per scene and view (eval/experiment.h); --physics adds physics.json and
// physics.md (eval/physics_check.h); --radiance adds radiance.json and radiance.md (eval/radiance_eval.h).
#include <memory>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "delegate.h"
#include "ltm/core/file_util.h"
#include "ltm/core/log.h"
#include "ltm/eval/eval_setup.h"
#include "ltm/eval/experiment.h"
#include "ltm/eval/physics_check.h"
#include "ltm/eval/radiance_eval.h"
#include "ltm/infer/neural_renderer.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/procgen/training_range.h"
#include "ltm/scene/scene_loader.h"

namespace ltm::cli {

namespace {
struct EvalArgs {
    std::string model, output, gen_config;
    std::vector<std::string> scenes, ablations;
    EvalOptions opt;
    PhysicsCheckOptions physics;
    bool no_grids = false, run_physics = false, physics_only = false, radiance = false;
    int direct_spp = 16, glossy_samples = 0, scene_points = 0;
    double prior_theta = -1;
    bool prior_rays = false;
    std::string bounce = "auto";
};

void declare(CLI::App &sub, EvalArgs &a) {
    sub.add_option("--model", a.model, "Weights (.safetensors from ltm export)")->required();
    sub.add_option("--ablation", a.ablations, "More models to compare: NAME=weights.safetensors (repeatable)");
    add_scene_points_option(&sub, a.scene_points, "every model, every scene; auto: each scene its own");
    sub.add_option("--prior-theta", a.prior_theta, k_prior_theta_help)->check(CLI::Range(0.0, 1.0));
    sub.add_flag("--prior-rays", a.prior_rays, k_prior_rays_help);
    sub.add_option("--scenes", a.scenes, "Generator seed ranges A:B and/or scene files (keep seeds disjoint from training)")
        ->required();
    sub.add_option("--gen-config", a.gen_config, "Generator config for seed ranges (default: built-in)");
    sub.add_option("--views", a.opt.views, "Views per scene (scene camera turned by 360°/views)")->capture_default_str();
    sub.add_option("--width", a.opt.width, "View width")->capture_default_str()->check(CLI::Range(16, 4096));
    sub.add_option("--height", a.opt.height, "View height")->capture_default_str()->check(CLI::Range(16, 4096));
    sub.add_option("--ref-spp", a.opt.ref_spp, "Reference samples per pixel")->capture_default_str();
    sub.add_option("--baseline-spp", a.opt.baseline_spp, "PT baseline samples per pixel (paper: 64)")->capture_default_str();
    sub.add_option("--ref-cache", a.opt.ref_cache_dir,
                   "Keep references in this directory and reuse them when scene, view, spp and seed match");
    sub.add_option("--gi-stride", a.opt.gi_stride,
                   "Also evaluate each model with E+ decoded on every N-th pixel and interpolated (rows model:NAME/giN)")
        ->capture_default_str()
        ->check(CLI::Range(1, 16));
    add_gi_refine_options(sub, a.opt.gi_levels, a.opt.gi_contrast);
    sub.add_flag("--ref-noise", a.opt.reference_noise,
                 "Also estimate each reference's own noise, the MSE floor no method can go below (one more reference with "
                 "independent samples, cached like it): reference_noise_mse in report.json, a line under the table");
    sub.add_flag("--no-grids", a.no_grids, "Skip the PNG grids");
    sub.add_flag("--physics", a.run_physics,
                 "Also run the physics checks (emission x0.25/x4, unit x0.1/x10, blue room shells, furnace box): "
                 "physics.json, physics.md");
    sub.add_flag("--physics-only", a.physics_only, "Only the physics checks (no Table 1)");
    sub.add_option("--physics-size", a.physics.width, "Physics checks: square G-buffer size")
        ->capture_default_str()
        ->check(CLI::Range(8, 1024));
    sub.add_option("--physics-spp", a.physics.ref_spp, "Physics checks: reference samples per pixel")
        ->capture_default_str()
        ->check(CLI::Range(1, 1 << 20));
    sub.add_flag("--radiance", a.radiance,
                 "Also compare the rendered images (direct + GI; conductors by one traced bounce, and through the "
                 "directional head where the model has one) with path "
                 "tracing, over all pixels and over conductor pixels: radiance.json, radiance.md, radiance_*.png");
    sub.add_option("--direct-spp", a.direct_spp, "--radiance: the neural render's light samples per pixel")
        ->capture_default_str()
        ->check(CLI::Range(1, 1 << 16));
    sub.add_option("--glossy-samples", a.glossy_samples,
                   "--radiance: the neural render's GGX samples per conductor pixel (0: 64 traced, 16 through the head)")
        ->capture_default_str()
        ->check(CLI::Range(0, 1 << 16));
    sub.add_option("--bounce-irradiance", a.bounce,
                   std::string("--radiance: ") + k_bounce_irradiance_help + "; the other way is a row of its own (/bounce-…)")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "nodes", "decode"}));
    add_output_option(sub, a.output, "Output directory");
}

void run(const EvalArgs &a, const CommonOptions &common) {
    EvalOptions opt = a.opt;
    opt.seed = common.seed;
    if (opt.views < 1) LTM_THROW("--views ", opt.views, ": must be >= 1");
    if (opt.ref_spp < 1 || opt.baseline_spp < 1) LTM_THROW("--ref-spp/--baseline-spp must be >= 1");
    opt.out_dir = a.no_grids ? "" : a.output;
    std::vector<EvalModel> models;
    models.push_back({"ours", a.model, load_model(a.model).model});
    for (const auto &spec : a.ablations) {
        const size_t eq = spec.find('=');
        if (eq == std::string::npos || eq == 0) LTM_THROW("--ablation ", spec, ": expected NAME=weights.safetensors");
        models.push_back({spec.substr(0, eq), spec.substr(eq + 1), load_model(spec.substr(eq + 1)).model});
    }
    for (auto &m : models) {
        if (apply_point_options(m.model, a.scene_points, a.prior_theta, a.prior_rays) == k_scene_points_auto)
            m.enable_auto_scene_points(a.prior_theta >= 0);
    }
    // Scenes: seed ranges are generated in memory, files are loaded.
    const GenConfig gen = a.gen_config.empty() ? GenConfig{} : GenConfig::from_json(parse_json_file(a.gen_config), a.gen_config);
    std::vector<EvalScene> scenes;
    const std::vector<std::string> labels = scene_labels(a.scenes);
    size_t next_label = 0;
    for (const auto &s : a.scenes) {
        if (is_seed_range(s)) {
            const auto [lo, hi] = parse_seed_range(s, "--scenes");
            for (uint64_t seed = lo; seed < hi; ++seed)
                scenes.push_back({"seed-" + std::to_string(seed), generate_indoor(gen, seed).scene});
        } else {
            Scene sc = load_scene(s);
            for (const auto &w : scene_range_warnings(sc, models.empty() || models.front().model->cfg.physics.length_scale))
                log_warn(s, ": ", w);
            scenes.push_back({labels[next_label++], std::move(sc)});
        }
    }
    if (scenes.empty()) LTM_THROW("--scenes: no scenes");
    create_directories(a.output);
    if (a.run_physics || a.physics_only) {
        PhysicsCheckOptions po = a.physics;
        po.height = po.width;
        po.seed = common.seed, po.ref_cache_dir = opt.ref_cache_dir, po.exclude_enclosed = opt.exclude_enclosed;
        const PhysicsReport pr = run_physics_checks(scenes, models, po);
        OrderedJson j = pr.to_json();
        j["models"] = OrderedJson::object();
        for (const auto &m : models) j["models"][m.name] = m.path;
        write_file_atomic(a.output + "/physics.json", j.dump(2) + "\n");
        const std::string table = pr.table_markdown();
        write_file_atomic(a.output + "/physics.md", table);
        std::fprintf(stderr, "%s", table.c_str());
        log_info("wrote ", a.output, "/physics.json, physics.md");
        if (a.physics_only) return;
    }
    if (a.radiance) {
        RadianceEvalOptions ro;
        ro.base = opt, ro.direct_spp = a.direct_spp, ro.glossy_samples = a.glossy_samples;
        ro.bounce = parse_bounce_irradiance(a.bounce);
        const RadianceEvalReport rr = run_radiance_evaluation(scenes, models, ro);
        if (rr.all.views.empty()) LTM_THROW("eval --radiance: no view saw any surface");
        OrderedJson j = rr.to_json();
        j["model"] = a.model, j["scenes"] = a.scenes, j["threads"] = common.threads;
        write_file_atomic(a.output + "/radiance.json", j.dump(2) + "\n");
        const std::string table = rr.table_markdown();
        write_file_atomic(a.output + "/radiance.md", table);
        std::fprintf(stderr, "%s", table.c_str());
        log_info("wrote ", a.output, "/radiance.json, radiance.md", a.no_grids ? "" : " and radiance_*.png");
    }
    const EvalReport r = run_evaluation(scenes, models, opt);
    if (r.views.empty()) LTM_THROW("eval: no view saw any surface");
    OrderedJson j = r.to_json();
    j["model"] = a.model;
    j["ablations"] = a.ablations;
    j["scenes"] = a.scenes;
    j["threads"] = common.threads;
    // The models' M (--scene-points or their own; with auto, each view's model rows carry theirs):
    // one value when every model agrees, else each model's by name.
    auto points_of = [](const EvalModel &m) { return m.auto_scene_points ? OrderedJson("auto") : OrderedJson(m.model->cfg.scene_points); };
    j["scene_points"] = points_of(models.front());
    for (const auto &m : models)
        if (points_of(m) != j["scene_points"]) {
            OrderedJson each = OrderedJson::object();
            for (const auto &n : models) each[n.name] = points_of(n);
            j["scene_points"] = each;
            break;
        }
    write_file_atomic(a.output + "/report.json", j.dump(2) + "\n");
    const std::string table = r.table_markdown();
    write_file_atomic(a.output + "/table.md", table);
    std::fprintf(stderr, "%s", table.c_str());
    log_info("wrote ", a.output, "/report.json, table.md", a.no_grids ? "" : " and grids");
}
}  // namespace

Command make_eval_command() {
    return make_command(
        "eval", k_eval_help,
        declare, run);
}

}  // namespace ltm::cli
