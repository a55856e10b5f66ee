// radiance_eval_test.cpp: `ltm eval --radiance` on the built-in room with one conductor wall and
// the tiny model with a random directional head: every method has a row in both tables, the
// conductor table covers exactly the G-buffer's conductor pixels, and the two tables agree — the
// head changes only conductor pixels, so its change of the whole image's error is its change of
// the conductors' error, weighted by their share of the pixels.
#include <cmath>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/eval/radiance_eval.h"
#include "ltm/render/gbuffer.h"
#include "ltm/scene/scene_loader.h"
#include "test_util.h"

using namespace ltm;

namespace {
const MethodResult &row(const ViewResult &v, const std::string &method) {
    for (const auto &m : v.methods)
        if (m.method == method) return m;
    throw std::runtime_error("no row " + method);
}
}  // namespace

TEST(RadianceEval, ConductorTableIsTheWholeImagesErrorOnConductorPixels) {
    set_log_level(LogLevel::quiet);
    Scene scene = load_scene("builtin:quad-light-room");
    Material metal;
    metal.name = "metal", metal.bsdf = BsdfKind::conductor, metal.roughness = 0.1f, metal.specular = Vec3f(0.9f, 0.6f, 0.3f);
    scene.meshes[0].material = scene.add_material(metal);
    Camera cam;
    cam.name = "main", cam.eye = {1.f, 1.5f, 3.5f}, cam.target = {2.5f, 0.3f, 1.5f}, cam.width = cam.height = 24;
    scene.cameras = {cam};
    ModelConfig cfg = ModelConfig::from_file(test::source_path("configs/model/tiny.json"));
    DirectionalConfig d;
    d.dim = 16, d.groups = 4, d.n_layers = 1, d.direction_frequencies = 2, d.bin_resolution = 4;
    cfg.directional = d;
    torch::manual_seed(5);
    std::vector<EvalModel> models{{"tiny", "", LtmModel(cfg)}};
    {
        torch::NoGradGuard g;
        for (auto &p : models[0].model->parameters()) p.add_(torch::randn_like(p) * 0.2);
        models[0].model->eval();
    }
    RadianceEvalOptions opt;
    opt.base.width = opt.base.height = 24, opt.base.ref_spp = 16, opt.base.baseline_spp = 4;
    opt.direct_spp = 4, opt.glossy_samples = 4, opt.bounce = BounceIrradiance::nodes;
    const RadianceEvalReport r = run_radiance_evaluation({{"room", scene}}, models, opt);
    ASSERT_EQ(r.all.views.size(), 1u);
    ASSERT_EQ(r.conductors.views.size(), 1u);
    const EmbreeAccel accel(scene);
    const GBuffer gb = render_gbuffer(accel, cam);
    int64_t n_conductor = 0;
    for (uint8_t dfs : gb.diffuse) n_conductor += !dfs;
    ASSERT_GT(n_conductor, 20);
    EXPECT_EQ(r.conductor_pixels, n_conductor);
    EXPECT_EQ(r.conductors.views[0].pixels, n_conductor);
    const ViewResult &all = r.all.views[0], &cond = r.conductors.views[0];
    for (const char *m : {"model:tiny", "model:tiny/bounce-decode", "model-prior:tiny", "model:tiny/head-conductors",
                          "model:tiny/diffuse-conductors", "pt4", "pt-equal-time", "flat-oracle"}) {
        for (const ViewResult *v : {&all, &cond}) {
            const MethodResult &x = row(*v, m);
            EXPECT_TRUE(std::isfinite(x.metrics.mse) && std::isfinite(x.metrics.rel_mse) && std::isfinite(x.field.level_ratio)) << m;
        }
    }
    EXPECT_NEAR(row(all, "flat-oracle").field.level_ratio, 1.0, 1e-6);
    // The random network moves its prior, at the pixels and on the conductors.
    EXPECT_NE(row(all, "model-prior:tiny").metrics.mse, row(all, "model:tiny").metrics.mse);
    EXPECT_NE(row(cond, "model-prior:tiny").metrics.mse, row(cond, "model:tiny").metrics.mse);
    EXPECT_GT(row(all, "pt-equal-time").spp, 0);
    // The traced bounce and the head change only conductor pixels: (MSE_all(x) − MSE_all(diffuse)) ·
    // N_pixels equals (MSE_cond(x) − MSE_cond(diffuse)) · N_conductor, with N_pixels the whole image.
    const double n_pixels = 24.0 * 24.0;
    for (const char *m : {"model:tiny", "model:tiny/bounce-decode", "model:tiny/head-conductors"}) {
        const double d_all = (row(all, m).metrics.mse - row(all, "model:tiny/diffuse-conductors").metrics.mse) * n_pixels;
        const double d_cond = (row(cond, m).metrics.mse - row(cond, "model:tiny/diffuse-conductors").metrics.mse) * double(n_conductor);
        EXPECT_GT(std::abs(d_cond), 1e-6) << m;
        EXPECT_NEAR(d_all, d_cond, 1e-6 * n_pixels) << m;
    }
    // The bounce's hits (opt.bounce nodes, set above): the /bounce-decode row (decoded at each hit)
    // is the model row of --bounce-irradiance decode, whose own extra row is the render here
    // (interpolated from the points) and another image.
    RadianceEvalOptions decode = opt;
    decode.bounce = BounceIrradiance::decode;
    const RadianceEvalReport rd = run_radiance_evaluation({{"room", scene}}, models, decode);
    const ViewResult &cond_d = rd.conductors.views[0];
    EXPECT_EQ(row(cond_d, "model:tiny").metrics.mse, row(cond, "model:tiny/bounce-decode").metrics.mse);
    EXPECT_EQ(row(cond_d, "model:tiny/bounce-nodes").metrics.mse, row(cond, "model:tiny").metrics.mse);
    EXPECT_NE(row(cond_d, "model:tiny").metrics.mse, row(cond, "model:tiny").metrics.mse);
    const std::string md = r.table_markdown();
    EXPECT_NE(md.find("Conductor pixels (" + std::to_string(n_conductor)), std::string::npos) << md;
    EXPECT_NE(md.find("| model:tiny/diffuse-conductors |"), std::string::npos);
    EXPECT_NE(md.find("| model:tiny/head-conductors |"), std::string::npos);
    // Bad options are refused with the reason.
    RadianceEvalOptions bad = opt;
    bad.glossy_samples = -1;
    EXPECT_THROW(run_radiance_evaluation({{"room", scene}}, models, bad), Error);
}
