// bench_scenes.h: the prior benches' SCENES argument as scenes — a seed range A:B of generated
// houses (GenConfig{}), or scene files and builtin:NAME, comma-separated, named as `ltm eval` names
// them (so the benches read and write the same reference cache entries).
#pragma once

#include <string>
#include <vector>

#include "ltm/eval/eval_setup.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/scene/scene_loader.h"
#include "scene_list.h"

namespace ltm::bench {

struct BenchScene {
    std::string name;   ///< "seed-N" for a generated house, else scene_labels' name
    std::string path;   ///< empty for a generated house
    uint64_t seed = 0;  ///< the house's seed (path empty)
};

/// "100000:100016" -> 16 houses; "a.pbrt,builtin:cornell-box" -> the two files.
inline std::vector<BenchScene> bench_scenes(const std::string &spec) {
    std::vector<BenchScene> out;
    if (is_seed_range(spec)) {
        const uint64_t lo = std::stoull(spec.substr(0, spec.find(':'))), hi = std::stoull(spec.substr(spec.find(':') + 1));
        for (uint64_t seed = lo; seed < hi; ++seed) out.push_back({"seed-" + std::to_string(seed), "", seed});
    } else {
        const std::vector<std::string> paths = split_commas(spec);
        const std::vector<std::string> labels = scene_labels(paths);   // as ltm eval names them
        for (size_t i = 0; i < paths.size(); ++i) out.push_back({labels[i], paths[i], 0});
    }
    return out;
}

/// The scene itself: the generated house or the loaded file.
inline Scene load_bench_scene(const BenchScene &s) {
    return s.path.empty() ? generate_indoor(GenConfig{}, s.seed).scene : load_scene(s.path);
}

}  // namespace ltm::bench
