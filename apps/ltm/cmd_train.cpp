// cmd_train.cpp: `ltm train --model configs/model/cpu.json --data DIR [--data DIR2 ...] --out runs/NAME [--resume]`.
// Data-parallel: `--nproc N` launches N local ranks; a process started with torchrun's variables
// (WORLD_SIZE, RANK, ...; e.g. by torchrun or srun) joins that group instead.
#include <cstdlib>
#include <memory>
#include <thread>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "delegate.h"
#include "rank_launcher.h"
#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/nn/checkpoint.h"
#include "ltm/train/trainer.h"

namespace ltm::cli {

namespace {
struct TrainArgs {
    std::string model, out, config, init, head, freeze, frame_cache, device = "cpu";
    std::vector<std::string> data, val_data, overrides;
    bool start_at_prior = false;
    bool resume = false;
    int steps = -1;
    int nproc = 1;
    double dist_timeout = 300.0;
};

// The command line one rank of `--nproc` runs: these arguments without --nproc, with its share of
// the threads.
std::vector<std::string> rank_args(const TrainArgs &a, const CommonOptions &common, int threads) {
    std::vector<std::string> v = {"train", "--out", a.out, "--device", a.device, "--threads",
                                  std::to_string(threads), "--seed", std::to_string(common.seed),
                                  "--dist-timeout", std::to_string(a.dist_timeout)};
    if (!a.model.empty()) v.insert(v.end(), {"--model", a.model});
    for (const auto &d : a.data) v.insert(v.end(), {"--data", d});
    for (const auto &d : a.val_data) v.insert(v.end(), {"--val-data", d});
    for (const auto &o : a.overrides) v.insert(v.end(), {"--set", o});
    if (!a.config.empty()) v.insert(v.end(), {"--config", a.config});
    if (!a.init.empty()) v.insert(v.end(), {"--init", a.init});
    if (!a.head.empty()) v.insert(v.end(), {"--head", a.head});
    if (!a.freeze.empty()) v.insert(v.end(), {"--freeze", a.freeze});
    if (!a.frame_cache.empty()) v.insert(v.end(), {"--frame-cache", a.frame_cache});
    if (a.steps >= 0) v.insert(v.end(), {"--steps", std::to_string(a.steps)});
    if (a.resume) v.push_back("--resume");
    if (a.start_at_prior) v.push_back("--start-at-prior");
    if (common.quiet) v.push_back("--quiet");
    if (common.verbose) v.push_back("--verbose");
    return v;
}

// torchrun's variables, when WORLD_SIZE is set (else a group of one).
DistSettings settings_from_environment(double timeout_s) {
    DistSettings s;
    s.timeout_s = timeout_s;
    const char *ws = std::getenv("WORLD_SIZE");
    if (!ws) return s;
    auto integer = [](const char *name, const char *fallback) {
        const char *v = std::getenv(name);
        const std::string text = v ? v : (fallback ? fallback : "");
        if (text.empty()) LTM_THROW("WORLD_SIZE is set but ", name, " is not (torchrun sets RANK, WORLD_SIZE, MASTER_ADDR, MASTER_PORT)");
        char *end = nullptr;
        const long x = std::strtol(text.c_str(), &end, 10);
        if (*end != '\0' || end == text.c_str()) LTM_THROW(name, "=", text, ": not an integer");
        return int(x);
    };
    s.world_size = integer("WORLD_SIZE", nullptr);
    s.rank = integer("RANK", nullptr);
    s.local_rank = integer("LOCAL_RANK", "0");
    s.master_port = integer("MASTER_PORT", "29500");
    const char *addr = std::getenv("MASTER_ADDR");
    s.master_addr = addr && *addr ? addr : "127.0.0.1";
    return s;
}
void declare(CLI::App &sub, TrainArgs &a) {
    sub.add_option("--model", a.model, "Model config (configs/model/{tiny,cpu,paper}.json); default with --init: the weights' own");
    sub.add_option("--data", a.data, "Dataset directory (ltm dataset build); repeat to train on several")->required();
    sub.add_option("--val-data", a.val_data,
                   "Validation dataset directory (repeatable); with it every --data record trains and val_fraction is unused");
    sub.add_option("--out", a.out, "Run directory: log.jsonl, last/best.ltmckpt")->required();
    sub.add_option("--config", a.config, "Training config JSON (default: built-in defaults, configs/train/default.json)");
    sub.add_option("--set", a.overrides, "Override a training key, e.g. --set lr=5e-4");
    sub.add_option("--steps", a.steps, "Shorthand for --set steps=N");
    sub.add_flag("--resume", a.resume, "Continue the run in --out from last.ltmckpt");
    sub.add_option("--init", a.init, "Start from these weights (.safetensors; fresh optimizer), e.g. to fine-tune");
    sub.add_flag("--start-at-prior", a.start_at_prior,
                 "Zero the decoder's output layer after --init (or at a fresh start): the model starts as its prior "
                 "(E⁺ = output scale, e.g. physics.prior_field \"transport\") and learns the correction");
    sub.add_option("--head", a.head,
                   "Shorthand for --set head=...: irradiance (E⁺) or directional (L_in over hemisphere bins; adds a default "
                   "\"directional\" section to a model config without one)")
        ->check(CLI::IsMember({"irradiance", "directional"}));
    sub.add_option("--freeze", a.freeze, "Shorthand for --set freeze=...: encoder keeps the embedding and PTv3 weights")
        ->check(CLI::IsMember({"none", "encoder"}));
    sub.add_option("--frame-cache", a.frame_cache,
                   "Keep each house's prepared draw (its scene points, groups and solved prior) in this folder and reuse "
                   "what an earlier run of this program kept there: a later run skips the per-house solve");
    sub.add_option("--device", a.device, "cpu | cuda")->capture_default_str()->check(CLI::IsMember({"cpu", "cuda"}));
    sub.add_option("--nproc", a.nproc,
                   "Data-parallel ranks to launch on this machine (torchrun's variables; scenes_per_step and batch_queries "
                   "are per rank); a process started with WORLD_SIZE/RANK set joins that group instead")
        ->capture_default_str()->check(CLI::Range(1, 256));
    sub.add_option("--dist-timeout", a.dist_timeout, "Seconds to wait for the other ranks (rendezvous, each collective)")
        ->capture_default_str()->check(CLI::PositiveNumber);
}

void run(const TrainArgs &a, const CommonOptions &common) {
    if (a.nproc > 1) {
        if (std::getenv("WORLD_SIZE")) LTM_THROW("--nproc: this process is already a rank (WORLD_SIZE is set)");
        const int cores = common.threads > 0 ? common.threads : int(std::max(1u, std::thread::hardware_concurrency()));
        launch_local_ranks(a.nproc, rank_args(a, common, std::max(1, cores / a.nproc)));
        return;
    }
    const DistSettings dist = settings_from_environment(a.dist_timeout);
    // Rank 0 speaks for the group; the others say only warnings and errors.
    if (dist.rank != 0 && !common.verbose) set_log_level(LogLevel::quiet);
    Json cfg = a.config.empty() ? Json(TrainConfig{}.to_json()) : parse_json_file(a.config);
    cfg["seed"] = common.seed;
    // Given, it is checked as --set steps=N is (0 is an error, not "the default"): -1 means not given.
    if (a.steps >= 0) cfg["steps"] = a.steps;
    if (!a.head.empty()) cfg["head"] = a.head;
    if (!a.freeze.empty()) cfg["freeze"] = a.freeze;
    for (const auto &o : a.overrides) apply_json_override(cfg, o);
    const TrainConfig tc = TrainConfig::from_json(cfg, a.config.empty() ? "training config" : a.config);
    // The model config: --model, else a resumed run's own, else the --init weights'.
    const std::string model = !a.model.empty() || !a.resume ? a.model : a.out + "/model.json";
    if (model.empty() && a.init.empty()) LTM_THROW("--model is required (or --init, whose weights carry their config)");
    ModelConfig mc = model.empty() ? load_weights(a.init)->cfg : ModelConfig::from_file(model);
    if (model.empty() && mc.auto_scene_points) {
        // The shipped prior-only model follows each scene's point count at inference; a network
        // trained here learns at scene_points, so its weights keep that count.
        mc.auto_scene_points = false;
        log_info(a.init, ": auto_scene_points off for training: the trained weights run at its ", mc.scene_points, " scene points");
    }
    if (tc.head == "directional" && !mc.directional) {
        mc.directional = DirectionalConfig{};
        log_info("model '", mc.name, "': adding a directional head with the default \"directional\" section");
    }
    if (a.device == "cuda" && !torch::cuda::is_available())
        LTM_THROW("--device cuda: this libtorch has no CUDA device (", torch::cuda::device_count(), " found)");
    Trainer trainer(mc, tc, a.data, a.out, a.device == "cuda" ? torch::Device(torch::kCUDA) : torch::Device(torch::kCPU),
                    a.val_data);
    log_info("model '", mc.name, "': ", trainer.model()->n_parameters(), " parameters");
    if (!a.frame_cache.empty()) trainer.set_frame_cache(a.frame_cache);
    if (!a.init.empty()) {
        if (a.resume) LTM_THROW("--init and --resume exclude each other (a resumed run has its own weights)");
        trainer.init_weights(a.init);
        log_info("initialised from ", a.init);
    }
    if (a.start_at_prior) {
        if (a.resume) LTM_THROW("--start-at-prior and --resume exclude each other (a resumed run has its own weights)");
        trainer.model()->decoder->start_at_prior();
        log_info("decoder output zeroed: the model starts as its prior");
    }
    if (dist.world_size > 1) {
        if (a.device != "cpu")
            LTM_THROW("--device ", a.device, " with WORLD_SIZE ", dist.world_size,
                      ": data-parallel training runs on Gloo (CPU tensors); this libtorch has no NCCL backend");
        trainer.set_communicator(std::make_shared<Communicator>(dist, trainer.fingerprint()));
    }
    trainer.run(a.resume);
}
}  // namespace

Command make_train_command() {
    return make_command(
        "train", k_train_help,
        declare, run);
}

}  // namespace ltm::cli
