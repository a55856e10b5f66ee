// cmd_render_neural.cpp: the libtorch half of `ltm render --method neural`.
#include "cli.h"
#include "ltm/core/file_util.h"
#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/core/tonemap.h"
#include "ltm/infer/neural_renderer.h"
#include "ltm/procgen/training_range.h"
#include "ltm/scene/scene_loader.h"

namespace ltm::cli {

void run_neural_render(const NeuralRenderArgs &a, const CommonOptions &common) {
    LoadedModel m = load_model(a.model);
    if (a.prior_theta >= 0) set_prior_theta(m.model, a.prior_theta);
    if (a.scene_points > 0) set_scene_points(m.model, a.scene_points);
    const GlossyShading glossy = parse_glossy_shading(a.glossy);
    if (glossy == GlossyShading::head && !m.model->directional)
        LTM_THROW(a.model, ": --glossy head needs a directional head, and these weights have none (use --glossy trace or diffuse)");
    const Scene scene = load_scene(a.scene);
    for (const auto &w : scene_range_warnings(scene, m.model->cfg.physics.length_scale)) log_warn(a.scene, ": ", w);
    const Camera cam = choose_camera(scene, a.camera, a.width, a.height, a.scene);
    const EmbreeAccel accel(scene);
    check_camera(accel, cam, a.scene);
    PathTracerConfig cfg;
    cfg.seed = common.seed;
    const PathTracer pt(accel, cfg);
    NeuralRenderOptions opt;
    opt.direct_spp = a.direct_spp, opt.direct = parse_direct_estimator(a.direct_estimator);
    opt.seed = common.seed, opt.exclude_enclosed = a.exclude_enclosed;
    opt.gi.stride = a.gi_stride;
    opt.glossy_samples = a.glossy_samples;
    opt.glossy = glossy;
    const NeuralRender r = render_neural(m.model, pt, cam, opt);
    if (r.n_conductor > 0 && r.glossy == GlossyShading::diffuse)
        log_warn(r.n_conductor, " pixels see conductors: shaded as diffuse (--glossy diffuse)");
    else if (r.n_conductor > 0)
        log_info(r.n_conductor, " conductor pixels shaded by ", r.glossy == GlossyShading::head ? "the directional head" : "one traced bounce",
                 " (", r.glossy_samples, " GGX samples each) in ", format_duration(r.timings.glossy));
    write_rendered_image(r.image, a.prefix, a.exposure);
    write_png(a.prefix + ".irradiance.png", r.image.irradiance, tonemap_scale(r.image.irradiance));
    const auto &t = r.timings;
    OrderedJson j = {{"scene", a.scene},
                     {"model", a.model},
                     {"width", cam.width},
                     {"height", cam.height},
                     {"queries", r.n_queries},
                     {"gi_stride", a.gi_stride},
                     {"decoded", r.n_decoded},
                     {"scene_points", r.n_scene_points},
                     {"direct_spp", a.direct_spp},
                     {"direct_estimator", direct_estimator_name(r.direct)},
                     {"conductor_pixels", r.n_conductor},
                     {"glossy", glossy_shading_name(r.glossy)},
                     {"glossy_samples", r.glossy_samples},
                     {"threads", common.threads},
                     {"timings", t.to_json()}};
    write_file_atomic(a.prefix + ".timings.json", j.dump(2) + "\n");
    log_info("neural render ", cam.width, "x", cam.height, " (", r.n_queries, " queries, ", r.n_decoded, " decoded, ", r.n_scene_points,
             " scene points) in ", format_duration(t.total), ": encode ", format_duration(t.sample + t.geometry + t.encode),
             " (sample ", format_duration(t.sample), ", fps/knn ", format_duration(t.geometry), ", ptv3 ",
             format_duration(t.encode), "), g-buffer ", format_duration(t.gbuffer), ", knn ", format_duration(t.knn),
             ", decode ", format_duration(t.decode), ", direct ", format_duration(t.direct));
    log_info("wrote ", a.prefix, ".exr, ", a.prefix, ".png, ", a.prefix, ".irradiance.png, ", a.prefix, ".timings.json");
}

}  // namespace ltm::cli
