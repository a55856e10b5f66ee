// trainer.h: training of the light transport model (paper §5): relative L2 loss in log space,
// AdamW, linear warm-up + cosine decay, gradient clipping, NaN/Inf guard, periodic validation on
// held-out scenes, JSONL log, atomic checkpoints and exact resume.
#pragma once

#include <cstdint>

#include <functional>
#include <string>
#include <vector>

#include "ltm/core/json_util.h"
#include "ltm/nn/ltm_model.h"
#include "ltm/train/dataset.h"

namespace ltm {

struct TrainConfig {
    int steps = 20000;            ///< optimizer steps
    int batch_queries = 8192;     ///< query points per step (paper: 8192)
    float lr = 1e-3f;             ///< peak learning rate
    float min_lr_ratio = 0.05f;   ///< cosine decays to lr·ratio
    int warmup_steps = 500;       ///< linear warm-up from 0
    float weight_decay = 0.01f;   ///< AdamW decoupled weight decay
    float grad_clip = 1.0f;       ///< max global gradient norm
    float loss_eps = 1e-2f;       ///< ε of the relative loss denominator
    float val_fraction = 0.1f;    ///< highest-seed records held out for validation (seeds disjoint)
    int val_scenes = 8;           ///< at most this many held-out scenes are evaluated
    int val_queries = 8192;       ///< first queries of each validation scene
    int val_every = 250;          ///< steps between validations (and best-checkpoint updates)
    /// Each step sees its scene turned by k·90° about +y and/or mirrored (train/augment.h): 8× the
    /// scene configurations for the same records. Validation never is.
    bool augment = true;
    /// What "best" means: "val_loss" (the training loss on held-out scenes) or "val_mse_log"
    /// (MSE of log1p(E⁺)); the relative loss can rise from a few dark points while the images improve.
    std::string select_by = "val_loss";
    int ckpt_every = 250;         ///< steps between last.ltmckpt writes
    int log_every = 10;           ///< steps between JSONL log lines
    uint64_t seed = 0;            ///< everything random is a function of (seed, step)

    static TrainConfig from_json(const Json &j, const std::string &where);
    OrderedJson to_json() const;
};

/// lr at `step`: linear warm-up, then cosine from lr to lr·min_lr_ratio at the last step.
double learning_rate(const TrainConfig &cfg, int64_t step);

struct TrainStepLog {
    int64_t step;
    double loss, lr, grad_norm;
    bool skipped;   ///< non-finite loss or gradient: no update
};

class Trainer {
public:
    /// Records of all data_dirs are split into train/validation by seed (the highest seeds
    /// validate); out_dir receives log.jsonl, last.ltmckpt, best.ltmckpt, model.json and train.json.
    Trainer(const ModelConfig &model_cfg, const TrainConfig &cfg, const std::vector<std::string> &data_dirs,
            const std::string &out_dir,
            torch::Device device = torch::kCPU);
    /// Starts from exported weights (fine-tuning; the optimizer starts fresh). The weights'
    /// config must equal the model config.
    void init_weights(const std::string &weights_path);
    /// Trains up to cfg.steps (or stop_at, if smaller); with resume, continues from last.ltmckpt.
    void run(bool resume, int64_t stop_at = -1);
    /// Mean validation loss over the held-out scenes (also sets val_mse_log()).
    double validate();
    const std::vector<TrainStepLog> &history() const { return m_history; }
    LtmModel &model() { return m_model; }
    int64_t step() const { return m_step; }
    double val_mse_log() const { return m_val_mse_log; }

private:
    struct CachedScene {
        SceneRecord record;
        SceneGeometry geometry;
        torch::Tensor scene_points, query_points, target;   // device tensors
    };
    CachedScene &scene(size_t index);
    TrainStepLog train_step();
    ModelConfig m_model_cfg;
    TrainConfig m_cfg;
    std::string m_out;
    torch::Device m_device;
    LtmModel m_model{nullptr};
    std::unique_ptr<torch::optim::AdamW> m_opt;
    std::vector<std::string> m_train_paths, m_val_paths;
    std::map<std::string, std::unique_ptr<CachedScene>> m_cache;
    std::vector<TrainStepLog> m_history;
    int64_t m_step = 0;
    double m_best_val = 1e30;
    double m_val_mse_log = NAN;   ///< mean((z − log1p(E⁺))²) of the last validation
};

}  // namespace ltm
