// dataset.h: one safetensors record per scene (ARCHITECTURE.md §4): scene_points [M, 12],
// query_points [N, 9], E_direct [N, 3], E_indirect [N, 3], emission_scale [3] (S = Φ/A of the
// sampled surface; absent in records built before it existed) + JSON metadata; presets that say how
// records are made; building them (generate → sample → bake), and reading them back.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ltm/core/config_fields.h"
#include "ltm/core/json_util.h"
#include "ltm/core/math.h"
#include "ltm/points/point_set.h"

namespace ltm {

inline constexpr int k_record_format_version = 1;

/// How records are made (configs/data/<name>.json).
struct DataPreset {
    std::string name = "cpu";     ///< ci | cpu | paper (informational; checked against the model)
    int scene_points = 8192;      ///< M
    int query_points = 65536;     ///< N
    int spp = 256;                ///< samples per query point for training records (paper: 1024)
    int test_spp = 4096;          ///< samples per point with --test (held-out references)
    int max_depth = 5;            ///< scattering events after the point (paper: 5)
    bool exclude_enclosed = true; ///< drop points inside closed solids (docs/formats.md)
    /// Share of the query points drawn through the scene's cameras (render/view_samples.h) rather
    /// than area-uniformly: 0 = all area-uniform (the paper), 1 = all where a camera looks.
    float camera_queries = 0.f;
    std::string generator;        ///< generator config file ("" = built-in defaults)
    /// Paper §7's directional ground truth: incident radiance L_in over R×R hemisphere bins per
    /// query point (render/hemisphere_bins.h), R = bin_resolution; 0 = none (irradiance only).
    int bin_resolution = 0;
    int bin_spp = 64;             ///< samples per bin (paper: 64)

    /// The keys, limits and docs of the fields above (core/config_fields.h; docs/config.md).
    static const ConfigFields<DataPreset> &fields();
    static DataPreset from_json(const Json &j, const std::string &where);
    static DataPreset from_file(const std::string &path);
    OrderedJson to_json() const;
};

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

struct BuildOptions {
    DataPreset preset;
    std::vector<uint64_t> seeds;   ///< scenes to build (already restricted to this shard)
    bool test = false;             ///< use preset.test_spp
    std::string out_dir;
};

/// Builds every missing record (skips existing files), then rewrites out_dir/manifest.json
/// from the records present. Progress with ETA on stderr.
void build_dataset(const BuildOptions &opt);

/// Adds `emission_scale` to the records of `dir` built before it existed: regenerates each scene
/// from its metadata (preset, seed; the generator version must match) and computes S = Φ/A as a
/// build would. Points and labels are untouched; files are rewritten atomically. Returns the
/// number of records upgraded.
int64_t upgrade_dataset(const std::string &dir);

}  // namespace ltm
