// ply_scalar.h: the scalar property types of the PLY format, shared by the point reader
// (points/ply_io) and the mesh reader (scene/ply_mesh): names, sizes, and decoding from bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>

namespace ltm {

enum class PlyType { i8, u8, i16, u16, i32, u32, f32, f64 };

/// "char"/"int8", "uchar"/"uint8", ..., "double"/"float64" → type; false for an unknown name.
inline bool parse_ply_type(const std::string &s, PlyType &t) {
    static const std::pair<const char *, PlyType> names[] = {
        {"char", PlyType::i8},   {"int8", PlyType::i8},     {"uchar", PlyType::u8},   {"uint8", PlyType::u8},
        {"short", PlyType::i16}, {"int16", PlyType::i16},   {"ushort", PlyType::u16}, {"uint16", PlyType::u16},
        {"int", PlyType::i32},   {"int32", PlyType::i32},   {"uint", PlyType::u32},   {"uint32", PlyType::u32},
        {"float", PlyType::f32}, {"float32", PlyType::f32}, {"double", PlyType::f64}, {"float64", PlyType::f64}};
    for (const auto &[n, ty] : names)
        if (s == n) return t = ty, true;
    return false;
}

inline size_t ply_type_size(PlyType t) {
    switch (t) {
    case PlyType::i8: case PlyType::u8: return 1;
    case PlyType::i16: case PlyType::u16: return 2;
    case PlyType::i32: case PlyType::u32: case PlyType::f32: return 4;
    case PlyType::f64: return 8;
    }
    return 0;
}

/// The value at p (ply_type_size(t) bytes). big_endian: the bytes are reversed first (ltm runs
/// on little-endian hosts only; checked at start-up).
inline double decode_ply_scalar(const char *p, PlyType t, bool big_endian = false) {
    unsigned char b[8];
    const size_t n = ply_type_size(t);
    std::memcpy(b, p, n);
    if (big_endian)
        for (size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    switch (t) {
    case PlyType::i8: { int8_t v; std::memcpy(&v, b, 1); return v; }
    case PlyType::u8: return b[0];
    case PlyType::i16: { int16_t v; std::memcpy(&v, b, 2); return v; }
    case PlyType::u16: { uint16_t v; std::memcpy(&v, b, 2); return v; }
    case PlyType::i32: { int32_t v; std::memcpy(&v, b, 4); return v; }
    case PlyType::u32: { uint32_t v; std::memcpy(&v, b, 4); return v; }
    case PlyType::f32: { float v; std::memcpy(&v, b, 4); return v; }
    case PlyType::f64: { double v; std::memcpy(&v, b, 8); return v; }
    }
    return 0;
}

}  // namespace ltm
