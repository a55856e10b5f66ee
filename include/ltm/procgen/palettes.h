// palettes.h: realistic linear-RGB albedo palettes for generated interiors, and the choice of
// plain vs spatially varying (wood, checker, stripes, noise) albedo per surface.
#pragma once

#include "ltm/core/rng.h"
#include "ltm/procgen/gen_config.h"
#include "ltm/scene/texture.h"

namespace ltm {

/// What a surface is made of; selects the palette and which patterns it may get.
enum class SurfaceKind { wall, ceiling, floor, wood, painted, fabric, bedding, metal, ceramic, foliage, books, carpet };

const char *surface_kind_name(SurfaceKind kind);

/// Draws an albedo for a surface: a palette colour with per-object jitter, and with the
/// config's probabilities a procedural pattern. Every colour is linear RGB with max component
/// <= 0.85 and quantised to 1e-4 (byte-stable output).
Texture sample_albedo(SurfaceKind kind, const GenConfig::Textures &cfg, Pcg32 &rng);

/// Rounds to a multiple of 1e-4, so float noise from libm never reaches the output.
float quantize(float v);
Vec3f quantize(Vec3f v);

}  // namespace ltm
