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

/// One subcommand: `setup` declares its options on `sub`, `run` executes after parsing.
struct Command {
    std::string name, help;
    std::function<void(CLI::App &sub, CommonOptions &common)> setup;
    std::function<void(const CommonOptions &common)> run;
};

/// A command whose options are parsed into a fresh Args: `setup` declares them on `sub` (binding
/// to fields of `a`), `run` executes with them after parsing. One Args per Command, shared by the
/// two closures, so commands() hands out independent state each call.
template <class Args>
Command make_command(std::string name, std::string help, std::function<void(CLI::App &, Args &, CommonOptions &)> setup,
                     std::function<void(Args &, const CommonOptions &)> run) {
    auto a = std::make_shared<Args>();
    return {std::move(name), std::move(help),
            [a, setup = std::move(setup)](CLI::App &sub, CommonOptions &common) { setup(sub, *a, common); },
            [a, run = std::move(run)](const CommonOptions &common) { run(*a, common); }};
}

/// The command table (one file per command: cmd_<name>.cpp), with fresh argument state.
std::vector<Command> commands();

Command make_generate_command();
Command make_sample_command();
Command make_preview_command();
Command make_info_command();
Command make_render_command();
Command make_bake_command();
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
    int glossy_samples = 16;   ///< GGX samples per conductor pixel, each the directional head's L̂⁺
};
void run_neural_render(const NeuralRenderArgs &args, const CommonOptions &common);

/// `--shard i/N` when given, else a Slurm array task's SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT,
/// else 0/1. The CLI reads the environment; the libraries only take a Shard.
Shard shard_option(const std::string &flag_value);

/// "A:B" → seeds A .. B-1 (0 <= A < B); `option` names the flag in the error.
std::pair<uint64_t, uint64_t> parse_seed_range(const std::string &s, const std::string &option);

/// Parses and runs `args` (without the program name). Exit codes: 0 ok, 1 error (message
/// "ltm <cmd>: error: <what>" on stderr), 2 usage error.
int run_cli(const std::vector<std::string> &args);

}  // namespace ltm::cli
