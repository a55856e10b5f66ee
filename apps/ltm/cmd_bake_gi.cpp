// cmd_bake_gi.cpp: `ltm bake-gi <scene> --model M -o out.glb` (issue #32): the scene refined
// (render/gi_bake.h), the model's Ê⁺ and the renderer's E_direct at every vertex, written as glTF
// with per-vertex radiance. `--method pathtrace --spp N` bakes the path tracer's E_direct and E⁺ at
// the same vertices instead, for comparison.
#include <chrono>
#include <filesystem>
#include <optional>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "command_model.h"
#include "ltm/core/file_util.h"
#include "ltm/core/image.h"
#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/render/direct_light.h"
#include "ltm/render/embree_accel.h"
#include "ltm/render/gi_bake.h"
#include "ltm/render/path_tracer.h"
#include "ltm/scene/scene_loader.h"

namespace ltm::cli {

namespace {

struct BakeGiArgs {
    std::string scene, output, method = "neural", model, view, camera;
    int view_size = 0;
    int spp = 256, direct_spp = 16, scene_points = 0;   // direct_spp: `ltm render`'s default
    double prior_theta = -1;
    bool prior_rays = false;
    float max_edge = 0.f, exposure = 1.f;
    int64_t max_vertices = 8'000'000;
};

std::vector<Vec3f> column(const Image &img) { return img.pixels; }   // vertex_points(): one row, a vertex per pixel

void declare(CLI::App &sub, BakeGiArgs &a) {
    add_scene_argument(sub, a.scene);
    sub.add_option("--method", a.method, "neural (the model's E+) | pathtrace (the path tracer's, for comparison)")
        ->capture_default_str()
        ->check(CLI::IsMember({"neural", "pathtrace"}));
    sub.add_option("--model", a.model, "Weights for --method neural (models/ltm-cpu.safetensors)");
    sub.add_option("--spp", a.spp, "Samples per vertex for E_direct and E+ (pathtrace)")->capture_default_str()->check(CLI::Range(1, 1 << 20));
    sub.add_option("--direct-spp", a.direct_spp, "Light samples per vertex for E_direct (neural)")
        ->capture_default_str()
        ->check(CLI::Range(1, 1 << 20));
    add_scene_points_option(&sub, a.scene_points, "neural");
    sub.add_option("--prior-theta", a.prior_theta, k_prior_theta_help)->check(CLI::Range(0.0, 1.0));
    sub.add_flag("--prior-rays", a.prior_rays, k_prior_rays_help);
    sub.add_option("--max-edge", a.max_edge, "Longest edge after refinement, scene units (0: the scene's largest extent / 64)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    sub.add_option("--max-vertices", a.max_vertices, "Refuse a refinement with more vertices than this")
        ->capture_default_str()
        ->check(CLI::Range(int64_t(3), int64_t(1) << 34));
    sub.add_option("--exposure", a.exposure, "Exposure of COLOR_0 (the tone-mapped radiance any viewer shows)")->capture_default_str();
    sub.add_option("--view", a.view,
                   "Also write <prefix>.png: the bake seen through --camera as a rasteriser shows the .glb (COLOR_0's tone map; the viewer's reference)");
    add_camera_option(sub, a.camera);
    sub.add_option("--view-size", a.view_size, "Square size of --view in pixels (0: the camera's own size)")->check(CLI::Range(0, 16384));
    add_output_option(sub, a.output, "Output .glb (binary glTF 2.0)");
}

void run(const BakeGiArgs &a, const CommonOptions &common) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    if (!(a.exposure > 0.f)) LTM_THROW("--exposure ", a.exposure, ": must be > 0");
    if (a.method == "neural" && a.model.empty()) LTM_THROW("--method neural needs --model <weights.safetensors>");
    if (a.method == "pathtrace" && !a.model.empty()) LTM_THROW("--model is only used with --method neural");
    if (a.method == "pathtrace" && (a.scene_points != 0 || a.prior_theta >= 0 || a.prior_rays))
        LTM_THROW("--scene-points, --prior-theta and --prior-rays are only used with --method neural");
    const std::filesystem::path out(a.output);
    if (out.extension() != ".glb") LTM_THROW(a.output, ": the output must be a .glb file");
    check_output_directory(a.output);
    if (!a.view.empty()) check_output_directory(a.view + ".png");
    // The weights first: what needs libtorch is handed over before any work (command_model.h), and
    // weights at their prior bake without it (infer/prior_model.h): the same numbers.
    std::optional<CommandModel> m;
    if (a.method == "neural") m = open_command_model(load_prior_model(a.model));
    const Scene scene = load_scene(a.scene);
    bool lit = false;
    for (const Material &m : scene.materials) lit |= m.is_emissive();
    if (!lit) LTM_THROW(a.scene, ": no emitter (area light): nothing to bake");
    RefineOptions ro;
    ro.max_edge = a.max_edge, ro.max_vertices = a.max_vertices;
    std::vector<BakedMesh> meshes = refine_for_bake(scene, ro);
    const GBuffer gb = vertex_points(meshes);
    log_info("bake-gi: ", scene.meshes.size(), " meshes refined to ", gb.n_hits(), " vertices");
    const EmbreeAccel accel(scene);
    PathTracerConfig pc;
    pc.seed = common.seed;
    const PathTracer pt(accel, pc);
    std::vector<Vec3f> direct, indirect;
    if (a.method == "pathtrace") {
        const IrradianceImages ir = irradiance_images(pt, gb, a.spp, /*with_indirect=*/true);
        direct = column(ir.direct), indirect = column(ir.indirect);
    } else {
        ModelConfig &cfg = m->cfg();
        if (apply_point_options(cfg, a.scene_points, a.prior_theta, a.prior_rays) == k_scene_points_auto)
            set_auto_scene_points(cfg, scene, a.prior_theta >= 0);
        bool decoded = false;
#if LTM_WITH_TORCH
        if (m->tensor) {
            const EncodedScene enc = encode_scene(m->tensor->model, accel, common.seed);
            indirect = predict_gbuffer(m->tensor->model, enc, gb);
            decoded = true;
        }
#endif
        if (!decoded) {
            const PriorScene ps = encode_prior_scene(cfg, accel, common.seed, true, m->prior.skip);
            indirect = decode_gbuffer(prior_decoder(std::make_shared<const SceneFrame>(ps.frame), nullptr, m->prior.skip), gb);
        }
        // Direct light as `ltm render --method neural` computes it (ratio estimator when every
        // emitter is constant, else the path tracer's MIS).
        if (RatioDirectLight::supports(scene)) {
            const RatioDirectLight ratio(accel, common.seed);
            direct = column(direct_images_ratio(ratio, gb, a.direct_spp).direct);
        } else {
            direct = column(irradiance_images(pt, gb, a.direct_spp, /*with_indirect=*/false).direct);
        }
    }
    compose_bake(meshes, direct, indirect);
    write_bake_glb(a.output, scene, meshes, a.exposure, "ltm bake-gi (" + a.method + ")");
    if (!a.view.empty()) {
        const Camera cam = choose_camera(scene, a.camera, a.view_size, a.view_size, a.scene);
        const BakeView v = view_bake(meshes, cam);
        Image shown(cam.width, cam.height);   // write_png encodes sRGB: the pixels are COLOR_0's
        for (size_t i = 0; i < shown.pixels.size(); ++i) shown.pixels[i] = bake_display(v.radiance.pixels[i], a.exposure);
        write_png(a.view + ".png", shown);
    }
    log_info("bake-gi: ", gb.n_hits(), " vertices (", a.method, ") -> ", a.output, " in ",
             format_duration(seconds_since(t0)));
}

}  // namespace

Command make_bake_gi_command() {
    return make_command("bake-gi", "Bake global illumination at the vertices of the refined scene into glTF (.glb): radiance and E+ per vertex",
                        declare, run);
}

}  // namespace ltm::cli
