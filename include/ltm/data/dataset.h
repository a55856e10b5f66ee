// dataset.h: presets that say how records are made (points/scene_record.h is the record itself),
// and building them: generate → sample → bake, one scene after another, resumable. Torch-free, so
// `ltm dataset build` runs in every build, torch or not.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ltm/core/config_fields.h"
#include "ltm/core/json_util.h"
#include "ltm/core/math.h"
#include "ltm/points/scene_record.h"
#include "ltm/scene/scene.h"

namespace ltm {

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
    /// What the bins hold: "incident" (emission + scattered light: the paper's L_in) or
    /// "indirect" (L_in⁺, light scattered at least once: what the directional head predicts
    /// beside exact direct lighting; its cosine integral is E⁺).
    std::string bin_radiance = "incident";

    /// The keys, limits and docs of the fields above (core/config_fields.h; docs/config.md).
    static const ConfigFields<DataPreset> &fields();
    static DataPreset from_json(const Json &j, const std::string &where);
    static DataPreset from_file(const std::string &path);
    OrderedJson to_json() const;
};

struct BuildOptions {
    DataPreset preset;
    std::vector<uint64_t> seeds;   ///< scenes to build (already restricted to this shard)
    bool test = false;             ///< use preset.test_spp
    std::string out_dir;
};

/// Builds every missing record (skips existing files), then rewrites out_dir/manifest.json
/// from the records present. Progress with ETA on stderr.
void build_dataset(const BuildOptions &opt);

/// The scene a record was baked from, regenerated from its metadata (the preset's generator config,
/// read from its path as recorded, relative to the working directory; the seed). Throws
/// ltm::Error naming the record when the generator version or the scene's name differs; an edited
/// config file is not detected here (check_points_match_scene in render/bake.h catches a moved
/// surface).
Scene regenerate_scene(const SceneRecord &record);

/// Adds `emission_scale` to the records of `dir` built before it existed: regenerates each scene
/// from its metadata (preset, seed; the generator version must match) and computes S = Φ/A as a
/// build would. Points and labels are untouched; files are rewritten atomically. Returns the
/// number of records upgraded.
int64_t upgrade_dataset(const std::string &dir);

}  // namespace ltm
