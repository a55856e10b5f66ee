// material.cpp: the named metals' F0.
#include "ltm/scene/material.h"

namespace ltm {

// F0 (linear sRGB) of the metals pbrt-v4 names as "metal-<X>-eta"/"-k" spectra, from their
// complex refractive indices at ~650/550/450 nm ((n−1)²+k²)/((n+1)²+k²).
const std::map<std::string, Vec3f> &named_metal_f0() {
    static const std::map<std::string, Vec3f> m = {
        {"Ag", {0.97f, 0.96f, 0.92f}}, {"Al", {0.91f, 0.92f, 0.92f}}, {"Au", {0.98f, 0.78f, 0.35f}},
        {"Cu", {0.96f, 0.64f, 0.54f}}, {"CuZn", {0.94f, 0.79f, 0.51f}}, {"MgO", {0.07f, 0.07f, 0.07f}},
        {"TiO2", {0.20f, 0.22f, 0.27f}}};
    return m;
}

}  // namespace ltm
