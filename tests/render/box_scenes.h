// box_scenes.h: the unit furnace box with axis-aligned boxes standing in it — coincident faces
// for the intersector's and the enclosure test's tests.
#pragma once

#include <initializer_list>
#include <string>

#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/mesh_builder.h"

namespace ltm::test {

struct Box {
    Vec3f lo, hi;
};

/// furnace_box(0.5, 1) (mesh 0) and one mesh per box with outward faces, meshes 1, 2, … in the
/// order given, all of the furnace's material.
inline Scene furnace_with_boxes(std::initializer_list<Box> boxes) {
    Scene s = furnace_box(0.5f, 1.f);
    for (const Box &b : boxes) {
        TriangleMesh m;
        m.name = "box" + std::to_string(s.meshes.size());
        m.material = s.meshes[0].material;
        add_box(m, b.lo, b.hi);
        s.meshes.push_back(m);
    }
    return s;
}

}  // namespace ltm::test
