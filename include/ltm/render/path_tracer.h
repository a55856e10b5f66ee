// path_tracer.h: the ground-truth estimators (ARCHITECTURE.md §5). Everything ltm learns and
// reports is judged against these, so they are validated against closed forms in tests.
//
// Definitions. E(x) = ∫_H L_i(x,ω) cosθ dω. E_direct: radiance emitted by a light arriving at x
// unscattered. E_indirect (E⁺): everything else (light that scattered at least once).
// Depth convention: max_depth counts scattering events after x. E⁺ with max_depth D sums paths
// x ← y1 ← … ← yk ← light with 1 ≤ k ≤ D; the image of a diffuse point uses the same E⁺.
#pragma once

#include <cstdint>
#include <vector>

#include "ltm/render/embree_accel.h"
#include "ltm/render/guide_cache.h"
#include "ltm/render/interaction.h"
#include "ltm/render/light_sampler.h"

namespace ltm {

struct PathTracerConfig {
    uint64_t seed = 0;
    uint64_t scene_id = 0;   ///< mixes into every random stream (default: hash of the scene name)
    int max_depth = 5;       ///< scattering events after the query point (paper: 5)
    int rr_depth = 5;        ///< Russian roulette from this many scattering events on (unbiased)
    /// Floor of the rays' self-intersection offset (render/ray.h offset_ray_origin), scene units:
    /// 1 (a metre) for rendering; a length of the scene's own where the answer must not depend on
    /// the unit (the model's traced inputs, infer/prior_model.h: 1 % of the extent; with a metre's
    /// floor a 10 m house scaled ×10 offsets its rays 8 % less, and paths that graze an edge go elsewhere).
    float offset_length = 1.f;
};

struct IrradianceEstimate {
    Vec3f direct, indirect;   ///< E_direct, E⁺ in W/m²
};

class Pcg32;

class PathTracer {
public:
    PathTracer(const EmbreeAccel &accel, const PathTracerConfig &cfg);

    /// E_direct and E⁺ at (p, n) from n_samples strata: for E⁺, stratified cosine-weighted
    /// directions (each adds π·L_r(y), L_r without emission at y, by path tracing with NEE+MIS);
    /// for E_direct, one light sample per stratum, MIS-combined (power heuristic) with the
    /// cosine directions that hit a light. Deterministic in (seed, scene_id, point_index, sample).
    IrradianceEstimate irradiance(Vec3f p, Vec3f n, uint64_t point_index, int n_samples, bool with_indirect = true) const;

    /// Incident radiance L_i (emission + scattered, up to max_depth scattering events) averaged
    /// over each of the resolution² bins of hemisphere_bins.h, samples_per_bin stratified samples
    /// each. Returns [resolution², 3] row-major (bin i·R + j). with_emission false: L_i⁺, only
    /// the light scattered at least once (no emitter seen directly), whose cosine integral
    /// (π/R²) Σ L̄ is the indirect irradiance E⁺.
    std::vector<Vec3f> incident_radiance_bins(Vec3f p, Vec3f n, uint64_t point_index, int resolution,
                                              int samples_per_bin, bool with_emission = true) const;

    /// One stratum of irradiance(): sample s of n_samples, random stream `key`.
    /// with_indirect = false skips the path continuation (E⁺ = 0): the same E_direct estimator, for
    /// renderers that take E⁺ from elsewhere (the neural renderer).
    IrradianceEstimate irradiance_sample(Vec3f p, Vec3f n, uint64_t key, int s, int n_samples,
                                         bool with_indirect = true) const;

    /// Radiance leaving surface point `si` towards -wo_dir... reflected only (no emission at si),
    /// with at most `max_scatter` scattering events counting si as the first.
    Vec3f reflected_radiance(const SurfaceInteraction &si, Vec3f wo_world, int max_scatter, Pcg32 &rng) const;

    /// Stream key for (point or pixel index, sample index).
    uint64_t stream_key(uint64_t index, uint64_t sample) const;
    const PathTracerConfig &config() const { return m_cfg; }
    /// Path guiding (render/guide_cache.h): at every vertex of reflected_radiance() with a cache
    /// point nearby, the next direction comes from α·BSDF + (1 − α)·guide (product with the BSDF
    /// for conductors), with the mixture's exact pdf in the MIS weights: unbiased. irradiance_sample()
    /// (with_indirect) draws its first direction from α·cos/π + (1 − α)·guide, its pdf in both
    /// MIS weights of direct light. Null: plain BSDF sampling, bit-identical to a tracer without a guide.
    void set_guide(const GuideCache *guide, float alpha = 0.25f);
    const EmbreeAccel &accel() const { return m_accel; }

private:
    Vec3f light_sample_contribution(const SurfaceInteraction &si, const Frame &frame, Vec3f wo_local,
                                    const Bsdf &bsdf, const GuidedSampler &sampler, Pcg32 &rng) const;
    const EmbreeAccel &m_accel;
    const Scene &m_scene;
    PathTracerConfig m_cfg;
    LightSampler m_lights;
    const GuideCache *m_guide = nullptr;
    float m_guide_alpha = 0.25f;
};

/// Power heuristic (β = 2) for combining two strategies with pdfs a (taken) and b (other).
inline float power_heuristic(float a, float b) {
    const float a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.f ? a2 / (a2 + b2) : 0.f;
}

/// FNV-1a of a string: stable scene ids from names.
uint64_t stable_hash(const std::string &s);

/// E_dir and E⁺ at n points, `strata` strata each (PathTracer::irradiance, point i on stream
/// keys[i], or i without keys): rows hold p at floats 0–2 and the unit normal at 3–5, `stride`
/// floats a row; direct [n], indirect [n], keys [n] or null. Parallel, the same numbers at any
/// thread count. The model's traced inputs (nn/model_config.h traced_inputs) are these at its scene points.
void trace_irradiance(const PathTracer &pt, const float *rows, size_t stride, size_t n, int strata, Vec3f *direct, Vec3f *indirect,
                      const uint64_t *keys = nullptr);

}  // namespace ltm
