// interaction.cpp: hit → surface interaction.
#include "ltm/render/interaction.h"

namespace ltm {

SurfaceInteraction make_interaction(const Scene &scene, const Ray &ray, const Hit &hit) {
    const TriangleMesh &mesh = scene.meshes[hit.mesh];
    SurfaceInteraction si;
    const float b0 = 1.f - hit.b1 - hit.b2;
    si.p = mesh.position_at(hit.triangle, b0, hit.b1, hit.b2);
    si.n = hit.n;
    si.uv = mesh.uv_at(hit.triangle, b0, hit.b1, hit.b2);
    si.material = &scene.materials[size_t(mesh.material)];
    si.front = dot(ray.d, hit.n) < 0.f;
    return si;
}

Bsdf SurfaceInteraction::bsdf() const {
    Bsdf b;
    b.kind = material->bsdf;
    b.albedo = albedo();
    b.f0 = material->specular;
    b.alpha = material->roughness;
    return b;
}

}  // namespace ltm
