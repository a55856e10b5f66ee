// interaction.cpp: hit → surface interaction.
#include "ltm/render/interaction.h"

namespace ltm {

SurfaceInteraction make_interaction(const Scene &scene, const Ray &ray, const Hit &hit) {
    const TriangleMesh &mesh = scene.meshes[hit.mesh];
    SurfaceInteraction si;
    const float b0 = 1.f - hit.b1 - hit.b2;
    si.p = mesh.vertex(hit.triangle, 0) * b0 + mesh.vertex(hit.triangle, 1) * hit.b1 + mesh.vertex(hit.triangle, 2) * hit.b2;
    si.n = hit.n;
    const Vec2f t0 = mesh.uv(hit.triangle, 0), t1 = mesh.uv(hit.triangle, 1), t2 = mesh.uv(hit.triangle, 2);
    si.uv = {t0.x * b0 + t1.x * hit.b1 + t2.x * hit.b2, t0.y * b0 + t1.y * hit.b1 + t2.y * hit.b2};
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
