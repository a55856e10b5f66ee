// bake.h: ground-truth irradiance for query points (the dataset targets), sharded and resumable.
// Shard i of N covers points [i·n/N, (i+1)·n/N); each shard is one atomic safetensors file, and
// the merged result is byte-identical whatever the sharding (every point's estimate depends only
// on (seed, scene id, point index, sample index)).
#pragma once

#include <cstdint>

#include <string>
#include <vector>

#include "ltm/points/point_set.h"
#include "ltm/render/path_tracer.h"

namespace ltm {

struct BakeSettings {
    int spp = 1024;            ///< stratified samples per point (paper: 1024)
    int max_depth = 5;         ///< scattering events after the point (paper: 5)
    uint64_t seed = 0;
    bool bins = false;         ///< also bake L_in over resolution² hemisphere bins
    int bin_resolution = 32;   ///< paper: 32×32
    int bin_spp = 64;          ///< samples per bin (paper: 64)
    bool bins_indirect = false;   ///< bins hold L_i⁺ (no emitter seen directly; integrates to E⁺)
    bool progress = true;      ///< a progress bar (off inside `ltm dataset build`, which has its own)
};

struct Shard {
    int index = 0, count = 1;
    /// Parses "i/N" (0 ≤ i < N); throws on anything else.
    static Shard parse(const std::string &s);
    int64_t begin(int64_t n) const { return n * index / count; }
    int64_t end(int64_t n) const { return n * (index + 1) / count; }
};

struct BakedPoints {
    std::vector<Vec3f> direct, indirect;   ///< [n] each
    std::vector<Vec3f> bins;               ///< [n, R²] if baked
    uint64_t rays = 0;
    double seconds = 0;
};

/// Estimates E_direct, E⁺ (and bins) for points [begin, end) of `query` ([N, 9] layout).
BakedPoints bake_points(const PathTracer &pt, const PointSet &query, int64_t begin, int64_t end,
                        const BakeSettings &s);

/// Throws "where: ..." if the points do not lie on the scene's surfaces (checked on a sample of
/// points by casting a short ray back along -n) or lie outside its bounds.
void check_points_match_scene(const EmbreeAccel &accel, const PointSet &query, const std::string &where);

/// File names inside a bake output directory.
std::string shard_path(const std::string &dir, const Shard &shard);
std::string merged_path(const std::string &dir);

}  // namespace ltm
