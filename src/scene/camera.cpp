// camera.cpp: pinhole ray directions.
#include "ltm/scene/camera.h"

#include <cmath>

namespace ltm {

Vec3f Camera::ray_direction(float px, float py) const {
    const Vec3f forward = normalize(target - eye);
    const Vec3f right = normalize(cross(forward, up));
    const Vec3f true_up = cross(right, forward);
    const float tan_half = std::tan(0.5f * fov_y_deg * k_pi / 180.f);
    const float aspect = float(width) / float(height);
    const float sx = (2.f * px / float(width) - 1.f) * tan_half * aspect;
    const float sy = (1.f - 2.f * py / float(height)) * tan_half;
    return normalize(forward + right * sx + true_up * sy);
}

}  // namespace ltm
