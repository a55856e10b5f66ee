// cmd_sample.cpp: `ltm sample <scene> --scene-points M --query-points N --seed S -o DIR`.
// Writes DIR/scene_points.ply [M,12], DIR/query_points.ply [N,9] and DIR/sample.json; all three
// are committed together at the end, so a failure leaves none of them.
#include <chrono>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "ltm/core/file_util.h"
#include "ltm/core/json_util.h"
#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/points/ply_io.h"
#include "ltm/points/surface_sampler.h"
#include "ltm/render/enclosure.h"
#include "ltm/render/scene_points.h"
#include "ltm/scene/scene_loader.h"

namespace ltm::cli {

namespace {
struct SampleArgs {
    std::string scene, output;
    int64_t scene_points = 8192, query_points = 65536;
    bool exclude_enclosed = true, ascii = false;   // as the dataset and the neural renderer
};

void check_count(int64_t n, const char *flag) {
    if (n <= 0) LTM_THROW(flag, " ", n, ": must be > 0");
    if (n > k_max_sample_count) LTM_THROW(flag, " ", n, ": too large (at most ", k_max_sample_count, ")");
}
void declare(CLI::App &sub, SampleArgs &a) {
    add_scene_argument(sub, a.scene);
    sub.add_option("-M,--scene-points", a.scene_points, "Scene points (p, n, albedo, emission)")->capture_default_str();
    sub.add_option("-N,--query-points", a.query_points, "Query points (p, n, albedo)")->capture_default_str();
    sub.add_flag("--exclude-enclosed,!--keep-enclosed", a.exclude_enclosed,
                 "Drop points inside closed solids (floor under carpets/furniture; the default, as the dataset "
                 "and the neural renderer do); --keep-enclosed keeps them; see docs/formats.md");
    sub.add_flag("--ascii", a.ascii, "Write ASCII PLY instead of binary little-endian");
    add_output_option(sub, a.output, "Output directory");
}

void run(const SampleArgs &a, const CommonOptions &common) {
    check_count(a.scene_points, "--scene-points");
    check_count(a.query_points, "--query-points");
    const Scene scene = load_scene(a.scene);
    const auto t0 = std::chrono::steady_clock::now();
    // The scene points come from the one recipe the dataset and the neural renderer use
    // (render/scene_points.h), so a model fed these PLY files sees what it was trained on.
    const EmbreeAccel accel(scene);
    const PointSet scene_pts = sample_scene_points(accel, a.scene_points, common.seed, a.exclude_enclosed).points;
    SampleFilter filter;
    if (a.exclude_enclosed) filter = enclosed_filter(accel);
    const PointSet query_pts = to_query_points(
        sample_surface(scene, a.query_points, common.seed, SampleStream::query_points, filter));
    const double secs = seconds_since(t0);

    OrderedJson meta;
    meta["format"] = "ltm-samples";
    meta["version"] = 1;
    meta["scene"] = a.scene;
    meta["scene_name"] = scene.name;
    meta["seed"] = common.seed;
    meta["scene_points"] = a.scene_points;
    meta["query_points"] = a.query_points;
    meta["exclude_enclosed"] = a.exclude_enclosed;
    meta["scene_point_columns"] = scene_point_columns();
    meta["query_point_columns"] = query_point_columns();
    meta["surface_area_m2"] = scene.total_area();

    create_directories(a.output);
    PlyWriteOptions opt;
    opt.binary = !a.ascii;
    opt.comment = "ltm sample seed " + std::to_string(common.seed) + " scene " + scene.name;
    AtomicFile f_scene(a.output + "/scene_points.ply"), f_query(a.output + "/query_points.ply");
    AtomicFile f_meta(a.output + "/sample.json");
    write_ply(f_scene.stream(), scene_pts, opt);
    write_ply(f_query.stream(), query_pts, opt);
    f_meta.stream() << dump_json_compact(meta);
    f_scene.commit();
    f_query.commit();
    f_meta.commit();
    log_info("sampled ", a.scene_points, " scene points and ", a.query_points, " query points on ",
             scene.total_area(), " m² in ", secs, " s -> ", a.output, "/");
}
}  // namespace

Command make_sample_command() {
    return make_command("sample", "Sample scene points and query points on a scene's surfaces (PLY)", declare, run);
}

}  // namespace ltm::cli
