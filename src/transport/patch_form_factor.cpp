// patch_form_factor.cpp: Lambert's contour integral for a square clipped to a hemisphere (header).
#include "ltm/transport/patch_form_factor.h"

#include <algorithm>
#include <cmath>

namespace ltm {

namespace {
// The square's first side: ŷ × n_s where that is not short (it maps with quarter turns about ŷ and
// mirrors), else x̂ made orthogonal to n_s (a floor or ceiling: the square's sides along x̂ and ẑ).
Vec3f patch_tangent(Vec3f nc) {
    const Vec3f t = cross(Vec3f(0.f, 1.f, 0.f), nc);
    if (length(t) > 1e-4f) return normalize(t);
    return normalize(Vec3f(1.f, 0.f, 0.f) - nc * nc.x);
}
}  // namespace

float patch_form_factor(Vec3f p, Vec3f n, Vec3f c, Vec3f nc, float side) {
    // Behind the patch, in its plane, or within rounding of it (a coplanar neighbour on a tilted
    // facet must not see the square from its own plane).
    const float eps = 1e-5f * side;
    if (!(dot(nc, p - c) > eps)) return 0.f;
    const Vec3f t1 = patch_tangent(nc), t2 = cross(nc, t1);
    const float h = 0.5f * side;
    // Vertices relative to p, clipped to n·v ≥ 0 (Sutherland–Hodgman against one plane). The
    // heights n·v are formed from three scalars, Q ± A ± B, so their signs are those of an affine
    // function on a parallelogram: the cut is convex (at most 5 vertices; 8 slots for safety).
    const Vec3f q = c - p;
    const float Q = dot(n, q), A = h * dot(n, t1), B = h * dot(n, t2);
    const Vec3f square[4] = {q - t1 * h - t2 * h, q + t1 * h - t2 * h, q + t1 * h + t2 * h, q - t1 * h + t2 * h};
    const float height[4] = {Q - A - B, Q + A - B, Q + A + B, Q - A + B};
    Vec3f v[8];
    int count = 0;
    for (int k = 0; k < 4 && count <= 6; ++k) {
        const int l = (k + 1) % 4;
        const float da = height[k], db = height[l];
        if (da >= 0.f) v[count++] = square[k];
        if ((da >= 0.f) != (db >= 0.f)) v[count++] = square[k] + (square[l] - square[k]) * (da / (da - db));
    }
    if (count < 3) return 0.f;
    // γ_k = atan2(|a × b|, a · b): one square root per edge, and accurate at small angles (acos is not).
    float sum = 0.f;
    for (int k = 0; k < count; ++k) {
        const Vec3f a = v[k], b = v[(k + 1) % count];
        const Vec3f axb = cross(a, b);
        const float len = length(axb);
        if (!(len > 0.f)) continue;   // a vertex at p, or two collinear with it: no angle
        sum += std::atan2(len, dot(a, b)) * dot(n, axb) / len;
    }
    // The orientation of the contour decides the sign; the patch faces p, so the magnitude counts.
    return std::min(1.f, std::abs(sum) / (2.f * float(k_pi)));
}

// Out of line: the dense rows (transport_prior.cpp) and the tree (prior_hierarchy.cpp, built without
// FMA contraction) call one compiled copy of the gate.
float near_form_factor(Vec3f p, Vec3f n, Vec3f c, Vec3f nc, float side) {
    return dot(n, c - p) > 0.f ? patch_form_factor(p, n, c, nc, side) : 0.f;
}

}  // namespace ltm
