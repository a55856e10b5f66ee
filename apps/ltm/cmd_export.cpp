// cmd_export.cpp: `ltm export runs/NAME/best.ltmckpt -o models/ltm-cpu.safetensors`.
#include <memory>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "ltm/core/log.h"
#include "ltm/nn/checkpoint.h"

namespace ltm::cli {

Command make_export_command() {
    auto a = std::make_shared<std::pair<std::string, std::string>>();
    Command c;
    c.name = "export";
    c.help = "Export a training checkpoint's weights to safetensors (config in the metadata)";
    c.setup = [a](CLI::App &sub, CommonOptions &) {
        sub.add_option("checkpoint", a->first, "Checkpoint (.ltmckpt)")->required();
        sub.add_option("-o,--output", a->second, "Weights file (.safetensors)")->required();
    };
    c.run = [a](const CommonOptions &) {
        const TrainState st = read_checkpoint_state(a->first);
        const ModelConfig mc = ModelConfig::from_json(parse_json(st.model_config, a->first), a->first);
        LtmModel model(mc);
        torch::optim::AdamW opt(model->parameters());
        load_checkpoint(a->first, model, opt);
        save_weights(a->second, model, {{"step", std::to_string(st.step)}, {"best_val_loss", std::to_string(st.best_val)}});
        log_info("exported ", model->n_parameters(), " parameters (step ", st.step, ") -> ", a->second);
    };
    return c;
}

}  // namespace ltm::cli
