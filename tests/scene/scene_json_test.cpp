// scene_json_test.cpp: the scene JSON format round-trips, and bad files fail with located errors.
#include <fstream>

#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/scene_json.h"
#include "ltm/scene/scene_loader.h"
#include "test_util.h"

using namespace ltm;

namespace {
std::string load_error(const std::string &path) {
    try {
        load_scene(path);
    } catch (const Error &e) {
        return e.what();
    }
    return "";
}

const char *k_minimal = R"({
  "format": "ltm-scene", "version": 1, "name": "tri",
  "materials": [{"name": "w", "type": "diffuse", "albedo": [0.5, 0.5, 0.5]},
                {"name": "l", "type": "emissive", "radiance": [1, 1, 1]}],
  "meshes": [{"name": "t", "material": "w", "positions": [0,0,0, 1,0,0, 0,0,1], "indices": [0,1,2]},
             {"name": "light", "material": "l", "positions": [0,1,0, 0,1,1, 1,1,0], "indices": [0,1,2]}]
})";

std::string write(const test::TempDir &dir, const std::string &name, const std::string &text) {
    write_file_atomic(dir.path(name), text);
    return dir.path(name);
}

std::string replace(std::string s, const std::string &from, const std::string &to) {
    const size_t p = s.find(from);
    EXPECT_NE(p, std::string::npos) << from;
    return s.replace(p, from.size(), to);
}
}  // namespace

TEST(SceneJson, RoundTripIsExact) {
    test::TempDir dir;
    Scene s = cornell_box();
    Material tex;
    tex.name = "checker";
    tex.albedo.kind = TextureKind::checker;
    tex.albedo.color_a = {0.1f, 0.2f, 0.3f};
    tex.albedo.scale = 0.05f;
    s.materials.push_back(tex);
    s.meshes[0].material = int(s.materials.size()) - 1;
    save_scene_json(s, dir.path("a.json"));
    const Scene r = load_scene(dir.path("a.json"));
    ASSERT_EQ(r.meshes.size(), s.meshes.size());
    for (size_t m = 0; m < s.meshes.size(); ++m) {
        EXPECT_EQ(r.meshes[m].name, s.meshes[m].name);
        EXPECT_EQ(r.meshes[m].indices, s.meshes[m].indices);
        for (size_t i = 0; i < s.meshes[m].positions.size(); ++i) EXPECT_EQ(r.meshes[m].positions[i], s.meshes[m].positions[i]);
    }
    EXPECT_EQ(r.materials.back().albedo.kind, TextureKind::checker);
    EXPECT_EQ(r.materials.back().albedo.scale, 0.05f);
    // Saving what was loaded gives the same bytes.
    save_scene_json(r, dir.path("b.json"));
    EXPECT_EQ(read_file(dir.path("a.json")), read_file(dir.path("b.json")));
}

TEST(SceneJson, TransformAndObjReferenceAreApplied) {
    test::TempDir dir;
    const std::string obj = test::source_path("examples/cornell-box/cornell-box.obj");
    const std::string p = write(dir, "s.json", R"({"materials": [],
      "meshes": [{"name": "cb", "file": ")" + obj + R"(",
                  "transform": {"scale": 2, "translate": [10, 0, 0]}}]})");
    const Scene s = load_scene(p);
    const Bounds3f b = s.bounds();
    EXPECT_NEAR(b.lo.x, 10.f, 1e-4f);
    EXPECT_NEAR(b.hi.x, 10.f + 2 * 0.556f, 1e-4f);
    EXPECT_NEAR(s.total_area(), 4 * cornell_box().total_area(), 1e-3);
}

TEST(SceneJson, BadFilesFailWithLocatedErrors) {
    test::TempDir dir;
    const std::string good = k_minimal;
    EXPECT_EQ(load_error(write(dir, "ok.json", good)), "");
    struct Case { std::string text, expect; };
    const Case cases[] = {
        {good.substr(0, good.size() / 2), "bad_0.json:"},                                   // truncated
        {replace(good, "\"name\": \"tri\"", "\"name\": \"tri\", \"colour\": 1"), "unknown key 'colour'"},
        {replace(good, "0,0,0, 1,0,0", "0,0,0, 1e999,0,0"), "number overflow"},              // Inf literal
        {replace(good, "[0,1,2]}", "[0,1,1]}"), "degenerate"},                              // zero area
        {replace(good, "\"radiance\": [1, 1, 1]", "\"radiance\": [0, 0, 0]"), "no emitter"},
        {replace(good, "\"material\": \"w\"", "\"material\": \"q\""), "material 'q' is not defined"},
        {replace(good, "[0.5, 0.5, 0.5]", "{\"type\": \"image\", \"file\": \"missing.png\"}"), "missing.png"},
        {replace(good, "[0.5, 0.5, 0.5]", "[0.5, 0.5]"), "/materials/0/albedo"},
        {replace(good, "[0,1,2]}", "[0,1,7]}"), "out of range"},
        {replace(good, "\"version\": 1", "\"version\": 9"), "version 9"},
        {"[]", "expected an object"},
        {"", "bad_11.json:1:1"},
    };
    for (size_t i = 0; i < std::size(cases); ++i) {
        const std::string name = "bad_" + std::to_string(i) + ".json";
        const std::string msg = load_error(write(dir, name, cases[i].text));
        EXPECT_NE(msg.find(cases[i].expect), std::string::npos) << "case " << i << ": '" << msg << "'";
        EXPECT_NE(msg.find(name), std::string::npos) << "case " << i << " must name the file: " << msg;
    }
}

TEST(SceneJson, UnknownFormatAndBuiltinNamesAreErrors) {
    EXPECT_NE(load_error("scene.fbx").find("unknown scene format"), std::string::npos);
    EXPECT_NE(load_error("builtin:nope").find("known: cornell-box"), std::string::npos);
    EXPECT_NE(load_error("/nonexistent/scene.json").find("/nonexistent/scene.json"), std::string::npos);
}
