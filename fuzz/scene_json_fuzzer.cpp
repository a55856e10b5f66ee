// scene_json_fuzzer.cpp: any byte string either parses into a valid scene or throws ltm::Error.
// Anything else (a crash, a sanitizer report, another exception type) is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ltm/core/error.h"
#include "ltm/scene/scene_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string text(reinterpret_cast<const char *>(data), size);
    try {
        // Relative texture/mesh paths resolve inside a directory that does not exist.
        const ltm::Scene s = ltm::scene_from_json(ltm::parse_json(text, "fuzz.json"), "fuzz.json",
                                                  "/nonexistent-ltm-fuzz");
        ltm::validate_scene(s, "fuzz.json");
        (void)ltm::scene_to_json(s);
    } catch (const ltm::Error &) {
    }
    return 0;
}
