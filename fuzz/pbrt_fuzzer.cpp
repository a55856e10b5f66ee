// pbrt_fuzzer.cpp: any text either parses into a Scene (tokenizer + directives, no file access)
// or throws ltm::Error.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/scene/pbrt_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    static const bool quiet = (ltm::set_log_level(ltm::LogLevel::quiet), true);   // warnings are not findings
    (void)quiet;
    const std::string text(reinterpret_cast<const char *>(data), size);
    try {
        const ltm::Scene s = ltm::parse_pbrt(text, "fuzz.pbrt", "/nonexistent", /*allow_files=*/false);
        for (const auto &m : s.meshes)
            for (uint32_t i : m.indices)
                if (i >= m.positions.size()) __builtin_trap();
    } catch (const ltm::Error &) {
    }
    return 0;
}
