// color.cpp: black-body → XYZ → linear sRGB (D65 primaries), numerically integrated over
// 360–830 nm in 1 nm steps. Double precision throughout: the result must be bit-stable.
#include "ltm/core/color.h"

namespace ltm {
namespace {

// Wyman, Sloan, Shirley 2013, "Simple Analytic Approximations to the CIE XYZ Colour Matching
// Functions", multi-lobe piecewise Gaussian fit (their Eq. 2).
double g(double x, double mu, double s1, double s2) {
    const double t = (x - mu) / (x < mu ? s1 : s2);
    return std::exp(-0.5 * t * t);
}
double cie_x(double l) {
    return 1.056 * g(l, 599.8, 37.9, 31.0) + 0.362 * g(l, 442.0, 16.0, 26.7) -
           0.065 * g(l, 501.1, 20.4, 26.2);
}
double cie_y(double l) { return 0.821 * g(l, 568.8, 46.9, 40.5) + 0.286 * g(l, 530.9, 16.3, 31.1); }
double cie_z(double l) { return 1.217 * g(l, 437.0, 11.8, 36.0) + 0.681 * g(l, 459.0, 26.0, 13.8); }

double planck(double lambda_nm, double kelvin) {
    const double c = 299792458.0, h = 6.62607015e-34, kb = 1.380649e-23;
    const double l = lambda_nm * 1e-9;
    return 2.0 * h * c * c / (l * l * l * l * l) / (std::exp(h * c / (l * kb * kelvin)) - 1.0);
}

}  // namespace

Vec3f blackbody_rgb(float kelvin) {
    double X = 0, Y = 0, Z = 0;
    for (int l = 360; l <= 830; ++l) {
        const double b = planck(l, kelvin);
        X += b * cie_x(l), Y += b * cie_y(l), Z += b * cie_z(l);
    }
    X /= Y, Z /= Y, Y = 1.0;
    // XYZ -> linear sRGB (IEC 61966-2-1).
    double r = 3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z;
    double gg = -0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z;
    double b = 0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z;
    // Out-of-gamut (very warm) colours: clip negatives, then renormalise luminance to 1.
    r = std::max(r, 0.0), gg = std::max(gg, 0.0), b = std::max(b, 0.0);
    const double lum = 0.2126 * r + 0.7152 * gg + 0.0722 * b;
    return {float(r / lum), float(gg / lum), float(b / lum)};
}

}  // namespace ltm
