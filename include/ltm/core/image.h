// image.h: float RGB images in linear space, PNG output (tone mapped sRGB) and texture input.
#pragma once

#include <string>
#include <vector>

#include "ltm/core/math.h"

namespace ltm {

/// Row-major linear RGB image, (0,0) = top-left.
struct Image {
    int width = 0, height = 0;
    std::vector<Vec3f> pixels;
    Image() = default;
    Image(int w, int h) : width(w), height(h), pixels(size_t(w) * size_t(h)) {}
    Vec3f &at(int x, int y) { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
    const Vec3f &at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
};

/// Writes an 8-bit sRGB PNG of exposure-scaled linear values (clamped), atomically.
void write_png(const std::string &path, const Image &img, float exposure = 1.f);

/// Reads PNG/JPEG/TGA/BMP (8-bit sRGB, decoded to linear) or EXR (linear RGB).
/// `srgb = false` takes 8-bit values as linear (data textures).
Image read_image(const std::string &path, bool srgb = true);

}  // namespace ltm
