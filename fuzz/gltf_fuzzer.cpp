// gltf_fuzzer.cpp: any bytes (first byte picks .glb or JSON) either convert into a Scene or throw
// ltm::Error. tinygltf itself is Debian's uninstrumented shared library: coverage guides the
// search through ltm's conversion code only.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/scene/gltf_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    static const bool quiet = (ltm::set_log_level(ltm::LogLevel::quiet), true);
    (void)quiet;
    if (size < 1) return 0;
    const bool binary = data[0] & 1;
    const std::string bytes(reinterpret_cast<const char *>(data + 1), size - 1);
    try {
        const ltm::Scene s = ltm::parse_gltf(bytes, "fuzz.gltf", binary);
        for (const auto &m : s.meshes)
            for (uint32_t i : m.indices)
                if (i >= m.positions.size()) __builtin_trap();
    } catch (const ltm::Error &) {
    }
    return 0;
}
