// view_samples.h: surface points that a scene's cameras see, drawn at uniformly random raster
// positions — the distribution of the points a renderer asks the model about (one per pixel),
// as opposed to the area-uniform points of surface_sampler.h, which weight every room of a house
// alike whether or not a camera looks into it. The dataset mixes the two (DataPreset
// camera_queries).
#pragma once

#include <cstdint>
#include <vector>

#include "ltm/points/surface_sampler.h"
#include "ltm/render/embree_accel.h"

namespace ltm {

/// n points seen through accel.scene().cameras (camera i % n_cameras for draw i), each at a raster
/// position uniform over that camera's image. Each point's normal faces its camera (as the
/// G-buffer's do), its albedo and emission are the texture values at the hit. Rays that miss are
/// redrawn (up to 64 tries per point, then an error: the camera sees almost nothing).
/// Deterministic for (scene, n, seed) at any thread count. Throws ltm::Error when the scene has no
/// camera.
std::vector<SurfaceSample> sample_view_points(const EmbreeAccel &accel, int64_t n, uint64_t seed);

}  // namespace ltm
