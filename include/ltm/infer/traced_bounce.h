// traced_bounce.h: one traced bounce into a model's irradiance field — the incident radiance L⁺
// along any ray from a surface point, resolved as finely as the scene's geometry (issue #11).
//
// The radiance arriving at x from direction ω (emitters seen directly excluded) is what leaves
// the surface y = hit(x, ω) towards x without y's emission. For a Lambertian y that is
//     L⁺(x, ω) = ρ(y)/π · (E_direct(y) + E⁺(y)),
// E_direct traced (shadow rays), E⁺ from the model's irradiance head: the neural render's own
// diffuse shading, one vertex further down the path. A conductor y is path traced on (its
// outgoing radiance is itself directional), a miss contributes 0. The renderer shades
// conductors with it (GlossyShading::trace) and eval-directional compares it with the head and SH.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "ltm/points/point_interpolation.h"
#include "ltm/points/point_set.h"
#include "ltm/render/direct_light.h"
#include "ltm/render/path_tracer.h"

namespace ltm {

/// E_direct at a surface point (p, unit normal n on the side the light is wanted), random stream `key`.
using DirectIrradianceFn = std::function<Vec3f(Vec3f p, Vec3f n, uint64_t key)>;

/// The ratio estimator when `ratio` is given, else the path tracer's MIS estimator; spp light
/// samples per call.
DirectIrradianceFn direct_irradiance_fn(const PathTracer &pt, const RatioDirectLight *ratio, int spp);

/// Ê⁺ at query rows (p, n on the side the light is wanted, albedo), raw units: what the bounce
/// reads at its diffuse hits.   rows [n, 9] (row-major) -> n values (W/m²)
using IrradianceDecoder = std::function<std::vector<Vec3f>(const std::vector<float> &rows)>;

/// Ê⁺ decoded once at the M scene points (each point its own query: p, n, albedo) for the bounce's
/// hits to interpolate (PointInterpolator) instead of decoding each: a gather of the prior costs
/// ~50× an interpolation, and a conductor pixel asks for 64 hits.
struct NodeIrradiance {
    PointInterpolator interpolator;
    std::vector<Vec3f> irradiance;   ///< [M] Ê⁺ at the scene points (W/m²)
    double seconds = 0;              ///< the decode at the points
};
/// points: the scene points the decoder's scene was encoded from ([M, 12] scene_point_columns(),
/// raw); spacing: their mean spacing √(A/M) in metres.
NodeIrradiance decode_node_irradiance(const IrradianceDecoder &decode, const PointSet &points, float spacing);

/// L⁺ along n rays (origin offset off a surface, unit direction; a zero direction: the row is
/// skipped and gets 0), for a scene whose Ê⁺ `decode` gives and that `pt` traces (the same scene).
/// with_emission: L_in instead, the hit surface's emission towards the ray's origin added.
/// keys[i]: row i's random stream (direct light at its hit, the path beyond a conductor).
/// Ê⁺ of every diffuse hit is decoded in one batch; with `nodes`, interpolated from them instead,
/// and decoded only where no scene point lies on the hit's surface nearby. -> [n] radiance
/// (W/m²/sr per channel). Deterministic at any thread count.
std::vector<Vec3f> traced_bounce_radiance(const IrradianceDecoder &decode, const PathTracer &pt,
                                          const std::vector<Ray> &rays, const std::vector<uint64_t> &keys,
                                          const DirectIrradianceFn &direct, bool with_emission = false,
                                          const NodeIrradiance *nodes = nullptr);

}  // namespace ltm
