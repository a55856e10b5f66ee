// small_dataset.h: a tiny dataset of ci-preset records built once per test program and removed
// when it exits (the training tests share theirs).
#pragma once

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "ltm/core/log.h"
#include "ltm/data/dataset.h"
#include "test_util.h"

namespace ltm::test {

/// Builds records of `seeds` (ci preset with query_points and spp replaced) into a temporary
/// directory named `name`, once; later calls return the same directory.
inline std::string build_small_dataset(const std::string &name, const std::vector<uint64_t> &seeds, int query_points, int spp) {
    const std::string d = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
    BuildOptions opt;
    opt.preset = DataPreset::from_file(source_path("configs/data/ci.json"));
    opt.preset.query_points = query_points;
    opt.preset.spp = spp;
    opt.seeds = seeds;
    opt.out_dir = d;
    set_log_level(LogLevel::quiet);
    build_dataset(opt);
    return d;
}

/// Removes a directory when the test program exits.
struct RemoveAtExit {
    std::string path;
    ~RemoveAtExit() { std::filesystem::remove_all(path); }
};

}  // namespace ltm::test
