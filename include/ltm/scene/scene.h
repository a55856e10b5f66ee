// scene.h: the scene model shared by every layer: materials, world-space meshes, cameras.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ltm/scene/camera.h"
#include "ltm/scene/material.h"
#include "ltm/scene/mesh.h"

namespace ltm {

struct Scene {
    std::string name;
    std::vector<Material> materials;
    std::vector<TriangleMesh> meshes;
    std::vector<Camera> cameras;
    nlohmann::ordered_json metadata = nlohmann::ordered_json::object();  ///< free-form provenance

    Bounds3f bounds() const;
    /// The scene's own length: the longest side of its bounds (0 for an empty scene). Lengths that
    /// must not depend on the unit (ray offsets, probe distances) are fractions of it.
    float extent() const;
    size_t n_triangles() const;
    double total_area() const;
    /// Index of the material with this name, or -1.
    int find_material(const std::string &name) const;
    /// Adds a material and returns its index (names must be unique).
    int add_material(Material m);
    bool has_emitter() const;
};

struct ValidateOptions {
    bool require_emitter = true;      ///< a scene without light is an error for rendering/baking
};

/// Throws "<where>: <problem>" for: no meshes, non-finite positions/uvs, indices out of range,
/// degenerate triangles (is_degenerate_triangle, scene/mesh_builder.h: the loader drops them from
/// foreign formats, so only a scene JSON can still hold one), undefined materials, no emitter (if required), bad cameras.
void validate_scene(const Scene &scene, const std::string &where, const ValidateOptions &opt = {});

}  // namespace ltm
