// simd_clones.h: LTM_SIMD_CLONES — compile a hot function twice, for x86-64-v3 (AVX2) and for the
// baseline, and pick the clone at load time by the CPU (GCC's target_clones: an ifunc resolver).
// flatten inlines everything the function calls into each clone, so the helpers and templates it
// uses (8-lane vector types, the tree walk) run as one AVX register per 8 floats where the CPU has
// it and as two SSE registers elsewhere. A build on any x86-64 CPU runs on any other.
//
// Bits: IEEE operations give the same answers at either width, so a file compiled with
// -ffp-contract=off (the prior's tree walk, the disc occluder: src/CMakeLists.txt) gives the same
// results in either clone. Without it, x86-64-v3's FMA contracts a·b + c in one clone and not the
// other (the fused decoder: its results move in the last bits with the CPU). Helpers that take or
// return vector types by value must be inlined (always_inline): their ABI differs between clones.
//
// Clang refuses flatten on a multiversioned function: there the helpers stay baseline code
// (correct, slower); the shipped build is GCC's. Other architectures: no clones.
#pragma once

#if defined(__x86_64__) && defined(__clang__)
#define LTM_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#elif defined(__x86_64__) && defined(__GNUC__)
#define LTM_SIMD_CLONES __attribute__((flatten, target_clones("arch=x86-64-v3", "default")))
#else
#define LTM_SIMD_CLONES
#endif
