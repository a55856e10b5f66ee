// checkpoint.h: model weights as safetensors (shareable, Python-readable; the config JSON and
// format/architecture versions travel in the metadata), and exact-resume training checkpoints
// (.ltmckpt: torch archive with model, optimizer, step, config). All writes are atomic.
#pragma once

#include <cstdint>

#include <string>

#include <torch/torch.h>

#include "ltm/nn/ltm_model.h"
#include "ltm/nn/weights_file.h"

namespace ltm {

/// Writes every parameter and buffer (F32 CPU copies, or F16 with `half`: half the size, for
/// shipping; loading converts back to F32) plus metadata: format, format_version, arch_version,
/// config (JSON), and `extra` entries (e.g. step, val_loss).
void save_weights(const std::string &path, LtmModel &model, const std::map<std::string, std::string> &extra = {},
                  bool half = false);

/// Builds the model from the file's config and loads its tensors. Throws "path: ..." for another
/// format/architecture version, missing/unexpected tensors, or shape mismatches.
LtmModel load_weights(const std::string &path, std::map<std::string, std::string> *metadata = nullptr);

/// Copies tensors into an existing model (the same name and shape checks as load_weights); used by the trainer and tests.
void load_state(LtmModel &model, const std::map<std::string, torch::Tensor> &tensors, const std::string &where);

struct TrainState {
    int64_t step = 0;
    double best_val = 1e30;
    std::string model_config, train_config;   ///< JSON
};

void save_checkpoint(const std::string &path, LtmModel &model, torch::optim::Optimizer &opt, const TrainState &state);
/// Reads the state only (config strings, step) without touching a model.
TrainState read_checkpoint_state(const std::string &path);
/// Restores model + optimizer; the model must have been built from state.model_config.
void load_checkpoint(const std::string &path, LtmModel &model, torch::optim::Optimizer &opt);
/// Restores the model only (export): the optimizer's state is not read, so a run that trained a
/// subset of the parameters (`freeze`) exports like any other.
void load_checkpoint_model(const std::string &path, LtmModel &model);

}  // namespace ltm
