// guide_builder.cpp: sample → encode → FPS cache points → the head's bins at bin centres.
#include "ltm/infer/guide_builder.h"

#include <chrono>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/infer/neural_renderer.h"
#include "ltm/nn/point_tensor.h"
#include "ltm/points/farthest_points.h"
#include "ltm/transport/point_visibility.h"
#include "ltm/render/hemisphere_bins.h"
#include "ltm/render/scene_points.h"

namespace ltm {

GuideBuild build_guide_cache(LtmModel &model, const EmbreeAccel &accel, const GuideBuildOptions &opt) {
    if (!model->directional) LTM_THROW("--method guided: model '", model->cfg.name, "' has no directional head (train one: ltm train --head directional)");
    if (opt.points < 9) LTM_THROW("--guide-points ", opt.points, ": need at least 9");
    if (opt.resolution < 1 || opt.resolution > 256) LTM_THROW("--guide-resolution ", opt.resolution, ": need 1..256");
    const auto t0 = std::chrono::steady_clock::now();
    torch::NoGradGuard no_grad;
    model->eval();
    const ScenePoints sampled = sample_scene_points(accel, model->cfg.scene_points, opt.seed);
    const auto points = point_tensor(sampled.points);
    const Vec3f s = sampled.emission_scale;
    const SceneLatents lat =
        model->encode(points, model->scene_geometry(points), torch::tensor({s.x, s.y, s.z}), nullptr, prior_occlusion(model, accel),
                      traced_inputs_tracer(model->cfg, accel, sampled.ids));
    const PointSet &sp = sampled.points;
    const size_t m = sp.size(), c = std::min(m, size_t(opt.points));
    std::vector<float> xyz;
    for (size_t i = 0; i < m; ++i) xyz.insert(xyz.end(), {sp.at(i, 0), sp.at(i, 1), sp.at(i, 2)});
    const std::vector<int64_t> pick = farthest_points(xyz.data(), m, c);
    const int R = opt.resolution;
    std::vector<Vec3f> pos, nrm;
    for (int64_t i : pick) pos.push_back(sp.vec3(size_t(i), 0)), nrm.push_back(normalize(sp.vec3(size_t(i), 3)));
    const HemisphereRows hemi = hemisphere_rows(sp, pick, R);   // the scene points' first 9 columns: p, n, albedo
    const auto pred = model->predict_radiance(rows_tensor(hemi.query, 9), rows_tensor(hemi.direction, 3), lat).clamp_min(0.0).contiguous();
    const Vec3f *l = reinterpret_cast<const Vec3f *>(pred.data_ptr<float>());
    std::vector<Vec3f> radiance(l, l + pred.size(0));
    const float radius = opt.radius_spacings * point_spacing(pos);
    GuideBuild out{GuideCache(R, std::move(pos), std::move(nrm), std::move(radiance), radius), 0.0};
    out.seconds = seconds_since(t0);
    log_info("guide cache: ", c, " points × ", R, "² bins predicted in ", out.seconds, " s (lookup radius ", radius, ")");
    return out;
}

}  // namespace ltm
