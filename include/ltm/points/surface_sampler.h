// surface_sampler.h: area-weighted, stratified, low-discrepancy sampling of scene surfaces
// (paper §4.1): scene points carry p, n, albedo, emission; query points p, n, albedo.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "ltm/points/point_set.h"
#include "ltm/scene/scene.h"

namespace ltm {

struct SurfaceSample {
    Vec3f p, n;                 ///< position (m) and unit geometric normal (winding side)
    Vec3f albedo, emission;     ///< texture values at the sample's uv
    uint32_t mesh = 0, triangle = 0;
    /// The candidate's identity: its stream in the top 8 bits, round · n + index in its draw
    /// (sample_surface) below. What a seeded choice among samples, or a random stream of a sample,
    /// keys on: an index in the output shifts with every candidate the filter judged otherwise
    /// before it (the same scene in another unit, through float rounding), the identity does not.
    uint64_t id = 0;
};

/// Independent sample streams of one scene (different points for the same seed).
enum class SampleStream : uint64_t { scene_points = 1, query_points = 2, view_points = 3, emitter_points = 4 };

/// What a sample's triangle is drawn in proportion to: its area (the paper's surface sampling), or
/// the luminance power it emits, area × lum(Le at its centroid) (emitters only; scene_points.h).
enum class SampleWeight { area, emitted_power };

/// Largest point count one call accepts (memory guard: 48 bytes per sample).
inline constexpr int64_t k_max_sample_count = 50'000'000;

/// Returns true for samples to drop (e.g. enclosed surfaces, see render/enclosure.h). It may turn a
/// sample it keeps to the other side of its surface (n → −n; see enclosed_filter()).
using SampleFilter = std::function<bool(SurfaceSample &)>;

/// What a filtered draw saw: the filter's pass fraction over every candidate drawn estimates the
/// share of the surface area that passes (the area the scene points represent).
struct SampleStats {
    int64_t candidates = 0;   ///< candidates drawn (all rounds)
    int64_t passed = 0;       ///< of those, kept by the filter (== candidates without a filter)
    double pass_fraction() const { return candidates > 0 ? double(passed) / double(candidates) : 0.0; }
};

/// n_points samples, area-weighted over all triangles. Triangle choice is stratified in one
/// dimension ((i + ξ_i)/n through the area CDF), the in-triangle position follows Roberts' R2
/// sequence with a seeded shift, so every triangle's samples are well spread. Sample i is a pure
/// function of (seed, stream, n_points, i): identical at any thread count.
/// With a filter, candidates come in rounds of n_points independent stratified draws until enough
/// pass: all survivors of the earlier rounds and a seeded uniform subset of the last round's, still
/// area-weighted over the surfaces that pass the filter. One candidate whose verdict flips changes
/// at most one output point (tested): the same scene in another unit samples the same points.
/// With SampleWeight::emitted_power the same construction runs over the emitting triangles only,
/// weighted by their power (throws if nothing emits).
std::vector<SurfaceSample> sample_surface(const Scene &scene, int64_t n_points, uint64_t seed,
                                          SampleStream stream, const SampleFilter &filter = {},
                                          SampleStats *stats = nullptr, SampleWeight weight = SampleWeight::area);

/// π ∫ lum(Le) dA over the emitting triangles, Le taken at each triangle's centroid (the weights of
/// SampleWeight::emitted_power): the scene's luminance power (W).
double emitted_luminance_power(const Scene &scene);

/// [M, 12] scene points (scene_point_columns()).
PointSet to_scene_points(const std::vector<SurfaceSample> &samples);
/// [N, 9] query points (query_point_columns()).
PointSet to_query_points(const std::vector<SurfaceSample> &samples);

}  // namespace ltm
