// pbrt_writer.h (tests only): a Scene of constant diffuse materials written as pbrt-v4 text, as
// Bitterli's scenes are written ("Scale -1 1 1" + LookAt, one trianglemesh with normals per mesh,
// indices in the opposite winding so the normals decide) — optionally in another unit and with z
// up, to check that the reader brings any twin back to the same metric y-up scene.
#pragma once

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "ltm/scene/scene.h"

namespace ltm::test {

/// scale: positions × scale (a unit change); z_up: the world turned +90° about x (y → z), the
/// camera's up vector with it.
inline std::string pbrt_text(const Scene &scene, float scale = 1.f, bool z_up = false) {
    const auto world = [&](Vec3f p) { return z_up ? Vec3f(p.x, -p.z, p.y) * scale : p * scale; };
    const auto dir = [&](Vec3f d) { return z_up ? Vec3f(d.x, -d.z, d.y) : d; };
    const auto put = [](std::ostringstream &f, Vec3f v) { f << v.x << " " << v.y << " " << v.z << " "; };
    std::ostringstream f;
    f.precision(9);
    const Camera &c = scene.cameras.at(0);
    f << "Scale -1 1 1\nLookAt ";
    put(f, world(c.eye));
    put(f, world(c.target));
    put(f, dir(c.up));
    f << "\nCamera \"perspective\" \"float fov\" " << c.fov_y_deg << "\nFilm \"rgb\" \"integer xresolution\" " << c.width
      << " \"integer yresolution\" " << c.height << "\nWorldBegin\n";
    for (const TriangleMesh &m : scene.meshes) {
        const Material &mat = scene.materials[size_t(m.material)];
        f << "AttributeBegin\nMaterial \"diffuse\" \"rgb reflectance\" [";
        put(f, mat.albedo.color_a);
        f << "]\n";
        if (mat.is_emissive()) {
            f << "AreaLightSource \"diffuse\" \"rgb L\" [";
            put(f, mat.emission.color_a);
            f << "]\n";
        }
        f << "Shape \"trianglemesh\" \"point3 P\" [";
        for (const Vec3f &p : m.positions) put(f, world(p));
        f << "] \"integer indices\" [";
        for (size_t t = 0; t < m.n_triangles(); ++t)   // the opposite winding: N decides
            f << m.indices[3 * t] << " " << m.indices[3 * t + 2] << " " << m.indices[3 * t + 1] << " ";
        f << "] \"normal N\" [";
        std::vector<Vec3f> vn(m.positions.size(), Vec3f(0.f));
        for (size_t t = 0; t < m.n_triangles(); ++t)
            for (int k = 0; k < 3; ++k) vn[m.indices[3 * t + size_t(k)]] += normalize(m.cross_normal(t));
        for (const Vec3f &n : vn) put(f, dir(n));
        f << "]\nAttributeEnd\n";
    }
    return f.str();
}

}  // namespace ltm::test
