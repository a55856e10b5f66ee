// cmd_train.cpp: `ltm train --model configs/model/cpu.json --data DIR [--data DIR2 ...] --out runs/NAME [--resume]`.
#include <memory>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/train/trainer.h"

namespace ltm::cli {

namespace {
struct TrainArgs {
    std::string model, out, config, init, device = "cpu";
    std::vector<std::string> data, val_data, overrides;
    bool start_at_prior = false;
    bool resume = false;
    int steps = -1;
};
}  // namespace

Command make_train_command() {
    auto a = std::make_shared<TrainArgs>();
    Command c;
    c.name = "train";
    c.help = "Train the light transport model on a dataset (checkpoints, validation, exact resume)";
    c.setup = [a](CLI::App &sub, CommonOptions &) {
        sub.add_option("--model", a->model, "Model config (configs/model/{tiny,cpu,paper}.json)")->required();
        sub.add_option("--data", a->data, "Dataset directory (ltm dataset build); repeat to train on several")->required();
        sub.add_option("--val-data", a->val_data,
                       "Validation dataset directory (repeatable); with it every --data record trains and val_fraction is unused");
        sub.add_option("--out", a->out, "Run directory: log.jsonl, last/best.ltmckpt")->required();
        sub.add_option("--config", a->config, "Training config JSON (default: built-in defaults, configs/train/default.json)");
        sub.add_option("--set", a->overrides, "Override a training key, e.g. --set lr=5e-4");
        sub.add_option("--steps", a->steps, "Shorthand for --set steps=N");
        sub.add_flag("--resume", a->resume, "Continue the run in --out from last.ltmckpt");
        sub.add_option("--init", a->init, "Start from these weights (.safetensors; fresh optimizer), e.g. to fine-tune");
        sub.add_flag("--start-at-prior", a->start_at_prior,
                     "Zero the decoder's output layer after --init (or at a fresh start): the model starts as its prior "
                     "(E⁺ = output scale, e.g. physics.prior_field \"transport\") and learns the correction");
        sub.add_option("--device", a->device, "cpu | cuda")->capture_default_str()->check(CLI::IsMember({"cpu", "cuda"}));
    };
    c.run = [a](const CommonOptions &common) {
        Json cfg = a->config.empty() ? Json(TrainConfig{}.to_json()) : parse_json_file(a->config);
        cfg["seed"] = common.seed;
        if (a->steps > 0) cfg["steps"] = a->steps;
        for (const auto &o : a->overrides) apply_json_override(cfg, o);
        const TrainConfig tc = TrainConfig::from_json(cfg, a->config.empty() ? "training config" : a->config);
        const ModelConfig mc = ModelConfig::from_file(a->model);
        if (a->device == "cuda" && !torch::cuda::is_available())
            LTM_THROW("--device cuda: this libtorch has no CUDA device (", torch::cuda::device_count(), " found)");
        Trainer trainer(mc, tc, a->data, a->out, a->device == "cuda" ? torch::Device(torch::kCUDA) : torch::Device(torch::kCPU),
                        a->val_data);
        log_info("model '", mc.name, "': ", trainer.model()->n_parameters(), " parameters");
        if (!a->init.empty()) {
            if (a->resume) LTM_THROW("--init and --resume exclude each other (a resumed run has its own weights)");
            trainer.init_weights(a->init);
            log_info("initialised from ", a->init);
        }
        if (a->start_at_prior) {
            if (a->resume) LTM_THROW("--start-at-prior and --resume exclude each other (a resumed run has its own weights)");
            trainer.model()->decoder->start_at_prior();
            log_info("decoder output zeroed: the model starts as its prior");
        }
        trainer.run(a->resume);
    };
    return c;
}

}  // namespace ltm::cli
