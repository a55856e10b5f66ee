// camera.h: pinhole look-at cameras (y up).
#pragma once

#include <string>

#include "ltm/core/math.h"

namespace ltm {

struct Camera {
    std::string name = "main";
    Vec3f eye{0.f, 1.5f, 3.f};
    Vec3f target{0.f, 1.f, 0.f};
    Vec3f up{0.f, 1.f, 0.f};
    float fov_y_deg = 60.f;   ///< vertical field of view
    int width = 512, height = 512;

    /// World-space direction (unit) through raster position (px, py), (0,0) = top-left corner.
    Vec3f ray_direction(float px, float py) const;
};

}  // namespace ltm
