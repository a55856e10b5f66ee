// command_model.h: the weights a command runs (render and bake-gi with --method neural). They are
// read without libtorch; the tensor model is loaded only where its network must run. A program
// without libtorch then throws NeedsLibtorch (delegate.h) before any work, and ltm-torch takes over.
#pragma once

#include <optional>
#include <string>

#include "ltm/infer/prior_model.h"
#if LTM_WITH_TORCH
#include "ltm/infer/neural_renderer.h"
#endif

namespace ltm::cli {

struct CommandModel {
    PriorModel prior;   ///< the config, and whether the network is silenced or folds to its skip
#if LTM_WITH_TORCH
    std::optional<LoadedModel> tensor;   ///< loaded when the network runs
#endif
    /// The network runs: its weights are active, or the command needs it (e.g. --glossy head).
    bool network = false;
    /// The config the command runs with: the tensor model's own when it is loaded.
    ModelConfig &cfg();
};

/// `prior` (load_prior_model, already checked by the caller) with the tensor model when the network
/// must run: its weights are active, or `network_needed`, for the reason `why_needed` (what a
/// program without libtorch says, as "<path>: <why_needed>, and so libtorch").
CommandModel open_command_model(PriorModel prior, bool network_needed = false, const std::string &why_needed = "");

}  // namespace ltm::cli
