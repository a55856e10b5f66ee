// shipped_prior.h: the transport prior as the shipped model solves it (configs/model/cpu.json's
// physics: discs of one spacing, 1 024 clusters blended by 4, 8 × 8 open rays, no power balance,
// patches, the tree at θ 0.5; prior_ablation's setting 1:1024:0:1:1:2:5:4:1:8:0.5), for the benches
// that compare other estimators against it.
#pragma once

#include "ltm/render/scene_points.h"
#include "ltm/transport/transport_prior.h"

namespace ltm::bench {

inline VisibilityOptions shipped_visibility() {
    VisibilityOptions vis;
    vis.voxel_spacings = 1.f;
    vis.clusters = 1024;
    vis.splat_spacings = 0.f;
    vis.disc_spacings = 1.f;
    vis.blend = 4;
    vis.open_rays = 8;
    return vis;
}

/// node_area: the scene's area / M (the points' nominal spacing squared).
inline TransportPrior solve_shipped_prior(const ScenePoints &sp, float node_area, int bounces) {
    return solve_transport_prior(sp.points, node_area, bounces, &sp.emission_scale, shipped_visibility(), nullptr, PriorBalance::none,
                                 true, 0.5f);
}

}  // namespace ltm::bench
