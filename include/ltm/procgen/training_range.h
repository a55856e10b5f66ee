// training_range.h: is a scene like the generated houses the models were trained on? The
// generator's houses (configs/gen/indoor.json) have footprints of 2.5–11.2 m and ceilings of
// 2.5–3.2 m, y up. A unit-invariant model (PhysicsConfig::length_scale) does not see the unit,
// so only proportions matter to it; a legacy model also sees metres.
#pragma once

#include <string>
#include <vector>

#include "ltm/scene/scene.h"

namespace ltm {

/// One line per way the scene differs from the training houses (empty: inside the range).
/// unit_free: footprint / height within 0.75–4.6 (y up); else the extent in metres (footprint
/// 1.5–14 m, height 1.5–4 m).
std::vector<std::string> scene_range_warnings(const Scene &scene, bool unit_free);

}  // namespace ltm
