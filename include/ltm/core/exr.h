// exr.h: multi-channel OpenEXR output (named AOV channels, 32-bit float), written atomically.
#pragma once

#include <string>
#include <vector>

namespace ltm {

struct ExrChannel {
    std::string name;        ///< e.g. "R", "irradiance.G", "N.X", "Z"
    const float *data;       ///< first value, row-major from the top-left pixel
    size_t stride_floats;    ///< distance between consecutive pixels (3 for packed RGB)
};

void write_exr(const std::string &path, int width, int height, const std::vector<ExrChannel> &channels);

/// Reads one named channel of an EXR (float), e.g. for tests; throws if absent.
std::vector<float> read_exr_channel(const std::string &path, const std::string &name, int *width, int *height);

}  // namespace ltm
