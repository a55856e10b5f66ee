// safetensors.cpp: strict parsing: offsets must tile the data buffer exactly, sizes must match
// dtype × shape, and nothing may point outside the file.
#include "ltm/points/safetensors.h"

#include <algorithm>
#include <cstring>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/core/json_util.h"

namespace ltm {

namespace {
size_t dtype_size(const std::string &d) {
    static const std::map<std::string, size_t> sizes = {{"F64", 8}, {"F32", 4}, {"F16", 2}, {"BF16", 2},
                                                        {"I64", 8}, {"I32", 4}, {"I16", 2}, {"I8", 1},
                                                        {"U64", 8}, {"U32", 4}, {"U16", 2}, {"U8", 1},
                                                        {"BOOL", 1}};
    const auto it = sizes.find(d);
    return it == sizes.end() ? 0 : it->second;
}
}  // namespace

size_t StTensor::numel() const {
    size_t n = 1;
    for (int64_t s : shape) n *= size_t(s);
    return n;
}

std::vector<float> StTensor::as_f32(const std::string &where) const {
    if (dtype != "F32") LTM_THROW(where, ": expected dtype F32, got ", dtype);
    std::vector<float> v(numel());
    std::memcpy(v.data(), data.data(), v.size() * sizeof(float));
    return v;
}

float half_to_float(uint16_t h) {
    const uint32_t sign = uint32_t(h & 0x8000u) << 16, exponent = (h >> 10) & 0x1fu, mantissa = h & 0x3ffu;
    uint32_t bits;
    if (exponent == 0x1fu) {
        bits = sign | 0x7f800000u | (mantissa << 13);   // ±inf, NaN (payload kept)
    } else if (exponent != 0) {
        bits = sign | ((exponent + 112u) << 23) | (mantissa << 13);   // normal: bias 15 -> 127
    } else {
        const float f = float(mantissa) * 5.9604644775390625e-8f;   // ±0 and subnormals: m · 2⁻²⁴, exact
        std::memcpy(&bits, &f, 4);
        bits |= sign;
    }
    float out;
    std::memcpy(&out, &bits, 4);
    return out;
}

void StTensor::copy_f32(float *out, const std::string &where) const {
    const size_t n = numel();
    if (dtype == "F32") {
        std::memcpy(out, data.data(), n * sizeof(float));
    } else if (dtype == "F16") {
        const char *src = data.data();
        for (size_t i = 0; i < n; ++i) {
            uint16_t h;
            std::memcpy(&h, src + 2 * i, 2);
            out[i] = half_to_float(h);
        }
    } else {
        LTM_THROW(where, ": expected dtype F32 or F16, got ", dtype);
    }
}

const StTensor &SafetensorsFile::require(const std::string &name, const std::string &dtype,
                                         const std::vector<int64_t> &shape, const std::string &where) const {
    const auto it = tensors.find(name);
    if (it == tensors.end()) LTM_THROW(where, ": missing tensor '", name, "'");
    const StTensor &t = it->second;
    if (t.dtype != dtype) LTM_THROW(where, ": tensor '", name, "' has dtype ", t.dtype, ", expected ", dtype);
    bool ok = t.shape.size() == shape.size();
    for (size_t i = 0; ok && i < shape.size(); ++i) ok = shape[i] < 0 || shape[i] == t.shape[i];
    if (!ok) {
        std::string got, want;
        for (int64_t s : t.shape) got += (got.empty() ? "" : ", ") + std::to_string(s);
        for (int64_t s : shape) want += (want.empty() ? "" : ", ") + (s < 0 ? std::string("*") : std::to_string(s));
        LTM_THROW(where, ": tensor '", name, "' has shape [", got, "], expected [", want, "]");
    }
    return t;
}

StTensor make_f32_tensor(const std::vector<int64_t> &shape, const float *values) {
    StTensor t;
    t.dtype = "F32";
    t.shape = shape;
    t.data.resize(t.numel() * sizeof(float));
    if (!t.data.empty()) std::memcpy(t.data.data(), values, t.data.size());
    return t;
}

void write_safetensors(const std::string &path, const SafetensorsFile &file) {
    OrderedJson header = OrderedJson::object();
    if (!file.metadata.empty()) {
        OrderedJson meta = OrderedJson::object();
        for (const auto &[k, v] : file.metadata) meta[k] = v;
        header["__metadata__"] = meta;
    }
    size_t offset = 0;
    for (const auto &[name, t] : file.tensors) {
        LTM_CHECK_EQ(t.data.size(), t.numel() * dtype_size(t.dtype));
        header[name] = {{"dtype", t.dtype}, {"shape", t.shape}, {"data_offsets", {offset, offset + t.data.size()}}};
        offset += t.data.size();
    }
    std::string h = header.dump();
    h.resize((h.size() + 7) / 8 * 8, ' ');
    AtomicFile f(path);
    const uint64_t n = h.size();
    f.stream().write(reinterpret_cast<const char *>(&n), 8);
    f.stream().write(h.data(), std::streamsize(h.size()));
    for (const auto &[name, t] : file.tensors) f.stream().write(t.data.data(), std::streamsize(t.data.size()));
    f.commit();
}

SafetensorsFile parse_safetensors(std::string_view bytes, const std::string &where) {
    if (bytes.size() < 8) LTM_THROW(where, ": truncated safetensors file (", bytes.size(), " bytes)");
    uint64_t n = 0;
    std::memcpy(&n, bytes.data(), 8);
    if (n > bytes.size() - 8) LTM_THROW(where, ": header length ", n, " exceeds the file size");
    const Json header = parse_json(std::string(bytes.substr(8, size_t(n))), where + " (header)");
    if (!header.is_object()) LTM_THROW(where, ": header is not a JSON object");
    const size_t data_start = 8 + size_t(n), data_size = bytes.size() - data_start;
    SafetensorsFile out;
    std::vector<std::pair<size_t, size_t>> ranges;
    for (auto it = header.begin(); it != header.end(); ++it) {
        const std::string at = where + ": tensor '" + it.key() + "'";
        if (it.key() == "__metadata__") {
            if (!it->is_object()) LTM_THROW(where, ": __metadata__ is not an object");
            for (auto m = it->begin(); m != it->end(); ++m) {
                if (!m->is_string()) LTM_THROW(where, ": metadata '", m.key(), "' is not a string");
                out.metadata[m.key()] = m->get<std::string>();
            }
            continue;
        }
        JsonObject o(*it, at);
        StTensor t;
        t.dtype = o.require_string("dtype");
        const size_t es = dtype_size(t.dtype);
        if (es == 0) LTM_THROW(at, ": unknown dtype '", t.dtype, "'");
        t.shape = o.require_int_array("shape");
        size_t numel = 1;
        for (int64_t s : t.shape) {
            if (s < 0 || (s > 0 && numel > (size_t(1) << 40) / size_t(s))) LTM_THROW(at, ": bad shape");
            numel *= size_t(s);
        }
        const auto off = o.require_int_array("data_offsets");
        o.finish();
        if (off.size() != 2 || off[0] < 0 || off[1] < off[0] || size_t(off[1]) > data_size)
            LTM_THROW(at, ": data_offsets out of range");
        if (size_t(off[1] - off[0]) != numel * es)
            LTM_THROW(at, ": ", off[1] - off[0], " bytes for ", numel, " elements of ", t.dtype);
        t.data.assign(bytes.begin() + std::ptrdiff_t(data_start + size_t(off[0])),
                      bytes.begin() + std::ptrdiff_t(data_start + size_t(off[1])));
        ranges.push_back({size_t(off[0]), size_t(off[1])});
        out.tensors[it.key()] = std::move(t);
    }
    // The spec requires the tensors to tile the buffer with no holes or overlaps.
    std::sort(ranges.begin(), ranges.end());
    size_t expect = 0;
    for (const auto &[b, e] : ranges) {
        if (b != expect) LTM_THROW(where, ": tensor data overlaps or leaves a hole at byte ", expect);
        expect = e;
    }
    if (expect != data_size) LTM_THROW(where, ": ", data_size - expect, " trailing bytes after the tensors");
    return out;
}

SafetensorsFile read_safetensors(const std::string &path) {
    const MappedFile f(path);   // each tensor's bytes are copied once, from the page cache
    return parse_safetensors(f.bytes(), path);
}

}  // namespace ltm
