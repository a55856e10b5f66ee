// safetensors_test.cpp: round trip, F16 values, the mapped read, and malformed files are located errors.
#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/points/safetensors.h"
#include "test_util.h"

using namespace ltm;

TEST(Safetensors, RoundTripKeepsTensorsAndMetadata) {
    test::TempDir dir;
    SafetensorsFile f;
    const float a[6] = {1, 2, 3, 4, 5, 6};
    f.tensors["E_direct"] = make_f32_tensor({2, 3}, a);
    f.tensors["empty"] = make_f32_tensor({0, 3}, nullptr);
    f.metadata["format_version"] = "1";
    write_safetensors(dir.path("r.safetensors"), f);
    const std::string bytes = read_file(dir.path("r.safetensors"));
    uint64_t n = 0;
    std::memcpy(&n, bytes.data(), 8);
    EXPECT_EQ(n % 8, 0u);
    const SafetensorsFile r = read_safetensors(dir.path("r.safetensors"));
    EXPECT_EQ(r.metadata.at("format_version"), "1");
    EXPECT_EQ(r.require("E_direct", "F32", {-1, 3}, "r").as_f32("r"), std::vector<float>(a, a + 6));
    EXPECT_THROW(r.require("E_direct", "F32", {3, 3}, "r"), Error);
    EXPECT_THROW(r.require("missing", "F32", {3}, "r"), Error);
}

TEST(Safetensors, MalformedFilesAreErrors) {
    EXPECT_THROW(parse_safetensors("abc", "x"), Error);
    std::string big(8, '\0');
    big[0] = char(0xff);
    big[7] = char(0x7f);
    EXPECT_THROW(parse_safetensors(big, "x"), Error);
    const std::string header = R"({"t":{"dtype":"F32","shape":[2],"data_offsets":[0,12]}})";
    std::string bad(8, '\0');
    const uint64_t n = header.size();
    std::memcpy(bad.data(), &n, 8);
    EXPECT_THROW(parse_safetensors(bad + header + std::string(12, '\0'), "x"), Error);   // 12 bytes for 2 floats
}

// Every binary16 pattern against its definition: (−1)^s · 2^(e−15) · (1 + m/1024), subnormals
// 2^−14 · m/1024, e = 31 infinities and NaNs. (F16 weights load through this.)
TEST(Safetensors, EveryHalfConvertsToItsExactValue) {
    for (uint32_t h = 0; h < 65536; ++h) {
        const int s = int(h >> 15), e = int((h >> 10) & 31), m = int(h & 1023);
        const float got = half_to_float(uint16_t(h));
        if (e == 31 && m != 0) {
            EXPECT_TRUE(std::isnan(got)) << h;
            continue;
        }
        const double mag = e == 31 ? HUGE_VAL : e == 0 ? std::ldexp(double(m) / 1024.0, -14) : std::ldexp(1.0 + double(m) / 1024.0, e - 15);
        const double want = s ? -mag : mag;
        ASSERT_EQ(double(got), want) << "half 0x" << std::hex << h;
        ASSERT_EQ(std::signbit(got), bool(s)) << "half 0x" << std::hex << h;   // −0 stays −0
    }
    SafetensorsFile f;
    StTensor t;
    t.dtype = "F16", t.shape = {2};
    const uint16_t halves[2] = {0x3c00, 0xc500};   // 1, −5
    t.data.assign(reinterpret_cast<const char *>(halves), reinterpret_cast<const char *>(halves) + 4);
    float out[2];
    t.copy_f32(out, "t");
    EXPECT_EQ(out[0], 1.f);
    EXPECT_EQ(out[1], -5.f);
    t.dtype = "I32", t.shape = {1};
    EXPECT_THROW(t.copy_f32(out, "t"), Error);
}

// The mapped read equals the stream read, also for files that cannot be mapped (empty, a pipe).
TEST(Safetensors, MappedFilesReadAsTheirBytes) {
    test::TempDir dir;
    write_file_atomic(dir.path("a.bin"), std::string("ab\0cd", 5));
    EXPECT_EQ(std::string(MappedFile(dir.path("a.bin")).bytes()), std::string("ab\0cd", 5));
    write_file_atomic(dir.path("empty"), "");
    EXPECT_EQ(MappedFile(dir.path("empty")).bytes().size(), 0u);
    EXPECT_EQ(read_file(dir.path("empty")), "");
    EXPECT_THROW(MappedFile(dir.path("missing")), Error);
    EXPECT_THROW(MappedFile(dir.path("")), Error);
    EXPECT_FALSE(read_file("/proc/self/stat").empty());   // size 0 in stat(), yet has bytes
}
