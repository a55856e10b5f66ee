// patch_form_factor.cpp: Lambert's contour integral for a square clipped to a hemisphere (header).
#include "ltm/points/patch_form_factor.h"

#include <algorithm>
#include <cmath>

namespace ltm {

float patch_form_factor(Vec3f p, Vec3f n, Vec3f c, Vec3f nc, float side) {
    if (!(dot(nc, p - c) > 0.f)) return 0.f;   // behind the patch (or in its plane)
    const Vec3f up(0.f, 1.f, 0.f);
    const Vec3f t1 = std::abs(nc.y) > 0.99f ? Vec3f(1.f, 0.f, 0.f) : normalize(cross(up, nc));
    const Vec3f t2 = cross(nc, t1);
    const float h = 0.5f * side;
    // Vertices relative to p, then clipped to n·v ≥ 0 (Sutherland–Hodgman against one plane: a
    // square gives at most 5 vertices).
    const Vec3f q = c - p;
    const Vec3f square[4] = {q - t1 * h - t2 * h, q + t1 * h - t2 * h, q + t1 * h + t2 * h, q - t1 * h + t2 * h};
    Vec3f v[5];
    int count = 0;
    for (int k = 0; k < 4; ++k) {
        const Vec3f a = square[k], b = square[(k + 1) % 4];
        const float da = dot(n, a), db = dot(n, b);
        if (da >= 0.f) v[count++] = a;
        if ((da >= 0.f) != (db >= 0.f)) v[count++] = a + (b - a) * (da / (da - db));
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

}  // namespace ltm
