// trainer.h: training of the light transport model (paper §5): relative L2 loss in log space,
// AdamW, linear warm-up + cosine decay, gradient clipping, NaN/Inf guard, periodic validation on
// held-out scenes, JSONL log, atomic checkpoints and exact resume.
#pragma once

#include <cstdint>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ltm/core/config_fields.h"
#include "ltm/core/json_util.h"
#include "ltm/nn/ltm_model.h"
#include "ltm/data/dataset.h"
#include "ltm/train/distributed.h"
#include "ltm/train/frame_cache.h"

namespace ltm {

struct TrainConfig {
    int steps = 20000;            ///< optimizer steps
    int batch_queries = 8192;     ///< query points per step (paper: 8192)
    /// Scenes encoded per step; the batch's queries are split evenly among them. One scene per
    /// step makes every gradient a single house's (its level error dominates it); the authors' code
    /// draws 3. Costs one encoder pass per scene (gradients accumulate scene by scene, so memory
    /// stays that of one).
    int scenes_per_step = 1;
    float lr = 1e-3f;             ///< peak learning rate
    float min_lr_ratio = 0.05f;   ///< cosine decays to lr·ratio
    int warmup_steps = 500;       ///< linear warm-up from 0
    float weight_decay = 0.01f;   ///< AdamW decoupled weight decay
    float grad_clip = 1.0f;       ///< max global gradient norm
    /// "relative-l2": linear-space relative L2 with a detached denominator (unbiased with noisy,
    /// low-spp targets); "log-relative-l2": v0.3's log-space loss. Both compare in the model's
    /// output frame (E⁺ / SceneNormalization::output), so they are invariant to emission scale.
    /// "level-l2": the camera's error (level_l2_loss below; loss_eps unused).
    std::string loss = "relative-l2";
    /// ε of the loss denominator: relative-l2 adds ε · batch mean of the prediction (1: points far
    /// below the mean are weighted like absolute errors, bright ones relatively); log-relative-l2
    /// adds ε to z (v0.3 shipped 0.1).
    float loss_eps = 1.0f;
    float level_cap = 1.0f;   ///< level-l2: weight min(level_cap, prior / level) (level_l2_loss)
    /// > 0: the loss adds region_weight × region_level_loss over cubes of edge region_size·ℓ (ℓ the
    /// scene's length scale): the error of each region's summed light, which the view metric counts
    /// and a query's own loss hides under its target's noise (docs/results.md, session 27: each
    /// view's own level holds a third of the prior's removable error). 0 = off.
    float region_weight = 0.f;
    float region_size = 16.f;   ///< the regions' edge in units of ℓ (region_weight > 0)
    /// > 0: each training target is clamped at target_cap × its scene's level, per channel
    /// (capped_targets below) before the loss sees it — a 64-spp target's fireflies (up to 100× the
    /// level) make the loss heavy-tailed, and the view metric clamps at its 99th percentile anyway.
    /// Validation is never capped; the irradiance head only (refused with head "directional"). 0 = off.
    float target_cap = 0.f;
    /// > 0: the decoder's output layer (the last Linear, whose zero is the prior: start_at_prior;
    /// not the skip, see skip_lr_scale) takes this AdamW weight decay instead of weight_decay, every other weight keeps weight_decay.
    /// A pull toward the prior that each step pays on every house: a correction must earn its size
    /// on all of them, not on the few whose noise it fits (docs/results.md, session 35). 0 = off.
    float output_decay = 0.f;
    /// The decoder's skip weights (DecoderConfig::skip_inputs, ModelConfig::traced_queries) learn at
    /// lr × skip_lr_scale, always in a group of their own without weight decay (neither weight_decay
    /// nor output_decay: their scale is 1, so a pull toward 0 would bias them). Adam moves a weight
    /// by ~lr a step, and w = 1 is the regathered prior, so at lr 3·10⁻⁴ it would take thousands of
    /// steps to reach what one scalar per channel says; the other weights' steps are not changed.
    /// 1: the skip at the common lr. Ignored (one warning) for a model without a skip.
    float skip_lr_scale = 1.f;
    /// Point sets per training house: the record's own and point_sets − 1 more, sampled afresh
    /// from the regenerated house (seeds derived from the record's); each draw uses one at random.
    /// The prior's view level varies 5–10 % between point sets of one house (docs/results.md,
    /// session 19): with one set the network learns that set's error, not the house's. Validation
    /// uses the record's own set. Costs one scene generation and transport solve per extra set,
    /// once (cached).
    int point_sets = 1;
    /// Records whose scene point count differs from the model's: every point set of such a house
    /// (validation's too) is sampled afresh at the model's M from the regenerated house, with the
    /// record's queries and targets. false: refused (a mismatch is usually the wrong preset).
    bool resample_points = false;
    float val_fraction = 0.1f;    ///< highest-seed records held out for validation (seeds disjoint)
    int val_scenes = 8;           ///< at most this many held-out scenes are evaluated
    int val_queries = 8192;       ///< queries per validation scene, spread evenly over its records' rows
    int val_every = 250;          ///< steps between validations (and best-checkpoint updates)
    /// Each step sees its scene turned by k·90° about +y and/or mirrored (train/augment.h): 8× the
    /// scene configurations for the same records. Validation never is.
    bool augment = true;
    /// What "best" means: "val_loss" (the training loss on held-out scenes), "val_mse_log"
    /// (MSE of log1p(E⁺)) or "val_mse_vs_flat" (mean over scenes of the model's MSE divided by the
    /// flat oracle's, eval/field_metrics.h: below 1 beats the floor).
    std::string select_by = "val_loss";
    int ckpt_every = 250;         ///< steps between last.ltmckpt writes
    /// Also keep the weights of every validation step as step-<N>.ltmckpt (false: only last and
    /// best). The house-wide validation is not what a camera sees (docs/results.md, session 6):
    /// kept steps can be selected afterwards by `ltm eval` on the validation houses' views
    /// (scripts/select-by-views.sh).
    bool keep_val_checkpoints = false;
    int log_every = 10;           ///< steps between JSONL log lines
    /// What is trained: "irradiance" (E⁺, the decoder) or "directional" (L_in over hemisphere bins,
    /// the model's directional head; records must hold L_in at the head's bin resolution).
    std::string head = "irradiance";
    /// "encoder": the NN embedding and PTv3 keep their weights (and run in eval mode: no order
    /// shuffles, so a scene's latents are computed once per symmetry and cached); with
    /// head "directional" the irradiance decoder is frozen too — only the head's parameters change.
    std::string freeze = "none";
    /// head "directional": directions drawn per query point (uniform bin, uniform inside the bin);
    /// batch_queries counts (point, direction) pairs.
    int bins_per_query = 16;
    uint64_t seed = 0;            ///< everything random is a function of (seed, step)

    /// The keys, limits and docs of the fields above (core/config_fields.h; docs/config.md).
    static const ConfigFields<TrainConfig> &fields();
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

/// "level-l2": what a camera's view metric counts (tone-mapped MSE, each view divided by its own
/// level). In absolute units each point's error is divided by max(its prior, L_c), L_c the mean
/// prior of the scene's queries in the batch: below the level errors count absolutely (a dark
/// corner's ratio error matters as little as its light does — the relative loss weights it by
/// 1/prior², the camera does not), above it relatively (the metric clamps bright pixels). In the
/// model's ratio frame:  mean over points and channels of ((r̂ − r) · min(cap, prior / L))².
/// cap > 1 counts errors absolutely up to cap × the level (the metric clamps at its 99th
/// percentile, a few L): cap 1 is the loss as v0.7–v0.12 trained it.
///   pred, target [N, 3] (ratios to the prior), scale [3] or [N, 3] (output_scale) -> scalar
/// Unbiased with noisy targets (a weighted L2); invariant to a common scale of the prior.
torch::Tensor level_l2_loss(const torch::Tensor &pred, const torch::Tensor &target, const torch::Tensor &scale, double cap = 1.0);

/// Targets clamped at cap × the scene's level: min(target, cap · L_c), L_c the mean over the rows
/// of scale (the prior) per channel, as level_l2_loss's level. Biased low where a point's true light
/// exceeds cap · L or its estimate's tail does (fireflies), the price of a loss without them; with
/// the level held (decoder.level_points) the bias cannot move the scene's level. cap 0: unchanged.
///   target [N, 3] (absolute, the units of scale), scale [3] or [N, 3] -> [N, 3]
/// Invariant to a common scale of target and scale.
torch::Tensor capped_targets(const torch::Tensor &target, const torch::Tensor &scale, double cap);

/// The error of regional levels: queries are grouped by the cube of edge `cell` that holds them
/// (positions [N, 3], any frame), and each region r compares its light P_r = Σ_q Σ_c pred·scale with
/// the target's T_r:   Σ_r (T_r / Σ T) · ln²((P_r + ε) / (T_r + ε)),   ε = 10⁻³ · mean T_r.
/// A region's sum averages its targets' noise away (a 64-spp target is mostly noise, a region of a
/// hundred queries much less), so this sees the low-frequency error a per-query loss drowns.
///   pred, target [N, 3] (ratios to the prior), scale [3] or [N, 3], positions [N, 3], cell > 0 -> scalar
/// Zero when pred = target; invariant to a common scale of the prior and to the positions' unit
/// when cell scales with it.
torch::Tensor region_level_loss(const torch::Tensor &pred, const torch::Tensor &target, const torch::Tensor &scale,
                                const torch::Tensor &positions, double cell);

class Trainer {
public:
    /// Records of all data_dirs are split into train/validation by seed (the highest seeds
    /// validate), unless val_dirs is given: then every data_dirs record trains and val_dirs'
    /// records validate (a fixed validation set while the training data grows; a seed in both is
    /// an error). out_dir receives log.jsonl, last.ltmckpt, best.ltmckpt, model.json and train.json.
    Trainer(const ModelConfig &model_cfg, const TrainConfig &cfg, const std::vector<std::string> &data_dirs,
            const std::string &out_dir, torch::Device device = torch::kCPU,
            const std::vector<std::string> &val_dirs = {});
    /// Starts from exported weights (fine-tuning; the optimizer starts fresh). Every tensor of the
    /// model must be in the weights with its shape; the configs may differ where no tensor does.
    /// With head "directional", weights without a directional head are accepted: the head keeps
    /// its fresh initialisation (a uniform L_in = prior / π).
    void init_weights(const std::string &weights_path);
    /// Data-parallel training (train/distributed.h): each of the W ranks draws the same scenes
    /// u = t·K + k as one process would but runs only k in its block [rank·K/W, (rank+1)·K/W);
    /// gradients, the loss and the validation sums are summed over the ranks, so W processes
    /// train the model one process with a K-scene batch trains. Rank 0 alone writes the log and
    /// checkpoints. K (scenes_per_step) must be a multiple of W. Call before run().
    void set_communicator(std::shared_ptr<Communicator> comm);
    /// Keep each house's prepared draw (points, groups, frame, the prior at its queries) in `dir`
    /// and reuse what an earlier run kept there (train/frame_cache.h). Call before run().
    void set_frame_cache(const std::string &dir) { m_frame_cache = FrameCache(dir); }
    /// What every rank of a group must agree on: model config, training config, the training and
    /// validation records' file names (fingerprint_of).
    std::string fingerprint() const;
    /// Trains up to cfg.steps (or stop_at, if smaller); with resume, continues from last.ltmckpt.
    void run(bool resume, int64_t stop_at = -1);
    /// Mean validation loss over the held-out scenes (also sets val_mse_log()).
    double validate();
    const std::vector<TrainStepLog> &history() const { return m_history; }
    LtmModel &model() { return m_model; }
    int64_t step() const { return m_step; }
    double val_mse_log() const { return m_val_mse_log; }
    /// Physics and floor metrics of the last validation (JSON keys as in log.jsonl).
    const OrderedJson &val_physics() const { return m_val_physics; }

private:
    struct CachedScene {
        /// Shared by the house's point sets (they differ in scene points only).
        std::shared_ptr<const SceneRecord> record;
        SceneGeometry geometry;
        torch::Tensor scene_points, query_points, target;   // device tensors
        torch::Tensor emission_scale;                       // [3] S = Φ/A, undefined for older records
        std::map<int, SceneLatents> frozen_latents;        // freeze "encoder": latents per symmetry
        /// The scene's frame solved once (irradiance head): the normalisation without its
        /// transport solve, with point_prior [M, 3] when the model takes prior inputs, and the
        /// prior at every query, query_scale [nq, 3] (or [3] for the flat prior). The prior is a
        /// physical quantity, unchanged by the 8 horizontal symmetries, so each draw only moves
        /// the frame's centre (apply_symmetry) instead of solving the transport again (~1 s a step).
        SceneNormalization frame;
        torch::Tensor query_scale;
        /// ModelConfig::traced_queries: the regathered prior at every query [nq, 3] (invariant
        /// under the symmetries like the prior); undefined without.
        torch::Tensor query_regathered;
    };
    /// The cached output scale of query rows idx [n] -> [n, 3] (or [3] for the flat prior).
    static torch::Tensor query_scale(const CachedScene &sc, const torch::Tensor &idx);
    /// The cached regathered prior of query rows idx [n] -> [n, 3] (undefined without traced_queries).
    static torch::Tensor query_regathered(const CachedScene &sc, const torch::Tensor &idx);
    /// The scene's latents under symmetry sym (cached when the encoder is frozen).
    SceneLatents latents(CachedScene &sc, const torch::Tensor &scene_points, int sym);
    /// The directional head's loss on `share` (point, direction) pairs of scene draw u.
    torch::Tensor directional_step_loss(CachedScene &sc, uint64_t u, int64_t share, int sym);
    /// Validation of the directional head (loss, relative MSE, uniform-radiance floor, the
    /// hemisphere integral against the irradiance head); returns the mean loss.
    double validate_directional();
    /// Training or validation scene `index` with point set `set` (0: the record's own; TrainConfig::point_sets).
    CachedScene &scene(size_t index, int set = 0);
    /// The record's regenerated house and the prior's rays against it, for physics.prior_rays
    /// (records keep no meshes); null without prior_rays. Errors name `where`.
    struct HouseRays;
    std::unique_ptr<HouseRays> house_rays(const SceneRecord &record, const std::string &where) const;
    /// The same house with every length × factor (the unit check's twin), without regenerating it.
    static std::unique_ptr<HouseRays> scaled_rays(const HouseRays &rays, float length_factor);
    TrainStepLog train_step();
    bool is_root() const { return m_comm->is_root(); }
    /// Sums the gradients over the ranks; a parameter keeps no gradient only if no rank gave it one.
    void all_reduce_gradients();
    /// The configured loss in the model's output frame.   z [N, 3], target E⁺ [N, 3] -> scalar
    ///   z [N, 3], target [N, 3], scale [3] or [N, 3] (output_scale of the queries) -> scalar
    torch::Tensor loss(const torch::Tensor &z, const torch::Tensor &target, const torch::Tensor &scale) const;
    /// The directional head's loss in its ratio frame (relative-l2 or level-l2).
    ///   pred, target [N, 3] (ratios to scale), scale [3] or [N, 3] (prior / π) -> scalar
    torch::Tensor directional_loss(const torch::Tensor &pred, const torch::Tensor &target, const torch::Tensor &scale) const;
    /// Emission ×4 and lengths ×10 on one held-out scene: the exact invariances, measured.
    OrderedJson invariance_errors(CachedScene &sc, int64_t n_queries);
    ModelConfig m_model_cfg;
    TrainConfig m_cfg;
    std::string m_out;
    torch::Device m_device;
    LtmModel m_model{nullptr};
    std::unique_ptr<torch::optim::AdamW> m_opt;
    std::vector<double> m_group_lr_scale;   ///< per optimizer group: its lr is the schedule's × this (skip_lr_scale)
    /// The data-parallel group; a group of one (every collective the identity) unless set.
    std::shared_ptr<Communicator> m_comm = std::make_shared<Communicator>(DistSettings{}, "");
    std::vector<std::string> m_train_paths, m_val_paths;
    std::map<std::pair<std::string, int>, std::unique_ptr<CachedScene>> m_cache;   // (record path, point set)
    FrameCache m_frame_cache;   ///< on disk, across runs (disabled unless set_frame_cache)
    std::vector<TrainStepLog> m_history;
    int64_t m_step = 0;
    double m_best_val = 1e30;
    double m_val_mse_log = NAN;   ///< mean((log1p(Ê⁺) − log1p(E⁺))²) of the last validation
    OrderedJson m_val_physics = OrderedJson::object();
};

}  // namespace ltm
