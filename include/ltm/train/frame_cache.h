// frame_cache.h: the trainer's per-house preparation kept on disk (`ltm train --frame-cache DIR`).
//
// Before a house's first draw the trainer regenerates it, samples its scene points at the model's M
// (resample_points, extra point sets), groups them (FPS + kNN) and solves the transport prior for its
// frame — with the prior's rays, several seconds a house on 2 cores. A run over 256 houses and 2
// point sets paid ~6–7 s extra on each of its first 512 draws (session 33: 0.08–0.11 steps/s in the
// first epoch, 0.3 after), and every new run paid it again. The cache keeps what the draw uses (the
// points, their groups, the frame without the solve, the prior at the record's queries) in one
// safetensors file per (record, point set), so a later run on the same data starts at full speed.
//
// An entry is valid only for the same inputs: its name is a fingerprint of the record (file name,
// size, modification time), the point set, the model's keys that shape the points and the prior
// (scene_points, embedding, physics, prior_inputs) and the program itself (its size and modification
// time: a rebuild may change the prior, so it starts a new cache). Values are stored bit for bit, so
// a warm run trains exactly as a cold one. Files are written atomically; a malformed one is warned
// about and recomputed.
#pragma once

#include <optional>
#include <string>

#include <torch/torch.h>

#include "ltm/nn/model_config.h"

namespace ltm {

/// One (record, point set)'s prepared draw, CPU tensors.
struct FrameCacheEntry {
    torch::Tensor scene_points;     ///< [M, 12] f32
    torch::Tensor centers, groups;  ///< [m] i64, [m, k] i64 (SceneGeometry)
    torch::Tensor emission_scale;   ///< [3] f32, or undefined (records without one)
    torch::Tensor center, length, emission, output;   ///< the frame (SceneNormalization): [3], [], [3], [3]
    torch::Tensor point_prior;      ///< [M, 3] f32, or undefined (without prior_inputs)
    torch::Tensor point_traced;     ///< [M, 6] f32, or undefined (without traced_inputs)
    torch::Tensor query_scale;      ///< [nq, 3] or [3] f32: the prior at the record's queries
    torch::Tensor query_regathered; ///< [nq, 3] f32: the regathered prior there, or undefined (without traced_queries)
};

class FrameCache {
public:
    FrameCache() = default;   ///< disabled
    /// Creates `dir` when missing; throws ltm::Error when it cannot.
    explicit FrameCache(const std::string &dir);
    bool enabled() const { return !m_dir.empty(); }
    /// The entry's file for record `record_path`, point set `set`, under model `cfg` (header).
    std::string path_for(const ModelConfig &cfg, const std::string &record_path, int set) const;
    /// The entry, or nothing when the file is absent, malformed or not the prior at the record's
    /// n_queries queries (then with one warning).
    /// traced: the model has traced inputs, so an entry without them is a miss; traced_queries: the
    /// same for the regathered prior at the queries.
    std::optional<FrameCacheEntry> load(const std::string &path, int64_t n_queries, bool traced = false, bool traced_queries = false) const;
    /// Writes the entry atomically.
    void store(const std::string &path, const FrameCacheEntry &entry) const;

private:
    std::string m_dir;
    std::string m_program;   ///< the running program's identity (size, modification time)
};

}  // namespace ltm
