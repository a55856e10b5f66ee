// light_sampler.h: picks points on emissive triangles for next-event estimation, proportional to
// area × emitted luminance, and evaluates that pdf for MIS when a path hits an emitter.
#pragma once

#include <cstdint>

#include <vector>

#include "ltm/core/math.h"
#include "ltm/scene/scene.h"

namespace ltm {

struct LightSample {
    Vec3f p, n;          ///< point on the light and its unit normal (emitting side)
    Vec3f radiance;      ///< Le at the point (towards its normal side)
    float pdf_area = 0;  ///< pdf with respect to area on the light
};

class LightSampler {
public:
    explicit LightSampler(const Scene &scene);
    bool empty() const { return m_tris.empty(); }
    /// u: three uniforms (triangle choice, two for the point).
    LightSample sample(float u0, Vec2f u12) const;
    /// Area pdf of having sampled a point on (mesh, triangle); 0 for non-emitters.
    float pdf_area(uint32_t mesh, uint32_t triangle) const;
    /// Converts an area pdf to solid angle at a receiver: pdf_A · d² / |cosθ_light|.
    static float to_solid_angle(float pdf_area, float dist2, float cos_light) {
        return cos_light > 0.f ? pdf_area * dist2 / cos_light : 0.f;
    }

private:
    struct Tri {
        uint32_t mesh, triangle;
        float area;
    };
    const Scene &m_scene;
    std::vector<Tri> m_tris;
    std::vector<double> m_cdf;                    // over m_tris, last = 1
    std::vector<float> m_pmf;                     // selection probability per light triangle
    std::vector<std::vector<int32_t>> m_index;    // [mesh][triangle] -> light index or -1
};

}  // namespace ltm
