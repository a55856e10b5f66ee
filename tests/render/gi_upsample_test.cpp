// gi_upsample_test.cpp: lattice interpolation reproduces affine fields on a plane exactly, never
// blends across a depth step or a crease, and sends pixels without support to be decoded; coarse to
// fine, it decodes only the coarse lattice where a field is affine, gives one level's image exactly
// where a field is piecewise constant, and decodes every lattice pixel at contrast 0.
#include <gtest/gtest.h>

#include <cmath>

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


// A decoder of value(x, y) that records how many hits it was asked for.
template <class V>
GiDecode field_decoder(const GBuffer &gb, V value, int64_t &asked) {
    return [&gb, value, &asked](const std::vector<size_t> &hits) {
        std::vector<Vec3f> out;
        for (size_t i : hits) out.push_back(value(int(gb.hit_pixels[i] % gb.width), int(gb.hit_pixels[i] / gb.width)));
        asked += int64_t(hits.size());
        return out;
    };
}

GiUpsampleOptions levels_of(int stride, int levels, float contrast) {
    GiUpsampleOptions o;
    o.stride = stride, o.levels = levels, o.contrast = contrast;
    return o;
}

TEST(GiUpsample, OneLevelIsTheLatticeAndItsRejects) {
    // Half the image a far plane: the one-level path decodes the lattice, then what it rejects.
    const GBuffer gb = synthetic(13, 11, [](int x, int y) {
        return std::pair{Vec3f(0.05f * float(x), 0.05f * float(y), x < 6 ? 0.f : 2.f), Vec3f(0.f, 0.f, 1.f)};
    });
    auto field = [](int x, int y) { return Vec3f(1.f + float(x * x), 2.f + float(y), 0.5f); };
    int64_t asked = 0;
    const GiUpsampled up = upsample_gi(gb, camera_of(gb), levels_of(2, 1, 0.05f), field_decoder(gb, field, asked));
    GiInterpolation r = interpolate_from_lattice(gb, camera_of(gb), lattice_values(gb, 2, field), levels_of(2, 1, 0.05f));
    for (size_t i : r.needs_decode) r.values[i] = field(int(gb.hit_pixels[i] % 13), int(gb.hit_pixels[i] / 13));
    EXPECT_EQ(up.values, r.values);
    EXPECT_EQ(up.decoded, int64_t(lattice_hits(gb, 2).size() + r.needs_decode.size()));
    EXPECT_EQ(asked, up.decoded);
}

TEST(GiUpsample, CoarseToFineDecodesOnlyTheCoarseLatticeOfAnAffineField) {
    // 17 × 17: columns and rows 0, 8, 16 are the stride-8 lattice, so every pixel has its corners.
    const GBuffer gb = synthetic(17, 17, [](int x, int y) {
        return std::pair{Vec3f(0.01f * float(x), 0.01f * float(y), 0.f), Vec3f(0.f, 0.f, 1.f)};
    });
    auto field = [](int x, int y) { return Vec3f(4.f + 0.5f * float(x), 2.f + 0.25f * float(y), float(x + y)); };
    int64_t asked = 0;
    // Corners that differ by up to 8 × (0.5 + 0.25 + 2) against a blend of ≥ 6: contrast 5 lets every one through.
    const GiUpsampled up = upsample_gi(gb, camera_of(gb), levels_of(2, 3, 5.f), field_decoder(gb, field, asked));
    EXPECT_EQ(up.decoded, int64_t(lattice_hits(gb, 8).size()));
    for (size_t i = 0; i < gb.n_hits(); ++i) {
        const Vec3f want = field(int(gb.hit_pixels[i] % 17), int(gb.hit_pixels[i] / 17));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(up.values[i][c], want[c], 1e-4f) << "hit " << i;
    }
    // Contrast 0: every finer lattice pixel's corners differ, so each is decoded, and the image is
    // the one-level lattice's bit for bit, with as many decodes.
    int64_t asked0 = 0, asked1 = 0;
    const GiUpsampled all = upsample_gi(gb, camera_of(gb), levels_of(2, 3, 0.f), field_decoder(gb, field, asked0));
    const GiUpsampled one = upsample_gi(gb, camera_of(gb), levels_of(2, 1, 0.f), field_decoder(gb, field, asked1));
    EXPECT_EQ(all.values, one.values);
    EXPECT_EQ(all.decoded, one.decoded);
}

// Light 3× brighter on one side of a slanted line on a plane: the lattice pixels whose coarse
// corners straddle the line are decoded; the others lie on their corners' side (a half-plane is
// convex) and are blended from equal corners. So the image is the one-level lattice's exactly, for
// fewer decodes.
TEST(GiUpsample, CoarseToFineDecodesWhereTheLightChanges) {
    const GBuffer gb = synthetic(33, 33, [](int x, int y) {
        return std::pair{Vec3f(0.01f * float(x), 0.01f * float(y), 0.f), Vec3f(0.f, 0.f, 1.f)};
    });
    auto pool = [](int x, int y) { return 2 * x + y < 41 ? Vec3f(3.f) : Vec3f(1.f); };
    for (int stride : {1, 2}) {
        int64_t asked = 0;
        const GiUpsampled coarse = upsample_gi(gb, camera_of(gb), levels_of(stride, 3, 0.05f), field_decoder(gb, pool, asked));
        const GiUpsampled one = upsample_gi(gb, camera_of(gb), levels_of(stride, 1, 0.05f), field_decoder(gb, pool, asked));
        EXPECT_EQ(coarse.values, one.values) << "stride " << stride;
        EXPECT_LT(coarse.decoded, one.decoded / 2) << "stride " << stride;
    }
}

// Across a depth step the coarse corners are rejected, so the lattice pixels beside it are decoded
// even where the values agree: a blend must not reach over an edge it cannot see past.
TEST(GiUpsample, CoarseToFineDecodesBesideAnEdge) {
    const GBuffer gb = synthetic(33, 17, [](int x, int y) {
        return std::pair{Vec3f(0.05f * float(x), 0.05f * float(y), x < 13 ? 0.f : 1.f), Vec3f(0.f, 0.f, 1.f)};
    });
    std::vector<size_t> seen;
    const GiDecode record = [&](const std::vector<size_t> &hits) {
        seen.insert(seen.end(), hits.begin(), hits.end());
        return std::vector<Vec3f>(hits.size(), Vec3f(1.f));
    };
    const GiUpsampled up = upsample_gi(gb, camera_of(gb), levels_of(2, 3, 0.05f), record);
    for (const Vec3f &v : up.values) EXPECT_EQ(v, Vec3f(1.f));
    std::vector<bool> decoded(gb.n_hits(), false);
    for (size_t i : seen) decoded[i] = true;
    // The step lies between columns 12 and 13. Column 12's stride-4 pixels (from corners 8 and 16)
    // and column 14 (stride 2, from corners 12 and 16) have a corner across it and are decoded
    // (column 12's other pixels blend the decoded ones above and below); columns 26–30 (cells
    // wholly on one side) are blended.
    for (size_t i : lattice_hits(gb, 2)) {
        const int x = int(gb.hit_pixels[i] % 33), y = int(gb.hit_pixels[i] / 33);
        if ((x == 12 && y % 4 == 0) || x == 14) EXPECT_TRUE(decoded[i]) << "x " << x << " y " << y;
        if (x >= 26 && x <= 30) EXPECT_FALSE(decoded[i]) << "x " << x;
    }
}

// 36 × 36: the last lattice columns and rows of the coarse lattices (32) stop short of the image's
// edge, and the light changes past them. A corner past the image has nothing to agree with, so the
// pixels beside the edge are decoded: the image is the one-level lattice's exactly.
TEST(GiUpsample, CoarseToFineDecodesAlongTheImageEdge) {
    const GBuffer gb = synthetic(36, 36, [](int x, int y) {
        return std::pair{Vec3f(0.01f * float(x), 0.01f * float(y), 0.f), Vec3f(0.f, 0.f, 1.f)};
    });
    auto edge = [](int x, int y) { return x >= 33 || y >= 33 ? Vec3f(5.f) : Vec3f(1.f); };
    for (int stride : {1, 2}) {
        int64_t asked = 0;
        const GiUpsampled coarse = upsample_gi(gb, camera_of(gb), levels_of(stride, 3, 0.05f), field_decoder(gb, edge, asked));
        const GiUpsampled one = upsample_gi(gb, camera_of(gb), levels_of(stride, 1, 0.05f), field_decoder(gb, edge, asked));
        EXPECT_EQ(coarse.values, one.values) << "stride " << stride;
        EXPECT_LT(coarse.decoded, one.decoded) << "stride " << stride;
    }
}

TEST(GiUpsample, CoarseToFineRefusesBadOptionsAndDecoders) {
    const GBuffer gb = synthetic(8, 8, [](int x, int y) {
        return std::pair{Vec3f(0.05f * float(x), 0.05f * float(y), 0.f), Vec3f(0.f, 0.f, 1.f)};
    });
    int64_t asked = 0;
    const GiDecode ok = field_decoder(gb, [](int, int) { return Vec3f(1.f); }, asked);
    EXPECT_THROW(upsample_gi(gb, camera_of(gb), levels_of(2, 0, 0.05f), ok), Error);
    EXPECT_THROW(upsample_gi(gb, camera_of(gb), levels_of(2, 9, 0.05f), ok), Error);
    EXPECT_THROW(upsample_gi(gb, camera_of(gb), levels_of(2, 2, -1.f), ok), Error);
    EXPECT_THROW(upsample_gi(gb, camera_of(gb), levels_of(2, 2, std::nanf("")), ok), Error);
    EXPECT_THROW(upsample_gi(gb, camera_of(gb), levels_of(0, 2, 0.05f), ok), Error);
    const GiDecode short_by_one = [](const std::vector<size_t> &hits) { return std::vector<Vec3f>(hits.size() - 1, Vec3f(1.f)); };
    EXPECT_THROW(upsample_gi(gb, camera_of(gb), levels_of(2, 2, 0.05f), short_by_one), Error);
    Camera wrong = camera_of(gb);
    wrong.height = 9;
    EXPECT_THROW(upsample_gi(gb, wrong, levels_of(2, 2, 0.05f), ok), Error);
}

}  // namespace
}  // namespace ltm
