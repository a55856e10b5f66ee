// cmd_info.cpp: `ltm info <scene>`: what a scene file holds (counts, bounds, lights, cameras).
#include <iostream>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "ltm/scene/scene_io.h"

namespace ltm::cli {

Command make_info_command() {
    auto path = std::make_shared<std::string>();
    Command c;
    c.name = "info";
    c.help = "Describe a scene (json, obj or builtin:<name>)";
    c.setup = [path](CLI::App &sub, CommonOptions &) {
        sub.add_option("input", *path, "Scene file")->required();
    };
    c.run = [path](const CommonOptions &) {
        ValidateOptions opt;
        opt.require_emitter = false;
        const Scene s = load_scene(*path, opt);
        const Bounds3f b = s.bounds();
        double emissive_area = 0;
        for (const auto &m : s.meshes)
            if (s.materials[size_t(m.material)].is_emissive())
                for (size_t t = 0; t < m.n_triangles(); ++t) emissive_area += m.area(t);
        std::cout << "scene      " << s.name << "\n"
                  << "meshes     " << s.meshes.size() << "\n"
                  << "triangles  " << s.n_triangles() << "\n"
                  << "materials  " << s.materials.size() << "\n"
                  << "area       " << s.total_area() << " m² (" << emissive_area << " m² emissive)\n"
                  << "bounds     " << b.lo << " - " << b.hi << " m\n"
                  << "cameras    " << s.cameras.size() << "\n";
        if (!s.has_emitter()) std::cout << "warning    no emitter: this scene renders black\n";
        if (!s.metadata.empty()) std::cout << "metadata   " << s.metadata.dump().substr(0, 200) << "\n";
    };
    return c;
}

}  // namespace ltm::cli
