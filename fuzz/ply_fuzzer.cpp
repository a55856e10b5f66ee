// ply_fuzzer.cpp: any byte string either parses into a PointSet or throws ltm::Error.
#include <cstddef>
#include <cstdint>
#include <string>

#include "ltm/core/error.h"
#include "ltm/points/ply_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const std::string bytes(reinterpret_cast<const char *>(data), size);
    try {
        const ltm::PointSet p = ltm::parse_ply(bytes, "fuzz.ply");
        if (p.n_columns() > 0 && p.values.size() % p.n_columns() != 0) __builtin_trap();
    } catch (const ltm::Error &) {
    }
    return 0;
}
