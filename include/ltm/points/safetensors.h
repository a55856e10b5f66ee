// safetensors.h: an in-house reader/writer of the safetensors format (huggingface/safetensors):
// u64 little-endian header length, a JSON header {name: {dtype, shape, data_offsets}, __metadata__},
// then the raw little-endian tensor bytes. Python-readable; used for dataset records and weights.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace ltm {

struct StTensor {
    std::string dtype;             ///< "F32", "F64", "I32", "I64", "U8", ...
    std::vector<int64_t> shape;
    std::vector<char> data;        ///< raw bytes, row-major, little-endian
    size_t numel() const;
    /// Values as float (F32 only); throws naming `where` otherwise.
    std::vector<float> as_f32(const std::string &where) const;
    /// numel() values as float into `out`, from F32 or F16 (exactly: every half is a float);
    /// throws naming `where` for any other dtype.
    void copy_f32(float *out, const std::string &where) const;
};

/// IEEE 754 binary16 -> binary32, exact for every bit pattern (subnormals, ±inf, NaN payloads).
float half_to_float(uint16_t h);

struct SafetensorsFile {
    std::map<std::string, StTensor> tensors;
    std::map<std::string, std::string> metadata;
    /// The tensor, with a check of dtype and shape (-1 = any); throws "where: ..." on mismatch.
    const StTensor &require(const std::string &name, const std::string &dtype, const std::vector<int64_t> &shape,
                            const std::string &where) const;
};

StTensor make_f32_tensor(const std::vector<int64_t> &shape, const float *values);

/// Writes atomically (tensors in name order, header padded to 8 bytes).
void write_safetensors(const std::string &path, const SafetensorsFile &file);
SafetensorsFile read_safetensors(const std::string &path);
SafetensorsFile parse_safetensors(std::string_view bytes, const std::string &where);

}  // namespace ltm
