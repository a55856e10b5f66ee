// image_grid_test.cpp: tile placement, gap colour and sizes of hconcat / vconcat; resize_nearest.
#include <gtest/gtest.h>

#include <vector>

#include "ltm/core/error.h"
#include "ltm/eval/image_grid.h"

using namespace ltm;

namespace {

// Every pixel distinct: (tile id, x, y) encoded in the channels.
Image labelled_tile(int w, int h, float id) {
    Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) img.at(x, y) = {id, float(x), float(y)};
    return img;
}

}  // namespace

TEST(ImageGrid, HconcatPlacesTilesLeftToRightWithGaps) {
    const Vec3f gap_color(0.f, 0.f, 9.f);
    const std::vector<Image> tiles = {labelled_tile(3, 2, 1.f), labelled_tile(4, 2, 2.f),
                                      labelled_tile(1, 2, 3.f)};
    const Image out = hconcat(tiles, /*gap=*/2, gap_color);
    ASSERT_EQ(out.width, 3 + 2 + 4 + 2 + 1);
    ASSERT_EQ(out.height, 2);
    const int offsets[3] = {0, 5, 11};
    for (size_t t = 0; t < tiles.size(); ++t)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < tiles[t].width; ++x)
                EXPECT_EQ(out.at(offsets[t] + x, y), tiles[t].at(x, y)) << t << " " << x << " " << y;
    for (int x : {3, 4, 9, 10})
        for (int y = 0; y < 2; ++y) EXPECT_EQ(out.at(x, y), gap_color) << x;
}

TEST(ImageGrid, VconcatPlacesTilesTopToBottomWithGaps) {
    const std::vector<Image> tiles = {labelled_tile(3, 2, 1.f), labelled_tile(3, 5, 2.f)};
    const Image out = vconcat(tiles, /*gap=*/1);   // default gap colour: white
    ASSERT_EQ(out.width, 3);
    ASSERT_EQ(out.height, 2 + 1 + 5);
    for (int x = 0; x < 3; ++x) {
        for (int y = 0; y < 2; ++y) EXPECT_EQ(out.at(x, y), tiles[0].at(x, y));
        EXPECT_EQ(out.at(x, 2), Vec3f(1.f));
        for (int y = 0; y < 5; ++y) EXPECT_EQ(out.at(x, 3 + y), tiles[1].at(x, y));
    }
}

TEST(ImageGrid, SingleTileWithoutGapIsUnchanged) {
    const Image tile = labelled_tile(4, 3, 1.f);
    for (const Image &out : {hconcat({tile}), vconcat({tile}), hconcat({tile, tile}, /*gap=*/0)}) {
        ASSERT_EQ(out.height, 3);
        for (int y = 0; y < 3; ++y)
            for (int x = 0; x < 4; ++x) EXPECT_EQ(out.at(x, y), tile.at(x, y));
    }
}

TEST(ImageGrid, MismatchedOrEmptyTilesThrow) {
    EXPECT_THROW(hconcat({labelled_tile(3, 2, 1.f), labelled_tile(3, 4, 2.f)}), Error);
    EXPECT_THROW(vconcat({labelled_tile(3, 2, 1.f), labelled_tile(4, 2, 2.f)}), Error);
    EXPECT_THROW(hconcat({}), Error);
    EXPECT_THROW(vconcat({labelled_tile(3, 2, 1.f), Image()}), Error);
    EXPECT_THROW(hconcat({labelled_tile(3, 2, 1.f)}, /*gap=*/-1), Error);
}

TEST(ImageGrid, ResizeNearestReplicatesOnIntegerUpscale) {
    const Image img = labelled_tile(2, 2, 1.f);
    const Image up = resize_nearest(img, 4, 6);
    ASSERT_EQ(up.width, 4);
    ASSERT_EQ(up.height, 6);
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 4; ++x) EXPECT_EQ(up.at(x, y), img.at(x / 2, y / 3)) << x << " " << y;
}

TEST(ImageGrid, ResizeNearestDownscaleTakesThePixelUnderEachCentre) {
    const Image img = labelled_tile(6, 4, 1.f);
    const Image down = resize_nearest(img, 3, 2);   // centres at source x = 1, 3, 5; y = 1, 3
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) EXPECT_EQ(down.at(x, y), img.at(2 * x + 1, 2 * y + 1));
    const Image same = resize_nearest(img, 6, 4);
    for (size_t i = 0; i < img.pixels.size(); ++i) EXPECT_EQ(same.pixels[i], img.pixels[i]);
    EXPECT_THROW(resize_nearest(img, 0, 4), Error);
    EXPECT_THROW(resize_nearest(Image(), 2, 2), Error);
}
