// ltm_model.cpp: wiring of embedding, encoder and decoder, and the loss.
#include "ltm/nn/ltm_model.h"

#include <cmath>
#include <chrono>

#include "ltm/core/error.h"
#include "ltm/core/math.h"
#include "ltm/core/progress.h"
#include "ltm/nn/fused_decoder.h"
#include "ltm/nn/knn.h"
#include "ltm/nn/scene_frame.h"
#include "ltm/points/point_set.h"

#include <optional>
#include <tuple>
#include <utility>
#include <vector>

namespace ltm {

namespace {
// norm.output [3] as the gathers' floor scale.
Vec3f output_vec3(const SceneNormalization &norm) {
    const auto o = norm.output.detach().to(torch::kCPU, torch::kFloat32).contiguous();
    return Vec3f(o[0].item<float>(), o[1].item<float>(), o[2].item<float>());
}

// A transport (the prior or its regather) gathered at queries in the normalised frame and floored
// at 10⁻³ · norm.output (prior_scale_normalized).   q [N, 9] -> [N, 3]
torch::Tensor gathered_normalized(const torch::Tensor &q, const TransportPrior &transport, const SceneNormalization &norm) {
    torch::NoGradGuard no_grad;
    const auto qc = q.detach().to(torch::kCPU, torch::kFloat32).contiguous();
    auto out = torch::empty({qc.size(0), 3}, torch::kFloat32);
    prior_scale_normalized(&transport, output_vec3(norm), qc.data_ptr<float>(), 9, size_t(qc.size(0)),
                           reinterpret_cast<Vec3f *>(out.data_ptr<float>()));
    return out.to(norm.output.device());
}

// output_scale for queries already in the normalised frame.   q [N, 9] -> [3] or [N, 3]
torch::Tensor output_scale_normalized(const torch::Tensor &q, const SceneNormalization &norm) {
    if (!norm.transport) return norm.output;
    return gathered_normalized(q, *norm.transport, norm);
}

// A traced-queries model decodes against the frame's regather: named here, not by a missing tensor later.
void require_regather(const ModelConfig &cfg, const SceneNormalization &norm) {
    if (!norm.regather)
        LTM_THROW("model '", cfg.name, "' has traced queries: decoding needs the regathered prior (encode the scene with its path tracer)");
}

torch::Tensor vec3_tensor(Vec3f v, const torch::TensorOptions &opts) { return torch::tensor({v.x, v.y, v.z}).to(opts); }
}  // namespace

SceneNormalization scene_normalization(const torch::Tensor &sp, const SceneGeometry &geometry, const PhysicsConfig &physics,
                                       const torch::Tensor &emission_scale, std::shared_ptr<const SegmentOcclusion> occlusion,
                                       const PointTracer &tracer, bool point_inputs) {
    TORCH_CHECK(sp.dim() == 2 && sp.size(1) == 12, "scene points must be [M, 12], got ", sp.sizes());
    const auto c = sp.detach().to(torch::kCPU, torch::kFloat32).contiguous();
    PointGroups g;
    if (geometry.centers.defined()) {
        const auto ce = geometry.centers.to(torch::kCPU, torch::kInt64).contiguous(), gr = geometry.groups.to(torch::kCPU, torch::kInt64).contiguous();
        g.centers.assign(ce.data_ptr<int64_t>(), ce.data_ptr<int64_t>() + ce.numel());
        g.groups.assign(gr.data_ptr<int64_t>(), gr.data_ptr<int64_t>() + gr.numel());
        g.k = gr.dim() == 2 ? gr.size(1) : 0;
    }
    Vec3f given(0.f);
    if (emission_scale.defined()) {
        TORCH_CHECK(emission_scale.dim() == 1 && emission_scale.size(0) == 3, "emission scale must be [3], got ", emission_scale.sizes());
        const auto e = emission_scale.detach().to(torch::kCPU, torch::kFloat32).contiguous();
        given = Vec3f(e[0].item<float>(), e[1].item<float>(), e[2].item<float>());
    }
    // One implementation of the frame, tensor model or not (nn/scene_frame.h).
    const SceneFrame f = solve_scene_frame(c.data_ptr<float>(), size_t(c.size(0)), g, physics, emission_scale.defined() ? &given : nullptr,
                                           std::move(occlusion), tracer, point_inputs);
    const auto opts = sp.options();
    SceneNormalization n;
    n.center = vec3_tensor(f.center, opts);
    n.length = torch::full({}, f.length, opts);
    n.emission = vec3_tensor(f.emission, opts);
    n.output = vec3_tensor(f.output, opts);
    n.transport = f.transport;
    n.regather = f.regather;
    n.solve_seconds = f.solve_seconds;
    n.trace_seconds = f.trace_seconds;
    if (!f.traced.empty()) {
        const int64_t m = int64_t(f.traced.size());
        const auto traced = torch::from_blob(const_cast<Vec3f *>(f.traced.data()), {m, 3}, torch::kFloat32);
        if (!f.regathered.empty()) {
            const auto regathered = torch::from_blob(const_cast<Vec3f *>(f.regathered.data()), {m, 3}, torch::kFloat32);
            n.point_traced = torch::cat({traced, regathered}, 1).to(opts);   // [M, 6] (cat copies)
        } else {
            n.traced_light = traced.clone().to(opts);   // [M, 3]: point_traced's first half, for a deferred encoder
        }
    }
    return n;
}

torch::Tensor normalize_scene_points(const torch::Tensor &sp, const SceneNormalization &n) {
    TORCH_CHECK(sp.dim() == 2 && sp.size(1) == 12, "scene points must be [M, 12], got ", sp.sizes());
    const auto e = sp.slice(1, 9, 12);
    // A channel without emission (S_c = 0) stays 0 rather than 0/0.
    const auto e_norm = torch::where(n.emission > 0, e / n.emission.clamp_min(1e-30), torch::zeros_like(e));
    return torch::cat({(sp.slice(1, 0, 3) - n.center) / n.length, sp.slice(1, 3, 9), torch::log1p(e_norm)}, 1);
}

torch::Tensor normalize_query_points(const torch::Tensor &qp, const SceneNormalization &n) {
    TORCH_CHECK(qp.dim() == 2 && qp.size(1) == 9, "query points must be [N, 9], got ", qp.sizes());
    if (!torch::isfinite(qp).all().item<bool>()) LTM_THROW("query points contain NaN or Inf");
    return torch::cat({(qp.slice(1, 0, 3) - n.center) / n.length, qp.slice(1, 3, 9)}, 1);
}

LtmModelImpl::LtmModelImpl(const ModelConfig &c) : cfg(c) {
    // The JSON reader refuses these with the file's line; a config built in code meets them here,
    // before a shape error deep in the embedding or the decoder would.
    if (cfg.traced_inputs > 0 && !cfg.prior_inputs)
        LTM_THROW("model '", cfg.name, "': traced inputs need prior_inputs (they stand beside the prior's own)");
    if (cfg.traced_queries && cfg.traced_inputs <= 0)
        LTM_THROW("model '", cfg.name, "': traced queries need traced_inputs > 0 (the traced light they regather)");
    if (cfg.physics.prior_regathered && (!cfg.prior_inputs || cfg.traced_inputs <= 0 || cfg.traced_queries || cfg.decoder.level_points > 0 ||
                                         (cfg.directional && cfg.directional->prior_cells > 0)))
        LTM_THROW("model '", cfg.name, "': physics.prior_regathered needs prior_inputs and traced_inputs > 0, and not traced_queries, "
                  "decoder.level_points or directional.prior_cells");
    cfg.encoder.in_channels = cfg.embedding.dim;
    cfg.embedding.absolute_position = cfg.decoder.absolute_position = !cfg.physics.translation_invariant;
    cfg.embedding.extra_inputs = cfg.decoder.extra_inputs = cfg.prior_inputs ? 3 : 0;
    // The traced E⁺ and the regathered prior at each point; with R as the prior the traced E⁺ is the
    // points' prior input itself (the 3 above).
    if (cfg.traced_inputs > 0 && !cfg.physics.prior_regathered) cfg.embedding.extra_inputs += 6;
    if (cfg.traced_queries) cfg.decoder.extra_inputs += 3, cfg.decoder.skip_inputs = 3;   // ln(R / Ê) at each query
    embedding = register_module("embedding", NNEmbedding(cfg.embedding));
    encoder = register_module("encoder", PTv3(cfg.encoder));
    decoder = register_module("decoder", QueryDecoder(cfg.decoder, encoder->out_channels()));
    if (cfg.directional)
        directional = register_module("directional", DirectionalDecoder(*cfg.directional, encoder->out_channels(),
                                                                        !cfg.physics.translation_invariant));
}

SceneGeometry LtmModelImpl::scene_geometry(const torch::Tensor &scene_points) const {
    TORCH_CHECK(scene_points.dim() == 2 && scene_points.size(1) == 12, "scene points must be [M, 12], got ", scene_points.sizes());
    const auto pos = scene_points.slice(1, 0, 3).to(torch::kCPU, torch::kFloat32).contiguous();
    PointGroups pg = point_groups(pos.data_ptr<float>(), size_t(pos.size(0)), cfg.embedding);   // the prior's frame uses the same
    const auto dev = scene_points.device();
    SceneGeometry g;
    g.centers = torch::from_blob(pg.centers.data(), {int64_t(pg.centers.size())}, torch::kInt64).clone().to(dev);
    g.groups = torch::from_blob(pg.groups.data(), {int64_t(pg.centers.size()), pg.k}, torch::kInt64).clone().to(dev);
    return g;
}

SceneNormalization LtmModelImpl::scene_frame(const torch::Tensor &scene_points, const SceneGeometry &geometry,
                                             const torch::Tensor &emission_scale,
                                             std::shared_ptr<const SegmentOcclusion> occlusion, const PointTracer &tracer,
                                             bool point_inputs) const {
    if (cfg.physics.prior_regathered) {
        // R is the prior (physics.prior_regathered): the points' prior input is their traced E⁺, which
        // the regather reads anyway, so R is not gathered at the M points (point_inputs false below).
        SceneNormalization n = scene_normalization(scene_points, geometry, cfg.physics, emission_scale, std::move(occlusion), tracer,
                                                   /*point_inputs=*/false);
        if (point_inputs) n.point_prior = n.traced_light;
        return n;
    }
    SceneNormalization n = scene_normalization(scene_points, geometry, cfg.physics, emission_scale, std::move(occlusion),
                                               cfg.traced_inputs > 0 ? tracer : PointTracer{}, point_inputs);
    // Only the queries' column reads it (or a deferred encoder, which regathers at its points later):
    // otherwise its memory is the prior's again.
    if (!cfg.traced_queries && point_inputs) n.regather.reset();
    // The points as queries, so a query at a scene point sees that point's feature (and the level
    // points their prior: decoder.level_points reads it, with or without prior inputs).
    if ((cfg.prior_inputs && point_inputs) || cfg.decoder.level_points > 0) n.point_prior = output_scale(scene_points.slice(1, 0, 9), n);
    return n;
}

SceneLatents LtmModelImpl::encode(const torch::Tensor &scene_points, const SceneGeometry &geometry,
                                  const torch::Tensor &emission_scale, const SceneNormalization *frame,
                                  std::shared_ptr<const SegmentOcclusion> occlusion, const PointTracer &tracer) {
    SceneLatents out;
    // (Non-finite scene points take the network's path, which reports them.)
    // fold: the body is silent (𝓦_out zero), so the irradiance decoder's output does not depend on
    // the latents; at_prior: nor on the skip's input, so nothing traced is read either.
    const bool fold = fold_prior && !torch::GradMode::is_enabled() && decoder->body_silent() && torch::isfinite(scene_points).all().item<bool>();
    const bool at_prior = fold && decoder->skip_silent();
    // Folded at the prior without a directional head, no input is read: the traced inputs are not
    // traced. A silent body with a skip reads the regather (traced), not the latents.
    // Folded, the per-point inputs are gathered only if a directional head asks (encoder_inputs).
    out.norm = frame ? *frame
                     : scene_frame(scene_points, geometry, emission_scale, std::move(occlusion),
                                   at_prior && !directional && !cfg.physics.prior_regathered ? PointTracer{} : tracer,
                                   /*point_inputs=*/!fold);
    // Named here, not later: a fold with a skip reads the regather (a frame given by the trainer carries
    // R at its queries instead), and a deferred head's encoder reads the traced light at the points.
    if (!frame && fold && !at_prior && !out.norm.regather)
        LTM_THROW("model '", cfg.name, "' has traced queries: encoding a scene needs its path tracer (the regathered prior)");
    if (!frame && fold && directional && cfg.traced_inputs > 0 && !out.norm.traced_light.defined() && !out.norm.point_traced.defined())
        LTM_THROW("model '", cfg.name, "' has traced inputs (traced_inputs ", cfg.traced_inputs,
                  "): encoding a scene needs its path tracer (its directional head's encoder reads them)");
    auto x = normalize_scene_points(scene_points, out.norm);
    out.anchors = x.slice(1, 0, 3).index_select(0, geometry.centers);            // [m, 3]
    if (cfg.decoder.level_points > 0) {
        // The first K FPS centres: spread over the whole scene whatever K (FPS order).
        const auto first = geometry.centers.slice(0, 0, std::min<int64_t>(cfg.decoder.level_points, geometry.centers.size(0)));
        out.level_queries = scene_points.index_select(0, first).slice(1, 0, 9);                       // [K, 9]
        // A frame given without its solve (the trainer's cache) must carry the prior at the points:
        // output_scale would fall back to the flat scale there and weigh r otherwise than inference.
        if (!out.norm.point_prior.defined() && !out.norm.transport && cfg.physics.prior_field == "transport")
            LTM_THROW("encode: decoder.level_points needs the prior at the scene points (make the frame with scene_frame)");
        out.level_scale = out.norm.point_prior.defined() ? out.norm.point_prior.index_select(0, first)
                                                         : output_scale(out.level_queries, out.norm);
        out.level_scale = out.level_scale.expand({out.level_queries.size(0), 3});                    // [K, 3]
        if (cfg.traced_queries && !fold) {
            // The level held is R's (level_factor): R at the same points, from the frame's per-point
            // regather (point_traced's second half) or gathered here. A fold never reads the level
            // (and at its prior traces nothing).
            if (out.norm.point_traced.defined()) out.level_regathered = out.norm.point_traced.index_select(0, first).slice(1, 3, 6);
            else if (out.norm.regather) out.level_regathered = regathered_scale(out.level_queries, out.norm);
            else LTM_THROW("encode: decoder.level_points with traced queries needs R at the scene points (make the frame with its path tracer)");
        }
    }
    if (fold && !directional) {
        // The decoder's output does not depend on the latents (fold_prior in the header).
        out.features = torch::zeros({out.anchors.size(0), encoder->out_channels()}, x.options());
        return out;
    }
    if (fold) {
        // Only the directional head reads the latents, and only when asked: its encoder run waits,
        // and so do the per-point inputs it would read.
        out.deferred = std::make_shared<SceneLatents::Deferred>();
        out.deferred->x = x, out.deferred->rows = scene_points.slice(1, 0, 9);
        out.deferred->centers = geometry.centers, out.deferred->groups = geometry.groups;
        return out;
    }
    x = encoder_inputs(x, scene_points.slice(1, 0, 9), out.norm);
    const auto tokens = embedding->forward(x, geometry.centers, geometry.groups);   // [m, D]
    out.features = encoder->forward(tokens, out.anchors);                         // [m, C]
    return out;
}

torch::Tensor LtmModelImpl::encoder_inputs(torch::Tensor x, const torch::Tensor &rows, const SceneNormalization &norm) const {
    torch::Tensor prior = norm.point_prior, traced = norm.point_traced;
    if (cfg.physics.prior_regathered) {
        // The points' prior input is their traced E⁺ (scene_frame), a deferred encoder's too.
        if (!prior.defined()) prior = norm.traced_light;
        if (!prior.defined()) LTM_THROW("encode: the given frame has no traced light at the scene points (make it with scene_frame and the scene's path tracer)");
        TORCH_CHECK(prior.dim() == 2 && prior.size(0) == x.size(0) && prior.size(1) == 3,
                    "encode: point_prior must be [M, 3] for M = ", x.size(0), ", got ", prior.sizes());
        return torch::cat({x, prior_features(prior, norm)}, 1);   // [M, 15]
    }
    if (cfg.traced_inputs > 0 && !traced.defined() && norm.traced_light.defined()) {
        // A deferred encoder: the prior and the regather at every scene point, in one walk.
        if (!norm.regather) LTM_THROW("encode: the frame has the traced light but not its regather");
        torch::Tensor r;
        std::tie(prior, r) = prior_and_regathered(rows, norm);
        traced = torch::cat({norm.traced_light, r}, 1);   // [M, 6]
    } else if (cfg.prior_inputs && !prior.defined() && norm.transport) {
        prior = output_scale(rows, norm);   // a deferred encoder without traced inputs
    }
    if (cfg.prior_inputs) {
        if (!prior.defined()) LTM_THROW("encode: the given frame has no point_prior (make it with scene_frame)");
        TORCH_CHECK(prior.dim() == 2 && prior.size(0) == x.size(0) && prior.size(1) == 3,
                    "encode: point_prior must be [M, 3] for M = ", x.size(0), ", got ", prior.sizes());
        x = torch::cat({x, prior_features(prior, norm)}, 1);   // [M, 15]
    }
    if (cfg.traced_inputs > 0) {
        if (!traced.defined())
            LTM_THROW("model '", cfg.name, "' has traced inputs (traced_inputs ", cfg.traced_inputs,
                      "): encoding a scene needs its path tracer (render, eval, bake-gi and training draws pass it; scene points alone have none)");
        TORCH_CHECK(traced.dim() == 2 && traced.size(0) == x.size(0) && traced.size(1) == 6,
                    "encode: point_traced must be [M, 6] for M = ", x.size(0), ", got ", traced.sizes());
        x = torch::cat({x, prior_features(traced.slice(1, 0, 3), norm), prior_features(traced.slice(1, 3, 6), norm)}, 1);   // [M, 21]
    }
    return x;
}

torch::Tensor LtmModelImpl::features(const SceneLatents &latents) {
    if (latents.features.defined() || !latents.deferred) return latents.features;
    SceneLatents::Deferred &d = *latents.deferred;
    const std::lock_guard<std::mutex> lock(d.mutex);
    if (!d.features.defined()) {
        torch::NoGradGuard no_grad;
        const auto x = encoder_inputs(d.x, d.rows, latents.norm);
        d.features = encoder->forward(embedding->forward(x, d.centers, d.groups), latents.anchors);   // [m, C]
    }
    return d.features;
}

torch::Tensor LtmModelImpl::query_inputs(const torch::Tensor &query_points, const SceneNormalization &norm,
                                         const torch::Tensor &scale, const torch::Tensor &regathered) const {
    const auto q = normalize_query_points(query_points, norm);
    if (!cfg.prior_inputs) return q;
    const auto s = scale.defined() ? scale : output_scale_normalized(q, norm);
    TORCH_CHECK(s.dim() == 2 && s.size(0) == q.size(0) && s.size(1) == 3, "query_inputs: scale must be [N, 3] for N = ",
                q.size(0), ", got ", s.sizes());
    if (!cfg.traced_queries) return torch::cat({q, prior_features(s, norm)}, 1);   // [N, 12]
    if (!regathered.defined()) require_regather(cfg, norm);
    const auto r = regathered.defined() ? regathered : gathered_normalized(q, *norm.regather, norm);
    TORCH_CHECK(r.dim() == 2 && r.size(0) == q.size(0) && r.size(1) == 3, "query_inputs: regathered must be [N, 3] for N = ",
                q.size(0), ", got ", r.sizes());
    return torch::cat({q, prior_features(s, norm), traced_query_features(r, s)}, 1);   // [N, 15]
}

torch::Tensor LtmModelImpl::decode_network(const torch::Tensor &query_points, const SceneLatents &latents, const torch::Tensor &scale,
                                           const torch::Tensor &regathered) {
    const auto q = query_inputs(query_points, latents.norm, scale, regathered);
    const int64_t kappa = std::min<int64_t>(cfg.decoder.n_neighbors, latents.anchors.size(0));
    const auto idx = knn(q.slice(1, 0, 3).contiguous(), latents.anchors.contiguous(), kappa);
    return decoder->forward(q, features(latents), latents.anchors, idx);
}

torch::Tensor LtmModelImpl::decode(const torch::Tensor &query_points, const SceneLatents &latents, const torch::Tensor &scale,
                                   const torch::Tensor &regathered) {
    const auto z = decode_network(query_points, latents, scale, regathered);
    if (cfg.decoder.level_points <= 0) return z;
    return torch::log1p(level_factor(latents) * torch::expm1(z));
}

torch::Tensor LtmModelImpl::level_factor(const SceneLatents &latents) {
    if (cfg.decoder.level_points <= 0) return {};
    if (!latents.level_queries.defined()) LTM_THROW("level_factor: the latents have no level queries (make them with encode)");
    // With traced queries R's level is held (r = Σ R / Σ S g: the body corrects R's shape only; at a
    // silent body S g = R and r = 1), else the prior's.
    if (cfg.traced_queries && !latents.level_regathered.defined())
        LTM_THROW("level_factor: the latents have no regathered prior at their level queries (make them with encode, unfolded)");
    const auto g = torch::expm1(decode_network(latents.level_queries, latents, latents.level_scale, latents.level_regathered));   // [K, 3]
    const auto s = latents.level_scale.to(g.device(), g.scalar_type());
    const auto held = cfg.traced_queries ? latents.level_regathered.to(g.device(), g.scalar_type()) : s;
    return held.sum() / (s * g).sum().clamp_min(1e-30);
}

torch::Tensor LtmModelImpl::predict_irradiance(const torch::Tensor &query_points, const SceneLatents &latents,
                                               int64_t chunk, PredictTimings *timings) {
    torch::NoGradGuard no_grad;
    using clock = std::chrono::steady_clock;
    PredictTimings local;
    auto t = clock::now();
    if (fold_prior && decoder->body_silent()) {
        // 𝓦_out is zero (fold_prior in the header): z = softplus(skip ⊙ ln(R / Ê)) — at the prior
        // softplus(0), and only the prior is gathered; with a skip, the prior and the regather.
        const bool skip = !decoder->skip_silent();
        std::vector<torch::Tensor> parts;
        for (int64_t s = 0; s < query_points.size(0); s += chunk) {
            const auto qp = query_points.slice(0, s, std::min(query_points.size(0), s + chunk));
            if (!skip) {
                parts.push_back(prior_irradiance(qp, latents.norm));
                continue;
            }
            // One walk of the prior's rows for both (gather_transport_prior_pair).
            const auto [scale, regathered] = prior_and_regathered(qp, latents.norm);
            const auto x = traced_query_features(regathered, scale);
            parts.push_back(irradiance_from_z(torch::softplus(decoder->skip * x), scale));
        }
        local.decode += seconds_since(t);
        if (timings) timings->decode += local.decode;
        return parts.empty() ? torch::zeros({0, 3}) : torch::cat(parts, 0);
    }
    std::optional<FusedDecoder> fused;
    const torch::Tensor feats = features(latents);
    // One level factor for every chunk (decoder.level_points; 1 when undefined).
    const torch::Tensor level = level_factor(latents);
    const auto held = [&](torch::Tensor e) { return level.defined() ? e * level : e; };
    if (fused_inference && cfg.decoder.type == "attention" && query_points.is_cpu() && feats.is_cpu()) {
        fused.emplace(*decoder);   // rebuilt per call: ~0.1 M floats, negligible next to decoding
        fused->prepare(feats);
    }
    if (cfg.traced_queries) require_regather(cfg, latents.norm);
    std::vector<torch::Tensor> parts;
    for (int64_t s = 0; s < query_points.size(0); s += chunk) {
        const auto qp = query_points.slice(0, s, std::min(query_points.size(0), s + chunk));
        // The prior at the queries (input and output frame) and, for traced queries, the regather:
        // one walk of the prior's rows for both.
        torch::Tensor scale, regathered;
        if (cfg.traced_queries) std::tie(scale, regathered) = prior_and_regathered(qp, latents.norm);
        else scale = output_scale(qp, latents.norm);
        if (!fused) {
            parts.push_back(held(irradiance_from_z(decode_network(qp, latents, scale, regathered), scale)));
            continue;
        }
        const auto q = query_inputs(qp, latents.norm, scale, regathered);
        const int64_t kappa = std::min<int64_t>(cfg.decoder.n_neighbors, latents.anchors.size(0));
        local.decode += seconds_since(t);
        t = clock::now();
        const auto idx = knn(q.slice(1, 0, 3).contiguous(), latents.anchors.contiguous(), kappa);
        local.knn += seconds_since(t);
        t = clock::now();
        parts.push_back(held(irradiance_from_z(fused->forward(q, latents.anchors, idx), scale)));
    }
    auto out = parts.empty() ? torch::zeros({0, 3}) : torch::cat(parts, 0);
    local.decode += seconds_since(t);
    if (timings) timings->knn += local.knn, timings->decode += local.decode;
    return out;
}

torch::Tensor LtmModelImpl::decode_radiance(const torch::Tensor &query_points, const torch::Tensor &direction,
                                            const SceneLatents &latents) {
    if (!directional) LTM_THROW("model '", cfg.name, "' has no directional head (train one: ltm train --head directional)");
    const auto q = normalize_query_points(query_points, latents.norm);
    TORCH_CHECK(direction.dim() == 2 && direction.size(1) == 3 && direction.size(0) == query_points.size(0),
                "decode_radiance: direction must be [N, 3] for N = ", query_points.size(0), " queries, got ", direction.sizes());
    if (!torch::isfinite(direction).all().item<bool>()) LTM_THROW("directions contain NaN or Inf");
    // L_in is defined on the hemisphere around n: a unit ω with n·ω ≥ 0 (grazing allowed).
    const auto len_err = (direction.norm(2, 1) - 1.0).abs();
    if (direction.size(0) > 0 && len_err.max().item<double>() > 1e-3) {
        const int64_t i = len_err.argmax().item<int64_t>();
        LTM_THROW("direction ", i, " is not a unit vector (length ", direction[i].norm().item<double>(), ")");
    }
    const auto cos = (direction * query_points.slice(1, 3, 6)).sum(1);
    if (direction.size(0) > 0 && cos.min().item<double>() < -1e-3) {
        const int64_t i = cos.argmin().item<int64_t>();
        LTM_THROW("direction ", i, " is below the surface (n·ω = ", cos[i].item<double>(), ")");
    }
    const int64_t kappa = std::min<int64_t>(cfg.decoder.n_neighbors, latents.anchors.size(0));
    const auto idx = knn(q.slice(1, 0, 3).contiguous(), latents.anchors.contiguous(), kappa);
    return directional->forward(q, direction, features(latents), latents.anchors, idx);
}

torch::Tensor LtmModelImpl::predict_radiance(const torch::Tensor &query_points, const torch::Tensor &direction,
                                             const SceneLatents &latents, int64_t chunk) {
    torch::NoGradGuard no_grad;
    TORCH_CHECK(direction.dim() == 2 && direction.size(1) == 3 && direction.size(0) == query_points.size(0),
                "predict_radiance: direction must be [N, 3] for N = ", query_points.size(0), " queries, got ", direction.sizes());
    if (!directional) LTM_THROW("model '", cfg.name, "' has no directional head (train one: ltm train --head directional)");
    std::vector<torch::Tensor> parts;
    for (int64_t s = 0; s < query_points.size(0); s += chunk) {
        const int64_t e = std::min(query_points.size(0), s + chunk);
        const auto qp = query_points.slice(0, s, e);
        const auto d = direction.slice(0, s, e);
        parts.push_back(radiance_from_z(decode_radiance(qp, d, latents), radiance_scale(qp, d, latents.norm, cfg.directional->prior_cells)));
    }
    return parts.empty() ? torch::zeros({0, 3}) : torch::cat(parts, 0);
}

int64_t LtmModelImpl::n_parameters() const {
    int64_t n = 0;
    for (const auto &p : parameters()) n += p.numel();
    return n;
}

torch::Tensor output_scale(const torch::Tensor &query_points, const SceneNormalization &norm) {
    return norm.transport ? output_scale_normalized(normalize_query_points(query_points, norm), norm) : norm.output;
}

torch::Tensor regathered_scale(const torch::Tensor &query_points, const SceneNormalization &norm) {
    if (!norm.regather) LTM_THROW("the scene's frame has no regathered prior (it was made without the scene's path tracer)");
    return gathered_normalized(normalize_query_points(query_points.to(norm.output.device()), norm), *norm.regather, norm);
}

std::pair<torch::Tensor, torch::Tensor> prior_and_regathered(const torch::Tensor &query_points, const SceneNormalization &norm) {
    if (!norm.transport) LTM_THROW("the scene's frame has no transport prior to regather (physics.prior_field \"transport\")");
    if (!norm.regather) LTM_THROW("the scene's frame has no regathered prior (it was made without the scene's path tracer)");
    torch::NoGradGuard no_grad;
    const auto q = normalize_query_points(query_points.to(norm.output.device()), norm).detach().to(torch::kCPU, torch::kFloat32).contiguous();
    auto scale = torch::empty({q.size(0), 3}, torch::kFloat32), regathered = torch::empty({q.size(0), 3}, torch::kFloat32);
    prior_scale_pair_normalized(*norm.transport, *norm.regather, output_vec3(norm), q.data_ptr<float>(), 9, size_t(q.size(0)),
                                reinterpret_cast<Vec3f *>(scale.data_ptr<float>()),
                                reinterpret_cast<Vec3f *>(regathered.data_ptr<float>()));
    return {scale.to(norm.output.device()), regathered.to(norm.output.device())};
}

torch::Tensor traced_query_features(const torch::Tensor &regathered, const torch::Tensor &scale) {
    TORCH_CHECK(regathered.dim() == 2 && regathered.size(1) == 3 && regathered.sizes() == scale.sizes(),
                "traced_query_features: regathered and scale must both be [N, 3], got ", regathered.sizes(), " and ", scale.sizes());
    // Both are floored at 10⁻³ of the flat level, so the log is finite wherever the channel has light.
    const auto lit = (regathered > 0) & (scale > 0);
    return torch::where(lit, torch::log(regathered.clamp_min(1e-30) / scale.clamp_min(1e-30)), torch::zeros_like(scale));
}

torch::Tensor irradiance_from_z(const torch::Tensor &z, const torch::Tensor &scale) { return scale * torch::expm1(z); }

torch::Tensor prior_irradiance(const torch::Tensor &query_points, const SceneNormalization &norm) {
    torch::NoGradGuard no_grad;
    // The arithmetic of nn/scene_frame.h's prior_irradiance, step for step: the same numbers.
    auto scale = output_scale(query_points.to(norm.output.device()), norm);   // [N, 3], or [3] for the flat prior
    if (scale.dim() == 1) scale = scale.expand({query_points.size(0), 3});
    return scale * prior_gain();
}

torch::Tensor prior_features(const torch::Tensor &prior, const SceneNormalization &norm) {
    TORCH_CHECK(prior.dim() == 2 && prior.size(1) == 3, "prior_features: prior must be [N, 3], got ", prior.sizes());
    const auto o = norm.output.to(prior.device());
    return torch::log1p(torch::where(o > 0, prior / o.clamp_min(1e-30), torch::zeros_like(prior)));
}

torch::Tensor radiance_scale(const torch::Tensor &query_points, const torch::Tensor &direction, const SceneNormalization &norm,
                             int cells) {
    if (cells <= 0) return output_scale(query_points, norm) * (1.0 / k_pi);
    if (!norm.transport) LTM_THROW("the directional prior (prior_cells ", cells, ") needs the transport prior (physics.prior_field)");
    TORCH_CHECK(direction.dim() == 2 && direction.size(1) == 3 && direction.size(0) == query_points.size(0),
                "radiance_scale: direction must be [N, 3] for N = ", query_points.size(0), " queries, got ", direction.sizes());
    torch::NoGradGuard no_grad;
    const auto q = normalize_query_points(query_points, norm).detach().to(torch::kCPU, torch::kFloat32).contiguous();
    const auto d = direction.detach().to(torch::kCPU, torch::kFloat32).contiguous();
    auto out = torch::empty({q.size(0), 3}, torch::kFloat32);
    const float *p = q.data_ptr<float>();
    gather_transport_prior_radiance(*norm.transport, p, p + 3, 9, d.data_ptr<float>(), 3, size_t(q.size(0)), cells, out.data_ptr<float>());
    return torch::maximum(out.to(norm.output.device()), (1e-3 / k_pi) * norm.output);
}

torch::Tensor radiance_from_z(const torch::Tensor &z, const torch::Tensor &scale) { return scale * torch::expm1(z); }

torch::Tensor normalized_target(const torch::Tensor &target, const torch::Tensor &scale) {
    return torch::where(scale > 0, target / scale.clamp_min(1e-30), torch::zeros_like(target));
}

torch::Tensor relative_l2_loss(const torch::Tensor &pred, const torch::Tensor &target, double eps) {
    TORCH_CHECK(pred.sizes() == target.sizes(), "loss: prediction ", pred.sizes(), " and target ", target.sizes(), " differ");
    const auto p = pred.detach();
    const auto den = p + eps * p.mean() + 1e-12;   // + 1e-12: an all-zero prediction still has a finite loss
    return ((pred - target) / den).pow(2).mean();
}

torch::Tensor relative_l2_log_loss(const torch::Tensor &z, const torch::Tensor &target, double eps) {
    TORCH_CHECK(z.sizes() == target.sizes(), "loss: prediction ", z.sizes(), " and target ", target.sizes(), " differ");
    const auto diff = z - torch::log1p(target);
    return (diff / (z.detach() + eps)).pow(2).mean();
}

}  // namespace ltm
