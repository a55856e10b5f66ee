// eval_setup.h: what every evaluation shares — the views it renders and the random streams of
// each method — so `ltm eval`, `ltm eval --radiance` and the benches that reuse its reference
// cache (bench/prior_ablation.cpp) render the same images with the same samples.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ltm/render/gbuffer.h"
#include "ltm/render/path_tracer.h"
#include "ltm/scene/camera.h"
#include "ltm/scene/scene.h"

namespace ltm {

/// Who renders in an evaluation: each role has its own random streams, so no baseline shares
/// samples with the reference (the values enter the seeds and the reference cache's keys).
enum class EvalRole : uint64_t {
    reference = 1,
    baseline = 2,
    equal_time = 3,
    neural_direct = 4,
    reference_twin = 5,   ///< the reference's noise estimate (EvalOptions::reference_noise): one more
                          ///< reference at its spp, independent of it
};
/// The path tracer configuration of `role` for evaluation seed `seed`.
PathTracerConfig eval_tracer_config(uint64_t seed, EvalRole role);

/// View v of n: the scene's first camera turned about its eye by 360°·v/n (yaw about +y), resized.
/// A scene without a camera is seen from `ltm render`'s automatic camera (render/preview.h).
Camera eval_view_camera(const Scene &scene, int v, int n, int width, int height);

/// Is a --scenes entry a generator seed range A:B (digits:digits), not a scene to load (a file,
/// builtin:NAME)? A file of that name that exists is a scene.
bool is_seed_range(const std::string &spec);
/// The label of each scene to load in `specs` (seed ranges are skipped: they name their scenes
/// seed-N), in order: builtin:NAME → builtin-NAME; a file → its stem, or, where another entry has
/// the same stem (rooms that each ship a scene-v4.pbrt), its folder's name. Labels name report rows
/// and grid files.
std::vector<std::string> scene_labels(const std::vector<std::string> &specs);

/// One view of an evaluation: its camera and the G-buffer every method is compared at.
struct EvalView {
    Camera camera;
    GBuffer gbuffer;
};
/// View v of n of accel's scene (eval_view_camera) and its G-buffer; nothing, with a warning
/// naming `scene_name` and the view, when the camera sees no surface.
std::optional<EvalView> eval_view(const EmbreeAccel &accel, const std::string &scene_name, int v, int n, int width, int height);

}  // namespace ltm
