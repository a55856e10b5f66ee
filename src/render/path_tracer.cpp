// path_tracer.cpp: CPU reference estimators of irradiance and radiance (ground truth).
#include "ltm/render/path_tracer.h"

#include <cmath>

#include "ltm/core/error.h"
#include "ltm/core/parallel.h"
#include "ltm/core/rng.h"
#include "ltm/core/sampling.h"
#include "ltm/render/hemisphere_bins.h"

namespace ltm {

uint64_t stable_hash(const std::string &s) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
    return h;
}

PathTracer::PathTracer(const EmbreeAccel &accel, const PathTracerConfig &cfg)
    : m_accel(accel), m_scene(accel.scene()), m_cfg(cfg), m_lights(accel.scene()) {
    if (m_cfg.max_depth < 1) LTM_THROW("path tracer: max depth must be >= 1, got ", m_cfg.max_depth);
    if (m_cfg.scene_id == 0) m_cfg.scene_id = stable_hash(m_scene.name);
}

uint64_t PathTracer::stream_key(uint64_t index, uint64_t sample) const {
    return hash_keys({m_cfg.seed, m_cfg.scene_id, index, sample});
}

namespace {
// Stratum s of n in [0,1)²: a jittered √n×√n grid when n is a square, else a shifted R2 point
// (the shift is the stratum's own jitter, which keeps the estimate unbiased).
Vec2f stratified(int s, int n, Pcg32 &rng) {
    const int m = int(std::lround(std::sqrt(double(n))));
    if (m * m == n) {
        const float jx = rng.next_float(), jy = rng.next_float();
        return {(float(s / m) + jx) / float(m), (float(s % m) + jy) / float(m)};
    }
    return r2_sequence(uint64_t(s), {rng.next_float(), rng.next_float()});
}
}  // namespace

void PathTracer::set_guide(const GuideCache *guide, float alpha) {
    if (guide && !(alpha > 0.f && alpha <= 1.f)) LTM_THROW("path guiding: the BSDF share α = ", alpha, " must be in (0, 1]");
    m_guide = guide && !guide->empty() ? guide : nullptr;
    m_guide_alpha = alpha;
}

// NEE at si: one light sample, weighted against the vertex's sampler (power heuristic).
Vec3f PathTracer::light_sample_contribution(const SurfaceInteraction &si, const Frame &frame, Vec3f wo_local,
                                            const Bsdf &bsdf, const GuidedSampler &sampler, Pcg32 &rng) const {
    if (m_lights.empty()) return Vec3f(0.f);
    const float u0 = rng.next_float();
    const Vec2f u12{rng.next_float(), rng.next_float()};
    const LightSample ls = m_lights.sample(u0, u12);
    const Vec3f to = ls.p - si.p;
    const float d2 = dot(to, to);
    if (d2 <= 0.f) return Vec3f(0.f);
    const Vec3f wi = to / std::sqrt(d2);
    const float cos_light = -dot(ls.n, wi);
    const Vec3f wi_local = frame.to_local(wi);
    if (cos_light <= 0.f || wi_local.z <= 0.f) return Vec3f(0.f);
    const Vec3f f = bsdf.eval(wo_local, wi_local);
    if (max_component(f) <= 0.f) return Vec3f(0.f);
    if (m_accel.occluded(shadow_ray(si.p, frame.n, ls.p, m_cfg.offset_length))) return Vec3f(0.f);
    const float pdf_l = LightSampler::to_solid_angle(ls.pdf_area, d2, cos_light);
    const float w = power_heuristic(pdf_l, sampler.pdf(wo_local, wi_local));
    return ls.radiance * f * (wi_local.z * w / pdf_l);
}

Vec3f PathTracer::reflected_radiance(const SurfaceInteraction &si0, Vec3f wo_world, int max_scatter, Pcg32 &rng) const {
    Vec3f L(0.f), beta(1.f);
    SurfaceInteraction si = si0;
    Vec3f wo = wo_world;
    for (int depth = 1; depth <= max_scatter; ++depth) {
        // Two-sided reflection: shade on the side the path arrived from.
        const Frame frame(si.front ? si.n : -si.n);
        const Vec3f wo_local = frame.to_local(wo);
        const Bsdf bsdf = si.bsdf();
        // The vertex's sampler: BSDF alone, or the defensive mixture with the nearest cached guide.
        GuidedSampler sampler{&bsdf, nullptr, m_guide_alpha};
        BinDistribution product;
        if (m_guide) {
            if (const int c = m_guide->lookup(si.p, frame.n); c >= 0) {
                if (bsdf.kind == BsdfKind::diffuse) {
                    sampler.guide = &m_guide->diffuse(c);
                } else {
                    const int r = m_guide->resolution();
                    product = BinDistribution(r, product_weights(m_guide->radiance(c), r, bsdf, wo_local));
                    sampler.guide = &product;
                }
            }
        }
        L += beta * light_sample_contribution(si, frame, wo_local, bsdf, sampler, rng);
        const float u_pick = m_guide ? rng.next_float() : 0.f;   // drawn only when guiding: unguided streams unchanged
        const BsdfSample bs = sampler.sample(wo_local, u_pick, {rng.next_float(), rng.next_float()});
        if (bs.pdf <= 0.f || max_component(bs.weight) <= 0.f) break;
        beta = beta * bs.weight;
        const Vec3f wi = frame.to_world(bs.wi);
        const Ray ray{offset_ray_origin(si.p, frame.n, wi, m_cfg.offset_length), wi};
        const auto hit = m_accel.intersect(ray);
        if (!hit) break;
        const SurfaceInteraction next = make_interaction(m_scene, ray, *hit);
        const Vec3f le = next.emitted();
        if (max_component(le) > 0.f) {   // emission reached by BSDF sampling, MIS vs NEE
            const float pdf_l = LightSampler::to_solid_angle(m_lights.pdf_area(hit->mesh, hit->triangle),
                                                             hit->t * hit->t * dot(wi, wi), -dot(hit->n, wi));
            L += beta * le * power_heuristic(bs.pdf, pdf_l);
        }
        if (depth == max_scatter) break;
        if (depth >= m_cfg.rr_depth) {   // Russian roulette, survival ∝ throughput: unbiased
            const float q = std::max(0.05f, 1.f - max_component(beta));
            if (rng.next_float() < q) break;
            beta = beta / (1.f - q);
        }
        si = next;
        wo = -wi;
    }
    return L;
}

IrradianceEstimate PathTracer::irradiance_sample(Vec3f p, Vec3f n, uint64_t key, int s, int n_samples,
                                                 bool with_indirect) const {
    Pcg32 rng(key);
    IrradianceEstimate e;
    const Frame frame(n);
    // The irradiance integrand's direction: cosine-weighted (cos/pdf = π), or with a guide nearby
    // the mixture α·cos/π + (1 − α)·guide (stratified u either way), weighted cos/pdf exactly.
    const Vec2f u = stratified(s, n_samples, rng);
    const Bsdf lambert{BsdfKind::diffuse, Vec3f(1.f), Vec3f(0.f), 0.3f};
    GuidedSampler sampler{&lambert, nullptr, m_guide_alpha};
    if (m_guide && with_indirect)
        if (const int c = m_guide->lookup(p, n); c >= 0) sampler.guide = &m_guide->diffuse(c);
    Vec3f wi = frame.to_world(sample_cosine_hemisphere(u));
    float pdf_b = std::max(dot(wi, n), 0.f) * k_inv_pi, cos_over_pdf = k_pi;   // the cosine strategy, exactly as unguided
    bool traced = true;
    if (sampler.guide) {
        const float u_pick = rng.next_float();
        const BsdfSample bs = sampler.sample({0.f, 0.f, 1.f}, u_pick, u);
        traced = bs.pdf > 0.f && bs.wi.z > 0.f;
        wi = frame.to_world(bs.wi), pdf_b = bs.pdf, cos_over_pdf = traced ? bs.wi.z / bs.pdf : 0.f;
    }
    if (traced) {
        const Ray ray{offset_ray_origin(p, n, wi, m_cfg.offset_length), wi};
        if (const auto hit = m_accel.intersect(ray)) {
            const SurfaceInteraction y = make_interaction(m_scene, ray, *hit);
            const Vec3f le = y.emitted();
            if (max_component(le) > 0.f) {
                const float pdf_l = LightSampler::to_solid_angle(m_lights.pdf_area(hit->mesh, hit->triangle),
                                                                 hit->t * hit->t, -dot(hit->n, wi));
                e.direct = le * (cos_over_pdf * power_heuristic(pdf_b, pdf_l));
            }
            if (with_indirect) e.indirect = reflected_radiance(y, -wi, m_cfg.max_depth, rng) * cos_over_pdf;
        }
    }
    // Light sample: Le·cosθ / pdf_l, MIS-weighted against the cosine strategy.
    if (!m_lights.empty()) {
        const float u0 = rng.next_float();
        const LightSample ls = m_lights.sample(u0, {rng.next_float(), rng.next_float()});
        const Vec3f to = ls.p - p;
        const float d2 = dot(to, to);
        const Vec3f wl = to / std::sqrt(d2);
        const float cos_x = dot(n, wl), cos_light = -dot(ls.n, wl);
        if (d2 > 0.f && cos_x > 0.f && cos_light > 0.f) {
            if (!m_accel.occluded(shadow_ray(p, n, ls.p, m_cfg.offset_length))) {
                const float pdf_l = LightSampler::to_solid_angle(ls.pdf_area, d2, cos_light);
                const float pdf_b_l = sampler.guide ? sampler.pdf({0.f, 0.f, 1.f}, frame.to_local(wl)) : cos_x * k_inv_pi;
                e.direct += ls.radiance * (cos_x * power_heuristic(pdf_l, pdf_b_l) / pdf_l);
            }
        }
    }
    return e;
}

IrradianceEstimate PathTracer::irradiance(Vec3f p, Vec3f n, uint64_t point_index, int n_samples,
                                          bool with_indirect) const {
    if (n_samples <= 0) LTM_THROW("path tracer: samples per point must be > 0, got ", n_samples);
    IrradianceEstimate sum;
    for (int s = 0; s < n_samples; ++s) {
        const IrradianceEstimate e = irradiance_sample(p, n, stream_key(point_index, uint64_t(s)), s, n_samples, with_indirect);
        sum.direct += e.direct;
        sum.indirect += e.indirect;
    }
    const float inv = 1.f / float(n_samples);
    return {sum.direct * inv, sum.indirect * inv};
}

std::vector<Vec3f> PathTracer::incident_radiance_bins(Vec3f p, Vec3f n, uint64_t point_index, int resolution,
                                                      int samples_per_bin, bool with_emission) const {
    if (resolution <= 0 || samples_per_bin <= 0)
        LTM_THROW("path tracer: bin resolution and samples per bin must be > 0");
    const Frame frame(n);
    std::vector<Vec3f> bins(size_t(resolution * resolution));
    for (int b = 0; b < resolution * resolution; ++b) {
        Vec3f sum(0.f);
        for (int s = 0; s < samples_per_bin; ++s) {
            Pcg32 rng(stream_key(point_index, (uint64_t(b) << 32) | uint64_t(s)));
            const Vec2f u = stratified(s, samples_per_bin, rng);
            const Vec3f wi = frame.to_world(square_to_direction(bin_to_square(b, resolution, u)));
            const Ray ray{offset_ray_origin(p, n, wi, m_cfg.offset_length), wi};
            const auto hit = m_accel.intersect(ray);
            if (!hit) continue;
            const SurfaceInteraction y = make_interaction(m_scene, ray, *hit);
            sum += (with_emission ? y.emitted() : Vec3f(0.f)) + reflected_radiance(y, -wi, m_cfg.max_depth, rng);
        }
        bins[size_t(b)] = sum / float(samples_per_bin);
    }
    return bins;
}

void trace_irradiance(const PathTracer &pt, const float *rows, size_t stride, size_t n, int strata, Vec3f *direct, Vec3f *indirect,
                      const uint64_t *keys) {
    if (stride < 6) LTM_THROW("trace_irradiance: rows need p and n (stride >= 6), got ", stride);
    parallel_for(0, int64_t(n), 64, [&](int64_t b, int64_t e) {
        for (int64_t i = b; i < e; ++i) {
            const float *r = rows + size_t(i) * stride;
            const IrradianceEstimate est = pt.irradiance(Vec3f(r[0], r[1], r[2]), Vec3f(r[3], r[4], r[5]), keys ? keys[i] : uint64_t(i), strata);
            direct[i] = est.direct, indirect[i] = est.indirect;
        }
    });
}

}  // namespace ltm
