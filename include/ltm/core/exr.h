// exr.h: multi-channel OpenEXR output (named AOV channels, 32-bit float or 16-bit half per
// channel), written atomically.
#pragma once

#include <string>
#include <vector>

namespace ltm {

struct ExrChannel {
    std::string name;        ///< e.g. "R", "irradiance.G", "N.X", "Z"
    const float *data;       ///< first value, row-major from the top-left pixel
    size_t stride_floats;    ///< distance between consecutive pixels (3 for packed RGB)
    bool half = false;       ///< stored as 16-bit half (converted on write); else 32-bit float
};

/// Whether a channel's n values (every stride_floats-th float from data) keep their precision as
/// half: every finite |v| ≤ 65 504 (half's largest), and the largest |v| ≥ 2⁻⁷, so that half's
/// finest step near 0 (2⁻²⁴) is ≤ 2⁻¹⁷ of the channel's peak — below any display's or metric's
/// resolution — while values near the peak keep half's 11 significant bits (relative error ≤ 2⁻¹¹).
/// An all-zero channel fits. A scene in tiny or huge units fails the test and stays float.
bool fits_half(const float *data, size_t n, size_t stride_floats);

void write_exr(const std::string &path, int width, int height, const std::vector<ExrChannel> &channels);

/// Reads one named channel of an EXR (float), e.g. for tests; throws if absent.
std::vector<float> read_exr_channel(const std::string &path, const std::string &name, int *width, int *height);

}  // namespace ltm
