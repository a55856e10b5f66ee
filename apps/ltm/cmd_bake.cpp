// cmd_bake.cpp: `ltm bake <scene> --points DIR --spp 1024 --max-depth 5 [--shard i/N] -o OUT`.
// Each shard writes OUT/shard-i-of-N.safetensors atomically and is skipped when already done;
// the run that completes the set merges them into OUT/irradiance.safetensors (E_direct [N,3],
// E_indirect [N,3], optionally L_in [N,R²,3]) and OUT/irradiance.ply (points + irradiance).
#include <filesystem>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "ltm/core/file_util.h"
#include "ltm/core/json_util.h"
#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/points/ply_io.h"
#include "ltm/points/safetensors.h"
#include "ltm/render/bake.h"
#include "ltm/scene/scene_loader.h"

namespace fs = std::filesystem;

namespace ltm::cli {

namespace {
struct BakeArgs {
    std::string scene, points, output, shard;
    BakeSettings settings;
};

// Everything that determines the numbers; a shard baked with other settings is not reused.
std::string settings_json(const BakeSettings &s, const Scene &scene, int64_t n_points) {
    OrderedJson j;
    j["format"] = "ltm-bake";
    j["version"] = 1;
    j["scene"] = scene.name;
    j["n_points"] = n_points;
    j["spp"] = s.spp;
    j["max_depth"] = s.max_depth;
    j["seed"] = s.seed;
    j["bins"] = s.bins;
    if (s.bins) j["bin_resolution"] = s.bin_resolution, j["bin_spp"] = s.bin_spp;
    j["depth_convention"] = "max_depth = scattering events after the query point";
    return j.dump();
}

void write_vec3s(SafetensorsFile &f, const std::string &name, const std::vector<Vec3f> &v, int64_t rows, int64_t per_row) {
    std::vector<int64_t> shape = {rows, 3};
    if (per_row > 1) shape = {rows, per_row, 3};
    f.tensors[name] = make_f32_tensor(shape, v.empty() ? nullptr : &v[0].x);
}

// If every shard of `count` exists, concatenate them into the merged outputs.
void merge_if_complete(const std::string &out, int count, const std::string &settings, const PointSet &query,
                       const BakeSettings &s) {
    for (int i = 0; i < count; ++i)
        if (!fs::exists(shard_path(out, {i, count}))) return;
    const int64_t n = int64_t(query.size());
    const int nb = s.bin_resolution * s.bin_resolution;
    std::vector<float> direct, indirect, bins;
    for (int i = 0; i < count; ++i) {
        const std::string path = shard_path(out, {i, count});
        const SafetensorsFile f = read_safetensors(path);
        const int64_t rows = Shard{i, count}.end(n) - Shard{i, count}.begin(n);
        auto append = [&](std::vector<float> &dst, const std::string &name, std::vector<int64_t> shape) {
            const auto v = f.require(name, "F32", shape, path).as_f32(path);
            dst.insert(dst.end(), v.begin(), v.end());
        };
        append(direct, "E_direct", {rows, 3});
        append(indirect, "E_indirect", {rows, 3});
        if (s.bins) append(bins, "L_in", {rows, nb, 3});
    }
    SafetensorsFile merged;
    merged.metadata["settings"] = settings;
    merged.tensors["E_direct"] = make_f32_tensor({n, 3}, direct.data());
    merged.tensors["E_indirect"] = make_f32_tensor({n, 3}, indirect.data());
    if (s.bins) merged.tensors["L_in"] = make_f32_tensor({n, nb, 3}, bins.data());
    write_safetensors(merged_path(out), merged);

    std::vector<std::string> cols = query_point_columns();
    for (const char *c : {"direct_r", "direct_g", "direct_b", "irradiance_r", "irradiance_g", "irradiance_b"}) cols.push_back(c);
    PointSet ply(cols, size_t(n));
    for (size_t i = 0; i < size_t(n); ++i) {
        for (size_t c = 0; c < 9; ++c) ply.at(i, c) = query.at(i, c);
        for (size_t c = 0; c < 3; ++c) ply.at(i, 9 + c) = direct[3 * i + c], ply.at(i, 12 + c) = indirect[3 * i + c];
    }
    PlyWriteOptions opt;
    opt.comment = "ltm bake: E_direct as direct_*, E_indirect (E+) as irradiance_*";
    write_ply(out + "/irradiance.ply", ply, opt);
    log_info("all ", count, " shard(s) done: merged into ", merged_path(out), " and ", out, "/irradiance.ply");
}
void declare(CLI::App &sub, BakeArgs &a) {
    BakeSettings &s = a.settings;
    add_scene_argument(sub, a.scene);
    sub.add_option("--points", a.points, "Directory written by `ltm sample` (query_points.ply)")->required();
    sub.add_option("--spp", s.spp, "Stratified samples per point")->capture_default_str();
    sub.add_option("--max-depth", s.max_depth, "Scattering events after the point")->capture_default_str();
    sub.add_option("--shard", a.shard, "i/N: bake only the i-th of N equal parts (default: SLURM_ARRAY_TASK_ID/COUNT, else 0/1)");
    sub.add_flag("--bins", s.bins, "Also bake incident radiance over hemisphere bins (L_in)");
    sub.add_option("--bin-res", s.bin_resolution, "Bins per side (R×R)")->capture_default_str();
    sub.add_option("--bin-spp", s.bin_spp, "Samples per bin")->capture_default_str();
    add_output_option(sub, a.output, "Output directory");
}

void run(const BakeArgs &a, const CommonOptions &common) {
    BakeSettings s = a.settings;
    s.seed = common.seed;
    if (s.spp <= 0) LTM_THROW("--spp ", s.spp, ": must be > 0");
    if (s.max_depth < 1) LTM_THROW("--max-depth ", s.max_depth, ": must be >= 1");
    if (s.bins && (s.bin_resolution <= 0 || s.bin_resolution > 256 || s.bin_spp <= 0))
        LTM_THROW("--bin-res/--bin-spp: need 1..256 bins per side and > 0 samples per bin");
    const Shard shard = shard_option(a.shard);
    const Scene scene = load_scene(a.scene);
    const std::string ply_path = a.points + "/query_points.ply";
    const PointSet query = read_ply(ply_path).select(query_point_columns(), ply_path);
    const std::string meta_path = a.points + "/sample.json";
    if (fs::exists(meta_path)) {
        const Json meta = parse_json_file(meta_path);
        if (meta.contains("scene_name") && meta["scene_name"] != scene.name)
            LTM_THROW(meta_path, ": points were sampled on scene '", meta["scene_name"].get<std::string>(),
                      "', not '", scene.name, "'");
    }
    const EmbreeAccel accel(scene);
    check_points_match_scene(accel, query, ply_path);
    const int64_t n = int64_t(query.size());
    const std::string settings = settings_json(s, scene, n);
    create_directories(a.output);
    const std::string path = shard_path(a.output, shard);
    if (fs::exists(path)) {
        const SafetensorsFile done = read_safetensors(path);
        const auto it = done.metadata.find("settings");
        if (it == done.metadata.end() || it->second != settings)
            LTM_THROW(path, ": exists with different bake settings; remove it or choose another -o");
        log_info(path, " already baked; skipping");
    } else {
        PathTracerConfig cfg;
        cfg.seed = s.seed;
        cfg.max_depth = s.max_depth;
        const PathTracer pt(accel, cfg);
        const int64_t b = shard.begin(n), e = shard.end(n);
        log_info("baking points ", b, "..", e, " of ", n, " (shard ", shard.index, "/", shard.count, ") at ", s.spp,
                 " spp, max depth ", s.max_depth);
        const BakedPoints baked = bake_points(pt, query, b, e, s);
        SafetensorsFile f;
        f.metadata["settings"] = settings;
        f.metadata["begin"] = std::to_string(b);
        f.metadata["end"] = std::to_string(e);
        write_vec3s(f, "E_direct", baked.direct, e - b, 1);
        write_vec3s(f, "E_indirect", baked.indirect, e - b, 1);
        if (s.bins) write_vec3s(f, "L_in", baked.bins, e - b, s.bin_resolution * s.bin_resolution);
        write_safetensors(path, f);
        log_info("baked ", e - b, " points in ", format_duration(baked.seconds), ": ",
                 format_count(double(e - b) / baked.seconds), " points/s, ",
                 format_count(double(baked.rays) / baked.seconds), " rays/s -> ", path);
    }
    merge_if_complete(a.output, shard.count, settings, query, s);
}
}  // namespace

Command make_bake_command() {
    return make_command(
        "bake", "Path-trace ground-truth E_direct and E_indirect at query points (sharded, resumable)",
        declare, run);
}

}  // namespace ltm::cli
