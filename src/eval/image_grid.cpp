// image_grid.cpp: hconcat / vconcat / resize_nearest; see image_grid.h.
#include "ltm/eval/image_grid.h"

#include <algorithm>
#include <cstdint>

#include "ltm/core/error.h"

namespace ltm {

namespace {

// Shared by hconcat (horizontal = true) and vconcat: tiles are laid along one axis and must
// agree in the other.
Image concat(const std::vector<Image> &tiles, int gap, Vec3f gap_color, bool horizontal) {
    const char *fn = horizontal ? "hconcat" : "vconcat";
    if (tiles.empty()) LTM_THROW(fn, "(): no tiles");
    if (gap < 0) LTM_THROW(fn, "(): gap must be >= 0, got ", gap);
    const auto across = [&](const Image &t) { return horizontal ? t.height : t.width; };
    const auto along = [&](const Image &t) { return horizontal ? t.width : t.height; };
    int length = gap * int(tiles.size() - 1);
    for (size_t i = 0; i < tiles.size(); ++i) {
        const Image &t = tiles[i];
        if (t.width <= 0 || t.height <= 0) LTM_THROW(fn, "(): tile ", i, " is empty");
        if (across(t) != across(tiles[0]))
            LTM_THROW(fn, "(): tile ", i, " is ", t.width, "x", t.height, " but tile 0 is ",
                      tiles[0].width, "x", tiles[0].height, " (", horizontal ? "heights" : "widths",
                      " must match)");
        length += along(t);
    }
    Image out = horizontal ? Image(length, tiles[0].height) : Image(tiles[0].width, length);
    std::fill(out.pixels.begin(), out.pixels.end(), gap_color);
    int offset = 0;
    for (const Image &t : tiles) {
        for (int y = 0; y < t.height; ++y)
            for (int x = 0; x < t.width; ++x)
                out.at(horizontal ? offset + x : x, horizontal ? y : offset + y) = t.at(x, y);
        offset += along(t) + gap;
    }
    return out;
}

}  // namespace

Image hconcat(const std::vector<Image> &tiles, int gap, Vec3f gap_color) {
    return concat(tiles, gap, gap_color, /*horizontal=*/true);
}

Image vconcat(const std::vector<Image> &tiles, int gap, Vec3f gap_color) {
    return concat(tiles, gap, gap_color, /*horizontal=*/false);
}

Image resize_nearest(const Image &img, int w, int h) {
    if (img.width <= 0 || img.height <= 0) LTM_THROW("resize_nearest(): input image is empty");
    if (w <= 0 || h <= 0) LTM_THROW("resize_nearest(): target size ", w, "x", h, " is not positive");
    Image out(w, h);
    for (int y = 0; y < h; ++y) {
        // Integer form of ⌊(y + ½) · H / h⌋ = ⌊(2y + 1) · H / 2h⌋: exact, no float rounding.
        const int sy = int((2 * int64_t(y) + 1) * img.height / (2 * int64_t(h)));
        for (int x = 0; x < w; ++x) {
            const int sx = int((2 * int64_t(x) + 1) * img.width / (2 * int64_t(w)));
            out.at(x, y) = img.at(sx, sy);
        }
    }
    return out;
}

}  // namespace ltm
