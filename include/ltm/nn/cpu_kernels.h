// cpu_kernels.h: the CPU maths under the fused decoder (nn/fused_decoder.h) — clamp, e^x, exact
// GELU, reassociation-free row sums, LayerNorm, a register-blocked GEMM — plain C++ loops that GCC
// vectorises, as inline functions: a caller compiled for several targets (target_clones + flatten,
// as FusedDecoder's decode_tile) inlines them into each clone, so they run as AVX2 + FMA code
// there and as baseline x86-64 code elsewhere. Torch-free; every function states its shapes.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace ltm::kernels {

// 8 floats: one AVX register in the x86-64-v3 clone, two SSE registers in the baseline one.
typedef float Vec8 __attribute__((vector_size(32)));

// ---------------------------------------------------------------------------------------------
// Elementwise maths in loops GCC vectorises. A clamp gets its own loop: fused with the arithmetic
// after it, GCC (with trapping maths, the default) threads the branches and stops vectorising.

inline void clamp(float *__restrict x, int n, float lo, float hi) {
    for (int i = 0; i < n; ++i) x[i] = x[i] < lo ? lo : (x[i] > hi ? hi : x[i]);
}

// e^x in place (Cephes expf: x = n·ln2 + r, |r| ≤ ln2/2, degree-6 polynomial, ~1 ulp). x is
// clamped to [-87, 88], so e^x ≥ 1.6e-38 instead of 0 far below: harmless in softmax and erf.
inline void exp_inplace(float *__restrict x, int n) {
    clamp(x, n, -87.f, 88.f);
    for (int i = 0; i < n; ++i) {
        const float k = (x[i] * 1.44269504f + 12582912.f) - 12582912.f;   // round(x/ln2): 1.5·2²³ trick
        const float r = (x[i] - k * 0.693359375f) + k * 2.12194440e-4f;   // ln2 split in two for accuracy
        float p = 1.9875691500e-4f;
        p = p * r + 1.3981999507e-3f;
        p = p * r + 8.3334519073e-3f;
        p = p * r + 4.1665795894e-2f;
        p = p * r + 1.6666665459e-1f;
        p = p * r + 5.0000001201e-1f;
        const int32_t bits = (int32_t(k) + 127) << 23;   // 2^k
        float scale;
        std::memcpy(&scale, &bits, sizeof scale);
        x[i] = (p * r * r + r + 1.f) * scale;
    }
}

// Exact (erf) GELU as torch::nn::GELU(): x/2 · (1 + erf(x/√2)), erf by Abramowitz & Stegun 7.1.26
// (|error| ≤ 1.5e-7, the formula of ATen's vectorised erf).   x [n], in place
inline void gelu(float *__restrict x, int n) {
    constexpr int k_chunk = 64;
    float e[k_chunk];
    for (int i0 = 0; i0 < n; i0 += k_chunk) {
        const int m = std::min(k_chunk, n - i0);
        float *__restrict xc = x + i0;
        for (int i = 0; i < m; ++i) e[i] = -0.5f * xc[i] * xc[i];   // −(x/√2)²
        exp_inplace(e, m);
        for (int i = 0; i < m; ++i) {
            const float t = 1.f / (1.f + 0.3275911f * std::fabs(xc[i] * 0.70710678118654752f));
            const float poly =
                t * (0.254829592f + t * (-0.284496736f + t * (1.421413741f + t * (-1.453152027f + t * 1.061405429f))));
            xc[i] = 0.5f * xc[i] * (1.f + std::copysign(1.f - poly * e[i], xc[i]));
        }
    }
}

// Σ_i f(x_i) in 8 interleaved partial sums, so the loop vectorises without reassociation.
template <class F>
inline float sum(const float *__restrict x, int n, F f) {
    float part[8] = {};
    int i = 0;
    for (; i + 8 <= n; i += 8)
        for (int l = 0; l < 8; ++l) part[l] += f(x[i + l]);
    float total = 0.f;
    for (; i < n; ++i) total += f(x[i]);
    for (int l = 0; l < 8; ++l) total += part[l];
    return total;
}

// y = (x − μ)/√(σ² + ε)·w + b per row, biased σ² as torch.   x, y [rows, n] (may alias), w, b [n]
inline void layer_norm(const float *x, float *y, int rows, int n, const float *w, const float *b, float eps) {
    for (int r = 0; r < rows; ++r, x += n, y += n) {
        const float mean = sum(x, n, [](float v) { return v; }) / float(n);
        const float var = sum(x, n, [mean](float v) { return (v - mean) * (v - mean); }) / float(n);
        const float inv = 1.f / std::sqrt(var + eps);
        for (int i = 0; i < n; ++i) y[i] = (x[i] - mean) * inv * w[i] + b[i];
    }
}

// ---------------------------------------------------------------------------------------------
// GEMM y = x·wt (+ bias). x(i, k) = x[i·ldx + k·ldk], wt(k, j) = wt[k·ldw + j], y(i, j) = y[i·ldy + j].
// Register-blocked: MR rows × NV Vec8 columns of accumulators stay in registers over the k loop.
// Each y(i, j) is bias + Σ_k in k order whatever the block shape, so a row's result does not
// depend on which rows share its tile (nor on the thread count).

template <int MR, int NV>
inline void gemm_block(const float *__restrict x, int ldx, int ldk, int in, const float *__restrict wt, int ldw,
                const float *bias, float *__restrict y, int ldy) {
    Vec8 acc[MR][NV];
    for (int i = 0; i < MR; ++i)
        for (int v = 0; v < NV; ++v) {
            acc[i][v] = Vec8{};
            if (bias) std::memcpy(&acc[i][v], bias + 8 * v, sizeof(Vec8));
        }
    for (int k = 0; k < in; ++k) {
        Vec8 w[NV];
        for (int v = 0; v < NV; ++v) std::memcpy(&w[v], wt + size_t(k) * size_t(ldw) + 8 * v, sizeof(Vec8));
        for (int i = 0; i < MR; ++i) {
            const float xv = x[i * ldx + k * ldk];
            for (int v = 0; v < NV; ++v) acc[i][v] += xv * w[v];
        }
    }
    for (int i = 0; i < MR; ++i)
        for (int v = 0; v < NV; ++v) std::memcpy(y + i * ldy + 8 * v, &acc[i][v], sizeof(Vec8));
}

// 8 accumulators (MR·NV) hide the FMA latency.
template <int NV>
inline void gemm_columns(const float *x, int ldx, int ldk, int rows, int in, const float *wt, int ldw, const float *bias,
                  float *y, int ldy) {
    int r = 0;
    if (NV == 1)
        for (; r + 8 <= rows; r += 8) gemm_block<8, NV>(x + r * ldx, ldx, ldk, in, wt, ldw, bias, y + r * ldy, ldy);
    for (; r + 4 <= rows; r += 4) gemm_block<4, NV>(x + r * ldx, ldx, ldk, in, wt, ldw, bias, y + r * ldy, ldy);
    for (; r < rows; ++r) gemm_block<1, NV>(x + r * ldx, ldx, ldk, in, wt, ldw, bias, y + r * ldy, ldy);
}

//   x [rows, in] (strides ldx, ldk), wt [in, ≥ n_out] (row stride ldw), bias [n_out] or null  ->  y [rows, n_out]
inline void gemm(const float *x, int ldx, int ldk, int rows, int in, const float *wt, int ldw, int n_out, const float *bias,
          float *y, int ldy) {
    int j = 0;
    for (; j + 16 <= n_out; j += 16)
        gemm_columns<2>(x, ldx, ldk, rows, in, wt + j, ldw, bias ? bias + j : nullptr, y + j, ldy);
    for (; j + 8 <= n_out; j += 8)
        gemm_columns<1>(x, ldx, ldk, rows, in, wt + j, ldw, bias ? bias + j : nullptr, y + j, ldy);
    for (; j < n_out; ++j)   // narrow layers (G < 8, the 3 outputs): scalar, same k order
        for (int r = 0; r < rows; ++r) {
            float acc = bias ? bias[j] : 0.f;
            for (int k = 0; k < in; ++k) acc += x[r * ldx + k * ldk] * wt[size_t(k) * size_t(ldw) + size_t(j)];
            y[r * ldy + j] = acc;
        }
}

}  // namespace ltm::kernels
