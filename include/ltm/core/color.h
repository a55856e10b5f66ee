// color.h: sRGB transfer functions and black-body colours (for ceiling light temperatures).
#pragma once

#include <cmath>

#include "ltm/core/math.h"

namespace ltm {

inline float srgb_to_linear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}
inline float linear_to_srgb(float c) {
    c = clamp(c, 0.f, 1.f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.f / 2.4f) - 0.055f;
}
inline Vec3f srgb_to_linear(Vec3f c) {
    return {srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z)};
}

/// Linear-sRGB colour of a black body at `kelvin` (Planck's law integrated against the CIE 1931
/// 2° observer, Wyman et al. 2013 fit), scaled to luminance 1. Valid for 1000–40000 K.
Vec3f blackbody_rgb(float kelvin);

}  // namespace ltm
