// cmd_render_neural.cpp: `ltm render --method neural`. Weights whose body is silent (at their prior,
// or folded to the regathered prior by their skip: the shipped v0.14) render without libtorch
// (infer/prior_model.h), in any build; an active network, or a directional head, through the tensor
// model (libtorch builds).
#include <chrono>
#include <string>

#include "cli.h"
#include "command_model.h"
#include "ltm/core/file_util.h"
#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/core/startup.h"
#include "ltm/core/tonemap.h"
#include "ltm/nn/scene_frame.h"
#include "ltm/procgen/training_range.h"
#include "ltm/scene/scene_loader.h"

namespace ltm::cli {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

void run_neural_render(const NeuralRenderArgs &a, const CommonOptions &common) {
    // What a user waits for besides the render itself (issue #31: the time before the first pixel).
    const double before_command = process_age_seconds();   // exec, libraries, static initialisers, CLI
    auto t = Clock::now();
    PriorModel pm = load_prior_model(a.model);   // the config; whether its body is silent (the prior, or folded)
    const GlossyShading glossy = parse_glossy_shading(a.glossy);
    if (glossy == GlossyShading::head && !pm.cfg.directional)
        LTM_THROW(a.model, ": --glossy head needs a directional head, and these weights have none (use --glossy trace or diffuse)");
    CommandModel m = open_command_model(std::move(pm), glossy == GlossyShading::head, "--glossy head needs the directional head, a network");
    ModelConfig &cfg = m.cfg();
    const double load_model_s = seconds_since(t);
    const int scene_points = apply_point_options(cfg, a.scene_points, a.prior_theta, a.prior_rays);   // its bounds fail before the scene loads
    t = Clock::now();
    const Scene scene = load_scene(a.scene);
    const double load_scene_s = seconds_since(t);
    if (scene_points == k_scene_points_auto) set_auto_scene_points(cfg, scene, a.prior_theta >= 0);
    t = Clock::now();
    for (const auto &w : scene_range_warnings(scene, cfg.physics.length_scale)) log_warn(a.scene, ": ", w);
    const Camera cam = choose_camera(scene, a.camera, a.width, a.height, a.scene);
    const EmbreeAccel accel(scene);
    check_camera(accel, cam, a.scene);
    PathTracerConfig pcfg;
    pcfg.seed = common.seed;
    const PathTracer pt(accel, pcfg);
    const double accel_s = seconds_since(t);
    NeuralRenderOptions opt;
    opt.direct_spp = a.direct_spp, opt.direct = parse_direct_estimator(a.direct_estimator);
    opt.seed = common.seed, opt.exclude_enclosed = a.exclude_enclosed;
    opt.gi.stride = a.gi_stride, opt.gi.contrast = a.gi_contrast;
    opt.gi.levels = a.gi_levels > 0 ? a.gi_levels : auto_gi_levels(a.gi_stride, cam.width, cam.height);
    opt.glossy_samples = a.glossy_samples;
    opt.glossy = glossy;
    opt.bounce = parse_bounce_irradiance(a.bounce);
#if LTM_WITH_TORCH
    const NeuralRender r = m.tensor ? render_neural(m.tensor->model, pt, cam, opt) : render_prior(cfg, pt, cam, opt, m.prior.skip);
#else
    const NeuralRender r = render_prior(cfg, pt, cam, opt, m.prior.skip);
#endif
    if (r.n_conductor > 0 && r.glossy == GlossyShading::diffuse)
        log_warn(r.n_conductor, " pixels see conductors: shaded as diffuse (--glossy diffuse)");
    else if (r.n_conductor > 0)
        log_info(r.n_conductor, " conductor pixels shaded by ", r.glossy == GlossyShading::head ? "the directional head" : "one traced bounce",
                 " (", r.glossy_samples, " GGX samples each",
                 r.glossy == GlossyShading::trace ? std::string(r.bounce == BounceIrradiance::nodes ? "; E+ at its hits from the scene points" : "; E+ decoded at its hits") : "",
                 ") in ", format_duration(r.timings.glossy));
    t = Clock::now();
    write_rendered_image(r.image, a.prefix, a.exposure, a.exr_float);
    write_png(a.prefix + ".irradiance.png", r.image.irradiance, tonemap_scale(r.image.irradiance));
    const double write_s = seconds_since(t);
    const auto &rt = r.timings;
    // What inference ran: the network; a silent body folded to its skip (the prior and its regather,
    // no encoder, no attention: LtmModelImpl::fold_prior, or infer/prior_model.h without libtorch); or
    // the prior alone.
    std::string network = m.network ? "active" : "silenced: the prior alone, without libtorch";
    if (m.prior.folded() && !m.network && skip_reads_regather_alone(m.prior.skip))
        network = "folded at w = 1: the regather alone (the prior's bounces not solved), without the encoder or attention, without libtorch";
    else if (m.prior.folded())
        network = std::string("folded: the prior and its regather through the skip, without the encoder or attention") +
                  (m.network ? "" : ", without libtorch");
    OrderedJson j = {{"scene", a.scene},
                     {"model", a.model},
                     {"network", network},
                     {"width", cam.width},
                     {"height", cam.height},
                     {"queries", r.n_queries},
                     {"gi_stride", a.gi_stride},
                     {"gi_levels", opt.gi.levels},
                     {"gi_contrast", a.gi_contrast},
                     {"decoded", r.n_decoded},
                     {"scene_points", r.n_scene_points},
                     {"direct_spp", a.direct_spp},
                     {"direct_estimator", direct_estimator_name(r.direct)},
                     {"conductor_pixels", r.n_conductor},
                     {"glossy", glossy_shading_name(r.glossy)},
                     {"glossy_samples", r.glossy_samples},
                     {"bounce_irradiance", r.glossy == GlossyShading::trace ? bounce_irradiance_name(r.bounce) : "none"},
                     {"threads", common.threads},
                     {"timings", rt.to_json()},
                     {"outside_render", {{"before_command_s", before_command},
                                         {"load_model_s", load_model_s},
                                         {"load_scene_s", load_scene_s},
                                         {"accel_s", accel_s},
                                         {"write_images_s", write_s}}}};
    write_file_atomic(a.prefix + ".timings.json", j.dump(2) + "\n");
    log_info("neural render ", cam.width, "x", cam.height, " (", r.n_queries, " queries, ", r.n_decoded, " decoded, ", r.n_scene_points,
             " scene points) in ", format_duration(rt.total), ": encode ", format_duration(rt.sample + rt.geometry + rt.encode),
             " (sample ", format_duration(rt.sample), ", fps/knn ", format_duration(rt.geometry), ", prior solve ",
             format_duration(rt.prior_solve), rt.trace > 0 ? ", traced inputs " + format_duration(rt.trace) : std::string(), ", ptv3 ",
             format_duration(rt.encode - rt.prior_solve - rt.trace), "), g-buffer ", format_duration(rt.gbuffer), ", knn ", format_duration(rt.knn),
             ", decode ", format_duration(rt.decode), ", direct ", format_duration(rt.direct));
    log_info("outside the render: ", before_command >= 0 ? "process start to command " + format_duration(before_command) + ", " : std::string(),
             "weights ", format_duration(load_model_s), ", scene ", format_duration(load_scene_s), ", BVH ", format_duration(accel_s),
             ", writing the images ", format_duration(write_s));
    log_info("wrote ", a.prefix, ".exr, ", a.prefix, ".png, ", a.prefix, ".irradiance.png, ", a.prefix, ".timings.json");
}

}  // namespace ltm::cli
