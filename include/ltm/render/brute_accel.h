// brute_accel.h: O(n) reference intersector (Möller–Trumbore in double precision). Tests use it
// to check EmbreeAccel; nothing else should.
#pragma once

#include <optional>

#include "ltm/render/ray.h"
#include "ltm/scene/scene.h"

namespace ltm {

class BruteAccel {
public:
    explicit BruteAccel(const Scene &scene) : m_scene(scene) {}
    std::optional<Hit> intersect(const Ray &ray) const;
    bool occluded(const Ray &ray) const { return intersect(ray).has_value(); }

private:
    const Scene &m_scene;
};

}  // namespace ltm
