// patch_form_factor.h: the form factor from a differential surface element to a square patch —
// the transport prior's near field (transport/transport_prior.h).
//
// The prior treats each node as a small emitter of area a and weighs it by the point formula
// cosθ_r cosθ_s / (r² + a/π). Near a concave edge this fails where it matters most: a receiver at
// distance x from the edge sees the adjacent wall over half its hemisphere (form factor → 1/2 as
// x → 0), but from elements within ~x of the edge, while the nodes sit ~√a/2 from it — the point
// formula, evaluated at their centres, gives x·y/r⁴ → 0. So the prior's edges came out lit by the
// far room instead of darkened by the adjacent wall (the bright seams of v0.9–v0.10).
//
// Here the node is a square of side √a in its tangent plane, and the form factor is Lambert's
// exact contour integral (the polygon's edges seen from p, e.g. Baum, Rushmeier & Winget 1989):
//     F = (1/2π) Σ_k γ_k · n·(v_k × v_{k+1})/|v_k × v_{k+1}|,   γ_k = ∠(v_k, v_{k+1}),
// v_k the vertices relative to p, after clipping the square to the receiver's hemisphere
// (n·v ≥ 0). A receiver behind the patch's plane, in it or within 10⁻⁵ of the side of it gets 0. The square's sides follow t₁ = normalise(ŷ × n_s) (when n_s is ±ŷ: x̂, made orthogonal
// to n_s) and t₂ = n_s × t₁: the frame maps with the scene under the training symmetries (rotations
// about ŷ by quarter turns, mirrors) and is independent of the unit.
#pragma once

#include "ltm/core/math.h"

namespace ltm {

/// Form factor from the element (p, unit normal n) to the square of side `side` centred at c with
/// unit normal nc (frame in the header): in [0, 1]. 0 when p is behind the square's plane or in it.
float patch_form_factor(Vec3f p, Vec3f n, Vec3f c, Vec3f nc, float side);

/// The prior's near-field term: patch_form_factor, but 0 when the node's centre lies on or behind
/// the receiver's plane (n·(c − p) ≤ 0), as the point formula beyond the near field gives it. Such a
/// node's square reaches over the horizon only where other nodes stand for the surface: a floor
/// point under a wall lit the wall's foot and the door jamb from the next room in veach-ajar
/// (docs/results.md, session 26), a side face's node lit a top face near its edge.
float near_form_factor(Vec3f p, Vec3f n, Vec3f c, Vec3f nc, float side);

}  // namespace ltm
