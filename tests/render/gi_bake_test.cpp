// gi_bake_test.cpp: the GI bake's refinement, composition, glTF file and software view
// (render/gi_bake.h): edges bounded, area kept, shared lattice points shared, a room wound outward
// baked on its room side, Lo = Le + ρ/π·(E_d + E⁺) round-tripped through the .glb, and the view
// interpolating the vertices exactly where values are linear.
#include <filesystem>

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include "ltm/core/error.h"
#include "ltm/render/embree_accel.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/gi_bake.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/mesh_builder.h"
#include "ltm/scene/scene_loader.h"
#include "test_util.h"

using namespace ltm;

namespace {

/// One 2 m × 2 m floor quad (two triangles) under a small light.
Scene floor_scene() {
    Scene s;
    s.name = "floor";
    Material floor;
    floor.name = "floor";
    floor.albedo = Texture::constant(Vec3f(0.5f, 0.4f, 0.3f));
    Material light;
    light.name = "light";
    light.emission = Texture::constant(Vec3f(4.f));
    s.add_material(floor);
    s.add_material(light);
    TriangleMesh f;
    f.name = "floor";
    f.material = 0;
    add_quad(f, {0, 0, 0}, {0, 0, 2}, {2, 0, 2}, {2, 0, 0});   // normal +y
    TriangleMesh l;
    l.name = "light";
    l.material = 1;
    add_quad(l, {0.9f, 1.5f, 0.9f}, {1.1f, 1.5f, 0.9f}, {1.1f, 1.5f, 1.1f}, {0.9f, 1.5f, 1.1f});   // normal −y
    s.meshes = {f, l};
    return s;
}

double area(const BakedMesh &m) {
    double a = 0.0;
    for (size_t t = 0; t < m.indices.size(); t += 3)
        a += 0.5 * double(length(cross(m.position[m.indices[t + 1]] - m.position[m.indices[t]], m.position[m.indices[t + 2]] - m.position[m.indices[t]])));
    return a;
}

}  // namespace

TEST(GiBake, RefinementBoundsEdgesKeepsAreaAndSharesLatticePoints) {
    const Scene s = floor_scene();
    RefineOptions o;
    o.max_edge = 0.3f;
    const std::vector<BakedMesh> m = refine_for_bake(s, o);
    ASSERT_EQ(m.size(), 2u);
    // The floor is lit air on both sides here (an open quad): two copies, facing up and down.
    // The 2 m diagonal needs 10 segments (2.83 / 0.3): both triangles lattice the square at 0.2 m.
    EXPECT_EQ(m[0].position.size(), 2u * 121u);   // 11 × 11 a side: the diagonal's points are shared, not doubled
    EXPECT_EQ(m[0].indices.size(), 2u * 3u * 200u);
    EXPECT_NEAR(area(m[0]), 2 * 4.0, 1e-4);
    int up = 0;
    for (const Vec3f &n : m[0].normal) {
        EXPECT_NEAR(std::abs(n.y), 1.f, 1e-6f);
        up += n.y > 0.f;
    }
    EXPECT_EQ(up, 121);
    for (size_t t = 0; t < m[0].indices.size(); t += 3)
        for (int k = 0; k < 3; ++k)
            EXPECT_LE(length(m[0].position[m[0].indices[t + size_t(k)]] - m[0].position[m[0].indices[t + size_t(k + 1) % 3]]), 0.3f + 1e-5f);
    // A budget below the need is one error, before anything is built.
    o.max_vertices = 100;
    try {
        refine_for_bake(s, o);
        FAIL() << "no error";
    } catch (const Error &e) {
        EXPECT_NE(std::string(e.what()).find("over the budget of 100"), std::string::npos) << e.what();
    }
}

// The Cornell box with every face wound the other way: the bake still faces into the box.
TEST(GiBake, FacesWoundAwayFromTheRoomAreBakedOnTheRoomSide) {
    Scene s = cornell_box();
    const Bounds3f b = s.bounds();
    const Vec3f centre = (b.lo + b.hi) * 0.5f;
    for (TriangleMesh &m : s.meshes)
        if (!s.materials[size_t(m.material)].is_emissive())
            for (size_t t = 0; t < m.n_triangles(); ++t) std::swap(m.indices[3 * t + 1], m.indices[3 * t + 2]);
    const std::vector<BakedMesh> baked = refine_for_bake(s, RefineOptions{});
    int walls = 0;
    for (size_t i = 0; i < baked.size(); ++i) {
        if (s.materials[size_t(s.meshes[i].material)].is_emissive() || s.meshes[i].name.find("wall") == std::string::npos) continue;
        const BakedMesh &m = baked[i];
        double inward = 0.0, mesh_area = 0.0;
        for (size_t t = 0; t < s.meshes[i].n_triangles(); ++t) mesh_area += double(s.meshes[i].area(t));
        for (size_t t = 0; t < m.indices.size(); t += 3) {
            const Vec3f a = m.position[m.indices[t]];
            const Vec3f c = cross(m.position[m.indices[t + 1]] - a, m.position[m.indices[t + 2]] - a);
            // The winding follows the vertices' normal.
            EXPECT_GT(dot(c, m.normal[m.indices[t]]), 0.f);
            if (dot(m.normal[m.indices[t]], centre - a) > 0.f) inward += 0.5 * double(length(c));
        }
        EXPECT_NEAR(inward, mesh_area, 1e-3 * mesh_area) << m.name;   // the whole wall, baked on the box's side
        ++walls;
    }
    EXPECT_GT(walls, 0);
}

TEST(GiBake, GlbHoldsTheComposedRadianceAndLoadsBack) {
    const Scene s = floor_scene();
    RefineOptions o;
    o.max_edge = 0.5f;
    std::vector<BakedMesh> m = refine_for_bake(s, o);
    const GBuffer gb = vertex_points(m);
    std::vector<Vec3f> direct(gb.n_hits()), indirect(gb.n_hits());
    for (size_t k = 0; k < gb.n_hits(); ++k) direct[k] = Vec3f(1.f + gb.position[k].x), indirect[k] = Vec3f(0.5f, 0.25f, gb.position[k].z);
    compose_bake(m, direct, indirect);
    const Vec3f rho(0.5f, 0.4f, 0.3f);
    for (size_t v = 0; v < m[0].position.size(); ++v)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(m[0].radiance[v][c], rho[c] / 3.14159265f * (direct[v][c] + indirect[v][c]), 1e-6f);
    EXPECT_NEAR(m[1].radiance[0].x, 4.f + 0.8f / 3.14159265f * (direct[m[0].position.size()].x + 0.5f), 1e-5f);   // the light's Le + its reflection
    test::TempDir dir;
    const std::string path = dir.path("floor.glb");
    Scene with_camera = s;
    Camera cam;
    cam.name = "main", cam.eye = {1.f, 1.f, 3.f}, cam.target = {1.f, 0.f, 1.f};
    with_camera.cameras.push_back(cam);
    write_bake_glb(path, with_camera, m, 1.f, "test");
    tinygltf::Model g;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    ASSERT_TRUE(loader.LoadBinaryFromFile(&g, &err, &warn, path)) << err;
    ASSERT_EQ(g.meshes.size(), 2u);
    EXPECT_NE(std::find(g.extensionsUsed.begin(), g.extensionsUsed.end(), "KHR_materials_unlit"), g.extensionsUsed.end());
    const tinygltf::Primitive &p = g.meshes[0].primitives[0];
    for (const char *attr : {"POSITION", "NORMAL", "COLOR_0", "_RADIANCE", "_IRRADIANCE_INDIRECT"}) ASSERT_TRUE(p.attributes.count(attr)) << attr;
    const tinygltf::Accessor &ra = g.accessors[size_t(p.attributes.at("_RADIANCE"))];
    ASSERT_EQ(ra.count, m[0].position.size());
    const tinygltf::BufferView &view = g.bufferViews[size_t(ra.bufferView)];
    const auto *values = reinterpret_cast<const float *>(g.buffers[0].data.data() + view.byteOffset + ra.byteOffset);
    for (size_t v = 0; v < ra.count; ++v)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(values[3 * v + size_t(c)], m[0].radiance[v][c]);
    const tinygltf::Accessor &pa = g.accessors[size_t(p.attributes.at("POSITION"))];
    EXPECT_EQ(pa.minValues, (std::vector<double>{0.0, 0.0, 0.0}));
    EXPECT_EQ(pa.maxValues, (std::vector<double>{2.0, 0.0, 2.0}));
    // ltm's own glTF reader reads the geometry back, and the camera: same eye and view direction.
    const Scene back = load_scene(path);
    ASSERT_EQ(back.cameras.size(), 1u);
    EXPECT_LT(length(back.cameras[0].eye - cam.eye), 1e-5f);
    EXPECT_GT(dot(normalize(back.cameras[0].target - back.cameras[0].eye), normalize(cam.target - cam.eye)), 0.99999f);
    EXPECT_EQ(back.meshes.size(), 2u);
    EXPECT_EQ(back.meshes[0].n_triangles(), m[0].indices.size() / 3);
    EXPECT_GT(max_component(back.materials[size_t(back.meshes[1].material)].emission.color_a), 3.99f);   // the light still emits
    // An unwritable path: one error, no file.
    EXPECT_THROW(write_bake_glb(dir.path("missing/floor.glb"), s, m, 1.f, "test"), Error);
    EXPECT_FALSE(std::filesystem::exists(dir.path("missing/floor.glb.tmp")));
}

// Values linear in position are interpolated exactly: the view of the bake at each pixel is the
// value at the pixel's hit point, which the scene's own G-buffer gives.
TEST(GiBake, ViewInterpolatesTheVerticesAtEachPixelsHit) {
    const Scene s = floor_scene();
    RefineOptions o;
    o.max_edge = 0.4f;
    std::vector<BakedMesh> m = refine_for_bake(s, o);
    const GBuffer vp = vertex_points(m);
    std::vector<Vec3f> zero(vp.n_hits(), Vec3f(0.f)), lin(vp.n_hits());
    for (size_t k = 0; k < vp.n_hits(); ++k) lin[k] = Vec3f(vp.position[k].x, vp.position[k].z, 1.f);
    compose_bake(m, zero, lin);
    Camera cam;
    cam.eye = {1.f, 1.2f, 3.f}, cam.target = {1.f, 0.f, 1.f}, cam.width = cam.height = 24, cam.fov_y_deg = 60.f;
    const BakeView view = view_bake(m, cam);
    const EmbreeAccel accel(s);
    const GBuffer gb = render_gbuffer(accel, cam);
    int checked = 0;
    for (size_t h = 0; h < gb.n_hits(); ++h) {
        const int64_t px = gb.hit_pixels[h];
        if (gb.emitted[h].x > 0.f) continue;   // the light
        ASSERT_TRUE(view.hit[size_t(px)]);
        const Vec3f e = view.irradiance_indirect.at(int(px % 24), int(px / 24));
        EXPECT_NEAR(e.x, gb.position[h].x, 1e-4f);
        EXPECT_NEAR(e.y, gb.position[h].z, 1e-4f);
        ++checked;
    }
    EXPECT_GT(checked, 100);
}
