// dataset_test.cpp: records round-trip, building is resumable, bad records are located errors.
#include <filesystem>

#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/core/math.h"
#include "ltm/points/safetensors.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/render/scene_points.h"
#include "ltm/data/dataset.h"
#include "test_util.h"

using namespace ltm;

namespace {
DataPreset small_preset() {
    DataPreset p = DataPreset::from_file(test::source_path("configs/data/ci.json"));
    p.query_points = 512;
    p.spp = 8;
    return p;
}
// Builds the one record of `preset` for `seed` into `dir` and reads it back.
SceneRecord build_one(const DataPreset &preset, uint64_t seed, const std::string &dir) {
    BuildOptions opt;
    opt.preset = preset;
    opt.seeds = {seed};
    opt.out_dir = dir;
    build_dataset(opt);
    return read_record(list_records(dir)[0]);
}
// Σ over the points' bins of (π/R²) L̄ per channel: the bins' cosine integral (R² = nb bins).
double bins_integral(const SceneRecord &r, size_t n_points, int nb) {
    double sum = 0;
    for (size_t q = 0; q < n_points; ++q)
        for (int c = 0; c < 3; ++c)
            for (int b = 0; b < nb; ++b) sum += double(r.l_in[(q * size_t(nb) + size_t(b)) * 3 + size_t(c)]) * k_pi / double(nb);
    return sum;
}
}  // namespace

TEST(Dataset, BuildWritesRecordsAndSkipsExistingOnes) {
    test::TempDir dir;
    BuildOptions opt;
    opt.preset = small_preset();
    opt.seeds = {3, 4};
    opt.out_dir = dir.path("data");
    build_dataset(opt);
    const auto records = list_records(opt.out_dir);
    ASSERT_EQ(records.size(), 2u);
    const SceneRecord r = read_record(records[0]);
    EXPECT_EQ(r.seed, 3u);
    EXPECT_EQ(r.scene_points.size(), 1024u);
    EXPECT_EQ(r.query_points.size(), 512u);
    EXPECT_EQ(r.e_indirect.size(), 512u * 3);
    EXPECT_EQ(r.metadata["preset"]["name"], "ci");
    double sum = 0;
    for (float e : r.e_indirect) {
        EXPECT_GE(e, 0.f);
        sum += e;
    }
    EXPECT_GT(sum, 0.0) << "indirect light must reach some points";
    // The exact emission scale S = Φ/A travels with the record and agrees with the points' own
    // estimate π·mean(Le) within the noise of the few emitter points.
    ASSERT_TRUE(r.emission_scale.has_value());
    double point_mean = 0;
    for (size_t i = 0; i < r.scene_points.size(); ++i) point_mean += r.scene_points.at(i, 9);
    point_mean *= k_pi / double(r.scene_points.size());
    EXPECT_GT(r.emission_scale->x, 0.f);
    EXPECT_NEAR(r.emission_scale->x, point_mean, 0.5 * point_mean);
    // A record from before emission_scale existed is upgraded in place to the value a build computes.
    SceneRecord old = r;
    old.emission_scale.reset();
    write_record(records[0], old);
    EXPECT_FALSE(read_record(records[0]).emission_scale.has_value());
    EXPECT_EQ(upgrade_dataset(opt.out_dir), 1);
    const SceneRecord up = read_record(records[0]);
    ASSERT_TRUE(up.emission_scale.has_value());
    EXPECT_EQ(up.emission_scale->x, r.emission_scale->x);
    EXPECT_EQ(up.emission_scale->z, r.emission_scale->z);
    EXPECT_EQ(up.e_indirect, r.e_indirect);
    EXPECT_EQ(upgrade_dataset(opt.out_dir), 0);
    const auto before = std::filesystem::last_write_time(records[0]);
    opt.seeds = {3, 4, 5};
    build_dataset(opt);   // builds only seed 5
    EXPECT_EQ(std::filesystem::last_write_time(records[0]), before);
    EXPECT_EQ(list_records(opt.out_dir).size(), 3u);
    EXPECT_NE(read_file(opt.out_dir + "/manifest.json").find("scene-000005.safetensors"), std::string::npos);
}

// camera_queries: that share of the queries (the last ones) is seen by the house's camera — all face
// it — while area-uniform queries include surfaces turned away from it.
TEST(Dataset, CameraQueriesAreSeenByTheCamera) {
    test::TempDir dir;
    DataPreset preset = small_preset();
    preset.camera_queries = 0.25f;
    const SceneRecord r = build_one(preset, 3, dir.path("data"));
    EXPECT_EQ(r.metadata["preset"]["camera_queries"], 0.25);
    const Vec3f eye = generate_indoor(GenConfig{}, 3).scene.cameras.at(0).eye;
    ASSERT_EQ(r.query_points.size(), 512u);
    int facing_area = 0;
    for (size_t i = 0; i < r.query_points.size(); ++i) {
        const bool facing = dot(r.query_points.vec3(i, 3), eye - r.query_points.vec3(i, 0)) > 0.f;
        if (i >= 384) EXPECT_TRUE(facing) << "view query " << i;
        else facing_area += facing;
    }
    EXPECT_LT(facing_area, 384 * 9 / 10);
    EXPECT_THROW(DataPreset::from_json(parse_json(R"({"camera_queries": 1.5})", "p.json"), "p.json"), Error);
}

// Glossy ground truth (paper §7): with bin_resolution R the record holds L_in [N, R², 3], whose
// cosine-weighted sum is the point's irradiance E = (π/R²) Σ L̄_bin (E_direct + E⁺ from the
// independent irradiance bake: equal in expectation); a record with a malformed L_in is an error.
TEST(Dataset, GlossyRecordsHoldBinsThatIntegrateToTheIrradiance) {
    test::TempDir dir;
    DataPreset preset = small_preset();
    preset.query_points = 24;
    preset.spp = 1024;
    preset.bin_resolution = 8;
    preset.bin_spp = 64;
    preset.generator = test::source_path("configs/gen/glossy.json");
    const SceneRecord r = build_one(preset, 5, dir.path("data"));
    const std::string path = r.path;
    ASSERT_EQ(r.bin_resolution, 8);
    ASSERT_EQ(r.l_in.size(), size_t(24 * 64 * 3));
    EXPECT_EQ(r.metadata["preset"]["bin_resolution"], 8);
    const double from_bins = bins_integral(r, 24, 64);
    double irradiance = 0, e_plus = 0;
    for (size_t i = 0; i < 24 * 3; ++i) irradiance += double(r.e_direct[i]) + double(r.e_indirect[i]);
    EXPECT_NEAR(from_bins, irradiance, 0.05 * irradiance);
    // bin_radiance "indirect": the bins hold L_in⁺ (scattered light only), whose cosine sum is E⁺.
    preset.bin_radiance = "indirect";
    const SceneRecord ri = build_one(preset, 5, dir.path("indirect"));
    EXPECT_EQ(ri.metadata["preset"]["bin_radiance"], "indirect");
    const double from_bins_i = bins_integral(ri, 24, 64);
    for (size_t i = 0; i < 24 * 3; ++i) e_plus += double(ri.e_indirect[i]);
    EXPECT_NEAR(from_bins_i, e_plus, 0.05 * e_plus);
    EXPECT_LT(from_bins_i, 0.9 * from_bins) << "the emitters' direct light should be gone";
    // Without bins the key is not written (older presets keep their exact JSON).
    EXPECT_FALSE(small_preset().to_json().contains("bin_resolution"));
    // A non-square bin count is a located error.
    SafetensorsFile f = read_safetensors(path);
    std::vector<float> bad(24 * 60 * 3, 0.f);
    f.tensors["L_in"] = make_f32_tensor({24, 60, 3}, bad.data());
    write_safetensors(path, f);
    try {
        read_record(path);
        ADD_FAILURE() << "no error";
    } catch (const Error &e) {
        EXPECT_NE(std::string(e.what()).find("L_in"), std::string::npos) << e.what();
    }
}

// Several directories (e.g. two presets) merge into one seed-ordered list; a seed twice is an error.
TEST(Dataset, RecordsOfSeveralDirectoriesMergeBySeed) {
    test::TempDir dir;
    const std::string a = dir.path("a"), b = dir.path("b");
    std::filesystem::create_directories(a);
    std::filesystem::create_directories(b);
    for (uint64_t s : {0, 7, 12}) write_file_atomic(a + "/" + record_file_name(s), "x");
    for (uint64_t s : {3, 100}) write_file_atomic(b + "/" + record_file_name(s), "x");
    write_file_atomic(b + "/manifest.json", "{}");
    const auto all = list_records(std::vector<std::string>{a, b});
    std::vector<std::string> names;
    for (const auto &p : all) names.push_back(std::filesystem::path(p).filename().string());
    EXPECT_EQ(names, (std::vector<std::string>{record_file_name(0), record_file_name(3), record_file_name(7),
                                               record_file_name(12), record_file_name(100)}));
    EXPECT_EQ(std::filesystem::path(all[1]).parent_path().string(), b);
    write_file_atomic(b + "/" + record_file_name(7), "x");
    EXPECT_THROW(list_records(std::vector<std::string>{a, b}), Error);
    EXPECT_THROW(list_records(std::vector<std::string>{}), Error);
}

TEST(Dataset, ForeignOrCorruptRecordsAreErrors) {
    test::TempDir dir;
    SafetensorsFile f;
    const float x[12] = {};
    f.tensors["scene_points"] = make_f32_tensor({1, 12}, x);
    f.metadata["ltm"] = R"({"format_version": 99})";
    write_safetensors(dir.path("scene-000001.safetensors"), f);
    try {
        read_record(dir.path("scene-000001.safetensors"));
        FAIL();
    } catch (const Error &e) {
        EXPECT_NE(std::string(e.what()).find("version 99"), std::string::npos) << e.what();
    }
    write_file_atomic(dir.path("scene-000002.safetensors"), "garbage");
    EXPECT_THROW(read_record(dir.path("scene-000002.safetensors")), Error);
    EXPECT_THROW(DataPreset::from_json(parse_json(R"({"spp": 0})", "p.json"), "p.json"), Error);
    EXPECT_THROW(DataPreset::from_json(parse_json(R"({"sppp": 4})", "p.json"), "p.json"), Error);
}

// A record's scene points are what render-time sampling gives for its scene and seed (the one
// shared function, render/scene_points.h): the model sees at render time what it trained on.
TEST(Dataset, RecordScenePointsAreRenderTimeSampling) {
    test::TempDir dir;
    DataPreset preset = small_preset();
    preset.query_points = 16;
    const SceneRecord r = build_one(preset, 6, dir.path("data"));
    const GeneratedScene g = generate_indoor(GenConfig{}, 6);   // the ci preset's generator: built-in defaults
    const EmbreeAccel accel(g.scene);
    const ScenePoints s = sample_scene_points(accel, preset.scene_points, 6, preset.exclude_enclosed);
    EXPECT_EQ(r.scene_points.values, s.points.values);
    ASSERT_TRUE(r.emission_scale.has_value());
    EXPECT_EQ(*r.emission_scale, s.emission_scale);
}
