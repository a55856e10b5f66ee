// cmd_dataset.cpp: `ltm dataset build --config configs/data/cpu.json --seed-range A:B [--scenes N]
// [--shard i/N] [--test] -o DIR`: generate → sample → bake, one safetensors record per scene;
// `ltm dataset upgrade -o DIR` adds the exact emission scale to records built before it.

#include <CLI/CLI.hpp>

#include "cli.h"
#include "ltm/core/error.h"
#include "ltm/render/bake.h"
#include "ltm/data/dataset.h"

namespace ltm::cli {

namespace {
struct DatasetArgs {
    std::string action, config, seed_range, output, shard;
    int scenes = -1;
    bool test = false;
};

void declare(CLI::App &sub, DatasetArgs &a) {
    sub.add_option("action", a.action, "build | upgrade (add emission_scale to older records of -o DIR)")
        ->required()
        ->check(CLI::IsMember({"build", "upgrade"}));
    sub.add_option("--config", a.config, "Data preset (configs/data/{ci,cpu,paper}.json); required by build");
    sub.add_option("--seed-range", a.seed_range, "Generator seeds A:B (A .. B-1); keep test seeds disjoint; required by build");
    sub.add_option("--scenes", a.scenes, "Build only the first N seeds of the range");
    sub.add_option("--shard", a.shard, "i/N: build every N-th scene starting at i (default: SLURM array, else 0/1)");
    sub.add_flag("--test", a.test, "Held-out references: bake with the preset's test_spp");
    add_output_option(sub, a.output, "Dataset directory");
}

void run(const DatasetArgs &a, const CommonOptions &) {
    if (a.action == "upgrade") {
        upgrade_dataset(a.output);
        return;
    }
    if (a.config.empty() || a.seed_range.empty()) LTM_THROW("dataset build: --config and --seed-range are required");
    BuildOptions opt;
    opt.preset = DataPreset::from_file(a.config);
    const auto [lo, hi] = parse_seed_range(a.seed_range, "--seed-range");
    uint64_t end = hi;
    if (a.scenes >= 0) {
        if (a.scenes == 0) LTM_THROW("--scenes 0: must be > 0");
        end = std::min<uint64_t>(hi, lo + uint64_t(a.scenes));
    }
    const Shard shard = shard_option(a.shard);
    for (uint64_t s = lo; s < end; ++s)
        if (int((s - lo) % uint64_t(shard.count)) == shard.index) opt.seeds.push_back(s);
    opt.test = a.test;
    opt.out_dir = a.output;
    build_dataset(opt);
}
}  // namespace

Command make_dataset_command() {
    return make_command(
        "dataset", "Build a training dataset: generate, sample and bake one record per scene (resumable, shardable)",
        declare, run);
}

}  // namespace ltm::cli
