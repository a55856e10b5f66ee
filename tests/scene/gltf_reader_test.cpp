// gltf_reader_test.cpp: a glTF 2.0 room (external buffer, and the same as .glb) reads as its
// hand-built twin: node transforms (TRS), winding, materials (base colour, emissive strength),
// camera; bad files are one-line errors naming the file.
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/scene/gltf_reader.h"
#include "ltm/scene/obj_io.h"
#include "ltm/scene/pbrt_reader.h"
#include "ltm/scene/scene_loader.h"
#include "test_util.h"

using namespace ltm;

namespace {
// A 2×2 quad at y = 0, counter-clockwise seen from +y: 4 float3 positions, 6 uint16 indices.
std::string quad_buffer() {
    const float p[12] = {-1, 0, 1, 1, 0, 1, 1, 0, -1, -1, 0, -1};
    const uint16_t ix[6] = {0, 1, 2, 0, 2, 3};
    std::string b(sizeof p + sizeof ix, '\0');
    std::memcpy(b.data(), p, sizeof p);
    std::memcpy(b.data() + sizeof p, ix, sizeof ix);
    return b;
}

// The floor (material 0) and, through a node turned 180° about x, scaled and lifted to y = 2, a
// downward-facing lamp (material 1, emissive 1 0.5 0.25 × strength 4); a camera at (0, 1, 3).
std::string room_json(const std::string &buffer, const std::string &extra_accessor = "") {
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
 "extensionsUsed": ["KHR_materials_emissive_strength"],
 "nodes": [{"mesh": 0}, {"mesh": 1, "translation": [0, 2, 0], "rotation": [1, 0, 0, 0], "scale": [0.25, 1, 0.25]},
           {"camera": 0, "translation": [0, 1, 3]}],
 "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 1.5, "znear": 0.01}}],
 "meshes": [{"name": "floor", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]},
            {"name": "lamp", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 1}]}],
 "materials": [{"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1], "metallicFactor": 0}},
               {"name": "lamp", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0},
                "emissiveFactor": [1, 0.5, 0.25], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, 0, -1], "max": [1, 0, 1])" +
           extra_accessor + R"(},
               {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
 "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
 "buffers": [{)" + buffer + R"("byteLength": 60}]})";
}

void check_room(const Scene &s) {
    ASSERT_EQ(s.meshes.size(), 2u);
    const TriangleMesh &floor = s.meshes[0], &lamp = s.meshes[1];
    EXPECT_NEAR(floor.area(0) + floor.area(1), 4.f, 1e-6f);
    EXPECT_NEAR(lamp.area(0) + lamp.area(1), 0.25f, 1e-6f);
    for (size_t t = 0; t < 2; ++t) {
        EXPECT_NEAR(normalize(floor.cross_normal(t)).y, 1.f, 1e-6f);
        EXPECT_NEAR(normalize(lamp.cross_normal(t)).y, -1.f, 1e-6f);
        EXPECT_NEAR(lamp.vertex(t, 0).y, 2.f, 1e-6f);
    }
    const Material &fm = s.materials[size_t(floor.material)], &lm = s.materials[size_t(lamp.material)];
    EXPECT_EQ(fm.albedo.color_a, Vec3f(0.2f, 0.4f, 0.6f));
    EXPECT_FALSE(fm.is_emissive());
    EXPECT_EQ(lm.emission.color_a, Vec3f(4.f, 2.f, 1.f));
    ASSERT_EQ(s.cameras.size(), 1u);
    EXPECT_EQ(s.cameras[0].eye, Vec3f(0.f, 1.f, 3.f));
    EXPECT_NEAR(s.cameras[0].target.z, 2.f, 1e-6f);   // looking down −z
    EXPECT_NEAR(s.cameras[0].fov_y_deg, 0.8 * 180.0 / M_PI, 1e-4);
    EXPECT_EQ(s.cameras[0].height, int(std::lround(s.cameras[0].width / 1.5)));
    EXPECT_NO_THROW(validate_scene(s, "gltf"));
}

void put_u32(std::string &s, uint32_t v) { s.append(reinterpret_cast<const char *>(&v), 4); }
}  // namespace

TEST(GltfReader, RoomWithExternalBufferMatchesItsTwin) {
    test::TempDir dir;
    write_file_atomic(dir.path("room.bin"), quad_buffer());
    write_file_atomic(dir.path("room.gltf"), room_json(R"("uri": "room.bin", )"));
    check_room(load_scene(dir.path("room.gltf")));
}

TEST(GltfReader, BinaryGlbMatchesTheJsonFile) {
    test::TempDir dir;
    std::string json = room_json(""), bin = quad_buffer();
    while (json.size() % 4) json += ' ';
    while (bin.size() % 4) bin += '\0';
    std::string glb;
    put_u32(glb, 0x46546C67u);   // "glTF"
    put_u32(glb, 2);
    put_u32(glb, uint32_t(12 + 8 + json.size() + 8 + bin.size()));
    put_u32(glb, uint32_t(json.size()));
    put_u32(glb, 0x4E4F534Au);   // "JSON"
    glb += json;
    put_u32(glb, uint32_t(bin.size()));
    put_u32(glb, 0x004E4942u);   // "BIN\0"
    glb += bin;
    write_file_atomic(dir.path("room.glb"), glb);
    check_room(load_scene(dir.path("room.glb")));
}

TEST(GltfReader, BadFilesAreOneLineErrorsNamingTheFile) {
    test::TempDir dir;
    write_file_atomic(dir.path("room.bin"), quad_buffer());
    write_file_atomic(dir.path("nobuf.gltf"), room_json(R"("uri": "missing.bin", )"));
    write_file_atomic(dir.path("sparse.gltf"),
                      room_json(R"("uri": "room.bin", )",
                                R"(, "sparse": {"count": 1, "indices": {"bufferView": 1, "componentType": 5123}, "values": {"bufferView": 0}})"));
    write_file_atomic(dir.path("junk.gltf"), "{ not json");
    for (const char *name : {"nobuf.gltf", "sparse.gltf", "junk.gltf", "absent.glb"}) {
        try {
            load_scene(dir.path(name));
            ADD_FAILURE() << name << ": no error";
        } catch (const Error &e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(name), std::string::npos) << msg;
            EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
            if (std::string(name) == "sparse.gltf") {
                EXPECT_NE(msg.find("sparse"), std::string::npos) << msg;
            }
        }
    }
}

// The in-memory readers the fuzzers use never touch files: an external URI (glTF), an Include or
// PLY (pbrt) or a texture map (OBJ) is an error; the same content inline reads as from a file.
TEST(InMemoryReaders, NoFileAccessAndSameResult) {
    test::TempDir dir;
    write_file_atomic(dir.path("room.bin"), quad_buffer());
    EXPECT_THROW(parse_gltf(room_json(R"("uri": "room.bin", )"), "mem.gltf", false), Error);
    const std::string b64 = "data:application/octet-stream;base64,";
    const std::string raw = quad_buffer();
    static const char *k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string enc;
    for (size_t i = 0; i < raw.size(); i += 3) {
        const uint32_t n = (uint32_t(uint8_t(raw[i])) << 16) | (i + 1 < raw.size() ? uint32_t(uint8_t(raw[i + 1])) << 8 : 0) |
                           (i + 2 < raw.size() ? uint32_t(uint8_t(raw[i + 2])) : 0);
        enc += k[(n >> 18) & 63];
        enc += k[(n >> 12) & 63];
        enc += i + 1 < raw.size() ? k[(n >> 6) & 63] : '=';
        enc += i + 2 < raw.size() ? k[n & 63] : '=';
    }
    check_room(parse_gltf(room_json("\"uri\": \"" + b64 + enc + "\", "), "mem.gltf", false));
    EXPECT_THROW(parse_pbrt("Include \"x.pbrt\"", "mem.pbrt", dir.path(), false), Error);
    EXPECT_THROW(parse_pbrt("Shape \"plymesh\" \"string filename\" \"x.ply\"", "mem.pbrt", dir.path(), false), Error);
    const std::string obj = read_file(test::source_path("examples/cornell-box/cornell-box.obj"));
    const std::string mtl = read_file(test::source_path("examples/cornell-box/cornell-box.mtl"));
    const Scene a = parse_obj(obj, mtl, "mem.obj"), b = load_scene(test::source_path("examples/cornell-box/cornell-box.obj"));
    EXPECT_EQ(a.n_triangles(), b.n_triangles());
    EXPECT_EQ(a.materials.size(), b.materials.size());
    EXPECT_THROW(parse_obj(obj, "newmtl m\nKd 0.5 0.5 0.5\nmap_Kd /etc/passwd\n", "mem.obj"), Error);
}
