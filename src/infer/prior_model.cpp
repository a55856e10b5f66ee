// prior_model.cpp: a weights file's config, the prior's scene and its render, torch-free.
#include "ltm/infer/prior_model.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/nn/weights_file.h"
#include "ltm/render/mesh_occlusion.h"
#include "ltm/render/path_tracer.h"
#include "ltm/render/scene_points.h"

namespace ltm {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

PriorModel load_prior_model(const std::string &path) {
    const WeightsFile w = read_weights_file(path);
    PriorModel m;
    m.cfg = w.config;
    m.path = path;
    m.metadata = w.file.metadata;
    const std::optional<Vec3f> skip = silent_body_skip(w, path);
    m.silenced = skip && *skip == Vec3f(0.f);
    if (skip) m.skip = *skip;
    return m;
}

void set_scene_points(ModelConfig &cfg, int64_t n) {
    if (n < k_min_scene_points)
        LTM_THROW("--scene-points ", n, ": below the minimum of ", k_min_scene_points, " (the decoder's neighbourhoods need more points)");
    const bool tree = cfg.physics.prior_theta > 0.f;
    if (tree && n > k_max_scene_points_tree)
        LTM_THROW("--scene-points ", n, ": above the limit of ", k_max_scene_points_tree, " with the prior's tree (~1 KB per point: ",
                  double(n) * 1024.0 / double(1 << 30), " GiB here)");
    if (!tree && n > k_max_scene_points)
        LTM_THROW("--scene-points ", n, ": above the limit of ", k_max_scene_points, " (the transport prior's dense solve holds ~4·M² bytes: ",
                  double(n) * double(n) * 4.0 / double(1 << 30), " GiB here; --prior-theta 0.5 solves through a tree up to ",
                  k_max_scene_points_tree, ")");
    cfg.scene_points = int(n);
}

void set_auto_scene_points(ModelConfig &cfg, const Scene &scene, bool theta_given) {
    const int64_t m = auto_scene_points(scene);
    const bool tree = !theta_given && m > cfg.scene_points && cfg.physics.prior_field == "transport";
    if (tree) set_prior_theta(cfg, 0.5);
    set_scene_points(cfg, m);
    log_info("--scene-points auto: ", m, " scene points for ", scene.n_triangles(), " triangles", tree ? ", the prior through its tree (θ 0.5)" : "");
}

int apply_point_options(ModelConfig &cfg, int given, double prior_theta, bool prior_rays) {
    const int n = given != 0 ? given : cfg.auto_scene_points ? int(k_scene_points_auto) : 0;
    if (prior_rays) set_prior_rays(cfg);
    if (prior_theta >= 0) set_prior_theta(cfg, prior_theta);
    if (cfg.physics.prior_rays && !(cfg.physics.prior_theta > 0.f))
        LTM_THROW("--prior-rays (physics.prior_rays) needs --prior-theta > 0 (physics.prior_theta): the rays test the terms of the "
                  "prior's cluster tree (the dense rows have none)");
    if (n > 0) set_scene_points(cfg, n);
    return n;
}

void set_prior_theta(ModelConfig &cfg, double theta) {
    if (!(theta >= 0.0 && theta <= 1.0)) LTM_THROW("--prior-theta ", theta, ": must be in [0, 1] (0: the dense rows)");
    if (cfg.physics.prior_field != "transport")
        LTM_THROW("--prior-theta: the model's prior is \"", cfg.physics.prior_field, "\", not the transport prior");
    cfg.physics.prior_theta = float(theta);
}

void set_prior_rays(ModelConfig &cfg) {
    if (cfg.physics.prior_field != "transport")
        LTM_THROW("--prior-rays: the model's prior is \"", cfg.physics.prior_field, "\", not the transport prior");
    cfg.physics.prior_rays = true;
    if (!(cfg.physics.prior_theta > 0.f)) cfg.physics.prior_theta = 0.5f;   // rays test the tree's terms
}

std::shared_ptr<const SegmentOcclusion> prior_occlusion(const ModelConfig &cfg, const EmbreeAccel &accel) {
    if (!cfg.physics.prior_rays) return nullptr;
    return std::make_shared<MeshOcclusion>(accel);
}

PointTracer traced_inputs_tracer(const ModelConfig &cfg, const EmbreeAccel &accel, std::vector<uint64_t> point_keys) {
    if (cfg.traced_inputs <= 0) return {};
    PathTracerConfig tc;
    tc.seed = k_traced_inputs_seed;
    // E⁺ up to D − 1 scattering events: the regather's node re-emits ρ(E_dir + E⁺), and its gather
    // adds the last, so the regathered prior spans the prior's own 1 … D events (physics.prior_bounces).
    tc.max_depth = tc.rr_depth = std::max(1, cfg.physics.prior_bounces - 1);
    // The rays' offset floor in the scene's own length, so the traced light does not depend on the
    // unit: 1 % of its extent (a metre's floor for a 100 m scene; the whole extent would offset a
    // room beside a 1 km ground plane by 10 cm, through thin walls).
    tc.offset_length = std::max(1e-2f * accel.scene().extent(), 1e-30f);
    auto pt = std::make_shared<const PathTracer>(accel, tc);
    const int strata = cfg.traced_inputs;
    return [pt, strata, keys = std::move(point_keys)](const float *rows, size_t n, Vec3f *direct, Vec3f *indirect) {
        if (!keys.empty()) {
            LTM_CHECK_EQ(keys.size(), n);   // the keys of the points it is given
        }
        trace_irradiance(*pt, rows, 12, n, strata, direct, indirect, keys.empty() ? nullptr : keys.data());
    };
}

PriorScene encode_prior_scene(const ModelConfig &cfg, const EmbreeAccel &accel, uint64_t seed, bool exclude_enclosed, Vec3f skip) {
    // The steps of the tensor model's encode_scene (infer/neural_renderer.h), on plain arrays.
    const auto t = Clock::now();
    ScenePoints sampled = sample_scene_points(accel, cfg.scene_points, seed, exclude_enclosed);
    const double sample_seconds = seconds_since(t);
    return encode_prior_scene(cfg, accel, std::move(sampled), skip, sample_seconds);
}

PriorScene encode_prior_scene(const ModelConfig &cfg, const EmbreeAccel &accel, ScenePoints sampled, Vec3f skip, double sample_seconds) {
    PriorScene s;
    s.spacing = nominal_spacing(accel.scene(), int64_t(sampled.points.size()));
    s.points = std::move(sampled.points);
    s.n_scene_points = int64_t(s.points.size());
    if (s.points.n_columns() != 12) LTM_THROW("scene points: expected 12 columns, got ", s.points.n_columns());
    s.sample_seconds = sample_seconds;
    auto t = Clock::now();
    const size_t m = s.points.size();
    std::vector<float> pos(m * 3);
    for (size_t i = 0; i < m; ++i)
        for (size_t a = 0; a < 3; ++a) pos[i * 3 + a] = s.points.values[i * 12 + a];
    const PointGroups groups = point_groups(pos.data(), m, cfg.embedding);
    s.geometry_seconds = seconds_since(t);
    t = Clock::now();
    // physics.prior_rays: the prior's visibility by rays against this scene's meshes.
    // A folded skip: the traced paths and the regather for the queries only (no encoder reads the
    // points'); at w = 1 without the prior's bounces (R alone is read).
    const bool regather = !(skip == Vec3f(0.f)) || cfg.physics.prior_regathered;   // R is read, or is the prior itself
    s.frame = solve_scene_frame(s.points.values.data(), m, groups, cfg.physics, &sampled.emission_scale, prior_occlusion(cfg, accel),
                                regather ? traced_inputs_tracer(cfg, accel, std::move(sampled.ids)) : PointTracer{}, /*point_inputs=*/false,
                                /*regather_only=*/skip_reads_regather_alone(skip));
    s.encode_seconds = seconds_since(t);
    log_debug("scene frame: length unit ℓ = ", s.frame.length, ", emission scale S = ", s.frame.emission, ", output scale = ", s.frame.output);
    return s;
}

IrradianceDecoder prior_decoder(std::shared_ptr<const SceneFrame> frame, DecodeTimings *timings, Vec3f skip) {
    return [frame, timings, skip](const std::vector<float> &rows) {
        const auto t = Clock::now();
        std::vector<Vec3f> out(rows.size() / 9);
        folded_irradiance(*frame, skip, rows.data(), out.size(), out.data());
        if (timings) timings->decode += seconds_since(t);
        return out;
    };
}

NeuralRender render_prior(const ModelConfig &cfg, const PathTracer &pt, const Camera &camera, const NeuralRenderOptions &opt, Vec3f skip) {
    if (opt.glossy == GlossyShading::head)
        LTM_THROW("neural render: the prior alone has no directional head (use --glossy trace or diffuse)");
    const auto t0 = Clock::now();
    const bool folded = !(skip == Vec3f(0.f));
    if (folded && cfg.traced_inputs <= 0) LTM_THROW("neural render: a folded skip needs the model's traced inputs (traced_inputs)");
    PriorScene scene = encode_prior_scene(cfg, pt.accel(), opt.seed, opt.exclude_enclosed, skip);
    const auto frame = std::make_shared<const SceneFrame>(std::move(scene.frame));
    DecodeTimings timings;
    GiSource src;
    src.irradiance = prior_decoder(frame, &timings, skip);
    src.timings = &timings;
    src.points = &scene.points, src.spacing = scene.spacing, src.n_scene_points = scene.n_scene_points;
    src.sample_seconds = scene.sample_seconds, src.geometry_seconds = scene.geometry_seconds, src.encode_seconds = scene.encode_seconds;
    src.prior_solve_seconds = frame->solve_seconds, src.trace_seconds = frame->trace_seconds;
    NeuralRender r = render_with_gi(src, pt, camera, opt);
    r.timings.total = seconds_since(t0);   // the encode included
    r.image.seconds = r.timings.total;
    return r;
}

}  // namespace ltm
