// gi_bake.h: baked global illumination on refined meshes, written as glTF 2.0 (issue #32).
// The scene's triangles are split until no edge is longer than a set length (light varies across a
// large wall), each refined mesh's vertices are shared where position and facing agree, and every
// vertex gets the radiance a diffuse surface sends out, Lo = Le + ρ/π·(E_direct + E⁺), and E⁺ alone.
// Where E⁺ comes from is the caller's (the model: infer/, `ltm bake-gi`; or the path tracer here).
//
// glTF layout (docs/formats.md, "Baked GI"): one node and mesh per scene mesh, world space (the
// node has no transform), y up, metres as the scene's; attributes POSITION, NORMAL, COLOR_0 (Lo
// tone-mapped to [0, 1]: Reinhard on exposure × Lo, then sRGB, so any glTF viewer shows it),
// _RADIANCE (Lo, linear HDR float VEC3, W/m²/sr) and _IRRADIANCE_INDIRECT (E⁺, W/m²); the material
// is unlit (KHR_materials_unlit) and single-sided (each lit side is its own triangle), base colour
// ρ of the mesh (its mean albedo); emitters keep Le (emissiveFactor × KHR_materials_emissive_strength);
// conductors keep their roughness and F0 and carry extras {"ltm_conductor": true}.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ltm/core/image.h"
#include "ltm/core/math.h"
#include "ltm/scene/camera.h"
#include "ltm/render/gbuffer.h"
#include "ltm/scene/scene.h"

namespace ltm {

/// One refined scene mesh: vertex arrays and the values baked at them.
struct BakedMesh {
    std::string name;
    int material = -1;                 ///< index into the scene's materials
    std::vector<Vec3f> position, normal, albedo, emission;   ///< per vertex (normal: the lit side)
    std::vector<uint32_t> indices;     ///< 3 per triangle, wound so that `normal` is the front
    std::vector<Vec3f> radiance;       ///< Lo = Le + ρ/π·(E_direct + E⁺) per vertex (after bake)
    std::vector<Vec3f> irradiance_indirect;   ///< E⁺ per vertex (after bake)
    std::vector<Vec3f> irradiance_direct;     ///< E_direct per vertex (after bake)
};

struct RefineOptions {
    /// Longest edge after refinement (the scene's unit); ≤ 0: the scene's largest extent / 64.
    float max_edge = 0.f;
    /// A refinement needing more vertices than this is refused with a one-line error (no output).
    int64_t max_vertices = 8'000'000;
};

/// Splits each triangle into n² (n = ⌈longest edge / max_edge⌉, barycentric lattice) and shares
/// vertices of equal position and normal within each mesh. Each side of a triangle that light
/// reaches (render/reachable_air.h) gets its own copy, wound to face that side: a face wound away
/// from the room is baked on its room side, a curtain or an open box's wall on both.
/// Throws ltm::Error on an empty scene or a vertex count over the budget.
std::vector<BakedMesh> refine_for_bake(const Scene &scene, const RefineOptions &opt);

/// All meshes' vertices as one point list (the G-buffer layout: width = vertex count, height 1,
/// every "pixel" a hit), in mesh order, so any per-point estimator of the renderer runs on them.
GBuffer vertex_points(const std::vector<BakedMesh> &meshes);

/// Fills radiance and the two irradiances of every vertex from per-point E_direct and E⁺ (in the
/// order of vertex_points()). Conductors are shaded as diffuse with their F0 as ρ (marked in glTF).
void compose_bake(std::vector<BakedMesh> &meshes, const std::vector<Vec3f> &direct, const std::vector<Vec3f> &indirect);

/// COLOR_0's tone map before its sRGB encoding: Reinhard x / (1 + x) of exposure × Lo, per channel
/// (the viewer's shader and `ltm bake-gi --view` apply the same).
Vec3f bake_display(Vec3f lo, float exposure);

/// The bake seen through a camera: primary rays through the pixel centres against the refined
/// meshes, each hit's vertex values interpolated by its barycentrics — what a rasteriser shows of
/// the .glb (the reference for the viewer's screenshot, and the check against `ltm render`).
struct BakeView {
    Image radiance, irradiance_indirect;   ///< Lo and E⁺ per pixel (0 where nothing is hit)
    std::vector<uint8_t> hit;              ///< per pixel: 1 where a ray hits
};
BakeView view_bake(const std::vector<BakedMesh> &meshes, const Camera &camera);

/// Writes the bake as binary glTF (.glb) atomically: a file that exists is complete. exposure
/// scales Lo before COLOR_0's tone map. Throws ltm::Error naming the path on failure.
void write_bake_glb(const std::string &path, const Scene &scene, const std::vector<BakedMesh> &meshes, float exposure,
                    const std::string &generator);

}  // namespace ltm
