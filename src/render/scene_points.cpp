// scene_points.cpp: sampler + enclosure filter + exact emission scale, in one place.
#include "ltm/render/scene_points.h"

#include <cmath>

#include "ltm/transport/power_balance.h"
#include "ltm/points/surface_sampler.h"
#include "ltm/render/enclosure.h"

namespace ltm {

ScenePoints sample_scene_points(const EmbreeAccel &accel, int64_t n_points, uint64_t seed, bool exclude_enclosed,
                                float buried_spacings) {
    SampleFilter filter;
    if (exclude_enclosed) {
        EnclosureTest cfg;
        if (n_points > 0) cfg.buried_distance = buried_spacings * float(std::sqrt(accel.scene().total_area() / double(n_points)));
        filter = enclosed_filter(accel, cfg);
    }
    SampleStats stats;
    ScenePoints out;
    out.points = to_scene_points(sample_surface(accel.scene(), n_points, seed, SampleStream::scene_points, filter, &stats));
    out.emission_scale = scene_emission_scale(accel.scene(), stats.pass_fraction());
    return out;
}

}  // namespace ltm
