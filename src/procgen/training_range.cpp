// training_range.cpp: the generated houses' proportions and extent, as a check on other scenes.
#include "ltm/procgen/training_range.h"

#include <algorithm>

#include "ltm/core/error.h"

namespace ltm {

std::vector<std::string> scene_range_warnings(const Scene &scene, bool unit_free) {
    // The generator's houses (configs/gen/indoor.json): footprints 2.5–11.2 m, ceilings 2.5–3.2 m.
    std::vector<std::string> w;
    const Vec3f e = scene.bounds().extent();
    const float horizontal = std::max(e.x, e.z);
    if (unit_free) {
        const float ratio = horizontal / std::max(e.y, 1e-30f);
        if (!(ratio >= 0.75f && ratio <= 4.6f))
            w.push_back(detail::concat("scene proportions (footprint / height = ", ratio, ", extent ", e.x, " x ", e.y, " x ", e.z,
                                       ") are outside the training range (0.75-4.6, y up): expect larger errors"));
        return w;
    }
    if (horizontal > 14.f || horizontal < 1.5f || e.y > 4.f || e.y < 1.5f)
        w.push_back(detail::concat("scene extent ", e.x, " x ", e.y, " x ", e.z,
                           " m is outside the training range (footprint 2.5-11.2 m, height 2.5-3.2 m, y up): "
                           "expect larger errors"));
    return w;
}

}  // namespace ltm
