// cli.h: the ltm command line as a library: run_cli() is what main() calls and what tests call.
#pragma once

#include <cstdint>

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace CLI {
class App;
class Option;
}
namespace ltm {
struct Camera;
struct Scene;
struct Shard;
}  // namespace ltm

namespace ltm::cli {

/// Options every subcommand takes (STYLE.md: --threads, --seed, --quiet/--verbose everywhere).
struct CommonOptions {
    int threads = 0;        ///< 0 = all cores
    uint64_t seed = 0;
    bool quiet = false, verbose = false;
};

/// One subcommand as the CLI table holds it. Commands are written as command objects (below) and
/// wrapped by make_command(); run_cli() calls `declare` once, before parsing, and `run` at most
/// once, after a successful parse, with the common options parsed for that subcommand.
struct Command {
    std::string name, help;
    std::function<void(CLI::App &sub)> declare;
    std::function<void(const CommonOptions &common)> run;
};

/// A command object: `Args`, a plain struct with the command's flags as fields and their defaults
/// as initialisers, and two functions beside it in its cmd_<name>.cpp:
///   void declare(CLI::App &sub, Args &a);              // binds options on `sub` to fields of `a`
///   void run(const Args &a, const CommonOptions &c);   // does the work with the parsed values
/// make_command() owns one Args per Command (shared by both closures, because the options CLI11
/// parses write into it by reference), so each call of commands() hands out independent state.
/// The common options (--threads, --seed, -q, -v) are run_cli()'s, never declared by a command.
/// Free functions rather than members: run's locals (a loaded `scene`, a parsed `shard`) may then
/// share a flag's name without shadowing it, and the body reads `a.flag` for each flag.
template <class Args>
Command make_command(std::string name, std::string help, void (*declare)(CLI::App &, Args &),
                     void (*run)(const Args &, const CommonOptions &)) {
    auto a = std::make_shared<Args>();
    return {std::move(name), std::move(help), [a, declare](CLI::App &sub) { declare(sub, *a); },
            [a, run](const CommonOptions &common) { run(*a, common); }};
}

// Options several commands declare alike: one name, help text and check each, in cli.cpp.

/// The required positional `scene`: a scene file or builtin:<name> (scene/scene_loader.h).
CLI::Option *add_scene_argument(CLI::App &sub, std::string &scene);
/// The required `-o,--output`; `what` is its help text (what the command writes there).
CLI::Option *add_output_option(CLI::App &sub, std::string &output, const std::string &what);
/// `--camera NAME`, as choose_camera() reads it (empty: the scene's first camera, else automatic).
CLI::Option *add_camera_option(CLI::App &sub, std::string &camera);

/// The command table (one file per command: cmd_<name>.cpp), with fresh argument state.
std::vector<Command> commands();

Command make_generate_command();
Command make_sample_command();
Command make_preview_command();
Command make_info_command();
Command make_render_command();
Command make_bake_command();
Command make_bake_gi_command();
Command make_edit_command();
Command make_convert_command();
Command make_dataset_command();
Command make_train_command();   // this and the two below need libtorch (LTM_WITH_TORCH)
Command make_export_command();
Command make_eval_command();
Command make_eval_directional_command();

/// The scene's camera by name, else its first, else an automatic one; resized if width/height > 0.
Camera choose_camera(const Scene &scene, const std::string &name, int width, int height, const std::string &where);

/// `ltm render --method neural`: the arguments it needs (cmd_render_neural.cpp, libtorch builds).
struct NeuralRenderArgs {
    std::string scene, camera, model, prefix;
    int width = 0, height = 0, direct_spp = 16;
    float exposure = 1.f;
    bool exclude_enclosed = true;
    int gi_stride = 1;   ///< decode Ê⁺ on every gi_stride-th pixel and interpolate (render/gi_upsample.h)
    std::string direct_estimator = "auto";   ///< mis | ratio | auto (infer/neural_renderer.h)
    int glossy_samples = 0;    ///< GGX samples per conductor pixel (0: automatic)
    std::string glossy = "auto";   ///< conductor shading: auto | trace | head | diffuse (GlossyShading)
    int scene_points = 0;          ///< 0: the model's own M, -1: auto (set_auto_scene_points)
    double prior_theta = -1;       ///< < 0: the model's own (set_prior_theta otherwise)
    bool prior_rays = false;       ///< --prior-rays: the prior's visibility by rays (set_prior_rays)
    std::string bounce = "auto";   ///< --glossy trace: Ê⁺ at the bounce's hits, auto | nodes | decode (BounceIrradiance)
    int gi_levels = 0;             ///< --gi-levels: lattices decoded coarse to fine (GiUpsampleOptions::levels); 0: auto_gi_levels
    float gi_contrast = 0.05f;     ///< --gi-contrast: where a finer lattice pixel is decoded (GiUpsampleOptions::contrast)
    bool exr_float = false;        ///< --exr-float: every EXR channel float (write_rendered_image)
};

/// `--gi-levels` and `--gi-contrast` (render and eval).
void add_gi_refine_options(CLI::App &sub, int &levels, float &contrast);

/// `--bounce-irradiance`'s help, shared by render and eval.
inline constexpr const char *k_bounce_irradiance_help =
    "Conductors by a traced bounce (neural): E+ at the bounce's hits interpolated from the scene points (nodes: M "
    "decodes, then ~50x cheaper a hit), decoded at each (decode), or auto = nodes when the bounce has >= 2 M rays";

/// `--prior-theta`'s help, shared by render, eval and bake-gi.
inline constexpr const char *k_prior_theta_help =
    "The transport prior through its cluster tree with this opening bound (0: the dense rows; 0.5: far light from "
    "aggregates, O(M log M), needed above 32768 scene points; default: the model's own)";
/// `--prior-rays`' help, shared by render, eval and bake-gi.
inline constexpr const char *k_prior_rays_help =
    "The transport prior's visibility and closure by rays against the scene's meshes instead of from its points "
    "(one ray per term of the prior's tree; implies --prior-theta 0.5 unless given)";
void run_neural_render(const NeuralRenderArgs &args, const CommonOptions &common);

/// `--scene-points N|auto` on render and bake-gi: N into `dst`, "auto" as -1 (the scene's detail
/// picks M: auto_scene_points, render/scene_points.h).
CLI::Option *add_scene_points_option(CLI::App *sub, int &dst, const std::string &what);

/// `--shard i/N` when given, else a Slurm array task's SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT,
/// else 0/1. The CLI reads the environment; the libraries only take a Shard.
Shard shard_option(const std::string &flag_value);

/// "A:B" → seeds A .. B-1 (0 <= A < B); `option` names the flag in the error.
std::pair<uint64_t, uint64_t> parse_seed_range(const std::string &s, const std::string &option);

/// Parses and runs `args` (without the program name). Exit codes: 0 ok, 1 error (message
/// "ltm <cmd>: error: <what>" on stderr), 2 usage error.
int run_cli(const std::vector<std::string> &args);

}  // namespace ltm::cli
