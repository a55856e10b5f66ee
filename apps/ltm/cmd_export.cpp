// cmd_export.cpp: `ltm export runs/NAME/best.ltmckpt -o models/ltm-cpu.safetensors [--half]`;
// also converts a weights file (e.g. F32 → F16 for shipping).

#include <CLI/CLI.hpp>

#include "cli.h"
#include "delegate.h"
#include "ltm/core/json_util.h"
#include "ltm/core/log.h"
#include "ltm/nn/checkpoint.h"

namespace ltm::cli {

namespace {
struct ExportArgs {
    std::string input, output, note;
    bool half = false;
    std::vector<std::string> overrides;
};

bool ends_with(const std::string &s, const std::string &suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
void declare(CLI::App &sub, ExportArgs &a) {
    sub.add_option("input", a.input, "Checkpoint (.ltmckpt) or weights (.safetensors)")->required();
    add_output_option(sub, a.output, "Weights file (.safetensors)");
    sub.add_flag("--half", a.half, "Store F16 (half the size; inference converts back to F32)");
    sub.add_option("--note", a.note, "Free text stored in the metadata ('note'), e.g. provenance");
    sub.add_option("--set", a.overrides,
                   "Override an inference setting in the exported config, e.g. --set physics.prior_open_rays=16, --set "
                   "auto_scene_points=true, --set scene_points=32768 or --set traced_inputs=32 (only physics.prior_* keys, "
                   "auto_scene_points, scene_points and the count of traced_inputs: they carry no parameters)");
}

void run(const ExportArgs &a, const CommonOptions &) {
    std::map<std::string, std::string> meta;
    LtmModel model{nullptr};
    if (ends_with(a.input, ".safetensors")) {
        model = load_weights(a.input, &meta);
        for (const char *k : {"format", "format_version", "arch_version", "config"}) meta.erase(k);
    } else {
        const TrainState st = read_checkpoint_state(a.input);
        const ModelConfig mc = ModelConfig::from_json(parse_json(st.model_config, a.input), a.input);
        model = LtmModel(mc);
        load_checkpoint_model(a.input, model);
        meta = {{"step", std::to_string(st.step)}, {"best_val_loss", std::to_string(st.best_val)}};
    }
    if (!a.overrides.empty()) {
        // The prior's settings are computed at inference from the scene points, scene_points and the
        // point count's rule pick how many, and traced_inputs how many paths each point traces: they change what the
        // weights predict but not their shapes (traced_inputs only from N > 0 to M > 0: 0 ↔ N adds or
        // removes the embedding's six columns); any other key would.
        // Weights without a physics section (v0.3) read as PhysicsConfig::legacy(); a physics object
        // added by --set would be read over the new defaults and switch on what they never had.
        Json j = model->cfg.to_json();
        for (const auto &o : a.overrides) {
            const bool prior_key = o.rfind("physics.prior_", 0) == 0;
            if (!prior_key && o.rfind("auto_scene_points=", 0) != 0 && o.rfind("scene_points=", 0) != 0 && o.rfind("traced_inputs=", 0) != 0)
                LTM_THROW("--set ", o, ": only physics.prior_* keys, auto_scene_points, scene_points and traced_inputs can change in export");
            if (prior_key && !model->cfg.physics.any())
                LTM_THROW("--set: ", a.input, " has no physics settings (v0.3 weights): nothing to override");
            apply_json_override(j, o);
        }
        ModelConfig cfg = ModelConfig::from_json(j, "--set");
        if ((cfg.traced_inputs > 0) != (model->cfg.traced_inputs > 0))
            LTM_THROW("--set traced_inputs=", cfg.traced_inputs, ": ", a.input, " has traced_inputs ", model->cfg.traced_inputs,
                      "; export changes only the count of paths (0 and N differ by the embedding's input columns: ltm train --init widens)");
        model->cfg = std::move(cfg);
    }
    if (!a.note.empty()) meta["note"] = a.note;
    save_weights(a.output, model, meta, a.half);
    log_info("exported ", model->n_parameters(), " parameters", meta.count("step") ? " (step " + meta["step"] + ")" : "",
             a.half ? " as F16" : "", " -> ", a.output);
}
}  // namespace

Command make_export_command() {
    return make_command(
        "export", k_export_help,
        declare, run);
}

}  // namespace ltm::cli
