// simd_clones.h: LTM_SIMD_CLONES — compile a hot function twice, for x86-64-v3 (AVX2) and for the
// baseline, and pick the clone at load time by the CPU (GCC's target_clones: an ifunc resolver).
// flatten inlines everything the function calls into each clone, so the helpers and templates it
// uses (8-lane vector types, the tree walk) run as one AVX register per 8 floats where the CPU has
// it and as two SSE registers elsewhere. A build on any x86-64 CPU runs on any other.
//
// Results do not depend on the clone: IEEE operations give the same answers at either width, and a
// file whose bits must not move with the CPU compiles with -ffp-contract=off (x86-64-v3 has FMA,
// which contraction would otherwise use in one clone and not the other).
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
