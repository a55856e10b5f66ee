// image.cpp: stb_image(_write) from Debian's libstb (no IMPLEMENTATION macros here) and OpenEXR.
#include "ltm/core/image.h"

#include <cstdint>
#include <filesystem>

#include <ImfRgbaFile.h>
#include <ImfArray.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include "ltm/core/color.h"
#include "ltm/core/error.h"
#include "ltm/core/file_util.h"

namespace ltm {

namespace {
void write_to_stream(void *ctx, void *data, int size) {
    static_cast<std::ostream *>(ctx)->write(static_cast<const char *>(data), size);
}
}  // namespace

void write_png(const std::string &path, const Image &img, float exposure) {
    if (img.width <= 0 || img.height <= 0) LTM_THROW(path, ": cannot write an empty image");
    std::vector<uint8_t> rgb(img.pixels.size() * 3);
    for (size_t i = 0; i < img.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const float v = linear_to_srgb(img.pixels[i][c] * exposure);
            rgb[3 * i + size_t(c)] = uint8_t(std::lround(255.f * v));
        }
    AtomicFile f(path);
    if (!stbi_write_png_to_func(write_to_stream, &f.stream(), img.width, img.height, 3, rgb.data(),
                                img.width * 3))
        LTM_THROW(path, ": PNG encoding failed");
    f.commit();
}

namespace {
Image read_exr(const std::string &path) {
    try {
        Imf::RgbaInputFile file(path.c_str());
        const Imath::Box2i dw = file.dataWindow();
        const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
        Imf::Array2D<Imf::Rgba> px(h, w);
        file.setFrameBuffer(&px[0][0] - dw.min.x - dw.min.y * w, 1, size_t(w));
        file.readPixels(dw.min.y, dw.max.y);
        Image img(w, h);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                img.at(x, y) = {float(px[y][x].r), float(px[y][x].g), float(px[y][x].b)};
        return img;
    } catch (const std::exception &e) {
        LTM_THROW(path, ": cannot read EXR: ", e.what());
    }
}
}  // namespace

Image read_image(const std::string &path, bool srgb) {
    if (!std::filesystem::is_regular_file(path)) LTM_THROW(path, ": image file not found");
    if (file_extension(path) == "exr") return read_exr(path);
    int w = 0, h = 0, n = 0;
    uint8_t *data = stbi_load(path.c_str(), &w, &h, &n, 3);
    if (!data) LTM_THROW(path, ": cannot decode image: ", stbi_failure_reason());
    Image img(w, h);
    for (size_t i = 0; i < img.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const float v = float(data[3 * i + size_t(c)]) / 255.f;
            img.pixels[i][c] = srgb ? srgb_to_linear(v) : v;
        }
    stbi_image_free(data);
    return img;
}

}  // namespace ltm
