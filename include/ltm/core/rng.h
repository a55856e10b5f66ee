// rng.h: deterministic randomness. Every random stream in ltm is a PCG32 seeded by a hash of
// (seed, stable indices), so results never depend on thread count or scheduling order.
#pragma once

#include <cstdint>
#include <initializer_list>

namespace ltm {

/// SplitMix64 finaliser: a bijective 64-bit mix with full avalanche.
inline uint64_t mix64(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/// Order-dependent hash of several keys: hash_keys({seed, i_point, i_sample}).
inline uint64_t hash_keys(std::initializer_list<uint64_t> keys) {
    uint64_t h = 0x6a09e667f3bcc909ull;
    for (uint64_t k : keys) h = mix64(h ^ mix64(k));
    return h;
}

/// PCG32 (O'Neill 2014, XSH-RR): 64-bit state, 32-bit output, selectable stream.
class Pcg32 {
public:
    explicit Pcg32(uint64_t seed, uint64_t stream = 0x14057b7ef767814full) {
        m_inc = (stream << 1u) | 1u;
        m_state = 0;
        next_u32();
        m_state += seed;
        next_u32();
    }
    uint32_t next_u32() {
        const uint64_t old = m_state;
        m_state = old * 6364136223846793005ull + m_inc;
        const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
        const uint32_t rot = uint32_t(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
    }
    /// Uniform in [0, 1): 24 random mantissa bits, never returns 1.
    float next_float() { return float(next_u32() >> 8) * 0x1p-24f; }
    /// Uniform double in [0, 1) from 53 random bits.
    double next_double() {
        const uint64_t hi = next_u32(), lo = next_u32();
        return double(((hi << 32) | lo) >> 11) * 0x1p-53;
    }
    /// Uniform in [lo, hi).
    float uniform(float lo, float hi) { return lo + (hi - lo) * next_float(); }
    /// Uniform integer in [0, n) without modulo bias (Lemire's method with rejection).
    uint32_t next_below(uint32_t n);
    /// Uniform integer in [lo, hi] (inclusive).
    int uniform_int(int lo, int hi) { return lo + int(next_below(uint32_t(hi - lo + 1))); }
    bool bernoulli(float p) { return next_float() < p; }

private:
    uint64_t m_state = 0, m_inc = 0;
};

inline uint32_t Pcg32::next_below(uint32_t n) {
    if (n <= 1) return 0;
    uint64_t m = uint64_t(next_u32()) * n;
    uint32_t l = uint32_t(m);
    if (l < n) {
        const uint32_t t = (0u - n) % n;
        while (l < t) {
            m = uint64_t(next_u32()) * n;
            l = uint32_t(m);
        }
    }
    return uint32_t(m >> 32);
}

}  // namespace ltm
