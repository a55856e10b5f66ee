// ply_mesh_fuzzer.cpp: any byte string either parses into a PLY triangle mesh with in-range
// indices or throws ltm::Error.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ltm/core/error.h"
#include "ltm/scene/ply_mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string bytes(reinterpret_cast<const char *>(data), size);
    try {
        const ltm::PlyMesh m = ltm::parse_ply_mesh(bytes, "fuzz.ply");
        if (m.indices.size() % 3 != 0) __builtin_trap();
        for (uint32_t i : m.indices)
            if (i >= m.positions.size()) __builtin_trap();
    } catch (const ltm::Error &) {
    }
    return 0;
}
