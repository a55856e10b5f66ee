// validation_report.cpp: prints the path tracer's measured errors against closed forms (the
// figures quoted in docs/performance.md and the issue notes). Same set-ups as the unit tests,
// with more samples.   build/bench/validation_report
#include <cmath>
#include <cstdio>

#include "ltm/core/log.h"
#include "ltm/core/startup.h"
#include "ltm/render/image_renderer.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/mesh_builder.h"

using namespace ltm;

namespace {
IrradianceEstimate furnace(float rho, int depth, int spp) {
    const Scene s = furnace_box(rho, 1.f);
    const EmbreeAccel accel(s);
    PathTracerConfig cfg;
    cfg.seed = 1, cfg.max_depth = depth;
    const PathTracer pt(accel, cfg);
    IrradianceEstimate sum;
    for (int i = 0; i < 16; ++i) {
        const auto e = pt.irradiance({0.1f + 0.8f * float(i % 4) / 3.f, 0.f, 0.1f + 0.8f * float(i / 4) / 3.f}, {0, 1, 0}, uint64_t(i), spp);
        sum.direct += e.direct / 16.f, sum.indirect += e.indirect / 16.f;
    }
    return sum;
}
float polygon_irradiance(Vec3f p, const Vec3f (&poly)[4], float radiance) {
    double sum = 0;
    for (int i = 0; i < 4; ++i) {
        const Vec3f a = normalize(poly[i] - p), b = normalize(poly[(i + 1) % 4] - p), c = cross(a, b);
        sum += std::acos(std::clamp(double(dot(a, b)), -1.0, 1.0)) * double(c.y) / double(length(c));
    }
    return float(std::abs(0.5 * sum) * radiance);
}
}  // namespace

int main() {
    configure_process();
    set_log_level(LogLevel::quiet);
    std::printf("furnace (16 points x 8192 spp), relative error of E:\n");
    for (float rho : {0.3f, 0.8f}) {
        double series = 0, r = 1;
        for (int k = 1; k <= 5; ++k) series += (r *= rho);
        const auto d5 = furnace(rho, 5, 8192), inf = furnace(rho, 1000, 8192);
        std::printf("  rho %.1f  E_direct %+.4f%%  E+ depth 5 %+.4f%%  E total infinite depth %+.4f%%\n", rho,
                    100 * (d5.direct.x / k_pi - 1), 100 * (d5.indirect.x / (k_pi * series) - 1),
                    100 * ((inf.direct.x + inf.indirect.x) / (k_pi / (1 - rho)) - 1));
    }
    // Quad light 1 m x 1 m at height 1 over a plane, radiance 10.
    Scene s;
    Material plane, light;
    plane.name = "plane", light.name = "light";
    light.albedo = Texture::constant(Vec3f(0.f));
    light.emission = Texture::constant(Vec3f(10.f));
    s.add_material(plane), s.add_material(light);
    TriangleMesh floor, lamp;
    floor.name = "plane", floor.material = 0, lamp.name = "light", lamp.material = 1;
    add_quad_facing(floor, {-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}, {0, 1, 0});
    const Vec3f poly[4] = {{-.5f, 1, -.5f}, {.5f, 1, -.5f}, {.5f, 1, .5f}, {-.5f, 1, .5f}};
    add_quad_facing(lamp, poly[0], poly[1], poly[2], poly[3], {0, -10, 0});
    s.meshes = {floor, lamp};
    const EmbreeAccel accel(s);
    const PathTracer pt(accel, PathTracerConfig{});
    std::printf("quad light vs Lambert's formula (65536 spp), relative error of E_direct, E+:\n");
    const Vec3f pts[] = {{0, 0, 0}, {0.3f, 0, 0.2f}, {1.2f, 0, -0.4f}, {-2.f, 0, 1.5f}, {0.5f, 0, 0.5f}};
    for (const Vec3f &p : pts) {
        const auto e = pt.irradiance(p, {0, 1, 0}, 0, 65536);
        std::printf("  p (%5.2f, %4.2f)  exact %.5f  E_direct %+.4f%%  E+ %g\n", p.x, p.z, polygon_irradiance(p, poly, 10.f),
                    100 * (e.direct.x / polygon_irradiance(p, poly, 10.f) - 1), e.indirect.x);
    }
    // Cornell box image mean over seeds (32x32, 64 spp).
    const Scene cb = cornell_box();
    const EmbreeAccel cba(cb);
    double m[5], mean = 0;
    for (int sd = 0; sd < 5; ++sd) {
        PathTracerConfig cfg;
        cfg.seed = uint64_t(sd + 1);
        const PathTracer cpt(cba, cfg);
        Camera cam = cb.cameras[0];
        cam.width = cam.height = 32;
        const auto img = render_pathtraced(cpt, cam, 64);
        m[sd] = 0;
        for (const Vec3f &c : img.color.pixels) m[sd] += double(luminance(c)) / double(img.color.pixels.size());
        mean += m[sd] / 5;
    }
    double var = 0;
    for (double x : m) var += (x - mean) * (x - mean) / 4;
    std::printf("Cornell box 32x32 @ 64 spp, mean luminance over seeds 1-5: %.5f +- %.5f (std)\n", mean, std::sqrt(var));
    return 0;
}
