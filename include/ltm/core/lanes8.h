// lanes8.h: 8 floats as one value (GCC's vector extensions: element-wise IEEE operations, a scalar
// operand broadcast; one AVX register in an x86-64-v3 clone, two SSE registers in baseline code) and
// their comparisons' masks — the lanes of the prior tree's walk (8 receivers) and of the disc
// occluder's test (8 discs).
//
// A vector passed by value has a different ABI in the baseline and the AVX2 clones of a
// LTM_SIMD_CLONES function (core/simd_clones.h), so every helper here is always_inline: inlined
// into each clone, or a compile error — never a silent mismatch. GCC's -Wpsabi note on that ABI
// is therefore moot, and silenced for the files that include this header.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#pragma GCC diagnostic ignored "-Wpsabi"

namespace ltm::lanes8 {

constexpr int k_lanes = 8;
typedef float f8 __attribute__((vector_size(4 * k_lanes)));
typedef int32_t m8 __attribute__((vector_size(4 * k_lanes)));

/// 8 floats from p (any alignment).
__attribute__((always_inline)) inline f8 load8(const float *p) {
    f8 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
/// |v| per lane (the sign bit cleared: as std::abs, NaN included).
__attribute__((always_inline)) inline f8 abs8(f8 v) { return (f8)((m8)v & 0x7fffffff); }
/// √v per lane, as std::sqrt (SSE's sqrtps where there is SSE: one instruction, no errno).
__attribute__((always_inline)) inline f8 sqrt8(f8 v) {
    f8 r;
#if defined(__SSE__)
    typedef float f4 __attribute__((vector_size(16)));
    for (int h = 0; h < k_lanes; h += 4) {
        const f4 x = {v[h], v[h + 1], v[h + 2], v[h + 3]}, y = __builtin_ia32_sqrtps(x);
        for (int l = 0; l < 4; ++l) r[h + l] = y[l];
    }
#else
    for (int l = 0; l < k_lanes; ++l) r[l] = std::sqrt(v[l]);
#endif
    return r;
}
/// The mask as bits: lane l true -> bit l.
__attribute__((always_inline)) inline uint32_t bits(m8 m) {
    uint32_t b = 0;
    for (int l = 0; l < k_lanes; ++l) b |= m[l] ? 1u << l : 0u;
    return b;
}
/// Is any lane true?
__attribute__((always_inline)) inline bool any8(m8 m) {
    int32_t a = 0;
    for (int l = 0; l < k_lanes; ++l) a |= m[l];
    return a != 0;
}

}  // namespace ltm::lanes8
