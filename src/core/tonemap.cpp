// tonemap.cpp: see tonemap.h.
#include "ltm/core/tonemap.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "ltm/core/color.h"
#include "ltm/core/error.h"

namespace ltm {

namespace {
void check_finite_image(const Image &img, const char *fn) {
    if (img.width <= 0 || img.height <= 0) LTM_THROW(fn, "(): image is empty (", img.width, "x", img.height, ")");
    LTM_CHECK_EQ(img.pixels.size(), size_t(img.width) * size_t(img.height));
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (!is_finite(img.at(x, y))) LTM_THROW(fn, "(): image has a non-finite pixel at (", x, ", ", y, ")");
}
}  // namespace

float tonemap_scale(const Image &reference) {
    check_finite_image(reference, "tonemap_scale");
    std::vector<float> lum(reference.pixels.size());
    for (size_t i = 0; i < lum.size(); ++i) lum[i] = luminance(reference.pixels[i]);
    const size_t k = size_t(std::floor(0.99 * double(lum.size() - 1)));
    std::nth_element(lum.begin(), lum.begin() + std::ptrdiff_t(k), lum.end());
    // Below the smallest normal float, 1/p would overflow: treat as black.
    const float p = lum[k];
    return p > std::numeric_limits<float>::min() ? 1.f / p : 1.f;
}

Image tonemap(const Image &img, float scale) {
    check_finite_image(img, "tonemap");
    if (!(std::isfinite(scale) && scale >= 0)) LTM_THROW("tonemap(): scale must be finite and >= 0, got ", scale);
    Image out(img.width, img.height);
    for (size_t i = 0; i < img.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) out.pixels[i][c] = clamp(img.pixels[i][c] * scale, 0.f, 1.f);
    return out;
}

}  // namespace ltm
