// safetensors_test.cpp: round trip, and malformed files are located errors.
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
