// scene_record.h: one safetensors record per scene (ARCHITECTURE.md §4): scene_points [M, 12],
// query_points [N, 9], E_direct [N, 3], E_indirect [N, 3], emission_scale [3] (S = Φ/A of the
// sampled surface; absent in records built before it existed), L_in [N, R², 3] (glossy presets
// only) + JSON metadata; writing, reading with checks, listing a dataset's records.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ltm/core/json_util.h"
#include "ltm/core/math.h"
#include "ltm/points/point_set.h"

namespace ltm {

inline constexpr int k_record_format_version = 1;

/// One scene's record in memory (row-major float tables).
struct SceneRecord {
    std::string path;
    uint64_t seed = 0;
    PointSet scene_points;            ///< [M, 12] scene_point_columns()
    PointSet query_points;            ///< [N, 9]  query_point_columns()
    std::vector<float> e_direct;      ///< [N * 3]
    std::vector<float> e_indirect;    ///< [N * 3]
    std::optional<Vec3f> emission_scale;   ///< S = Φ/A (render/scene_points.h); nullopt in older records
    int bin_resolution = 0;           ///< R; 0 = no L_in
    std::vector<float> l_in;          ///< [N * R² * 3] incident radiance per bin (bin i·R + j), if R > 0
    OrderedJson metadata;             ///< format_version, preset, generator, seed, spp, timings, ...
};

std::string record_file_name(uint64_t seed);
void write_record(const std::string &path, const SceneRecord &rec);
/// Reads and checks a record (version, shapes, finiteness); errors name the file.
SceneRecord read_record(const std::string &path);
/// Record files of a dataset directory, sorted by seed.
std::vector<std::string> list_records(const std::string &dir);
/// Record files of several dataset directories (e.g. presets baked at different query counts),
/// merged and sorted by seed; a seed present in two directories is an error naming both files.
std::vector<std::string> list_records(const std::vector<std::string> &dirs);

}  // namespace ltm
