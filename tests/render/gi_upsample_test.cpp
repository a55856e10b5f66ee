// gi_upsample_test.cpp: lattice interpolation reproduces affine fields on a plane exactly, never
// blends across a depth step or a crease, and sends pixels without support to be decoded.
#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/render/gi_upsample.h"

namespace ltm {
namespace {

// A synthetic G-buffer: every pixel hits; `surface(x, y)` gives (position, normal).
template <class F>
GBuffer synthetic(int w, int h, F surface) {
    GBuffer gb;
    gb.width = w, gb.height = h;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const auto [p, n] = surface(x, y);
            gb.hit_pixels.push_back(int64_t(y) * w + x);
            gb.position.push_back(p);
            gb.normal.push_back(n);
            gb.albedo.push_back(Vec3f(0.5f));
            gb.emitted.push_back(Vec3f(0.f));
            gb.depth.push_back(2.f);
            gb.diffuse.push_back(1);
        }
    return gb;
}

Camera camera_of(const GBuffer &gb) {
    Camera c;
    c.width = gb.width, c.height = gb.height;
    return c;
}

// value(x, y) sampled at the lattice hits.
template <class V>
std::vector<Vec3f> lattice_values(const GBuffer &gb, int stride, V value) {
    std::vector<Vec3f> out;
    for (size_t i : lattice_hits(gb, stride)) out.push_back(value(int(gb.hit_pixels[i] % gb.width), int(gb.hit_pixels[i] / gb.width)));
    return out;
}

TEST(GiUpsample, AffineFieldOnAPlaneIsExact) {
    // Odd sizes: the last row and column are on the lattice, so every pixel has its four corners.
    const GBuffer gb = synthetic(9, 7, [](int x, int y) {
        return std::pair{Vec3f(0.01f * float(x), 0.01f * float(y), 0.f), Vec3f(0.f, 0.f, 1.f)};
    });
    auto field = [](int x, int y) { return Vec3f(1.f + 0.5f * float(x), 2.f - 0.25f * float(y), float(x + y)); };
    EXPECT_EQ(lattice_hits(gb, 2).size(), 5u * 4u);
    const GiInterpolation r = interpolate_from_lattice(gb, camera_of(gb), lattice_values(gb, 2, field), {});
    EXPECT_TRUE(r.needs_decode.empty());
    for (size_t i = 0; i < gb.n_hits(); ++i) {
        const Vec3f want = field(int(gb.hit_pixels[i] % 9), int(gb.hit_pixels[i] / 9));
        EXPECT_NEAR(r.values[i].x, want.x, 1e-5f);
        EXPECT_NEAR(r.values[i].y, want.y, 1e-5f);
        EXPECT_NEAR(r.values[i].z, want.z, 1e-5f);
    }
    // Stride 1: everything is a lattice pixel, values pass through.
    GiUpsampleOptions every_pixel;
    every_pixel.stride = 1;
    const GiInterpolation one = interpolate_from_lattice(gb, camera_of(gb), lattice_values(gb, 1, field), every_pixel);
    EXPECT_TRUE(one.needs_decode.empty());
    EXPECT_EQ(one.values[10].x, field(1, 1).x);
}

// A 1 m step (left half at z = 0, right half at z = 1) and a 90° crease: no value crosses them.
TEST(GiUpsample, NeverBlendsAcrossADepthStepOrACrease) {
    const GBuffer step = synthetic(12, 9, [](int x, int y) {
        return std::pair{Vec3f(0.05f * float(x), 0.05f * float(y), x < 5 ? 0.f : 1.f), Vec3f(0.f, 0.f, 1.f)};
    });
    const GBuffer crease = synthetic(12, 9, [](int x, int y) {
        return std::pair{Vec3f(0.05f * float(x), 0.05f * float(y), 0.f), x < 5 ? Vec3f(0.f, 0.f, 1.f) : Vec3f(1.f, 0.f, 0.f)};
    });
    auto side = [](int x, int) { return x < 5 ? Vec3f(1.f) : Vec3f(7.f); };
    for (const GBuffer *gb : {&step, &crease}) {
        for (int stride : {2, 3, 4}) {
            GiUpsampleOptions opt;
            opt.stride = stride;
            const GiInterpolation r = interpolate_from_lattice(*gb, camera_of(*gb), lattice_values(*gb, stride, side), opt);
            std::vector<bool> decode(gb->n_hits(), false);
            for (size_t i : r.needs_decode) decode[i] = true;
            for (size_t i = 0; i < gb->n_hits(); ++i) {
                if (decode[i]) continue;
                const int x = int(gb->hit_pixels[i] % 12);
                EXPECT_FLOAT_EQ(r.values[i].x, side(x, 0).x) << "pixel " << i << " stride " << stride;
            }
            EXPECT_LT(r.needs_decode.size(), gb->n_hits());
        }
    }
}

TEST(GiUpsample, PixelsWithoutSupportAreDecodedAndBadInputThrows) {
    // Every other column is a different, far plane: off-lattice pixels have no compatible corner.
    const GBuffer gb = synthetic(8, 8, [](int x, int y) {
        return std::pair{Vec3f(0.05f * float(x), 0.05f * float(y), x % 2 == 0 ? 0.f : 3.f), Vec3f(0.f, 0.f, 1.f)};
    });
    const auto vals = lattice_values(gb, 2, [](int, int) { return Vec3f(1.f); });
    const GiInterpolation r = interpolate_from_lattice(gb, camera_of(gb), vals, {});
    for (size_t i : r.needs_decode) EXPECT_EQ(gb.hit_pixels[i] % 8 % 2, 1) << "odd columns only";
    EXPECT_EQ(r.needs_decode.size(), 8u * 4u);
    EXPECT_THROW(interpolate_from_lattice(gb, camera_of(gb), {Vec3f(1.f)}, {}), Error);
    EXPECT_THROW(lattice_hits(gb, 0), Error);
    Camera wrong = camera_of(gb);
    wrong.width = 9;
    EXPECT_THROW(interpolate_from_lattice(gb, wrong, vals, {}), Error);
}

}  // namespace
}  // namespace ltm
