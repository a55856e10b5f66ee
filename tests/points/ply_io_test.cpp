// ply_io_test.cpp: PLY round trips (binary and ASCII), and malformed files fail with located errors.
#include <limits>

#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/points/ply_io.h"
#include "test_util.h"

using namespace ltm;

namespace {
PointSet make_points(size_t n) {
    PointSet p(scene_point_columns(), n);
    for (size_t i = 0; i < n; ++i)
        for (size_t c = 0; c < p.n_columns(); ++c) p.at(i, c) = float(i) * 0.37f - float(c) * 1.25e-3f + 1e-7f * float(i * c);
    return p;
}
std::string error_of(const std::string &bytes) {
    try {
        parse_ply(bytes, "f.ply");
    } catch (const Error &e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(PlyIo, BinaryAndAsciiRoundTripExactly) {
    test::TempDir dir;
    const PointSet p = make_points(1000);
    for (bool binary : {true, false}) {
        PlyWriteOptions opt;
        opt.binary = binary;
        write_ply(dir.path("p.ply"), p, opt);
        const PointSet r = read_ply(dir.path("p.ply")).select(scene_point_columns(), "p.ply");
        ASSERT_EQ(r.size(), p.size());
        EXPECT_EQ(r.values, p.values) << (binary ? "binary" : "ascii");   // %.9g is exact for float
    }
}

TEST(PlyIo, WritesViewerColoursFromAlbedo) {
    test::TempDir dir;
    PointSet p(query_point_columns(), 1);
    p.set_vec3(0, 6, {1.f, 0.f, 0.2158605f});   // sRGB (255, 0, 128)
    write_ply(dir.path("c.ply"), p);
    const PointSet r = read_ply(dir.path("c.ply"));
    EXPECT_EQ(r.at(0, r.require_column("red", "")), 255.f);
    EXPECT_EQ(r.at(0, r.require_column("green", "")), 0.f);
    EXPECT_EQ(r.at(0, r.require_column("blue", "")), 128.f);
    EXPECT_NE(read_file(dir.path("c.ply")).find("property uchar red"), std::string::npos);
}

TEST(PlyIo, ReadsForeignTypesAndIgnoresLaterElements) {
    const std::string ascii = "ply\nformat ascii 1.0\ncomment from elsewhere\nelement vertex 2\n"
                              "property double x\nproperty int y\nproperty uchar z\n"
                              "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                              "1.5 -2 255\n0.25 7 0\n3 0 1 1\n";
    const PointSet p = parse_ply(ascii, "a.ply");
    ASSERT_EQ(p.size(), 2u);
    EXPECT_EQ(p.at(0, 0), 1.5f);
    EXPECT_EQ(p.at(0, 1), -2.f);
    EXPECT_EQ(p.at(1, 2), 0.f);
}

TEST(PlyIo, MalformedFilesFailWithLocatedErrors) {
    const std::string head = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nend_header\n";
    EXPECT_NE(error_of(head + std::string(5, '\0')).find("truncated"), std::string::npos);
    EXPECT_NE(error_of("plx\n").find("f.ply:1:"), std::string::npos);
    EXPECT_NE(error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty flot x\nend_header\n1\n").find("f.ply:4:"),
              std::string::npos);
    EXPECT_NE(error_of("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n1\n").find("f.ply:7: truncated"),
              std::string::npos);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::string one = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nend_header\n";
    EXPECT_NE(error_of(one + std::string(reinterpret_cast<const char *>(&nan), 4)).find("not finite"), std::string::npos);
    EXPECT_NE(error_of("ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float x\nend_header\n").find("big_endian"),
              std::string::npos);
    EXPECT_NE(error_of("ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\nend_header\n").find("too large"),
              std::string::npos);
    EXPECT_NE(error_of("ply\nformat ascii 1.0\n").find("no end_header"), std::string::npos);
}
