// cmd_render.cpp: `ltm render <scene> --method pathtrace|neural|guided -o out` → out.exr, out.png,
// out.irradiance.png (+ out.timings.json for neural).
#include <memory>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "delegate.h"
#include "ltm/core/file_util.h"
#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/core/tonemap.h"
#include "ltm/render/image_renderer.h"
#include "ltm/scene/scene_loader.h"
#if LTM_WITH_TORCH
#include "ltm/infer/guide_builder.h"
#include "ltm/infer/neural_renderer.h"
#endif

namespace ltm::cli {

namespace {
struct RenderArgs {
    std::string scene, output, camera, method = "pathtrace", model, direct_estimator = "auto", glossy = "auto",
                bounce = "auto";
    int spp = 64, max_depth = 5, width = 0, height = 0, direct_spp = 16, gi_stride = 1, guide_points = 1024, guide_resolution = 16, glossy_samples = 0,
        scene_points = 0;
    float exposure = 1.f, guide_alpha = 0.25f, gi_contrast = 0.05f;
    int gi_levels = 0;   ///< 0: auto
    double prior_theta = -1;
    bool prior_rays = false;
    bool exr_float = false;
};

std::string strip_image_extension(std::string p) {
    for (const char *ext : {".exr", ".png"})
        if (p.size() > 4 && p.compare(p.size() - 4, 4, ext) == 0) p.resize(p.size() - 4);
    return p;
}
void declare(CLI::App &sub, RenderArgs &a) {
    add_scene_argument(sub, a.scene);
    sub.add_option("--method", a.method, "pathtrace | neural | guided (path tracing guided by the model's directional head)")
        ->capture_default_str()
        ->check(CLI::IsMember({"pathtrace", "neural", "guided"}));
    sub.add_option("--model", a.model, "Weights for --method neural (models/ltm-cpu.safetensors) or guided (with a directional head)");
    sub.add_option("--spp", a.spp, "Samples per pixel (pathtrace, guided)")->capture_default_str();
    sub.add_option("--glossy", a.glossy,
                   "Conductor pixels (neural): trace = one traced bounce into the model's E+ (auto), head = the "
                   "directional head's L_in+ (paper Fig. 11), diffuse = shaded as diffuse")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "trace", "head", "diffuse"}));
    sub.add_option("--glossy-samples", a.glossy_samples,
                   "GGX samples per conductor pixel (neural; 0: 64 with --glossy trace, 16 with head)")
        ->capture_default_str()
        ->check(CLI::Range(0, 4096));
    sub.add_option("--bounce-irradiance", a.bounce, k_bounce_irradiance_help)
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "nodes", "decode"}));
    sub.add_option("--guide-points", a.guide_points, "Surface points whose L_in bins the head predicts (guided)")
        ->capture_default_str()
        ->check(CLI::Range(9, 1 << 20));
    sub.add_option("--guide-resolution", a.guide_resolution, "R of the guide's R×R bins, predicted at their centres (guided)")
        ->capture_default_str()
        ->check(CLI::Range(1, 256));
    sub.add_option("--guide-alpha", a.guide_alpha, "BSDF share α of the defensive mixture α·BSDF + (1−α)·guide (guided)")
        ->capture_default_str()
        ->check(CLI::Range(0.001, 1.0));
    add_scene_points_option(&sub, a.scene_points, "neural, guided");
    sub.add_option("--prior-theta", a.prior_theta, k_prior_theta_help)->check(CLI::Range(0.0, 1.0));
    sub.add_flag("--prior-rays", a.prior_rays, k_prior_rays_help);
    sub.add_option("--direct-spp", a.direct_spp, "Shadow-ray samples per pixel for direct light (neural)")
        ->capture_default_str();
    sub.add_option("--direct-estimator", a.direct_estimator,
                   "Direct light (neural): ratio = analytic unshadowed x sampled visibility, mis = the path tracer's; "
                   "auto = ratio unless an emitter is textured")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "ratio", "mis"}));
    sub.add_option("--gi-stride", a.gi_stride,
                   "Decode E+ on every N-th pixel in x and y and interpolate on matching surfaces (neural; 1 with --gi-levels 1: every pixel)")
        ->capture_default_str()
        ->check(CLI::Range(1, 16));
    add_gi_refine_options(sub, a.gi_levels, a.gi_contrast);
    sub.add_option("--max-depth", a.max_depth, "Scattering events after the first hit (pathtrace)")->capture_default_str();
    add_camera_option(sub, a.camera);
    sub.add_option("--width", a.width, "Width (default: the camera's)")->check(CLI::Range(1, 16384));
    sub.add_option("--height", a.height, "Height (default: the camera's)")->check(CLI::Range(1, 16384));
    sub.add_option("--exposure", a.exposure, "PNG exposure scale")->capture_default_str();
    sub.add_flag("--exr-float", a.exr_float,
                 "Every EXR channel as 32-bit float (default: colour, irradiance, direct, albedo and N as 16-bit half "
                 "where their range fits, as pbrt-v4 and Mitsuba 3 write; P and Z always float)");
    add_output_option(sub, a.output, "Output prefix: writes <prefix>.exr and <prefix>.png");
}

void run(const RenderArgs &a, const CommonOptions &common) {
    if (!(a.exposure > 0.f)) LTM_THROW("--exposure ", a.exposure, ": must be > 0");
    const std::string prefix = strip_image_extension(a.output);
    check_output_directory(prefix + ".exr");   // before the render, not after it
    if (a.method == "neural") {
        if (a.model.empty()) LTM_THROW("--method neural needs --model <weights.safetensors>");
        if (a.direct_spp <= 0) LTM_THROW("--direct-spp ", a.direct_spp, ": must be > 0");
        run_neural_render(
            {a.scene, a.camera, a.model, prefix, a.width, a.height, a.direct_spp, a.exposure, true, a.gi_stride,
             a.direct_estimator, a.glossy_samples, a.glossy, a.scene_points, a.prior_theta, a.prior_rays, a.bounce,
             a.gi_levels, a.gi_contrast, a.exr_float},
            common);
        return;
    }
    if (a.method == "guided" && a.model.empty()) LTM_THROW("--method guided needs --model <weights with a directional head>");
    #if !LTM_WITH_TORCH
    if (a.method == "guided") throw NeedsLibtorch("--method guided reads the model's directional head, which needs libtorch");
    #endif
    if (!a.model.empty() && a.method != "guided") LTM_THROW("--model is only used with --method neural or guided");
    if (a.scene_points != 0 && a.method == "pathtrace") LTM_THROW("--scene-points is only used with --method neural or guided");
    if (a.prior_theta >= 0 && a.method == "pathtrace") LTM_THROW("--prior-theta is only used with --method neural or guided");
    if (a.prior_rays && a.method == "pathtrace") LTM_THROW("--prior-rays is only used with --method neural or guided");
    if (a.gi_stride != 1) LTM_THROW("--gi-stride is only used with --method neural");
    if (a.direct_estimator != "auto") LTM_THROW("--direct-estimator is only used with --method neural");
    if (a.spp <= 0) LTM_THROW("--spp ", a.spp, ": must be > 0");
    if (a.max_depth < 1) LTM_THROW("--max-depth ", a.max_depth, ": must be >= 1");
    const Scene scene = load_scene(a.scene);
    const Camera cam = choose_camera(scene, a.camera, a.width, a.height, a.scene);
    const EmbreeAccel accel(scene);
    check_camera(accel, cam, a.scene);
    PathTracerConfig cfg;
    cfg.seed = common.seed;
    cfg.max_depth = a.max_depth;
    PathTracer pt(accel, cfg);
    double guide_seconds = 0;
    #if LTM_WITH_TORCH
    GuideBuild guide;
    if (a.method == "guided") {
        LoadedModel m = load_model(a.model);
        if (apply_point_options(m.model, a.scene_points, a.prior_theta, a.prior_rays) == k_scene_points_auto)
            set_auto_scene_points(m.model, scene, a.prior_theta >= 0);
        GuideBuildOptions go;
        go.points = a.guide_points, go.resolution = a.guide_resolution, go.seed = common.seed;
        guide = build_guide_cache(m.model, accel, go);
        guide_seconds = guide.seconds;
        pt.set_guide(&guide.cache, a.guide_alpha);
    }
    #endif
    const RenderedImage img = render_pathtraced(pt, cam, a.spp);
    if (a.method == "guided")
        log_info("guided: ", format_duration(guide_seconds), " to predict the guide + ", format_duration(img.seconds), " to render");
    write_rendered_image(img, prefix, a.exposure, a.exr_float);
    write_png(prefix + ".irradiance.png", img.irradiance, tonemap_scale(img.irradiance));
    log_info("rendered ", cam.width, "x", cam.height, " at ", a.spp, " spp in ", format_duration(img.seconds), " (",
             format_count(double(accel.rays_traced()) / img.seconds), " rays/s) -> ", prefix, ".exr, ", prefix,
             ".png, ", prefix, ".irradiance.png");
}
}  // namespace

Command make_render_command() {
    return make_command(
        "render", "Render an image: path-traced reference or the neural model (EXR with AOVs + PNGs)",
        declare, run);
}

}  // namespace ltm::cli
