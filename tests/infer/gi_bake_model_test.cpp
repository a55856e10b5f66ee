// gi_bake_model_test.cpp: the shipped model's E⁺ baked at the refined vertices (render/gi_bake.h,
// `ltm bake-gi`) and seen through the demo scene's camera is the model's own E⁺ at the G-buffer
// points within 5 % (relative MSE): the bake interpolates the same model.
#include <gtest/gtest.h>

#include "ltm/infer/neural_renderer.h"
#include "ltm/render/gi_bake.h"
#include "ltm/scene/scene_loader.h"
#include "test_util.h"

using namespace ltm;

TEST(GiBakeModel, VertexBakeSeenByTheCameraMatchesTheRender) {
    LoadedModel m = load_model(test::source_path("models/ltm-cpu.safetensors"));
    const Scene scene = load_scene(test::source_path("examples/indoor-900012/scene.json"));
    const EmbreeAccel accel(scene);
    const EncodedScene enc = encode_scene(m.model, accel, 0);
    std::vector<BakedMesh> meshes = refine_for_bake(scene, RefineOptions{});
    const GBuffer vp = vertex_points(meshes);
    compose_bake(meshes, std::vector<Vec3f>(vp.n_hits(), Vec3f(0.f)), predict_gbuffer(m.model, enc, vp));
    Camera cam = scene.cameras.at(0);
    cam.width = cam.height = 64;
    const BakeView view = view_bake(meshes, cam);
    const GBuffer gb = render_gbuffer(accel, cam);
    const std::vector<Vec3f> e = predict_gbuffer(m.model, enc, gb);
    double err = 0.0, ref = 0.0;
    for (size_t h = 0; h < gb.n_hits(); ++h) {
        const int64_t px = gb.hit_pixels[h];
        ASSERT_TRUE(view.hit[size_t(px)]) << "pixel " << px;
        const Vec3f b = view.irradiance_indirect.at(int(px % cam.width), int(px / cam.width));
        for (int c = 0; c < 3; ++c) err += double(b[c] - e[h][c]) * double(b[c] - e[h][c]), ref += double(e[h][c]) * double(e[h][c]);
    }
    const double rel = err / ref;
    std::printf("baked vs rendered E+ at %zu pixels: relative MSE %.4f\n", gb.n_hits(), rel);
    EXPECT_LT(rel, 0.05);
}
