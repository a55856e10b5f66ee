// trainer.cpp: every random choice of step t (scenes, queries, PTv3 order shuffles) is a function
// of (seed, t), so a resumed run repeats an uninterrupted one exactly.
#include "ltm/train/trainer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <tuple>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/core/rng.h"
#include "ltm/eval/field_metrics.h"
#include "ltm/infer/prior_model.h"
#include "ltm/nn/checkpoint.h"
#include "ltm/nn/point_tensor.h"
#include "ltm/render/embree_accel.h"
#include "ltm/render/hemisphere_bins.h"
#include "ltm/render/mesh_occlusion.h"
#include "ltm/scene/scene_transform.h"
#include "ltm/render/scene_points.h"
#include "ltm/train/augment.h"

namespace fs = std::filesystem;

namespace ltm {

const ConfigFields<TrainConfig> &TrainConfig::fields() {
    using C = TrainConfig;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("steps", &C::steps, "optimizer steps", at_least(1))
            .field("batch_queries", &C::batch_queries, "query points per step and rank (paper: 8192), split evenly over the rank's scenes", at_least(1))
            .field("scenes_per_step", &C::scenes_per_step, "scenes encoded per step and rank (note 1); W data-parallel ranks train W times as many", at_least(1))
            .field("lr", &C::lr, "peak learning rate (AdamW)", positive())
            .field("min_lr_ratio", &C::min_lr_ratio, "cosine decay ends at lr·ratio (1: constant after warm-up)", between(0, 1))
            .field("warmup_steps", &C::warmup_steps, "linear warm-up from 0", at_least(0))
            .field("weight_decay", &C::weight_decay, "AdamW decoupled weight decay", at_least(0))
            .field("grad_clip", &C::grad_clip, "max global gradient norm", positive())
            .field("loss", &C::loss, "training loss (note 2)", {}, {"relative-l2", "log-relative-l2", "level-l2"})
            .field("loss_eps", &C::loss_eps, "ε of the relative losses' denominator (note 2)", positive())
            .field("val_fraction", &C::val_fraction, "highest-seed records held out for validation (without --val-data)", from_below(0, 1))
            .field("val_scenes", &C::val_scenes, "at most this many held-out scenes evaluated", at_least(1))
            .field("val_queries", &C::val_queries, "queries per validation scene, spread evenly over the record's rows (note 3)", at_least(1))
            .field("val_every", &C::val_every, "steps between validations (best.ltmckpt on improvement)", at_least(1))
            .field("augment", &C::augment, "turn each step's scene by k·90° about +y and/or mirror it (one of 8; train/augment.h); validation never")
            .field("select_by", &C::select_by, "what best.ltmckpt minimises (note 4)", {}, {"val_loss", "val_mse_log", "val_mse_vs_flat"})
            .field("ckpt_every", &C::ckpt_every, "steps between last.ltmckpt writes", at_least(1))
            .field("keep_val_checkpoints", &C::keep_val_checkpoints, "also keep every validation step's weights as step-N.ltmckpt (scripts/select-by-views.sh)")
            .field("log_every", &C::log_every, "steps between log.jsonl lines", at_least(1))
            .field("seed", &C::seed, "set by `--seed`; scenes, queries, augmentation and PTv3 shuffles are functions of (seed, step)")
            .field("head", &C::head, "what is trained: the irradiance decoder or the directional head (L_in bins; note 5)", {}, {"irradiance", "directional"})
            .omit_default()
            .field("freeze", &C::freeze, "\"encoder\": embedding and PTv3 keep their weights (note 5)", {}, {"none", "encoder"})
            .omit_default()
            .field("bins_per_query", &C::bins_per_query, "head \"directional\": directions per query point; batch_queries counts pairs", at_least(1))
            .omit_default()
            .field("level_cap", &C::level_cap, "level-l2: a point's weight min(level_cap, P/L) (note 2)", at_least(1))
            .omit_default()
            .field("region_weight", &C::region_weight, "weight of the regional-level term (note 2)", at_least(0))
            .omit_default()
            .field("region_size", &C::region_size, "regional-level term: the regions' edge in units of the length scale", positive())
            .omit_default()
            .field("target_cap", &C::target_cap, "> 0: training targets clamped at target_cap × the scene's level (note 2); validation never", at_least(0))
            .field("output_decay", &C::output_decay, "> 0: the decoder's output layer's AdamW weight decay (a pull toward the prior), the rest keeps weight_decay", at_least(0))
            .field("skip_lr_scale", &C::skip_lr_scale, "the decoder's skip weights (traced_queries) learn at lr × this, never decayed; 1 = at the common lr", at_least(0))
            .omit_default()
            .field("point_sets", &C::point_sets, "scene point sets per training house, one drawn per step (note 6)", between(1, 64))
            .omit_default()
            .field("resample_points", &C::resample_points, "records with another scene point count than the model's have every point set sampled afresh at the model's M (note 6); else they are refused")
            .omit_default();
    return f;
}

TrainConfig TrainConfig::from_json(const Json &j, const std::string &where) {
    const TrainConfig c = fields().read(j, where);
    if (c.scenes_per_step > c.batch_queries)
        LTM_THROW(where, ": /scenes_per_step: must be in [1, batch_queries]");
    return c;
}

OrderedJson TrainConfig::to_json() const { return fields().write(*this); }

double learning_rate(const TrainConfig &c, int64_t step) {
    if (step < c.warmup_steps) return double(c.lr) * double(step + 1) / double(c.warmup_steps);
    const double t = double(step - c.warmup_steps) / double(std::max(1, c.steps - c.warmup_steps));
    const double lo = double(c.lr) * double(c.min_lr_ratio);
    return lo + (double(c.lr) - lo) * 0.5 * (1.0 + std::cos(3.14159265358979323846 * std::min(1.0, t)));
}

Trainer::Trainer(const ModelConfig &model_cfg, const TrainConfig &cfg, const std::vector<std::string> &data_dirs,
                 const std::string &out_dir, torch::Device device, const std::vector<std::string> &val_dirs)
    : m_model_cfg(model_cfg), m_cfg(cfg), m_out(out_dir), m_device(device) {
    const auto records = list_records(data_dirs);
    if (records.empty()) LTM_THROW(data_dirs.front(), ": no dataset records (scene-*.safetensors)");
    if (!val_dirs.empty()) {
        m_train_paths = records;
        m_val_paths = list_records(val_dirs);
        if (m_val_paths.empty()) LTM_THROW(val_dirs.front(), ": no validation records (scene-*.safetensors)");
        std::vector<std::string> all = data_dirs;
        all.insert(all.end(), val_dirs.begin(), val_dirs.end());
        list_records(all);   // throws, naming both files, if a seed validates and trains
    } else {
        size_t n_val = size_t(std::floor(double(records.size()) * double(cfg.val_fraction)));
        if (cfg.val_fraction > 0.f && records.size() >= 2) n_val = std::max<size_t>(1, n_val);
        m_train_paths.assign(records.begin(), records.end() - std::ptrdiff_t(n_val));
        m_val_paths.assign(records.end() - std::ptrdiff_t(n_val), records.end());
    }
    if (m_val_paths.size() > size_t(cfg.val_scenes)) m_val_paths.resize(size_t(cfg.val_scenes));
    // The model must match the data: the same M, or records whose houses can be regenerated (their
    // points are then sampled afresh at the model's M, as the extra point sets are), and a record
    // of the expected format.
    const SceneRecord first = read_record(m_train_paths.front());
    if (int(first.scene_points.size()) != model_cfg.scene_points) {
        const std::string mismatch = detail::concat(m_train_paths.front(), ": record has ", first.scene_points.size(), " scene points, the model (",
                                                    model_cfg.name, ") expects ", model_cfg.scene_points, " (dataset preset '",
                                                    first.metadata.value("preset", OrderedJson::object()).value("name", std::string("?")), "'");
        if (!cfg.resample_points) LTM_THROW(mismatch, "; resample_points=true samples the model's afresh from each regenerated house)");
        try {
            regenerate_scene(first);
        } catch (const std::exception &e) {
            LTM_THROW(mismatch, "), and its house cannot be regenerated to sample them afresh: ", e.what());
        }
        log_info(m_train_paths.front(), ": records hold ", first.scene_points.size(), " scene points; the model's ", model_cfg.scene_points,
                 " are sampled afresh from each regenerated house");
    }
    if (cfg.head == "directional") {
        if (cfg.loss == "log-relative-l2") LTM_THROW("head \"directional\": loss \"log-relative-l2\" is for E⁺ only (use relative-l2 or level-l2)");
        // An incident-radiance bin that sees a lamp is legitimately far above the level: a cap
        // would clip the lamps themselves, not fireflies.
        if (cfg.target_cap > 0.f) LTM_THROW("head \"directional\": target_cap is for the irradiance head only (a bin that sees a lamp is not a firefly)");
        if (!model_cfg.directional)
            LTM_THROW("head \"directional\": model '", model_cfg.name, "' has no \"directional\" section");
        // The head's draws encode each symmetry afresh (no cached frame) from the record's points alone.
        if (model_cfg.traced_inputs > 0)
            LTM_THROW("head \"directional\": model '", model_cfg.name, "' has traced inputs, which its draws do not trace (train the head on a model without them)");
        check_directional_record(first, *model_cfg.directional);   // early, before any model is built
    }
    torch::manual_seed(cfg.seed);
    m_model = LtmModel(model_cfg);
    m_model->to(device);
    // Frozen layers leave the optimizer (so not even weight decay moves them) and autograd.
    if (cfg.freeze == "encoder") {
        for (auto &p : m_model->embedding->parameters()) p.requires_grad_(false);
        for (auto &p : m_model->encoder->parameters()) p.requires_grad_(false);
    }
    if (cfg.head == "directional" && cfg.freeze == "encoder")
        for (auto &p : m_model->decoder->parameters()) p.requires_grad_(false);
    // output_decay: the decoder's output layer in a group of its own, with its own decay (toward 0,
    // i.e. toward the prior); one group otherwise, as before.
    // The decoder's skip (traced_queries) in a group of its own, at lr × skip_lr_scale and never
    // decayed: its zero is the prior, but its scale is 1 and a pull toward 0 is a bias, not a prior.
    const torch::Tensor skip =
        m_model->decoder->skip.defined() && m_model->decoder->skip.requires_grad() ? m_model->decoder->skip : torch::Tensor();
    if (!m_model->decoder->skip.defined() && cfg.skip_lr_scale != 1.f)
        log_warn("skip_lr_scale ", cfg.skip_lr_scale, " is ignored: model '", m_model->cfg.name, "' has no decoder skip (traced_queries)");
    const auto in = [](const std::vector<torch::Tensor> &group, const torch::Tensor &p) {
        return std::any_of(group.begin(), group.end(), [&](const torch::Tensor &o) { return o.is_same(p); });
    };
    std::vector<torch::Tensor> own_groups;   // every parameter that is not in the common group
    if (skip.defined()) own_groups.push_back(skip);
    std::vector<torch::Tensor> out_layer;
    if (cfg.output_decay > 0.f)
        for (auto &p : m_model->decoder->output_parameters())
            if (p.requires_grad() && !in(own_groups, p)) out_layer.push_back(p), own_groups.push_back(p);
    std::vector<torch::Tensor> trained;
    for (auto &p : m_model->parameters())
        if (p.requires_grad() && !in(own_groups, p)) trained.push_back(p);
    const auto adamw = [&](double decay) { return torch::optim::AdamWOptions(cfg.lr).weight_decay(decay); };
    std::vector<torch::optim::OptimizerParamGroup> groups;
    groups.emplace_back(trained, std::make_unique<torch::optim::AdamWOptions>(adamw(cfg.weight_decay)));
    m_group_lr_scale = {1.0};
    if (!out_layer.empty()) {
        groups.emplace_back(out_layer, std::make_unique<torch::optim::AdamWOptions>(adamw(cfg.output_decay)));
        m_group_lr_scale.push_back(1.0);
    }
    if (skip.defined()) {
        groups.emplace_back(std::vector<torch::Tensor>{skip}, std::make_unique<torch::optim::AdamWOptions>(adamw(0.0)));
        m_group_lr_scale.push_back(double(cfg.skip_lr_scale));
    }
    m_opt = std::make_unique<torch::optim::AdamW>(std::move(groups), adamw(cfg.weight_decay));
    create_directories(out_dir);
}

void Trainer::init_weights(const std::string &path) {
    LtmModel w = load_weights(path);
    // Like load_state_dict(strict=True): every tensor must exist with its shape (load_state throws
    // otherwise). The configs may differ where no tensor does — e.g. turning physics switches on
    // for a fine-tune — and the log says so.
    if (w->cfg.to_json().dump() != m_model_cfg.to_json().dump())
        log_info(path, ": its model config differs from '", m_model_cfg.name, "' (same tensors; fine-tuning into the new config)");
    std::map<std::string, torch::Tensor> tensors;
    for (const auto &p : w->named_parameters()) tensors[p.key()] = p.value();
    for (const auto &b : w->named_buffers()) tensors[b.key()] = b.value();
    // Which inputs the file's first layers read so far (each conversion below widens them in turn).
    bool prior_inputs = w->cfg.prior_inputs;
    if (m_model_cfg.prior_inputs && !prior_inputs) {
        // The documented conversion (docs/config.md, prior_inputs): the embedding's and the decoder's
        // first layers read the prior's features in 3 columns after the point's own; they start at zero
        // weight, so the model starts as the weights it came from (the prior features are finite).
        for (const auto &[name, own] : {std::pair{"embedding.f.0.weight", 12}, std::pair{"decoder.embed.0.weight", 9}}) {
            torch::Tensor &t = tensors.at(name);
            if (t.dim() != 2 || t.size(1) != own) continue;   // another shape: load_state names it
            t = torch::cat({t, torch::zeros({t.size(0), 3}, t.options())}, 1);
            log_info(path, ": no prior inputs; ", name, " widened by 3 zero columns (the model starts as these weights)");
        }
        prior_inputs = true;
    }
    if (m_model_cfg.traced_inputs > 0 && w->cfg.traced_inputs == 0 && prior_inputs) {
        // The documented conversion (docs/config.md, traced_inputs): the embedding's first layer reads
        // the traced inputs in 6 columns after the prior's; they start at zero weight, so the model
        // starts as the weights it came from, whatever its scene traces.
        const std::string name = "embedding.f.0.weight";
        torch::Tensor &t = tensors.at(name);
        const int64_t want = 12 + m_model->cfg.embedding.extra_inputs;
        if (t.dim() == 2 && t.size(1) == want - 6) {
            t = torch::cat({t, torch::zeros({t.size(0), 6}, t.options())}, 1);
            log_info(path, ": no traced inputs; ", name, " widened by 6 zero columns (the model starts as these weights)");
        }
    }
    if (m_model_cfg.traced_queries && !w->cfg.traced_queries && prior_inputs) {
        // The documented conversion (docs/config.md, traced_queries): the decoder's first layer reads
        // ln(R / Ê) in 3 columns after the prior's, and the skip carries it to the output; both start
        // at zero, so the model starts as the weights it came from.
        const std::string name = "decoder.embed.0.weight";
        torch::Tensor &t = tensors.at(name);
        const int64_t want = 9 + m_model->cfg.decoder.extra_inputs;
        if (t.dim() == 2 && t.size(1) == want - 3) {
            t = torch::cat({t, torch::zeros({t.size(0), 3}, t.options())}, 1);
            tensors["decoder.skip"] = torch::zeros({3}, t.options());
            log_info(path, ": no traced queries; ", name, " widened by 3 zero columns, decoder.skip zero (the model starts as these weights)");
        }
    }
    if (w->directional && !m_model->directional) {
        // Fine-tuning into a config without the head (traced-input models, whose draws cannot train
        // one): the irradiance model is the same; the head's tensors stay behind.
        for (auto it = tensors.begin(); it != tensors.end();)
            it = it->first.rfind("directional.", 0) == 0 ? tensors.erase(it) : std::next(it);
        log_info(path, ": the model config has no directional head; the file's is left out");
    }
    if (m_cfg.head == "directional" && !w->directional) {
        // A new head on trained irradiance weights: it keeps its fresh (uniform-radiance) start.
        for (const auto &p : m_model->directional->named_parameters()) tensors["directional." + p.key()] = p.value().detach().clone();
        log_info(path, ": no directional head; the head starts fresh (L_in = its prior, radiance_scale)");
    }
    load_state(m_model, tensors, path);   // copy_ moves them to the training device
}

// Members in the order they need each other: destroyed in reverse, the occlusion (a reference to the
// BVH) first, then the BVH, then the house.
struct Trainer::HouseRays {
    Scene house;
    std::unique_ptr<EmbreeAccel> accel;
    std::shared_ptr<const SegmentOcclusion> occlusion;
    explicit HouseRays(Scene h)
        : house(std::move(h)), accel(std::make_unique<EmbreeAccel>(house)), occlusion(std::make_shared<MeshOcclusion>(*accel)) {}
};

std::unique_ptr<Trainer::HouseRays> Trainer::house_rays(const SceneRecord &record, const std::string &where) const {
    if (!m_model_cfg.physics.prior_rays && m_model_cfg.traced_inputs <= 0) return nullptr;
    Scene house;
    try {
        house = regenerate_scene(record);
    } catch (const std::exception &e) {
        LTM_THROW(where, ": ", m_model_cfg.physics.prior_rays ? "physics.prior_rays traces the prior's rays" : "traced_inputs traces paths",
                  " against the record's house, which cannot be regenerated: ", e.what());
    }
    return std::make_unique<HouseRays>(std::move(house));
}

std::unique_ptr<Trainer::HouseRays> Trainer::scaled_rays(const HouseRays &rays, float length_factor) {
    Scene twin = rays.house;
    scale_lengths(twin, length_factor);
    return std::make_unique<HouseRays>(std::move(twin));
}

Trainer::CachedScene &Trainer::scene(size_t index, int set) {
    const std::string &path = index < m_train_paths.size() ? m_train_paths[index] : m_val_paths[index - m_train_paths.size()];
    auto &slot = m_cache[{path, set}];
    if (!slot) {
        auto c = std::make_unique<CachedScene>();
        // The prepared draw from an earlier run (train/frame_cache.h): no regeneration, sampling or solve.
        const bool cacheable = m_frame_cache.enabled() && m_cfg.head != "directional";
        const std::string cache_path = cacheable ? m_frame_cache.path_for(m_model_cfg, path, set) : std::string();
        std::optional<FrameCacheEntry> hit;
        auto look_up = [&] {   // once the draw's queries are known: an entry must hold the prior at each
            if (cacheable)
                hit = m_frame_cache.load(cache_path, c->query_points.size(0), m_model_cfg.traced_inputs > 0 && !m_model_cfg.physics.prior_regathered,
                                         m_model_cfg.traced_queries);
        };
        PointSet points;
        // Points sampled afresh from the regenerated house as the record's were (its preset's rules),
        // at the model's M, with their emission scale where the record has one: extra point sets,
        // and every set of a record baked at another M.
        auto use_fresh_points = [&](const SceneRecord &r) {
            const DataPreset p = DataPreset::from_json(r.metadata.at("preset"), path + " (preset)");
            const Scene house = regenerate_scene(r);
            const EmbreeAccel accel(house);
            ScenePoints sampled =
                sample_scene_points(accel, m_model_cfg.scene_points, hash_keys({r.seed, 0x9015e75ull, uint64_t(set)}), p.exclude_enclosed);
            const Vec3f s = sampled.emission_scale;
            if (c->emission_scale.defined()) c->emission_scale = torch::tensor({s.x, s.y, s.z}).to(m_device);
            points = std::move(sampled.points);
        };
        if (set == 0) {
            auto r = std::make_shared<SceneRecord>(read_record(path));
            c->query_points = point_tensor(r->query_points).to(m_device);
            c->target = rows_tensor(r->e_indirect, 3).to(m_device);
            if (m_cfg.head == "directional") check_directional_record(*r, *m_model_cfg.directional);
            if (r->emission_scale) {
                const Vec3f s = *r->emission_scale;
                c->emission_scale = torch::tensor({s.x, s.y, s.z}).to(m_device);
            }
            look_up();
            if (int(r->scene_points.size()) == m_model_cfg.scene_points) {
                if (!hit) points = r->scene_points;
            } else {   // resample_points (checked in the constructor on the first record)
                if (!m_cfg.resample_points)
                    LTM_THROW(path, ": ", r->scene_points.size(), " scene points, the model expects ", m_model_cfg.scene_points,
                              " (resample_points=true samples them afresh from the regenerated house)");
                if (!hit) use_fresh_points(*r);
            }
            c->record = std::move(r);
        } else {
            // Another point set of the same house: the record's queries and targets, fresh points.
            const CachedScene &own = scene(index, 0);
            c->record = own.record;
            c->query_points = own.query_points, c->target = own.target, c->emission_scale = own.emission_scale;
            look_up();
            if (!hit) use_fresh_points(*c->record);
        }
        if (hit) {
            c->scene_points = hit->scene_points.to(m_device);
            c->geometry.centers = hit->centers.to(m_device), c->geometry.groups = hit->groups.to(m_device);
            c->emission_scale = hit->emission_scale.defined() ? hit->emission_scale.to(m_device) : torch::Tensor();
            c->frame.center = hit->center.to(m_device), c->frame.length = hit->length.to(m_device);
            c->frame.emission = hit->emission.to(m_device), c->frame.output = hit->output.to(m_device);
            if (hit->point_prior.defined()) c->frame.point_prior = hit->point_prior.to(m_device);
            if (hit->point_traced.defined()) c->frame.point_traced = hit->point_traced.to(m_device);
            c->query_scale = hit->query_scale.to(m_device);
            if (hit->query_regathered.defined()) c->query_regathered = hit->query_regathered.to(m_device);
            slot = std::move(c);
            return *slot;
        }
        const auto sp = point_tensor(points);
        c->geometry = m_model->scene_geometry(sp);   // FPS + kNN once per scene (CPU), cached
        c->geometry.centers = c->geometry.centers.to(m_device);
        c->geometry.groups = c->geometry.groups.to(m_device);
        c->scene_points = sp.to(m_device);
        if (m_cfg.head != "directional") {
            // The directional head's radiance_scale gathers the solved prior itself in the draw's frame.
            torch::NoGradGuard no_grad;
            // physics.prior_rays: the prior's visibility by rays against the regenerated house's meshes,
            // needed only while the prior is solved and gathered here.
            const auto rays = house_rays(*c->record, path);
            // traced_inputs: a few paths per scene point through the house (the draw's frame keeps them).
            c->frame = m_model->scene_frame(c->scene_points, c->geometry, c->emission_scale, rays ? rays->occlusion : nullptr,
                                            rays ? traced_inputs_tracer(m_model_cfg, *rays->accel) : PointTracer{});
            if (m_model_cfg.traced_queries) std::tie(c->query_scale, c->query_regathered) = prior_and_regathered(c->query_points, c->frame);
            else c->query_scale = output_scale(c->query_points, c->frame);
            c->frame.transport.reset(), c->frame.regather.reset();   // every value needed is kept; the solve's memory is not
            if (cacheable) {
                FrameCacheEntry e;
                e.scene_points = sp, e.centers = c->geometry.centers, e.groups = c->geometry.groups;
                e.emission_scale = c->emission_scale;
                e.center = c->frame.center, e.length = c->frame.length, e.emission = c->frame.emission, e.output = c->frame.output;
                e.point_prior = c->frame.point_prior, e.query_scale = c->query_scale;
                e.point_traced = c->frame.point_traced, e.query_regathered = c->query_regathered;
                m_frame_cache.store(cache_path, e);
            }
        }
        slot = std::move(c);
    }
    return *slot;
}

TrainStepLog Trainer::train_step() {
    const int64_t t = m_step;
    const double lr = learning_rate(m_cfg, t);
    for (size_t g = 0; g < m_opt->param_groups().size(); ++g)
        static_cast<torch::optim::AdamWOptions &>(m_opt->param_groups()[g].options()).lr(lr * m_group_lr_scale.at(g));
    m_model->train();
    if (m_cfg.freeze == "encoder") m_model->embedding->eval(), m_model->encoder->eval();
    m_opt->zero_grad();
    // Scene draw u = t·K + k (K scenes per step): every random choice is a function of (seed, u),
    // so K = 1 repeats the one-scene trainer exactly. Scenes follow a seeded permutation per epoch;
    // queries are uniform with replacement; the batch's queries are split evenly over the K scenes.
    // Per rank, as torchrun users expect: each of W ranks trains scenes_per_step scenes over
    // batch_queries queries, so the step's global batch is K = W · scenes_per_step scenes and
    // W · batch_queries queries (one process: W = 1, the single-process trainer exactly).
    const int64_t W = m_comm->world_size(), r = m_comm->rank();
    const int64_t K_rank = m_cfg.scenes_per_step, K = K_rank * W, B = int64_t(m_cfg.batch_queries) * W;
    const size_t n = m_train_paths.size();
    TrainStepLog log{t, 0.0, lr, 0.0, false};
    // This rank's block of the K draws (all of them in one process).
    for (int64_t k = r * K_rank; k < (r + 1) * K_rank && !log.skipped; ++k) {
        const uint64_t u = uint64_t(t * K + k);
        const uint64_t epoch = u / n;
        std::vector<size_t> perm(n);
        std::iota(perm.begin(), perm.end(), size_t(0));
        Pcg32 perm_rng(hash_keys({m_cfg.seed, 0x5ce4e5ull, epoch}));
        for (size_t i = n; i > 1; --i) std::swap(perm[i - 1], perm[perm_rng.next_below(uint32_t(i))]);
        // One of the house's point sets per draw (TrainConfig::point_sets; 1: always set 0, the
        // record's own points, or with resample_points at another M a fresh set of its own).
        const int set = m_cfg.point_sets > 1 ? int(hash_keys({m_cfg.seed, 0x5e75e7ull, u}) % uint64_t(m_cfg.point_sets)) : 0;
        CachedScene &sc = scene(perm[u % n], set);
        const int64_t nq = sc.query_points.size(0);
        const int64_t share = B / K + (k < B % K ? 1 : 0);
        // One of the 8 horizontal symmetries per scene draw (train/augment.h): targets and cached FPS/kNN stay valid.
        const int sym = m_cfg.augment ? int(hash_keys({m_cfg.seed, 0xa06e47ull, u}) % k_n_symmetries) : 0;
        if (m_cfg.head == "directional") {
            const auto l = directional_step_loss(sc, u, share, sym) / double(K);
            const double v = l.item<double>();
            if (!std::isfinite(v)) log.skipped = true;
            else l.backward(), log.loss += v;
            continue;
        }
        Pcg32 q_rng(hash_keys({m_cfg.seed, 0x9e4e5ull, u}));
        std::vector<int64_t> pick(static_cast<size_t>(share));
        for (auto &p : pick) p = int64_t(q_rng.next_below(uint32_t(nq)));
        const auto idx = torch::tensor(pick, torch::kInt64).to(m_device);
        m_model->encoder->reseed(hash_keys({m_cfg.seed, 0x0dde5ull, u}) >> 1);   // PTv3 order shuffles, drop path
        const auto scene_points = apply_symmetry(sc.scene_points, sym);
        const auto queries = apply_symmetry(sc.query_points.index_select(0, idx), sym);
        const SceneLatents lat = latents(sc, scene_points, sym);
        const auto scale = query_scale(sc, idx);
        const auto z = m_model->decode(queries, lat, scale, query_regathered(sc, idx));
        // The step's loss is the mean of the scenes' losses; gradients accumulate scene by scene.
        const auto target = capped_targets(sc.target.index_select(0, idx), scale, m_cfg.target_cap);
        auto l = loss(z, target, scale);
        if (m_cfg.region_weight > 0.f)
            l = l + double(m_cfg.region_weight) * region_level_loss(torch::expm1(z), normalized_target(target, scale), scale,
                                                                    queries.slice(1, 0, 3),
                                                                    double(m_cfg.region_size) * lat.norm.length.item<double>());
        l = l / double(K);
        const double v = l.item<double>();
        if (!std::isfinite(v)) log.skipped = true;
        else l.backward(), log.loss += v;
    }
    if (W > 1) {
        // The step's loss and "some rank saw a non-finite loss" are summed like the gradients.
        const std::vector<double> sums = m_comm->all_reduce_sum({log.skipped ? 0.0 : log.loss, log.skipped ? 1.0 : 0.0});
        log.loss = sums[0], log.skipped = sums[1] > 0.0;
        all_reduce_gradients();
    }
    if (!log.skipped) {
        log.grad_norm = torch::nn::utils::clip_grad_norm_(m_model->parameters(), m_cfg.grad_clip);
        if (!std::isfinite(log.grad_norm)) log.skipped = true;
        else m_opt->step();
    }
    if (log.skipped) {
        m_opt->zero_grad();
        log_warn("step ", t, ": non-finite loss or gradient, update skipped");
    }
    ++m_step;
    return log;
}

void Trainer::all_reduce_gradients() {
    std::vector<torch::Tensor> grads;
    std::vector<double> defined;
    for (auto &p : m_model->parameters()) {
        defined.push_back(p.grad().defined() ? 1.0 : 0.0);
        if (!p.grad().defined()) p.mutable_grad() = torch::zeros_like(p);
        grads.push_back(p.grad());
    }
    defined = m_comm->all_reduce_sum(defined);
    m_comm->all_reduce_sum(grads);
    // A parameter no rank used keeps no gradient, as in one process (AdamW then skips it).
    size_t i = 0;
    for (auto &p : m_model->parameters())
        if (defined[i++] == 0.0) p.mutable_grad() = torch::Tensor();
}

void Trainer::set_communicator(std::shared_ptr<Communicator> comm) {
    if (!comm) comm = std::make_shared<Communicator>(DistSettings{}, "");   // a group of one
    m_comm = std::move(comm);
}

std::string Trainer::fingerprint() const {
    std::string s = m_model_cfg.to_json().dump() + "\n" + m_cfg.to_json().dump() + "\n";
    for (const auto *paths : {&m_train_paths, &m_val_paths})
        for (const auto &p : *paths) s += fs::path(p).filename().string() + ",";
    return fingerprint_of(s);
}

torch::Tensor Trainer::loss(const torch::Tensor &z, const torch::Tensor &target, const torch::Tensor &scale) const {
    const auto y = normalized_target(target, scale);
    if (m_cfg.loss == "log-relative-l2") return relative_l2_log_loss(z, y, m_cfg.loss_eps);
    if (m_cfg.loss == "level-l2") return level_l2_loss(torch::expm1(z), y, scale, m_cfg.level_cap);
    return relative_l2_loss(torch::expm1(z), y, m_cfg.loss_eps);
}

torch::Tensor Trainer::directional_loss(const torch::Tensor &pred, const torch::Tensor &target, const torch::Tensor &scale) const {
    // level-l2 weighs each pair by its absolute light up to the batch's level (what a rendered
    // glossy reflection shows); relative-l2 by its own prediction.
    if (m_cfg.loss == "level-l2") return level_l2_loss(pred, target, scale, m_cfg.level_cap);
    return relative_l2_loss(pred, target, m_cfg.loss_eps);
}

torch::Tensor level_l2_loss(const torch::Tensor &pred, const torch::Tensor &target, const torch::Tensor &scale, double cap) {
    TORCH_CHECK(pred.sizes() == target.sizes() && pred.dim() == 2 && pred.size(1) == 3, "loss: prediction ", pred.sizes(),
                " and target ", target.sizes(), " must be the same [N, 3]");
    const auto s = scale.detach().expand_as(pred);
    const auto level = s.mean(0, /*keepdim=*/true).clamp_min(1e-30);
    const auto w = (s / level).clamp_max(cap);
    return ((pred - target) * w).pow(2).mean();
}

torch::Tensor capped_targets(const torch::Tensor &target, const torch::Tensor &scale, double cap) {
    if (!(cap > 0.0)) return target;
    TORCH_CHECK(target.dim() == 2 && target.size(1) == 3, "target cap: target ", target.sizes(), " must be [N, 3]");
    const auto level = scale.detach().expand_as(target).mean(0, /*keepdim=*/true);
    return torch::minimum(target, level * cap);
}

torch::Tensor region_level_loss(const torch::Tensor &pred, const torch::Tensor &target, const torch::Tensor &scale,
                                const torch::Tensor &positions, double cell) {
    TORCH_CHECK(pred.sizes() == target.sizes() && pred.dim() == 2 && pred.size(1) == 3, "region loss: prediction ", pred.sizes(),
                " and target ", target.sizes(), " must be the same [N, 3]");
    TORCH_CHECK(positions.dim() == 2 && positions.size(0) == pred.size(0) && positions.size(1) == 3, "region loss: positions ",
                positions.sizes(), " must be [N, 3] for ", pred.size(0), " queries");
    if (!(cell > 0.0) || !std::isfinite(cell)) LTM_THROW("region loss: cell edge must be finite and > 0, got ", cell);
    const auto s = scale.detach().expand_as(pred);
    // Region of each query: its cube's integer coordinates, made one key by torch::unique over rows.
    const auto cube = torch::floor(positions.detach().to(torch::kFloat64) / cell).to(torch::kInt64);
    const auto inverse = std::get<1>(torch::unique_dim(cube, 0, /*sorted=*/true, /*return_inverse=*/true));
    const int64_t regions = inverse.numel() > 0 ? inverse.max().item<int64_t>() + 1 : 0;
    const auto p = torch::zeros({regions}, pred.options()).index_add(0, inverse, (pred * s).sum(1));
    const auto t = torch::zeros({regions}, pred.options()).index_add(0, inverse, (target * s).detach().sum(1));
    const auto eps = 1e-3 * t.mean().clamp_min(1e-30);
    const auto share = t / t.sum().clamp_min(1e-30);
    return (share * torch::log((p.clamp_min(0) + eps) / (t.clamp_min(0) + eps)).pow(2)).sum();
}

namespace {
// k rows spread evenly over n: records keep their query points in surface-stratum order (mesh by
// mesh), so the first k rows would be one part of the house, not a sample of it.
torch::Tensor spread_rows(int64_t n, int64_t k, torch::Device device) {
    k = std::min(k, n);
    return torch::div(torch::arange(k, torch::kInt64) * n, k, "floor").to(device);
}

std::vector<float> cpu_floats(const torch::Tensor &t) {
    const auto c = t.detach().to(torch::kCPU, torch::kFloat32).contiguous();
    return {c.data_ptr<float>(), c.data_ptr<float>() + c.numel()};
}
}  // namespace

OrderedJson Trainer::invariance_errors(CachedScene &sc, int64_t nq) {
    const auto qp = sc.query_points.index_select(0, spread_rows(sc.query_points.size(0), nq, m_device));
    // With physics.prior_rays each encode traces the house (×10: the house scaled alike).
    const std::string where = "validation record " + std::to_string(sc.record->seed);
    const auto rays = house_rays(*sc.record, where), rays10 = rays ? scaled_rays(*rays, 10.f) : nullptr;
    auto occlusion = [](const std::unique_ptr<HouseRays> &r) { return r ? r->occlusion : nullptr; };
    // traced_inputs: the house's own tracer; emission ×4 traces four times the light (path tracing is
    // linear in emission: the same paths, ×4), lengths ×10 the scaled house.
    auto tracer = [&](const std::unique_ptr<HouseRays> &r, float gain) -> PointTracer {
        if (!r) return {};
        PointTracer t = traced_inputs_tracer(m_model_cfg, *r->accel);
        if (!t || gain == 1.f) return t;
        return [t, gain](const float *rows, size_t n, Vec3f *direct, Vec3f *indirect) {
            t(rows, n, direct, indirect);
            for (size_t i = 0; i < n; ++i) direct[i] = direct[i] * gain, indirect[i] = indirect[i] * gain;
        };
    };
    const auto base = m_model->predict_irradiance(
        qp, m_model->encode(sc.scene_points, sc.geometry, sc.emission_scale, nullptr, occlusion(rays), tracer(rays, 1.f)));
    const double mean = base.abs().mean().item<double>() + 1e-30;
    // Emission ×4: E⁺ ×4 (bit-exact for a power of two when emission_scale is on).
    auto sp4 = sc.scene_points.clone();
    sp4.slice(1, 9, 12).mul_(4.0);
    const auto s4 = sc.emission_scale.defined() ? sc.emission_scale * 4.0 : torch::Tensor();
    const auto e4 = m_model->predict_irradiance(qp, m_model->encode(sp4, sc.geometry, s4, nullptr, occlusion(rays), tracer(rays, 4.f)));
    // Lengths ×10 (positions of scene and query points): E⁺ unchanged. FPS/kNN are recomputed.
    auto sp10 = sc.scene_points.clone(), qp10 = qp.clone();
    sp10.slice(1, 0, 3).mul_(10.0);
    qp10.slice(1, 0, 3).mul_(10.0);
    SceneGeometry g10 = m_model->scene_geometry(sp10.cpu());
    g10.centers = g10.centers.to(m_device), g10.groups = g10.groups.to(m_device);
    const auto e10 =
        m_model->predict_irradiance(qp10, m_model->encode(sp10, g10, sc.emission_scale, nullptr, occlusion(rays10), tracer(rays10, 1.f)));
    return {{"val_emission_x4_error", (e4 - 4.0 * base).abs().mean().item<double>() / (4.0 * mean)},
            {"val_unit_x10_error", (e10 - base).abs().mean().item<double>() / mean}};
}

torch::Tensor Trainer::query_scale(const CachedScene &sc, const torch::Tensor &idx) {
    return sc.query_scale.dim() == 2 ? sc.query_scale.index_select(0, idx) : sc.query_scale;
}

torch::Tensor Trainer::query_regathered(const CachedScene &sc, const torch::Tensor &idx) {
    return sc.query_regathered.defined() ? sc.query_regathered.index_select(0, idx) : torch::Tensor();
}

SceneLatents Trainer::latents(CachedScene &sc, const torch::Tensor &scene_points, int sym) {
    // The irradiance head draws in the cached frame; the directional head solves per draw.
    const SceneNormalization f = sc.frame.center.defined() ? apply_symmetry(sc.frame, sym) : SceneNormalization{};
    const SceneNormalization *frame = f.center.defined() ? &f : nullptr;
    if (m_cfg.freeze != "encoder") return m_model->encode(scene_points, sc.geometry, sc.emission_scale, frame);
    // Frozen and in eval mode (no PTv3 order shuffles): a pure function of the scene and sym.
    // (Kept on the training device: m·C floats per scene and symmetry, ~1 MB for the cpu preset.)
    const auto it = sc.frozen_latents.find(sym);
    if (it != sc.frozen_latents.end()) return it->second;
    torch::NoGradGuard no_grad;
    // Without autograd a model at its prior folds the encoder away (zero features: LtmModelImpl::
    // fold_prior); these latents feed training, so the encoder must run.
    const bool fold = m_model->fold_prior;
    m_model->fold_prior = false;
    SceneLatents lat = m_model->encode(scene_points, sc.geometry, sc.emission_scale, frame);
    m_model->fold_prior = fold;
    return sc.frozen_latents[sym] = std::move(lat);
}

namespace {
// World direction of a point (u, v) of bin b's cell, in the tangent frame the bake used (Frame(n)).
Vec3f bin_direction(Vec3f n, int b, int resolution, float u, float v) {
    return normalize(Frame(n).to_world(square_to_direction(bin_to_square(b, resolution, {u, v}))));
}
}  // namespace

torch::Tensor Trainer::directional_step_loss(CachedScene &sc, uint64_t u, int64_t share, int sym) {
    const SceneRecord &r = *sc.record;
    const int R = r.bin_resolution, nb = R * R;
    const int64_t nq = int64_t(r.query_points.size());
    // ⌈share / B⌉ query points, B directions each (the last point may get fewer): uniform bin,
    // uniform inside it, so the head sees every direction, not only bin centres.
    Pcg32 rng(hash_keys({m_cfg.seed, 0xd14ec7ull, u}));
    std::vector<int64_t> rows(size_t(share), 0);
    std::vector<float> dirs(size_t(share) * 3), target(size_t(share) * 3);
    int64_t q = 0;
    for (int64_t i = 0; i < share; ++i) {
        if (i % m_cfg.bins_per_query == 0) q = int64_t(rng.next_below(uint32_t(nq)));
        const int b = int(rng.next_below(uint32_t(nb)));
        const float bu = rng.next_float(), bv = rng.next_float();
        const Vec3f w = bin_direction(r.query_points.vec3(size_t(q), 3), b, R, bu, bv);
        rows[size_t(i)] = q;
        for (int c = 0; c < 3; ++c) {
            dirs[size_t(i) * 3 + size_t(c)] = w[c];
            target[size_t(i) * 3 + size_t(c)] = r.l_in[(size_t(q) * size_t(nb) + size_t(b)) * 3 + size_t(c)];
        }
    }
    const auto idx = torch::tensor(rows, torch::kInt64).to(m_device);
    auto direction = rows_tensor(dirs, 3).to(m_device);
    if (sym != 0) direction = direction.mm(symmetry_matrix(sym).t().to(m_device));
    const auto scene_points = apply_symmetry(sc.scene_points, sym);
    const auto queries = apply_symmetry(sc.query_points.index_select(0, idx), sym);
    m_model->encoder->reseed(hash_keys({m_cfg.seed, 0x0dde5ull, u}) >> 1);
    const SceneLatents lat = latents(sc, scene_points, sym);
    const auto z = m_model->decode_radiance(queries, direction, lat);
    // In the head's ratio frame: L_in / scale, scale its prior's radiance (radiance_scale).
    const auto scale = radiance_scale(queries, direction, lat.norm, m_model_cfg.directional->prior_cells);
    return directional_loss(torch::expm1(z), normalized_target(rows_tensor(target, 3).to(m_device), scale), scale);
}

double Trainer::validate_directional() {
    torch::NoGradGuard no_grad;
    m_model->eval();
    double sum = 0, err = 0, err_uniform = 0, err_uniform_model = 0, gap_model = 0, gap_ref = 0, level = 0;
    const size_t W = size_t(m_comm->world_size()), r0 = size_t(m_comm->rank());
    for (size_t i = r0; i < m_val_paths.size(); i += W) {
        CachedScene &sc = scene(m_train_paths.size() + i);
        const SceneRecord &r = *sc.record;
        const int R = r.bin_resolution, nb = R * R;
        const int64_t nq = int64_t(r.query_points.size());
        const bool indirect = m_model_cfg.directional->radiance == "indirect";   // ∫ L⁺ cos = E⁺; ∫ L cos = E_d + E⁺
        // Whole hemispheres (bin centres) of points spread over the record: the loss, the error
        // against the bins, and ∫ L̂ cos dω = (π/R²) Σ_bins L̂ against E_direct + E⁺.
        const int64_t n_pts = std::max<int64_t>(1, std::min<int64_t>(nq, m_cfg.val_queries / nb));
        const auto pts = spread_rows(nq, n_pts, torch::kCPU);
        const std::vector<int64_t> rows(pts.data_ptr<int64_t>(), pts.data_ptr<int64_t>() + pts.size(0));
        std::vector<float> target, e_total;
        for (int64_t q : rows) {
            const float *bins = r.l_in.data() + size_t(q) * size_t(nb) * 3;
            target.insert(target.end(), bins, bins + size_t(nb) * 3);
            for (int c = 0; c < 3; ++c)
                e_total.push_back((indirect ? 0.f : r.e_direct[size_t(q) * 3 + size_t(c)]) + r.e_indirect[size_t(q) * 3 + size_t(c)]);
        }
        const HemisphereRows hemi = hemisphere_rows(r.query_points, rows, R);
        const auto queries = rows_tensor(hemi.query, 9).to(m_device);
        const auto direction = rows_tensor(hemi.direction, 3).to(m_device);
        const SceneLatents lat = latents(sc, sc.scene_points, 0);
        const auto z = m_model->decode_radiance(queries, direction, lat);
        const auto scale = radiance_scale(queries, direction, lat.norm, m_model_cfg.directional->prior_cells);
        const auto l_ref = rows_tensor(target, 3).to(m_device);
        sum += directional_loss(torch::expm1(z), normalized_target(l_ref, scale), scale).item<double>();
        const auto l_hat = radiance_from_z(z, scale);
        const int64_t np = pts.size(0);
        // Floor: a uniform radiance whose cosine integral is the reference's E_direct + E⁺.
        const auto e_ref = rows_tensor(e_total, 3).to(m_device);                     // [P, 3]
        const auto uniform = (e_ref / k_pi).repeat_interleave(nb, 0);                  // [P·R², 3]
        const double r2 = l_ref.pow(2).sum().item<double>() + 1e-30;
        err += (l_hat - l_ref).pow(2).sum().item<double>() / r2;
        err_uniform += (uniform - l_ref).pow(2).sum().item<double>() / r2;
        const auto integral = l_hat.view({np, nb, 3}).sum(1) * (k_pi / double(nb));   // [P, 3]
        const auto pts_dev = pts.to(m_device);
        auto e_model = m_model->predict_irradiance(sc.query_points.index_select(0, pts_dev), lat);
        if (!indirect) e_model = e_model + rows_tensor(r.e_direct, 3).to(m_device).index_select(0, pts_dev);
        err_uniform_model += ((e_model / k_pi).repeat_interleave(nb, 0) - l_ref).pow(2).sum().item<double>() / r2;
        gap_model += (integral - e_model).abs().mean().item<double>() / (e_model.abs().mean().item<double>() + 1e-30);
        gap_ref += (integral - e_ref).abs().mean().item<double>() / (e_ref.abs().mean().item<double>() + 1e-30);
        level += integral.mean().item<double>() / (e_ref.mean().item<double>() + 1e-30);
    }
    if (W > 1) {
        const std::vector<double> t = m_comm->all_reduce_sum({sum, err, err_uniform, gap_model, gap_ref, level, err_uniform_model});
        sum = t[0], err = t[1], err_uniform = t[2], gap_model = t[3], gap_ref = t[4], level = t[5], err_uniform_model = t[6];
    }
    const double n = double(m_val_paths.size());
    m_val_mse_log = NAN;
    m_val_physics = {{"val_dir_rel_mse", err / n}, {"val_dir_rel_mse_uniform", err_uniform / n},
                     {"val_dir_rel_mse_uniform_model", err_uniform_model / n},
                     {"val_hemisphere_gap_vs_model", gap_model / n}, {"val_hemisphere_gap_vs_ref", gap_ref / n},
                     {"val_dir_level_ratio", level / n}};
    m_model->train();
    return sum / n;
}

double Trainer::validate() {
    if (m_val_paths.empty()) return NAN;
    if (m_cfg.head == "directional") return validate_directional();
    torch::NoGradGuard no_grad;
    m_model->eval();
    double sum = 0, sum_mse = 0, chroma = 0, corr = 0, vs_flat = 0, log_level = 0;
    int in_band = 0, beats = 0;
    // Rank r validates scenes r, r + W, ...; the sums are then summed over the ranks.
    const size_t W = size_t(m_comm->world_size()), r0 = size_t(m_comm->rank());
    for (size_t i = r0; i < m_val_paths.size(); i += W) {
        CachedScene &sc = scene(m_train_paths.size() + i);
        const auto rows = spread_rows(sc.query_points.size(0), m_cfg.val_queries, m_device);
        const int64_t nq = rows.size(0);
        const SceneLatents lat = latents(sc, sc.scene_points, 0);
        const auto queries = sc.query_points.index_select(0, rows);
        const auto scale = query_scale(sc, rows);
        const auto z = m_model->decode(queries, lat, scale, query_regathered(sc, rows));
        const auto target = sc.target.index_select(0, rows);
        const auto pred = irradiance_from_z(z, scale);
        sum += loss(z, target, scale).item<double>();
        // Plain MSE of log1p(E⁺): not dominated by a few dark points the way a relative loss is.
        sum_mse += (torch::log1p(pred) - torch::log1p(target)).pow(2).mean().item<double>();
        const auto p = cpu_floats(pred), r = cpu_floats(target);
        const FieldMetrics f = compare_fields(p.data(), r.data(), size_t(nq));
        log_level += std::log(std::max(f.level_ratio, 1e-30));
        in_band += f.level_in_band(), beats += f.beats_flat();
        chroma += f.chroma_error, corr += f.luminance_correlation;
        vs_flat += f.mse / std::max(f.flat_mse, 1e-30);
    }
    if (W > 1) {
        const std::vector<double> t = m_comm->all_reduce_sum({sum, sum_mse, chroma, corr, vs_flat, log_level, double(in_band), double(beats)});
        sum = t[0], sum_mse = t[1], chroma = t[2], corr = t[3], vs_flat = t[4], log_level = t[5];
        in_band = int(t[6]), beats = int(t[7]);
    }
    const double n = double(m_val_paths.size());
    m_val_mse_log = sum_mse / n;
    m_val_physics = {{"val_mse_vs_flat", vs_flat / n}, {"val_beats_flat", double(beats) / n},
                     {"val_level_ratio_geomean", std::exp(log_level / n)}, {"val_level_in_band", double(in_band) / n},
                     {"val_chroma_error", chroma / n}, {"val_luminance_corr", corr / n}};
    if (is_root())   // one scene's invariances: rank 0's to log
        m_val_physics.update(invariance_errors(scene(m_train_paths.size()), std::min<int64_t>(m_cfg.val_queries, 4096)));
    m_model->train();
    return sum / n;
}

void Trainer::run(bool resume, int64_t stop_at) {
    const std::string last = m_out + "/last.ltmckpt", best = m_out + "/best.ltmckpt", log_path = m_out + "/log.jsonl";
    const std::string model_json = m_model_cfg.to_json().dump(), train_json = m_cfg.to_json().dump();
    if (resume) {
        if (!fs::exists(last)) LTM_THROW(last, ": nothing to resume from");
        const TrainState st = read_checkpoint_state(last);
        if (st.model_config != model_json)
            LTM_THROW(last, ": checkpoint was trained with another model config; resume with the same --model");
        load_checkpoint(last, m_model, *m_opt);
        m_step = st.step;
        m_best_val = st.best_val;
        if (is_root()) {
            // Drop log lines past the checkpoint (written by the interrupted run after it).
            std::string kept, line;
            std::ifstream in(log_path);
            while (std::getline(in, line))
                if (!line.empty() && parse_json(line, log_path).value("step", int64_t(0)) < m_step) kept += line + "\n";
            write_file_atomic(log_path, kept);
        }
        log_info("resuming at step ", m_step, " from ", last);
    } else {
        if (fs::exists(last)) LTM_THROW(last, ": a run exists here; pass --resume to continue it or choose another --out");
        if (is_root()) {
            write_file_atomic(m_out + "/model.json", dump_json_compact(m_model_cfg.to_json()));
            write_file_atomic(m_out + "/train.json", dump_json_compact(m_cfg.to_json()));
            write_file_atomic(log_path, "");
        }
    }
    if (m_comm->world_size() > 1) {
        // Every rank starts from rank 0's weights (an --init, a resume or a fresh initialisation
        // alike); from then on identical summed gradients keep them identical.
        std::vector<torch::Tensor> state;
        for (const auto &p : m_model->parameters()) state.push_back(p.detach());
        for (const auto &b : m_model->buffers()) state.push_back(b.detach());
        m_comm->broadcast_from_root(state);
    }
    // Rank 0 logs and checkpoints; the other ranks' log stream stays closed.
    std::ofstream log;
    if (is_root()) log.open(log_path, std::ios::app);
    const int64_t end = stop_at >= 0 ? std::min<int64_t>(stop_at, m_cfg.steps) : m_cfg.steps;
    auto t_last = std::chrono::steady_clock::now();
    int64_t steps_since = 0;
    double loss_since = 0;   // mean over the logged interval: one step's loss is one scene's
    auto save = [&](const std::string &path) {
        if (is_root()) save_checkpoint(path, m_model, *m_opt, {m_step, m_best_val, model_json, train_json});
    };
    // Validation: a log line, best.ltmckpt on improvement of the select_by score.
    auto run_validation = [&]() {
        const double v = validate();
        OrderedJson vj = {{"step", m_step - 1}, {"val_loss", v}, {"val_mse_log", m_val_mse_log}};
        vj.update(m_val_physics);
        log << vj.dump() << "\n" << std::flush;
        if (m_cfg.head == "directional")
            log_info("step ", m_step, " validation loss ", v, ", L_in relative MSE ", m_val_physics.value("val_dir_rel_mse", NAN),
                     " (uniform radiance of the irradiance head ", m_val_physics.value("val_dir_rel_mse_uniform_model", NAN),
                     ", of the reference ", m_val_physics.value("val_dir_rel_mse_uniform", NAN), "), hemisphere integral vs the irradiance head ",
                     m_val_physics.value("val_hemisphere_gap_vs_model", NAN), ", vs the reference ", m_val_physics.value("val_hemisphere_gap_vs_ref", NAN),
                     " (", m_val_paths.size(), " held-out scenes)");
        else
            log_info("step ", m_step, " validation loss ", v, ", log-space MSE ", m_val_mse_log, ", MSE/flat oracle ",
                     m_val_physics.value("val_mse_vs_flat", NAN), ", level ratio ", m_val_physics.value("val_level_ratio_geomean", NAN),
                     ", chroma error ", m_val_physics.value("val_chroma_error", NAN), " (", m_val_paths.size(), " held-out scenes)");
        const double score = m_cfg.head == "directional"            ? v   // the head's own loss
                             : m_cfg.select_by == "val_mse_log"       ? m_val_mse_log
                             : m_cfg.select_by == "val_mse_vs_flat" ? m_val_physics.value("val_mse_vs_flat", NAN)
                                                                    : v;
        if (std::isfinite(score) && score < m_best_val) {
            m_best_val = score;
            save(best);
        }
        if (m_cfg.keep_val_checkpoints) save(m_out + "/step-" + std::to_string(m_step) + ".ltmckpt");
    };
    // A fresh run validates its starting weights first (logged as step -1): with --start-at-prior
    // that is the prior's own score, the floor the network has to beat; best.ltmckpt starts there.
    if (m_step == 0 && end > 0) run_validation();
    while (m_step < end) {
        const TrainStepLog s = train_step();
        m_history.push_back(s);
        ++steps_since;
        if (!s.skipped) loss_since += s.loss;
        if (m_step % m_cfg.log_every == 0 || m_step == end) {
            const double dt = seconds_since(t_last);
            const double mean_loss = loss_since / double(steps_since);
            OrderedJson j = {{"step", s.step}, {"loss", mean_loss}, {"lr", s.lr}, {"grad_norm", s.grad_norm},
                             {"skipped", s.skipped}, {"steps_per_s", double(steps_since) / dt},
                             {"queries_per_s", double(steps_since * m_cfg.batch_queries * m_comm->world_size()) / dt}};
            log << j.dump() << "\n" << std::flush;
            log_info("step ", m_step, "/", m_cfg.steps, " loss ", mean_loss, " lr ", s.lr, " ", double(steps_since) / dt, " steps/s");
            t_last = std::chrono::steady_clock::now();
            steps_since = 0;
            loss_since = 0;
        }
        if (m_step % m_cfg.val_every == 0 || m_step == m_cfg.steps) run_validation();
        if (m_step % m_cfg.ckpt_every == 0 || m_step == end) save(last);
    }
    // No rank leaves (closing the store rank 0 serves) before rank 0's last checkpoint is written.
    m_comm->all_reduce_sum(std::vector<double>{0.0});
}

}  // namespace ltm
