// reference_cache.h: path-traced reference E⁺ images kept on disk between `ltm eval` runs.
// A reference at thousands of spp is most of an evaluation's time and does not depend on the
// model, so re-evaluating a new model on the same scenes and views reuses it. The key hashes
// everything the image depends on: the scene's content (geometry, materials, texture pixels),
// the camera and image size, the spp, the path tracer's configuration, and a version that is
// bumped whenever the path tracer's estimator changes.
#pragma once

#include <optional>
#include <string>

#include "ltm/core/image.h"
#include "ltm/core/json_util.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/path_tracer.h"
#include "ltm/scene/camera.h"
#include "ltm/scene/scene.h"

namespace ltm {

/// Bump when the reference estimator changes (cached images of older versions become misses).
inline constexpr int k_reference_cache_version = 1;

struct CachedReference {
    Image indirect;         ///< E⁺ per pixel (W/m²), black where the camera sees nothing
    double seconds = 0.0;   ///< the time it took to render when it was made
};

/// 16 hex digits: a hash of the scene's content, the camera, spp and the tracer configuration.
std::string reference_cache_key(const Scene &scene, const Camera &camera, int spp, const PathTracerConfig &cfg);

/// The cached image for `key`, or nothing if absent. A file that cannot be read or has another
/// size is a miss with a warning (the caller renders and overwrites it).
std::optional<CachedReference> load_cached_reference(const std::string &dir, const std::string &key, int width,
                                                     int height);

/// Writes DIR/KEY.exr (E⁺ as R, G, B) and DIR/KEY.json (seconds, provenance), both atomically.
void store_cached_reference(const std::string &dir, const std::string &key, const CachedReference &ref,
                            const OrderedJson &provenance);

/// The reference E⁺ of one view: from `dir` when it holds this exact reference (`*from_cache`
/// true), otherwise rendered with irradiance_images(pt, gb, spp) and stored there with
/// `provenance`. An empty `dir` always renders.
CachedReference reference_irradiance(const std::string &dir, const Scene &scene, const Camera &camera, const GBuffer &gb,
                                     const PathTracer &pt, const PathTracerConfig &cfg, int spp,
                                     const OrderedJson &provenance, bool *from_cache = nullptr);

}  // namespace ltm
