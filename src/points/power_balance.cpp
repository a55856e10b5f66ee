// power_balance.cpp: π · mean(e_c) · Σ_{k=1..D} mean(ρ_c)^k over area-uniform scene points.
#include "ltm/points/power_balance.h"

#include <algorithm>

#include "ltm/core/error.h"
#include "ltm/core/math.h"

namespace ltm {

std::array<double, 3> power_balance_irradiance(const PointSet &sp, int bounces) {
    if (sp.columns != scene_point_columns()) LTM_THROW("power_balance_irradiance: not a scene point table");
    if (sp.size() == 0) LTM_THROW("power_balance_irradiance: no scene points");
    if (bounces < 0) LTM_THROW("power_balance_irradiance: bounces must be >= 0, got ", bounces);
    std::array<double, 3> rho{0, 0, 0}, e{0, 0, 0}, out{0, 0, 0};
    for (size_t i = 0; i < sp.size(); ++i)
        for (size_t c = 0; c < 3; ++c) rho[c] += double(sp.at(i, 6 + c)), e[c] += double(sp.at(i, 9 + c));
    for (size_t c = 0; c < 3; ++c) {
        const double r = std::clamp(rho[c] / double(sp.size()), 0.0, 1.0);
        double term = 1, series = 0;
        for (int k = 0; k < bounces; ++k) series += (term *= r);
        out[c] = double(k_pi) * e[c] / double(sp.size()) * series;
    }
    return out;
}

}  // namespace ltm
