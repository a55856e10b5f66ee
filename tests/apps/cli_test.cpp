// cli_test.cpp: end-to-end runs of the CLI through run_cli(), as a user would type them.
#include <gtest/gtest.h>

#include <filesystem>

#include "cli.h"
#include "ltm/core/exr.h"
#include "ltm/core/file_util.h"
#include "ltm/core/image.h"
#include "ltm/points/ply_io.h"
#include "ltm/render/embree_accel.h"
#include "ltm/render/scene_points.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/scene_json.h"
#include "ltm/scene/scene_loader.h"
#include "test_util.h"
#ifdef LTM_WITH_TORCH
#include "ltm/nn/checkpoint.h"
#endif

using namespace ltm;

namespace {
struct Result {
    int code;
    std::string out, err;
};
Result run(const std::vector<std::string> &args) {
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    const int code = cli::run_cli(args);
    return {code, testing::internal::GetCapturedStdout(), testing::internal::GetCapturedStderr()};
}
}  // namespace

TEST(Cli, GenerateSamplePreviewSmoke) {
    test::TempDir dir;
    const std::string scene = dir.path("s.json"), pts = dir.path("pts"), png = dir.path("p.png");
    auto r = run({"generate", "--seed", "7", "-o", scene, "--quiet"});
    ASSERT_EQ(r.code, 0) << r.err;
    r = run({"sample", scene, "--scene-points", "2000", "--query-points", "3000", "--seed", "1", "-o", pts,
             "--threads", "2"});
    ASSERT_EQ(r.code, 0) << r.err;
    const PointSet sampled = read_ply(pts + "/scene_points.ply").select(scene_point_columns(), "");
    EXPECT_EQ(sampled.size(), 2000u);
    // The renderer's and the dataset's scene points (render/scene_points.h), exclusion on by default.
    const Scene loaded = load_scene(scene);   // EmbreeAccel keeps a reference to it
    const EmbreeAccel accel(loaded);
    EXPECT_EQ(sampled.values, sample_scene_points(accel, 2000, 1, true).points.values);
    EXPECT_EQ(read_ply(pts + "/query_points.ply").select(query_point_columns(), "").size(), 3000u);
    EXPECT_NE(read_file(pts + "/sample.json").find("\"exclude_enclosed\": true"), std::string::npos);
    r = run({"sample", scene, "--scene-points", "2000", "--query-points", "30", "--seed", "1", "-o", dir.path("keep"),
             "--keep-enclosed", "--quiet"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(read_ply(dir.path("keep") + "/scene_points.ply").select(scene_point_columns(), "").values,
              sample_scene_points(accel, 2000, 1, false).points.values);
    r = run({"preview", scene, "-o", png, "--width", "64", "--height", "48"});
    ASSERT_EQ(r.code, 0) << r.err;
    const Image img = read_image(png, /*srgb=*/false);
    EXPECT_EQ(img.width, 64);
    EXPECT_EQ(img.height, 48);
    double sum = 0;
    for (const Vec3f &p : img.pixels) sum += double(p.x + p.y + p.z);
    EXPECT_GT(sum / double(img.pixels.size()), 0.05) << "the preview of a room should not be black";
    r = run({"info", scene});
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.out.find("triangles"), std::string::npos);
    EXPECT_NE(r.out.find("range      inside the training houses' proportions"), std::string::npos) << r.out;
}

TEST(Cli, SampleIsDeterministicAcrossThreadCounts) {
    test::TempDir dir;
    for (const char *t : {"1", "2"})
        ASSERT_EQ(run({"sample", "builtin:cornell-box", "-M", "5000", "-N", "5000", "--seed", "3", "--threads", t,
                       "-o", dir.path(std::string("t") + t), "-q"}).code, 0);
    EXPECT_EQ(read_file(dir.path("t1/scene_points.ply")), read_file(dir.path("t2/scene_points.ply")));
    EXPECT_EQ(read_file(dir.path("t1/query_points.ply")), read_file(dir.path("t2/query_points.ply")));
}

TEST(Cli, HelpListsEveryCommandAndExitsZero) {
    auto r = run({"--help"});
    EXPECT_EQ(r.code, 0);
    for (const auto &c : cli::commands()) EXPECT_NE(r.out.find(c.name), std::string::npos) << c.name;
    r = run({"sample", "--help"});
    EXPECT_EQ(r.code, 0);
    for (const char *flag : {"--scene-points", "--query-points", "--threads", "--seed", "--quiet", "--verbose"})
        EXPECT_NE(r.out.find(flag), std::string::npos) << flag;
    EXPECT_NE(r.out.find("8192"), std::string::npos) << "defaults are shown";
}

TEST(Cli, UsageErrorsExitTwo) {
    EXPECT_EQ(run({}).code, 2);
    EXPECT_EQ(run({"frobnicate"}).code, 2);
    EXPECT_EQ(run({"sample", "builtin:cornell-box"}).code, 2);              // -o missing
    const auto r = run({"sample", "builtin:cornell-box", "-o", "x", "--bogus"});
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.err.find("ltm sample: usage error"), std::string::npos) << r.err;
}

// Same bytes at 1 vs 2 threads and for 1 vs 3 shards; a finished shard is skipped on re-run.
TEST(Cli, BakeIsDeterministicAcrossThreadsAndShards) {
    test::TempDir dir;
    const std::string pts = dir.path("pts");
    ASSERT_EQ(run({"sample", "builtin:cornell-box", "-M", "500", "-N", "300", "--seed", "2", "-o", pts, "-q"}).code, 0);
    ASSERT_EQ(run({"bake", "builtin:cornell-box", "--points", pts, "--spp", "64", "--threads", "1", "-o", dir.path("one"), "-q"}).code, 0);
    ASSERT_EQ(run({"bake", "builtin:cornell-box", "--points", pts, "--spp", "64", "--threads", "2", "-o", dir.path("two"), "-q"}).code, 0);
    for (const char *s : {"2/3", "0/3", "1/3"})
        ASSERT_EQ(run({"bake", "builtin:cornell-box", "--points", pts, "--spp", "64", "--shard", s, "-o", dir.path("sh"), "-q"}).code, 0);
    const std::string one = read_file(dir.path("one/irradiance.safetensors"));
    EXPECT_EQ(one, read_file(dir.path("two/irradiance.safetensors")));
    EXPECT_EQ(one, read_file(dir.path("sh/irradiance.safetensors")));
    EXPECT_EQ(read_file(dir.path("one/irradiance.ply")), read_file(dir.path("sh/irradiance.ply")));
    const auto r = run({"bake", "builtin:cornell-box", "--points", pts, "--spp", "64", "--shard", "1/3", "-o", dir.path("sh")});
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.err.find("already baked"), std::string::npos) << r.err;
    // A different spp must not reuse the shard.
    EXPECT_EQ(run({"bake", "builtin:cornell-box", "--points", pts, "--spp", "32", "--shard", "1/3", "-o", dir.path("sh"), "-q"}).code, 1);
}

TEST(Cli, RenderWritesExrAovsAndPng) {
    test::TempDir dir;
    const auto r = run({"render", "builtin:cornell-box", "--spp", "4", "--width", "24", "--height", "16", "-o", dir.path("cb.exr"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    int w = 0, h = 0;
    for (const char *ch : {"R", "G", "B", "irradiance.R", "direct.G", "albedo.B", "N.X", "P.Y", "Z"})
        EXPECT_EQ(read_exr_channel(dir.path("cb.exr"), ch, &w, &h).size(), 24u * 16u) << ch;
    EXPECT_EQ(w, 24);
    EXPECT_EQ(h, 16);
    EXPECT_EQ(read_image(dir.path("cb.png")).width, 24);
}

#ifdef LTM_WITH_TORCH
// dataset build → train → resume → export → info, through the CLI, with the tiny model.
TEST(Cli, DatasetTrainExportInfoSmoke) {
    test::TempDir dir;
    const std::string data = dir.path("data"), run_dir = dir.path("run"), weights = dir.path("w.safetensors");
    const std::string preset = test::source_path("configs/data/ci.json"), model = test::source_path("configs/model/tiny.json");
    auto r = run({"dataset", "build", "--config", preset, "--seed-range", "5:8", "--scenes", "2", "-o", data, "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(read_file(data + "/manifest.json").find("scene-000006.safetensors"), std::string::npos);
    r = run({"train", "--model", model, "--data", data, "--out", run_dir, "--steps", "2", "--set", "batch_queries=256",
             "--set", "val_every=2", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    r = run({"train", "--model", model, "--data", data, "--out", run_dir, "--steps", "3", "--set", "batch_queries=256",
             "--set", "val_every=2", "--resume", "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(read_file(run_dir + "/log.jsonl").find("\"step\":2"), std::string::npos);
    r = run({"export", run_dir + "/last.ltmckpt", "-o", weights, "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    r = run({"info", weights});
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.out.find("ltm-weights"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\"decoder\""), std::string::npos) << r.out;   // the embedded config
    EXPECT_NE(r.out.find("step  3"), std::string::npos) << r.out;
    r = run({"info", run_dir + "/last.ltmckpt"});
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.out.find("step       3"), std::string::npos) << r.out;
    // Weights whose config asks for the auto point count (an inference policy) train at their
    // scene_points when their config comes from --init, and the run's config says so.
    const std::string auto_weights = dir.path("auto.safetensors");
    ASSERT_EQ(run({"export", weights, "--set", "auto_scene_points=true", "-o", auto_weights, "-q"}).code, 0);
    r = run({"train", "--init", auto_weights, "--data", data, "--out", dir.path("run-auto"), "--steps", "1", "--set", "batch_queries=256"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("auto_scene_points off for training"), std::string::npos) << r.err;
    EXPECT_EQ(read_file(dir.path("run-auto/model.json")).find("auto_scene_points"), std::string::npos);
    // --steps 0 is refused as --set steps=0 is, in one line: not read as "not given" (20 000 steps).
    r = run({"train", "--init", auto_weights, "--data", data, "--out", dir.path("run-zero"), "--steps", "0"});
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_NE(r.err.find("steps"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("run-zero/step-0.ltmckpt"))) << "nothing trained";
    // A model whose M does not match the records is refused with the preset named.
    r = run({"train", "--model", test::source_path("configs/model/cpu.json"), "--data", data, "--out", dir.path("run2")});
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("dataset preset 'ci'"), std::string::npos) << r.err;
}
#endif

TEST(Cli, EditMovesALightAndRefusesBadEdits) {
    test::TempDir dir;
    const std::string scene = dir.path("s.json"), edited = dir.path("e.json");
    ASSERT_EQ(run({"generate", "--seed", "11", "-o", scene, "-q"}).code, 0);
    auto r = run({"edit", scene, "--move", "light0=0.25,0,-0.5", "--albedo", "room0_walls=0.8,0.3,0.2", "-o", edited, "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const Scene a = load_scene(scene), b = load_scene(edited);
    for (size_t i = 0; i < a.meshes.size(); ++i) {
        const Vec3f shift = a.meshes[i].name == "light0" ? Vec3f(0.25f, 0.f, -0.5f) : Vec3f(0.f);
        EXPECT_LT(length(b.meshes[i].positions[0] - (a.meshes[i].positions[0] + shift)), 1e-5f) << a.meshes[i].name;
    }
    for (const auto &args : std::vector<std::vector<std::string>>{
             {"edit", scene, "--move", "sofa99=1,0,0", "-o", dir.path("x.json")},
             {"edit", scene, "--albedo", "room0_walls=1.5,0,0", "-o", dir.path("x.json")},
             {"edit", scene, "--move", "light0=1,0", "-o", dir.path("x.json")},
             {"edit", scene, "-o", dir.path("x.json")}}) {
        r = run(args);
        EXPECT_EQ(r.code, 1) << args[2];
        EXPECT_NE(r.err.find("ltm edit: error:"), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir.path("x.json")));
    }
}

#ifdef LTM_WITH_TORCH
// Neural render and eval end to end with a tiny random model: files, timings, report.
TEST(Cli, NeuralRenderAndEvalSmoke) {
    test::TempDir dir;
    const std::string weights = dir.path("tiny.safetensors"), scene = dir.path("s.json");
    {
        LtmModel m(ModelConfig::from_file(test::source_path("configs/model/tiny.json")));
        save_weights(weights, m);
    }
    ASSERT_EQ(run({"generate", "--seed", "900003", "-o", scene, "-q"}).code, 0);
    auto r = run({"render", scene, "--method", "neural", "--model", weights, "--width", "32", "--height", "24",
                  "--direct-spp", "2", "-o", dir.path("n"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char *f : {"n.exr", "n.png", "n.irradiance.png", "n.timings.json"})
        EXPECT_TRUE(std::filesystem::exists(dir.path(f))) << f;
    const Json t = parse_json_file(dir.path("n.timings.json"));
    for (const char *k : {"encode_s", "knn_s", "decode_s", "direct_s", "total_s"}) EXPECT_TRUE(t["timings"].contains(k)) << k;
    EXPECT_EQ(t["scene_points"].get<int>(), 1024);
    // --scene-points overrides the model's own M (the tiny model's 1 024).
    r = run({"render", scene, "--method", "neural", "--model", weights, "--width", "32", "--height", "24", "--direct-spp", "2",
             "--scene-points", "2048", "-o", dir.path("n2"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(parse_json_file(dir.path("n2.timings.json"))["scene_points"].get<int>(), 2048);
    r = run({"eval", "--model", weights, "--ablation", "again=" + weights, "--scenes", scene, "--width", "24", "--height",
             "24", "--ref-spp", "8", "--baseline-spp", "2", "--views", "2", "-o", dir.path("ev"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const Json rep = parse_json_file(dir.path("ev/report.json"));
    EXPECT_EQ(rep["views"].size(), 2u);
    EXPECT_EQ(rep["scene_points"].get<int>(), 1024);
    for (const char *m : {"model:ours", "model:again", "model-prior:ours", "pt2", "pt-equal-time"}) EXPECT_TRUE(rep["summary"].contains(m)) << m;
    // The tiny random model's network is active: its row is not its prior's.
    EXPECT_NE(rep["summary"]["model:ours"]["mse"]["mean"], rep["summary"]["model-prior:ours"]["mse"]["mean"]);
    // The same weights give the same metrics: the ablation path is the model path.
    EXPECT_EQ(rep["summary"]["model:ours"]["mse"]["mean"], rep["summary"]["model:again"]["mse"]["mean"]);
    EXPECT_NE(read_file(dir.path("ev/table.md")).find("| pt-equal-time |"), std::string::npos);
    EXPECT_TRUE(std::filesystem::exists(dir.path("ev/s_main.png")));
    // Bad input: a corrupted model file and a non-model file are one-line errors.
    write_file_atomic(dir.path("bad.safetensors"), "not a safetensors file");
    r = run({"render", scene, "--method", "neural", "--model", dir.path("bad.safetensors"), "-o", dir.path("b")});
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("bad.safetensors"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path("b.png")));
    r = run({"render", scene, "--method", "neural", "-o", dir.path("b")});
    EXPECT_EQ(r.code, 1);
    // A scene unlike the training distribution renders, with a warning that names the range: the
    // unit-free model judges proportions (a Cornell box flattened to 1/10 of its height), not size.
    Scene flat = cornell_box();
    for (auto &m : flat.meshes)
        for (auto &p : m.positions) p.y *= 0.1f;
    flat.cameras[0].eye.y *= 0.1f, flat.cameras[0].target.y *= 0.1f;
    save_scene_json(flat, dir.path("flat.json"));
    r = run({"render", dir.path("flat.json"), "--method", "neural", "--model", weights, "--width", "16", "--height",
             "16", "--direct-spp", "1", "-o", dir.path("cb")});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("outside the training range"), std::string::npos) << r.err;
    // eval takes every scene form the other commands take: a built-in, an OBJ without a camera
    // (the automatic camera of render), beside a seed range.
    r = run({"eval", "--model", weights, "--scenes", "builtin:cornell-box", test::source_path("examples/cornell-box/cornell-box.obj"),
             "--width", "16", "--height", "16", "--ref-spp", "4", "--baseline-spp", "1", "--no-grids", "-o", dir.path("forms"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const Json forms = parse_json_file(dir.path("forms/report.json"));
    ASSERT_EQ(forms["views"].size(), 2u);
    EXPECT_EQ(forms["views"][0]["scene"], "builtin-cornell-box");
    EXPECT_EQ(forms["views"][1]["scene"], "cornell-box");
    // The same box in millimetres is no warning for it: its proportions are a room's.
    r = run({"render", "builtin:cornell-box", "--method", "neural", "--model", weights, "--width", "16", "--height",
             "16", "--direct-spp", "1", "-o", dir.path("cb2")});
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err.find("outside the training range"), std::string::npos) << r.err;
}
#endif

// A pbrt-v4 room renders directly and converts to scene JSON that reads back the same.
TEST(Cli, PbrtSceneRendersAndConverts) {
    test::TempDir dir;
    write_file_atomic(dir.path("room.pbrt"), R"(LookAt 0 1 -0.9  0 1 0  0 1 0
Camera "perspective" "float fov" 60
Film "rgb" "integer xresolution" 32 "integer yresolution" 32
WorldBegin
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [5 5 5]
  Shape "trianglemesh" "point3 P" [-0.3 1.99 -0.3  0.3 1.99 -0.3  0.3 1.99 0.3  -0.3 1.99 0.3]
        "integer indices" [0 1 2 0 2 3] "normal N" [0 -1 0 0 -1 0 0 -1 0 0 -1 0]
AttributeEnd
Material "diffuse" "rgb reflectance" [0.6 0.5 0.4]
# a closed box facing inwards: floor, ceiling and walls from one bilinear mesh
Shape "bilinearmesh" "point3 P" [-1 0 -1  1 0 -1  -1 0 1  1 0 1   -1 2 -1  1 2 -1  -1 2 1  1 2 1]
      "integer indices" [2 3 0 1  4 5 6 7  0 1 4 5  6 7 2 3  2 0 6 4  1 3 5 7]
)");
    auto r = run({"convert", dir.path("room.pbrt"), "-o", dir.path("room.json"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const Scene a = load_scene(dir.path("room.pbrt")), b = load_scene(dir.path("room.json"));
    EXPECT_EQ(a.n_triangles(), b.n_triangles());
    EXPECT_NEAR(a.total_area(), b.total_area(), 1e-6);
    ASSERT_EQ(b.cameras.size(), 1u);
    EXPECT_EQ(b.cameras[0].width, 32);
    r = run({"render", dir.path("room.pbrt"), "--spp", "4", "-o", dir.path("img"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const Image img = read_image(dir.path("img.png"), false);
    double sum = 0;
    for (const Vec3f &p : img.pixels) sum += double(p.x + p.y + p.z);
    EXPECT_GT(sum, 0.0) << "the lit pbrt room renders";
}
