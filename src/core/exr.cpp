// exr.cpp: OpenEXR through its stream API so the file goes to a temporary and is renamed.
#include "ltm/core/exr.h"

#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfHeader.h>
#include <ImfFrameBuffer.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <ImfThreading.h>
#include <Imath/half.h>

#include <algorithm>
#include <cmath>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/core/parallel.h"

namespace ltm {

void write_exr(const std::string &path, int width, int height, const std::vector<ExrChannel> &channels) {
    AtomicFile f(path);
    try {
        // ZIP compresses blocks of 16 scanlines independently: OpenEXR's own pool compresses them in
        // parallel (a 512² render's 19 float channels: most of the time spent writing), and the bytes
        // do not depend on the thread count.
        if (Imf::globalThreadCount() != num_threads()) Imf::setGlobalThreadCount(num_threads());
        Imf::Header header(width, height);
        header.compression() = Imf::ZIP_COMPRESSION;
        for (const auto &c : channels) header.channels().insert(c.name, Imf::Channel(c.half ? Imf::HALF : Imf::FLOAT));
        Imf::StdOFStream os(f.file(), path.c_str());
        Imf::OutputFile out(os, header);
        Imf::FrameBuffer fb;
        // An output slice's type must be its channel's: half channels are converted here first.
        const size_t n = size_t(width) * size_t(height);
        std::vector<std::vector<Imath::half>> halves;
        halves.reserve(channels.size());
        for (const auto &c : channels) {
            if (c.half) {
                std::vector<Imath::half> &h = halves.emplace_back(n);
                for (size_t i = 0; i < n; ++i) h[i] = Imath::half(c.data[i * c.stride_floats]);
                fb.insert(c.name, Imf::Slice(Imf::HALF, (char *)h.data(), sizeof(Imath::half), sizeof(Imath::half) * size_t(width)));
            } else {
                fb.insert(c.name, Imf::Slice(Imf::FLOAT, (char *)c.data, sizeof(float) * c.stride_floats,
                                             sizeof(float) * c.stride_floats * size_t(width)));
            }
        }
        out.setFrameBuffer(fb);
        out.writePixels(height);
    } catch (const Error &) {
        throw;
    } catch (const std::exception &e) {
        LTM_THROW(path, ": cannot write EXR: ", e.what());
    }
    f.commit();
}

bool fits_half(const float *data, size_t n, size_t stride_floats) {
    constexpr float k_half_max = 65504.f, k_least_peak = 1.f / 128.f;
    float peak = 0.f;
    for (size_t i = 0; i < n; ++i) {
        const float v = std::abs(data[i * stride_floats]);
        if (!std::isfinite(v)) continue;
        if (v > k_half_max) return false;
        peak = std::max(peak, v);
    }
    return peak == 0.f || peak >= k_least_peak;
}

std::vector<float> read_exr_channel(const std::string &path, const std::string &name, int *width, int *height) {
    try {
        Imf::InputFile in(path.c_str());
        const Imath::Box2i dw = in.header().dataWindow();
        const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
        if (!in.header().channels().findChannel(name)) LTM_THROW(path, ": no channel '", name, "'");
        std::vector<float> data(size_t(w) * size_t(h));
        Imf::FrameBuffer fb;
        fb.insert(name, Imf::Slice(Imf::FLOAT, (char *)(data.data() - dw.min.x - dw.min.y * w), sizeof(float),
                                   sizeof(float) * size_t(w)));
        in.setFrameBuffer(fb);
        in.readPixels(dw.min.y, dw.max.y);
        if (width) *width = w;
        if (height) *height = h;
        return data;
    } catch (const Error &) {
        throw;
    } catch (const std::exception &e) {
        LTM_THROW(path, ": cannot read EXR: ", e.what());
    }
}

}  // namespace ltm
