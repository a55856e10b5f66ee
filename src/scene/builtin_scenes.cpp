// builtin_scenes.cpp: analytic scenes for tests and docs. Geometry in metres, y up.
#include "ltm/scene/builtin_scenes.h"

#include "ltm/core/error.h"
#include "ltm/scene/mesh_builder.h"

namespace ltm {

namespace {
Material diffuse(const std::string &name, Vec3f albedo) {
    Material m;
    m.name = name;
    m.albedo = Texture::constant(albedo);
    return m;
}
Material emitter(const std::string &name, Vec3f radiance, Vec3f albedo = Vec3f(0.f)) {
    Material m = diffuse(name, albedo);
    m.emission = Texture::constant(radiance);
    return m;
}
TriangleMesh named_mesh(const std::string &name, int material) {
    TriangleMesh m;
    m.name = name;
    m.material = material;
    return m;
}
Vec3f mm(float x, float y, float z) { return {x * 1e-3f, y * 1e-3f, z * 1e-3f}; }
Camera looking_at(Vec3f eye, Vec3f target, float fov_y_deg) {
    Camera cam;
    cam.eye = eye;
    cam.target = target;
    cam.fov_y_deg = fov_y_deg;
    return cam;
}
// Reverses every triangle's winding: add_box's outward faces become a room's inward ones.
void flip_winding(TriangleMesh &m) {
    for (size_t t = 0; t < m.n_triangles(); ++t) std::swap(m.indices[3 * t + 1], m.indices[3 * t + 2]);
}
}  // namespace

Scene cornell_box() {
    // Cornell PCG measured data (mm). Walls face the box centre, blocks face outward.
    Scene s;
    s.name = "cornell-box";
    const int white = s.add_material(diffuse("white", {0.725f, 0.71f, 0.68f}));
    const int red = s.add_material(diffuse("red", {0.63f, 0.065f, 0.05f}));
    const int green = s.add_material(diffuse("green", {0.14f, 0.45f, 0.091f}));
    const int light = s.add_material(emitter("light", {17.f, 12.f, 4.f}, {0.78f, 0.78f, 0.78f}));
    const Vec3f inside = mm(278.f, 274.4f, 279.6f);

    TriangleMesh floor = named_mesh("floor", white), ceiling = named_mesh("ceiling", white);
    TriangleMesh back = named_mesh("back_wall", white), left = named_mesh("left_wall", red);
    TriangleMesh right = named_mesh("right_wall", green);
    add_quad_facing(floor, mm(552.8f, 0, 0), mm(0, 0, 0), mm(0, 0, 559.2f), mm(549.6f, 0, 559.2f), inside);
    add_quad_facing(ceiling, mm(556, 548.8f, 0), mm(556, 548.8f, 559.2f), mm(0, 548.8f, 559.2f), mm(0, 548.8f, 0), inside);
    add_quad_facing(back, mm(549.6f, 0, 559.2f), mm(0, 0, 559.2f), mm(0, 548.8f, 559.2f), mm(556, 548.8f, 559.2f), inside);
    add_quad_facing(right, mm(0, 0, 559.2f), mm(0, 0, 0), mm(0, 548.8f, 0), mm(0, 548.8f, 559.2f), inside);
    add_quad_facing(left, mm(552.8f, 0, 0), mm(549.6f, 0, 559.2f), mm(556, 548.8f, 559.2f), mm(556, 548.8f, 0), inside);

    TriangleMesh lamp = named_mesh("light", light);
    add_quad_facing(lamp, mm(343, 548.7f, 227), mm(343, 548.7f, 332), mm(213, 548.7f, 332), mm(213, 548.7f, 227), mm(278, 0, 280));

    auto block = [&](const std::string &name, const Vec3f top[4], float h) {
        TriangleMesh m = named_mesh(name, white);
        Vec3f c(0.f);
        for (int i = 0; i < 4; ++i) c += top[i] * 0.25f;
        c.y = h * 0.5f;
        const Vec3f up_far = c + Vec3f(0, 10, 0);
        add_quad_facing(m, top[0], top[1], top[2], top[3], up_far);
        for (int i = 0; i < 4; ++i) {
            const Vec3f a = top[i], b = top[(i + 1) % 4];
            const Vec3f a0{a.x, 0.f, a.z}, b0{b.x, 0.f, b.z};
            const Vec3f out = c + ((a + b) * 0.5f - c) * 4.f;   // beyond the face, outward
            add_quad_facing(m, a0, b0, b, a, Vec3f(out.x, c.y, out.z));
        }
        return m;
    };
    const Vec3f short_top[4] = {mm(130, 165, 65), mm(82, 165, 225), mm(240, 165, 272), mm(290, 165, 114)};
    const Vec3f tall_top[4] = {mm(423, 330, 247), mm(265, 330, 296), mm(314, 330, 456), mm(472, 330, 406)};
    s.meshes = {floor, ceiling, back, right, left, lamp, block("short_block", short_top, 0.165f),
                block("tall_block", tall_top, 0.33f)};

    s.cameras.push_back(looking_at(mm(278, 273, -800), mm(278, 273, 0), 39.3077f));
    return s;
}

Scene furnace_box(float albedo, float emission) {
    Scene s;
    s.name = "furnace";
    const int m = s.add_material(emitter("furnace", Vec3f(emission), Vec3f(albedo)));
    TriangleMesh box = named_mesh("box", m);
    add_box(box, Vec3f(0.f), Vec3f(1.f));
    flip_winding(box);
    s.meshes.push_back(box);
    s.cameras.push_back(looking_at({0.5f, 0.5f, 0.95f}, {0.5f, 0.5f, 0.f}, 90.f));
    return s;
}

Scene quad_light_room() {
    Scene s;
    s.name = "quad-light-room";
    const int wall = s.add_material(diffuse("wall", {0.7f, 0.7f, 0.68f}));
    const int floor_m = s.add_material(diffuse("floor", {0.45f, 0.3f, 0.2f}));
    const int box_m = s.add_material(diffuse("box", {0.2f, 0.35f, 0.6f}));
    const int light = s.add_material(emitter("light", Vec3f(15.f)));
    const Vec3f lo{0, 0, 0}, hi{5.f, 2.7f, 4.f};
    TriangleMesh shell = named_mesh("walls", wall), floor = named_mesh("floor", floor_m);
    add_box(shell, lo, hi);
    // Inward-facing room: flip the box; then move the floor (the -y face) to its own mesh.
    flip_winding(shell);
    TriangleMesh walls = named_mesh("walls", wall);
    for (size_t t = 0; t < shell.n_triangles(); ++t) {
        TriangleMesh &dst = shell.cross_normal(t).y > 0.5f ? floor : walls;
        for (int k = 0; k < 3; ++k) {
            dst.indices.push_back(uint32_t(dst.positions.size()));
            dst.positions.push_back(shell.vertex(t, k));
            dst.uvs.push_back(shell.uv(t, k));
        }
    }
    TriangleMesh lamp = named_mesh("light", light);
    add_quad_facing(lamp, {2.f, 2.699f, 1.5f}, {3.f, 2.699f, 1.5f}, {3.f, 2.699f, 2.5f}, {2.f, 2.699f, 2.5f}, {2.5f, 0.f, 2.f});
    TriangleMesh box = named_mesh("box", box_m);
    add_box(box, {3.2f, 0.f, 0.8f}, {4.0f, 0.9f, 1.6f});
    s.meshes = {walls, floor, lamp, box};
    s.cameras.push_back(looking_at({0.4f, 1.6f, 3.6f}, {3.5f, 0.8f, 1.0f}, 65.f));
    return s;
}

std::vector<std::string> builtin_scene_names() { return {"cornell-box", "furnace", "quad-light-room"}; }

Scene builtin_scene(const std::string &name) {
    if (name == "cornell-box") return cornell_box();
    if (name == "furnace") return furnace_box(0.5f, 1.f);
    if (name == "quad-light-room") return quad_light_room();
    std::string known;
    for (const auto &n : builtin_scene_names()) known += (known.empty() ? "" : ", ") + n;
    LTM_THROW("builtin:", name, ": unknown built-in scene (known: ", known, ")");
}

}  // namespace ltm
