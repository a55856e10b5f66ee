// safetensors_fuzzer.cpp: any bytes either parse into tensors whose data lie inside the file, or
// throw ltm::Error.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ltm/core/error.h"
#include "ltm/points/safetensors.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string bytes(reinterpret_cast<const char *>(data), size);
    try {
        const ltm::SafetensorsFile f = ltm::parse_safetensors(bytes, "fuzz.safetensors");
        for (const auto &[name, t] : f.tensors)
            if (t.dtype == "F32") (void)t.as_f32(name);
    } catch (const ltm::Error &) {
    }
    return 0;
}
