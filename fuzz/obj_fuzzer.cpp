// obj_fuzzer.cpp: OBJ text (+ an MTL after a "\n#MTL\n" separator) either converts into a Scene
// with in-range indices or throws ltm::Error. tinyobjloader is Debian's library (uninstrumented).
#include <cstddef>
#include <cstdint>
#include <string>

#include "ltm/core/error.h"
#include "ltm/scene/obj_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string text(reinterpret_cast<const char *>(data), size);
    const size_t cut = text.find("\n#MTL\n");
    const std::string obj = text.substr(0, cut), mtl = cut == std::string::npos ? "" : text.substr(cut + 6);
    try {
        const ltm::Scene s = ltm::parse_obj(obj, mtl, "fuzz.obj");
        for (const auto &m : s.meshes)
            for (uint32_t i : m.indices)
                if (i >= m.positions.size()) __builtin_trap();
    } catch (const ltm::Error &) {
    }
    return 0;
}
