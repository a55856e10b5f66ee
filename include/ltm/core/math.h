// math.h: small fixed-size vector types and geometry helpers used by every layer.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <ostream>

namespace ltm {

inline constexpr float k_pi = 3.14159265358979323846f;
inline constexpr float k_inv_pi = 0.31830988618379067154f;

/// Inclusive integer range [lo, hi] (a config's count range).
struct IntRange {
    int lo = 0, hi = 0;
};

struct Vec2f {
    float x = 0, y = 0;
};

struct Vec3f {
    float x = 0, y = 0, z = 0;
    constexpr Vec3f() = default;
    constexpr Vec3f(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    constexpr explicit Vec3f(float s) : x(s), y(s), z(s) {}
    float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    float &operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};

inline Vec3f operator+(Vec3f a, Vec3f b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3f operator-(Vec3f a, Vec3f b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3f operator-(Vec3f a) { return {-a.x, -a.y, -a.z}; }
inline Vec3f operator*(Vec3f a, Vec3f b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline Vec3f operator*(Vec3f a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3f operator*(float s, Vec3f a) { return a * s; }
inline Vec3f operator/(Vec3f a, float s) { return a * (1.f / s); }
inline Vec3f &operator+=(Vec3f &a, Vec3f b) { return a = a + b; }
inline Vec3f &operator-=(Vec3f &a, Vec3f b) { return a = a - b; }
inline Vec3f &operator*=(Vec3f &a, float s) { return a = a * s; }
inline bool operator==(Vec3f a, Vec3f b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
inline bool operator!=(Vec3f a, Vec3f b) { return !(a == b); }
inline std::ostream &operator<<(std::ostream &os, Vec3f v) {
    return os << "(" << v.x << ", " << v.y << ", " << v.z << ")";
}

inline float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3f cross(Vec3f a, Vec3f b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3f a) { return std::sqrt(dot(a, a)); }
inline Vec3f normalize(Vec3f a) { return a / length(a); }
inline Vec3f min(Vec3f a, Vec3f b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
inline Vec3f max(Vec3f a, Vec3f b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
inline float max_component(Vec3f a) { return std::max(a.x, std::max(a.y, a.z)); }
inline bool is_finite(Vec3f a) {
    return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}
/// Rec. 709 luminance of a linear RGB triple.
inline float luminance(Vec3f rgb) { return 0.2126f * rgb.x + 0.7152f * rgb.y + 0.0722f * rgb.z; }

/// Orthonormal basis around a unit normal (Duff et al. 2017, branchless).
struct Frame {
    Vec3f s, t, n;
    explicit Frame(Vec3f n_) : n(n_) {
        const float sign = std::copysign(1.f, n.z);
        const float a = -1.f / (sign + n.z), b = n.x * n.y * a;
        s = {1.f + sign * n.x * n.x * a, sign * b, -sign * n.x};
        t = {b, sign + n.y * n.y * a, -n.y};
    }
    Vec3f to_world(Vec3f v) const { return s * v.x + t * v.y + n * v.z; }
    Vec3f to_local(Vec3f v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
};

/// Axis-aligned bounding box; empty when lo > hi.
struct Bounds3f {
    Vec3f lo{std::numeric_limits<float>::infinity()};
    Vec3f hi{-std::numeric_limits<float>::infinity()};
    void expand(Vec3f p) { lo = min(lo, p), hi = max(hi, p); }
    void expand(const Bounds3f &b) { lo = min(lo, b.lo), hi = max(hi, b.hi); }
    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    Vec3f center() const { return (lo + hi) * 0.5f; }
    Vec3f extent() const { return hi - lo; }
};

/// Affine transform p' = A p + t, stored row-major (3x4). Normals use the inverse transpose.
struct Transform {
    float m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
    Vec3f apply_point(Vec3f p) const {
        return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    }
    Vec3f apply_vector(Vec3f v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
                m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
    /// Determinant of the linear part; negative when the transform mirrors (winding flips).
    float determinant() const {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
               m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    }
    bool is_identity() const;
    static Transform translate(Vec3f t);
    static Transform scale(Vec3f s);
    /// Rotation by `degrees` about a unit axis (right-handed).
    static Transform rotate(Vec3f axis, float degrees);
    /// Composition: (a * b).apply(p) == a.apply(b.apply(p)).
    friend Transform operator*(const Transform &a, const Transform &b);
};

inline float clamp(float v, float lo, float hi) { return std::min(std::max(v, lo), hi); }
inline float lerp(float a, float b, float t) { return a + (b - a) * t; }

}  // namespace ltm
