// obj_io_test.cpp: OBJ+MTL import: the Cornell box file has the measured areas and emission.
#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/obj_io.h"
#include "ltm/scene/scene_loader.h"
#include "test_util.h"

using namespace ltm;

namespace {
double material_area(const Scene &s, const std::string &name) {
    double a = 0;
    for (const auto &m : s.meshes)
        if (s.materials[size_t(m.material)].name == name)
            for (size_t t = 0; t < m.n_triangles(); ++t) a += m.area(t);
    return a;
}
}  // namespace

// Light: 130 mm × 105 mm; red wall: a planar quadrilateral whose area follows from its corners;
// both files and the built-in describe the same box, so every material's area agrees.
TEST(ObjIo, CornellBoxHasTheRightAreasAndEmission) {
    const Scene s = load_scene(test::source_path("examples/cornell-box/cornell-box.obj"));
    EXPECT_NEAR(material_area(s, "light"), 0.130 * 0.105, 1e-6);
    const int light = s.find_material("light");
    ASSERT_GE(light, 0);
    EXPECT_EQ(s.materials[size_t(light)].emission.color_a, Vec3f(17.f, 12.f, 4.f));
    EXPECT_EQ(s.materials[size_t(s.find_material("red"))].albedo.color_a, Vec3f(0.63f, 0.065f, 0.05f));
    EXPECT_FALSE(s.materials[size_t(s.find_material("white"))].is_emissive());
    const Scene b = cornell_box();
    for (const char *m : {"white", "red", "green", "light"}) EXPECT_NEAR(material_area(s, m), material_area(b, m), 2e-4) << m;
    // Floor quad (552.8,0,0) (0,0,0) (0,0,559.2) (549.6,0,559.2) mm: shoelace ½·559.2·(549.6+552.8).
    double floor_area = 0;
    for (const auto &m : s.meshes)
        if (m.name == "floor")
            for (size_t t = 0; t < m.n_triangles(); ++t) floor_area += m.area(t);
    EXPECT_NEAR(floor_area, 0.5 * 0.5592 * (0.5496 + 0.5528), 1e-5);
}

TEST(ObjIo, MalformedFilesAreErrors) {
    test::TempDir dir;
    write_file_atomic(dir.path("bad.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 9\n");
    EXPECT_THROW(load_obj(dir.path("bad.obj")), Error);
    write_file_atomic(dir.path("nomtl.obj"), "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_THROW(load_obj(dir.path("nomtl.obj")), Error);
    EXPECT_THROW(load_obj(dir.path("absent.obj")), Error);
}
