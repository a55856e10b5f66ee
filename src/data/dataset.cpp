// dataset.cpp: records = safetensors files; building runs the same library calls as
// `ltm generate`, `ltm sample --exclude-enclosed` and `ltm bake`.
#include "ltm/data/dataset.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/points/safetensors.h"
#include "ltm/points/surface_sampler.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/render/bake.h"
#include "ltm/render/enclosure.h"
#include "ltm/render/scene_points.h"
#include "ltm/render/view_samples.h"

namespace fs = std::filesystem;

namespace ltm {

const ConfigFields<DataPreset> &DataPreset::fields() {
    using P = DataPreset;
    const double n_max = double(k_max_sample_count);
    static const ConfigFields<P> f =
        ConfigFields<P>()
            .field("name", &P::name, "preset name (informational; written into every record)")
            .field("scene_points", &P::scene_points, "M, the model's input points per scene (must match the model)", between(16, n_max))
            .field("query_points", &P::query_points, "N, labelled query points per scene", between(1, n_max))
            .field("spp", &P::spp, "path-traced samples per query point of training records (paper: 1024)", at_least(1))
            .field("test_spp", &P::test_spp, "samples per point with --test (held-out references)", at_least(1))
            .field("max_depth", &P::max_depth, "scattering events after the point (paper: 5)", at_least(1))
            .field("exclude_enclosed", &P::exclude_enclosed, "drop points inside closed solids (docs/formats.md)")
            .field("generator", &P::generator, "generator config file (\"\" = built-in defaults)")
            .field("camera_queries", &P::camera_queries,
                   "share of the query points drawn through the scene's cameras at random raster positions (render/view_samples.h); 0 = area-uniform, the paper's",
                   between(0, 1))
            .field("bin_resolution", &P::bin_resolution,
                   "R: also bake incident radiance L_in over R×R hemisphere bins per query point (`L_in` [N, R², 3]; paper §7: 32); 0 = none",
                   between(0, 256))
            .omit_default()
            .field("bin_spp", &P::bin_spp, "samples per bin (paper: 64)", between(1, 1 << 20))
            .omit_default()
            .field("bin_radiance", &P::bin_radiance, "what the bins hold: emission + scattered light (the paper's L_in), or only scattered light (L_in⁺, integrates to E⁺)", {}, {"incident", "indirect"})
            .omit_default();
    return f;
}

DataPreset DataPreset::from_json(const Json &j, const std::string &where) {
    return fields().read(j, where, DataPreset{}, [](JsonObject &o, DataPreset &p) {
        // L_in holds N·R² radiances per record (and the bake as many in memory).
        if (double(p.query_points) * double(p.bin_resolution) * double(p.bin_resolution) > double(k_max_sample_count))
            LTM_THROW(o.where("bin_resolution"), ": ", p.query_points, " query points × ", p.bin_resolution, "² bins exceed ",
                      k_max_sample_count, " radiances per record");
    });
}

DataPreset DataPreset::from_file(const std::string &path) { return from_json(parse_json_file(path), path); }

OrderedJson DataPreset::to_json() const { return fields().write(*this); }

namespace {
/// The preset's query points: round(camera_queries·N) seen through the cameras, the rest
/// area-uniform (independent sample streams), view points last.
std::vector<SurfaceSample> sample_queries(const EmbreeAccel &accel, const DataPreset &p, uint64_t seed, const SampleFilter &filter) {
    const int64_t n_view = std::llround(double(p.camera_queries) * p.query_points), n_area = p.query_points - n_view;
    std::vector<SurfaceSample> q;
    if (n_area > 0) q = sample_surface(accel.scene(), n_area, seed, SampleStream::query_points, filter);
    const std::vector<SurfaceSample> v = sample_view_points(accel, n_view, seed);
    q.insert(q.end(), v.begin(), v.end());
    return q;
}

SceneRecord make_record(const DataPreset &p, const GenConfig &gen, uint64_t seed, bool test) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    const GeneratedScene g = generate_indoor(gen, seed);
    const auto t1 = clock::now();
    const EmbreeAccel accel(g.scene);
    SampleFilter filter;
    if (p.exclude_enclosed) filter = enclosed_filter(accel);
    SceneRecord r;
    r.seed = seed;
    ScenePoints sampled = sample_scene_points(accel, p.scene_points, seed, p.exclude_enclosed);
    r.scene_points = std::move(sampled.points);
    r.emission_scale = sampled.emission_scale;
    r.query_points = to_query_points(sample_queries(accel, p, seed, filter));
    const auto t2 = clock::now();
    BakeSettings bs;
    bs.spp = test ? p.test_spp : p.spp;
    bs.max_depth = p.max_depth;
    bs.seed = seed;
    bs.bins = p.bin_resolution > 0;
    bs.bin_resolution = p.bin_resolution;
    bs.bin_spp = p.bin_spp;
    bs.bins_indirect = p.bin_radiance == "indirect";
    bs.progress = false;   // per-scene bake bars would drown the dataset bar
    PathTracerConfig pc;
    pc.seed = seed;
    pc.max_depth = p.max_depth;
    const PathTracer pt(accel, pc);
    const BakedPoints b = bake_points(pt, r.query_points, 0, int64_t(r.query_points.size()), bs);
    for (size_t i = 0; i < b.direct.size(); ++i)
        for (int c = 0; c < 3; ++c) r.e_direct.push_back(b.direct[i][c]), r.e_indirect.push_back(b.indirect[i][c]);
    if (bs.bins) {
        r.bin_resolution = p.bin_resolution;
        r.l_in.reserve(b.bins.size() * 3);
        for (const Vec3f &l : b.bins)
            for (int c = 0; c < 3; ++c) r.l_in.push_back(l[c]);
    }
    const auto t3 = clock::now();
    auto secs = [](auto a, auto b2) { return std::chrono::duration<double>(b2 - a).count(); };
    r.metadata = {{"format", "ltm-record"},
                  {"format_version", k_record_format_version},
                  {"preset", p.to_json()},
                  {"test", test},
                  {"scene", g.scene.name},
                  {"seed", seed},
                  {"generator", "ltm-indoor"},
                  {"generator_version", k_indoor_generator_version},
                  {"spp", bs.spp},
                  {"max_depth", p.max_depth},
                  {"surface_area_m2", g.scene.total_area()},
                  {"n_rooms", g.rooms.size()},
                  {"ajar", g.ajar},
                  {"timings_s", {{"generate", secs(t0, t1)}, {"sample", secs(t1, t2)}, {"bake", secs(t2, t3)}}},
                  {"rays", b.rays}};
    return r;
}
}  // namespace

void build_dataset(const BuildOptions &opt) {
    create_directories(opt.out_dir);
    const GenConfig gen = opt.preset.generator.empty() ? GenConfig{}
                                                        : GenConfig::from_json(parse_json_file(opt.preset.generator), opt.preset.generator);
    std::vector<uint64_t> todo;
    for (uint64_t s : opt.seeds)
        if (!fs::exists(opt.out_dir + "/" + record_file_name(s))) todo.push_back(s);
    log_info("dataset: ", opt.seeds.size() - todo.size(), " of ", opt.seeds.size(), " records present, building ", todo.size());
    // Nothing to build: no progress bar (a "0/1 scenes" line would say something is missing).
    std::optional<Progress> progress;
    if (!todo.empty()) progress.emplace("dataset", todo.size(), "scenes");
    for (uint64_t seed : todo) {
        const SceneRecord r = make_record(opt.preset, gen, seed, opt.test);
        write_record(opt.out_dir + "/" + record_file_name(seed), r);
        progress->add(1);
    }
    if (progress) progress->finish();
    // The manifest describes what is on disk (robust to shards finishing in any order).
    OrderedJson manifest;
    manifest["format"] = "ltm-dataset";
    manifest["format_version"] = k_record_format_version;
    manifest["preset"] = opt.preset.to_json();
    manifest["records"] = OrderedJson::array();
    for (const auto &path : list_records(opt.out_dir)) manifest["records"].push_back(fs::path(path).filename().string());
    write_file_atomic(opt.out_dir + "/manifest.json", dump_json_compact(manifest));
}

Scene regenerate_scene(const SceneRecord &r) {
    const std::string &path = r.path;
    const DataPreset p = DataPreset::from_json(r.metadata.at("preset"), path + " (preset)");
    if (r.metadata.value("generator_version", -1) != k_indoor_generator_version)
        LTM_THROW(path, ": generator version ", r.metadata.value("generator_version", -1), ", this build generates ",
                  k_indoor_generator_version, ": the scene cannot be regenerated");
    const GenConfig gen = p.generator.empty() ? GenConfig{} : GenConfig::from_json(parse_json_file(p.generator), p.generator);
    GeneratedScene g = generate_indoor(gen, r.seed);
    if (g.scene.name != r.metadata.value("scene", std::string()))
        LTM_THROW(path, ": regenerated scene '", g.scene.name, "' is not the record's '", r.metadata.value("scene", std::string()), "'");
    return std::move(g.scene);
}

int64_t upgrade_dataset(const std::string &dir) {
    std::vector<std::string> todo;
    for (const auto &path : list_records(dir))
        if (!read_record(path).emission_scale) todo.push_back(path);
    log_info("dataset upgrade: ", todo.size(), " records without emission_scale in ", dir);
    if (todo.empty()) return 0;
    Progress progress("upgrade", todo.size(), "records");
    for (const auto &path : todo) {
        SceneRecord r = read_record(path);
        const DataPreset p = DataPreset::from_json(r.metadata.at("preset"), path + " (preset)");
        const Scene scene = regenerate_scene(r);
        const EmbreeAccel accel(scene);
        r.emission_scale = sample_scene_points(accel, p.scene_points, r.seed, p.exclude_enclosed).emission_scale;
        write_record(path, r);
        progress.add(1);
    }
    progress.finish();
    return int64_t(todo.size());
}

}  // namespace ltm
