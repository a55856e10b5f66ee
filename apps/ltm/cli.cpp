// cli.cpp: the command table, the options several commands share, and the only place that catches
// exceptions.
#include "cli.h"
#include "delegate.h"

#include <cstdlib>
#include <iostream>
#include <limits>
#include <map>

#include <CLI/CLI.hpp>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/core/parallel.h"
#include "ltm/core/startup.h"
#include "ltm/render/bake.h"
#include "ltm/render/preview.h"
#ifdef LTM_WITH_TORCH
#include "ltm/nn/torch_runtime.h"
#endif

namespace ltm::cli {

std::vector<Command> commands() {
    // Built afresh per call: each Command owns its parsed-argument state.
    std::vector<Command> table = {make_generate_command(), make_sample_command(), make_preview_command(),
                                  make_bake_command(), make_bake_gi_command(), make_render_command(), make_info_command(),
                                  make_edit_command(), make_convert_command(), make_dataset_command()};
#ifdef LTM_WITH_TORCH
    for (auto make : {make_train_command, make_export_command, make_eval_command, make_eval_directional_command}) table.push_back(make());
#else
    // Listed by --help; run_cli hands them to ltm-torch before parsing (delegate.h).
    for (const LibtorchCommand &c : k_libtorch_commands)
        table.push_back({c.name, std::string(c.help) + " [libtorch: ltm-torch]", [](CLI::App &sub) { sub.allow_extras(); },
                         [name = std::string(c.name)](const CommonOptions &) { throw NeedsLibtorch("ltm " + name + " needs libtorch"); }});
#endif
    return table;
}

namespace {

// One line per error: libtorch's c10::Error carries a multi-line C++ backtrace after its message.
std::string error_line(const std::exception &e) {
#ifdef LTM_WITH_TORCH
    return exception_line(e);
#else
    return first_line(e.what());
#endif
}

void add_common_options(CLI::App &sub, CommonOptions &c) {
    sub.add_option("--threads", c.threads, "Worker threads (0 = all cores)")->capture_default_str()->check(CLI::Range(0, 4096));
    sub.add_option("--seed", c.seed, "Random seed; outputs are a pure function of it")->capture_default_str();
    sub.add_flag("-q,--quiet", c.quiet, "Only warnings and errors");
    sub.add_flag("-v,--verbose", c.verbose, "Debug output");
}

std::string version_string() {
    std::string v = "ltm 0.1.0";
#ifdef LTM_WITH_TORCH
    v += ", " + torch_runtime_description();
#else
    v += ", built without libtorch (weights at their prior render; the rest needs ltm-torch)";
#endif
    return v;
}

}  // namespace

int run_cli(const std::vector<std::string> &args) {
    configure_process();
#ifdef LTM_WITH_TORCH
    ::unsetenv(k_delegated_env);   // handed over (delegate.h): not inherited by what this runs
#else
    // A program without libtorch hands the libtorch commands, and --version (which names the
    // libtorch in use), to ltm-torch beside it (delegate.h); the exec returns only if it cannot.
    if (!args.empty() && (is_libtorch_command(args[0]) || args[0] == "--version")) {
        const std::string why = exec_libtorch_program(args);
        if (args[0] != "--version") {
            std::cerr << "ltm " << args[0] << ": error: the command needs libtorch: " << why << "\n";
            return 1;
        }
    }
#endif
    CLI::App app("ltm: generalizable neural global illumination (light transport 3D embedding)", "ltm");
    app.require_subcommand(1);
    app.set_version_flag("--version", version_string());
    app.get_formatter()->column_width(34);
    const std::vector<Command> table = commands();
    std::vector<CommonOptions> common(table.size());
    std::vector<CLI::App *> subs;
    for (size_t i = 0; i < table.size(); ++i) {
        const Command &cmd = table[i];
        CLI::App *sub = app.add_subcommand(cmd.name, cmd.help);
        add_common_options(*sub, common[i]);
        cmd.declare(*sub);
        subs.push_back(sub);
    }
    std::vector<std::string> reversed(args.rbegin(), args.rend());   // CLI11 parses a reversed vector
    try {
        app.parse(reversed);
    } catch (const CLI::ParseError &e) {
        if (e.get_exit_code() == 0) {   // --help / --version
            app.exit(e, std::cout, std::cerr);
            return 0;
        }
        std::string cmd_name;
        for (CLI::App *s : subs)
            if (s->parsed()) cmd_name = " " + s->get_name();
        std::cerr << "ltm" << cmd_name << ": usage error: " << e.what() << "\n"
                  << "Run 'ltm" << cmd_name << " --help' for the options.\n";
        return 2;
    }
    for (size_t i = 0; i < subs.size(); ++i) {
        if (!subs[i]->parsed()) continue;
        const CommonOptions &c = common[i];
        try {
            set_log_level(c.quiet ? LogLevel::quiet : (c.verbose ? LogLevel::verbose : LogLevel::normal));
            set_num_threads(c.threads);
#ifdef LTM_WITH_TORCH
            configure_torch_threads(num_threads());
#endif
            table[i].run(c);
            return 0;
        } catch (const NeedsLibtorch &e) {
            // Found before anything was written (delegate.h): ltm-torch runs the whole command line.
            const std::string why = exec_libtorch_program(args);
            std::cerr << "ltm " << subs[i]->get_name() << ": error: " << e.what() << ": " << why << "\n";
            return 1;
        } catch (const std::exception &e) {
            // ltm::Error is bad input; anything else (std::bad_alloc, logic_error) is reported the
            // same way: one line, exit 1, and the command's atomic writers left nothing behind.
            std::cerr << "ltm " << subs[i]->get_name() << ": error: " << error_line(e) << "\n";
            return 1;
        }
    }
    return 2;
}

CLI::Option *add_scene_argument(CLI::App &sub, std::string &scene) {
    return sub.add_option("scene", scene, "Scene (json, obj, pbrt, gltf, glb or builtin:<name>)")->required();
}

CLI::Option *add_output_option(CLI::App &sub, std::string &output, const std::string &what) {
    return sub.add_option("-o,--output", output, what)->required();
}

CLI::Option *add_camera_option(CLI::App &sub, std::string &camera) {
    return sub.add_option("--camera", camera, "Camera name (default: the scene's first, else automatic)");
}

Camera choose_camera(const Scene &scene, const std::string &name, int width, int height, const std::string &where) {
    Camera cam;
    if (!name.empty()) {
        bool found = false;
        for (const auto &k : scene.cameras)
            if (k.name == name) cam = k, found = true;
        if (!found) LTM_THROW(where, ": no camera named '", name, "'");
    } else if (!scene.cameras.empty()) {
        cam = scene.cameras.front();
    } else {
        cam = automatic_camera(scene, 512, 512);
        log_info("scene has no camera; using an automatic one at ", cam.eye);
    }
    if (width > 0) cam.width = width;
    if (height > 0) cam.height = height;
    return cam;
}

CLI::Option *add_scene_points_option(CLI::App *sub, int &dst, const std::string &what) {
    return sub
        ->add_option("--scene-points", dst,
                     "Scene points the model samples (" + what +
                         "; default: the model's own count, or auto where its config asks, as the shipped one's does); more follow finer detail at "
                         "more time. auto: "
                         "16384, or 32768 for scenes of 100k triangles or more, then through the prior's tree (θ 0.5)")
        ->transform(CLI::Transformer(std::map<std::string, int>{{"auto", -1}}))
        ->check(CLI::Range(-1, std::numeric_limits<int>::max()));
}

void add_gi_refine_options(CLI::App &sub, int &levels, float &contrast) {
    sub.add_option("--gi-levels", levels,
                   "GI lattices decoded coarse to fine (neural): the first at stride x 2^(N-1); each finer lattice's new "
                   "pixels are blended from the coarser one where its corners agree within --gi-contrast and lie on "
                   "their surface, else decoded (1: one lattice, every lattice pixel decoded; auto: up to 4, the "
                   "first lattice keeping >= 64 pixels across the image)")
        ->transform(CLI::Transformer(std::map<std::string, int>{{"auto", 0}}))
        ->check(CLI::Range(0, 8))
        ->default_str(levels == 0 ? "auto" : std::to_string(levels));
    sub.add_option("--gi-contrast", contrast,
                   "With --gi-levels > 1: a finer lattice pixel is decoded where its coarse corners' E+ differ by more "
                   "than this share of their blend (summed over the channels)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 10.0));
}

Shard shard_option(const std::string &flag_value) {
    if (!flag_value.empty()) return Shard::parse(flag_value);
    const char *id = std::getenv("SLURM_ARRAY_TASK_ID"), *n = std::getenv("SLURM_ARRAY_TASK_COUNT");
    if (!id || !n) return {};
    return Shard::parse(std::string(id) + "/" + n);
}

std::pair<uint64_t, uint64_t> parse_seed_range(const std::string &s, const std::string &option) {
    const size_t colon = s.find(':');
    try {
        if (colon == std::string::npos) throw std::invalid_argument("");
        const long long a = std::stoll(s.substr(0, colon)), b = std::stoll(s.substr(colon + 1));
        if (a < 0 || b <= a) throw std::invalid_argument("");
        return {uint64_t(a), uint64_t(b)};
    } catch (const std::exception &) {
        LTM_THROW(option, " ", s, ": expected A:B with 0 <= A < B (seeds A .. B-1)");
    }
}

}  // namespace ltm::cli
