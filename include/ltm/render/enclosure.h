// enclosure.h: detects surface points that lie inside closed solids (the floor under a carpet
// or under a box-shaped piece of furniture): light can never reach them, so `ltm sample
// --exclude-enclosed` drops them. With the scene's reachable air (render/reachable_air.h) the test
// no longer trusts the faces' winding: a side counts as enclosed when the air in front of it is not
// air that light or a camera is in, when it faces nothing at all, or when its rays end on back faces
// reached through unreached air (inside a solid) or on anything within the buried distance; and the
// sampler's filter then takes a point's other side when its winding side is enclosed.
#pragma once

#include "ltm/points/surface_sampler.h"
#include "ltm/render/embree_accel.h"
#include "ltm/render/reachable_air.h"

namespace ltm {

struct EnclosureTest {
    int n_rays = 32;                  ///< stratified cosine-weighted directions (4 × 8 strata)
    float back_face_fraction = 0.9f;  ///< enclosed if at least this fraction of rays hit a back face
    /// Floor of the rays' self-intersection offset (offset_ray_origin), in scene units;
    /// enclosed_filter() sets it to the scene's extent, so the test does not depend on the unit.
    float offset_length = 1.f;
    /// > 0: a ray that meets any surface (either side) within this distance also votes closed, so
    /// a point buried in a thin gap — the floor under a rug, the wall behind a cabinet, a shelf
    /// under a book — counts as enclosed: it sees only the gap's other side and the room sees it
    /// only edge-on, so it carries ~no light, but as a node of the transport prior its cluster's
    /// visibility lets it trade light with the room. Scene units. 0 = back faces only.
    float buried_distance = 0.f;
    /// The scene's reachable air, or null: then a back face always votes closed and a side that
    /// faces nothing is not enclosed (the test for consistently wound scenes). With it, a side whose
    /// every ray escapes is enclosed; with it and seeds, also a side with unreached air in front of
    /// it, and a back face votes closed only if the air the ray came through is not reached (the
    /// wall of a room wound outward does not enclose the room).
    const ReachableAir *air = nullptr;
};

/// True if at least `back_face_fraction` of the rays leaving (p, n) first hit the back side of a
/// surface (or, with buried_distance, any surface that near), i.e. the point sits inside a closed,
/// outward-facing solid (or in a thin gap). A first hit on a front face
/// that coincides with a back face (within the rays' offset) counts as back, so coincident faces
/// vote the same whichever of them float rounding puts first. Deterministic (fixed directions).
/// Limitation: a face pressed against the floor from above (a carpet's underside) looks into the
/// space behind the floor, which has no surfaces, so it is not detected.
bool is_enclosed(const EmbreeAccel &accel, Vec3f p, Vec3f n, const EnclosureTest &cfg = {});

/// A SampleFilter for sample_surface(): keeps a sample whose winding side is not enclosed; else its
/// other side (n → −n, no emission: emitters are one-sided) if that is not enclosed; else drops it.
/// It builds the scene's ReachableAir (cfg.air is replaced) and replaces cfg.offset_length by the
/// largest extent of the scene's bounding box.
SampleFilter enclosed_filter(const EmbreeAccel &accel, const EnclosureTest &cfg = {});

}  // namespace ltm
