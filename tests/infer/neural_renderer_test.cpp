// neural_renderer_test.cpp: the neural renderer's invariants on the tiny model with random
// weights: view consistency, batch independence, composition, and direct light = the PT estimator.
#include <gtest/gtest.h>

#include <set>

#include "ltm/core/color.h"
#include "ltm/core/error.h"
#include "ltm/core/rng.h"
#include "ltm/infer/neural_renderer.h"
#include "ltm/infer/prior_model.h"
#include "ltm/infer/traced_bounce.h"
#include "ltm/nn/checkpoint.h"
#include "ltm/nn/point_tensor.h"
#include "ltm/points/safetensors.h"
#include "ltm/render/direct_light.h"
#include "ltm/render/interaction.h"
#include "ltm/render/scene_points.h"
#include "ltm/scene/builtin_scenes.h"
#include "ltm/scene/pbrt_reader.h"
#include "ltm/scene/scene_loader.h"
#include "pbrt_writer.h"
#include "test_util.h"

using namespace ltm;

namespace {
LtmModel tiny_model() {
    torch::manual_seed(5);
    LtmModel m(ModelConfig::from_file(test::source_path("configs/model/tiny.json")));
    // Non-trivial outputs: perturb every parameter (a fresh decoder's output layer may be near 0).
    torch::NoGradGuard g;
    for (auto &p : m->parameters()) p.add_(torch::randn_like(p) * 0.2);
    m->eval();
    return m;
}

Camera looking_at(Vec3f eye, Vec3f target, int size) {
    Camera c;
    c.eye = eye, c.target = target, c.width = size, c.height = size, c.fov_y_deg = 50.f;
    return c;
}

// The built-in room, its accelerator and path tracer, and the tiny model: most tests' set-up.
struct Room {
    Scene scene = load_scene("builtin:quad-light-room");
    EmbreeAccel accel{scene};
    PathTracer pt{accel, PathTracerConfig{}};
    LtmModel model = tiny_model();
    /// The render tests' view: size×size pixels of the floor, the box and the walls.
    static Camera view(int size) { return looking_at({1.f, 1.5f, 3.5f}, {2.5f, 0.8f, 1.5f}, size); }
};
// The built-in room with its first mesh (a wall) turned into a GGX conductor: the glossy tests' scene.
Scene room_with_metal() {
    Scene scene = load_scene("builtin:quad-light-room");
    Material metal;
    metal.name = "metal", metal.bsdf = BsdfKind::conductor, metal.roughness = 0.1f, metal.specular = Vec3f(0.9f, 0.6f, 0.3f);
    scene.meshes[0].material = scene.add_material(metal);   // one of the room's surfaces becomes a GGX conductor
    return scene;
}
}  // namespace

// The same world-space point seen from two cameras gets the same prediction: the model's input is
// (p, n, albedo) and the scene latents, never the view. Odd sizes put a pixel centre on the axis.
TEST(NeuralRenderer, SamePointFromTwoCamerasSamePrediction) {
    const Scene scene = load_scene("builtin:quad-light-room");
    const EmbreeAccel accel(scene);
    LtmModel model = tiny_model();
    const EncodedScene enc = encode_scene(model, accel, /*seed=*/3);
    // Camera a looks somewhere; camera b is placed elsewhere and aimed at the point a's centre
    // pixel sees (eyes tried in turn until the point is not occluded from b).
    const Camera a = looking_at({1.f, 1.6f, 3.4f}, {3.1f, 0.4f, 1.2f}, 33);
    const GBuffer ga = render_gbuffer(accel, a);
    const int64_t centre = 16 * 33 + 16;
    const auto ia = std::find(ga.hit_pixels.begin(), ga.hit_pixels.end(), centre) - ga.hit_pixels.begin();
    ASSERT_LT(size_t(ia), ga.n_hits());
    const Vec3f p = ga.position[size_t(ia)];
    GBuffer gb;
    std::ptrdiff_t ib = -1;
    for (const Vec3f eye : {Vec3f{4.2f, 2.1f, 3.3f}, Vec3f{0.6f, 2.2f, 0.5f}, Vec3f{4.3f, 1.2f, 0.4f}}) {
        gb = render_gbuffer(accel, looking_at(eye, p, 33));
        ib = std::find(gb.hit_pixels.begin(), gb.hit_pixels.end(), centre) - gb.hit_pixels.begin();
        if (size_t(ib) < gb.n_hits() && length(gb.position[size_t(ib)] - p) < 1e-4f) break;
        ib = -1;
    }
    ASSERT_GE(ib, 0) << "no second camera sees " << p;
    EXPECT_LT(length(ga.normal[size_t(ia)] - gb.normal[size_t(ib)]), 1e-6f);
    const auto ea = predict_gbuffer(model, enc, ga), eb = predict_gbuffer(model, enc, gb);
    const Vec3f va = ea[size_t(ia)], vb = eb[size_t(ib)];
    EXPECT_GT(max_component(va), 0.f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(va[c], vb[c], 1e-3f * std::max(1.f, std::abs(va[c]))) << "channel " << c;
}

// A pixel's prediction does not depend on the other pixels decoded with it.
TEST(NeuralRenderer, PredictionIndependentOfBatch) {
    const Scene scene = load_scene("builtin:quad-light-room");
    const EmbreeAccel accel(scene);
    LtmModel model = tiny_model();
    const EncodedScene enc = encode_scene(model, accel, 1);
    const GBuffer gb = render_gbuffer(accel, looking_at({1.f, 1.5f, 3.5f}, {2.5f, 0.8f, 1.5f}, 24));
    const auto all = predict_gbuffer(model, enc, gb);
    GBuffer one = gb;   // keep a single hit
    const size_t k = gb.n_hits() / 2;
    for (auto *v : {&one.position, &one.normal, &one.albedo, &one.emitted}) *v = {(*v)[k]};
    one.hit_pixels = {gb.hit_pixels[k]}, one.depth = {gb.depth[k]}, one.diffuse = {gb.diffuse[k]};
    const auto single = predict_gbuffer(model, enc, one);
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(single[0][c], all[k][c]);
}

// render_neural = Le + albedo/π·(E_direct + Ê⁺) with E_direct the path tracer's direct estimator
// (--direct-estimator mis) or the ratio estimator (the default for constant-radiance emitters).
TEST(NeuralRenderer, ComposesDirectAndPredictedIrradiance) {
    Room room;
    const Camera cam = Room::view(20);
    NeuralRenderOptions opt;
    opt.direct_spp = 4, opt.seed = 2, opt.direct = DirectEstimator::mis;
    const NeuralRender r = render_neural(room.model, room.pt, cam, opt);
    EXPECT_EQ(r.direct, DirectEstimator::mis);
    const GBuffer gb = render_gbuffer(room.accel, cam);
    ASSERT_EQ(r.n_queries, int64_t(gb.n_hits()));
    EXPECT_EQ(r.n_scene_points, room.model->cfg.scene_points);
    const IrradianceImages direct = irradiance_images(room.pt, gb, 4, /*with_indirect=*/false);
    const auto pred = predict_gbuffer(room.model, encode_scene(room.model, room.accel, 2), gb);
    for (size_t k = 0; k < gb.n_hits(); k += 7) {
        const size_t i = size_t(gb.hit_pixels[k]);
        EXPECT_EQ(r.image.direct.pixels[i], direct.direct.pixels[i]);
        EXPECT_EQ(direct.indirect.pixels[i], Vec3f(0.f));
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(r.image.irradiance.pixels[i][c], pred[k][c], 1e-6f * std::max(1.f, pred[k][c]));
            const float want = gb.emitted[k][c] + gb.albedo[k][c] * k_inv_pi * (direct.direct.pixels[i][c] + pred[k][c]);
            EXPECT_NEAR(r.image.color.pixels[i][c], want, 1e-5f * std::max(1.f, want));
        }
    }
    for (double t : {r.timings.encode, r.timings.decode, r.timings.direct, r.timings.total}) EXPECT_GE(t, 0.0);
    EXPECT_GE(r.timings.total, r.timings.encode + r.timings.decode);
}

// prior_only renders the model's prior where the render reads Ê⁺: predict_gbuffer_prior's values,
// bit for bit, at every pixel and on a lattice (--gi-stride 2) where it is decoded; the random
// network's render is another image.
TEST(NeuralRenderer, PriorOnlyRenderIsTheModelsOwnPrior) {
    Room room;
    // A transport prior (tiny-pi: its Ê⁺ varies over the view, unlike the tiny config's flat one)
    // under a random network with a directional head.
    ModelConfig cfg = ModelConfig::from_file(test::source_path("configs/model/tiny-pi.json"));
    DirectionalConfig d;
    d.dim = 16, d.groups = 4, d.n_layers = 1, d.direction_frequencies = 2, d.bin_resolution = 4;
    cfg.directional = d;
    torch::manual_seed(5);
    LtmModel model(cfg);
    {
        torch::NoGradGuard g;
        for (auto &p : model->parameters()) p.add_(torch::randn_like(p) * 0.2);
        model->eval();
    }
    const Camera cam = Room::view(20);
    NeuralRenderOptions opt;
    opt.direct_spp = 4, opt.seed = 2, opt.direct = DirectEstimator::mis, opt.prior_only = true;
    const NeuralRender r = render_neural(model, room.pt, cam, opt);
    const GBuffer gb = render_gbuffer(room.accel, cam);
    const auto prior = predict_gbuffer_prior(encode_scene(model, room.accel, 2), gb);
    const auto pred = predict_gbuffer(model, encode_scene(model, room.accel, 2), gb);
    int differ = 0, varies = 0;
    for (size_t k = 0; k < gb.n_hits(); ++k) {
        const size_t i = size_t(gb.hit_pixels[k]);
        EXPECT_EQ(r.image.irradiance.pixels[i], prior[k]) << "pixel " << i;
        differ += prior[k] != pred[k], varies += prior[k] != prior[0];
    }
    EXPECT_GT(differ, int(gb.n_hits()) / 2) << "the random network moves its prior";
    EXPECT_GT(varies, int(gb.n_hits()) / 2) << "a prior that varies: a mix-up of pixels would show";
    EXPECT_GT(r.timings.prior_solve, 0.0);
    EXPECT_LE(r.timings.prior_solve, r.timings.encode);
    opt.gi.stride = 2;
    const NeuralRender lattice = render_neural(model, room.pt, cam, opt);
    int on_lattice = 0, decoded_same = 0;
    for (size_t k = 0; k < gb.n_hits(); ++k) {
        const int64_t px = gb.hit_pixels[k];
        if ((px % cam.width) % 2 != 0 || (px / cam.width) % 2 != 0) continue;
        ++on_lattice, decoded_same += lattice.image.irradiance.pixels[size_t(px)] == prior[k];
    }
    EXPECT_GT(on_lattice, 50);
    EXPECT_EQ(decoded_same, on_lattice) << "each gathered query's value does not depend on its company";
    opt.glossy = GlossyShading::head;   // the model has a head; its prior has none
    EXPECT_THROW(render_neural(model, room.pt, cam, opt), Error);
    opt.prior_only = false;
    EXPECT_NO_THROW(render_neural(model, room.pt, cam, opt));
}

// A model at its prior (the decoder's output layer zeroed, as the shipped model) renders without
// libtorch (infer/prior_model.h) exactly as the tensor model does: the same image to the bit, pixels,
// Ê⁺ and direct light, with the prior dense or through its tree, every pixel decoded or coarse to
// fine, and conductors by the traced bounce (Ê⁺ at its hits decoded, then from the scene points);
// and to float rounding against the unfolded tensor decoder. Its weights file says the network is
// silenced; the random network's does not.
TEST(NeuralRenderer, PriorRenderWithoutTorchIsTheTensorModelAtItsPrior) {
    const Scene scene = room_with_metal();
    const EmbreeAccel accel(scene);
    const PathTracer pt(accel, PathTracerConfig{});
    torch::manual_seed(5);
    LtmModel model(ModelConfig::from_file(test::source_path("configs/model/tiny-pi.json")));
    {
        torch::NoGradGuard g;
        for (auto &p : model->parameters()) p.add_(torch::randn_like(p) * 0.2);
    }
    model->eval();
    test::TempDir dir;
    save_weights(dir.path("active.safetensors"), model);
    EXPECT_FALSE(load_prior_model(dir.path("active.safetensors")).silenced);
    model->decoder->start_at_prior();
    save_weights(dir.path("prior.safetensors"), model, {}, /*half=*/true);
    const PriorModel pm = load_prior_model(dir.path("prior.safetensors"));
    EXPECT_TRUE(pm.silenced);
    EXPECT_EQ(pm.cfg.to_json().dump(), model->cfg.to_json().dump());
    // Its output layer is all the prior path reads of the tensors: missing or misshapen, it is refused.
    SafetensorsFile broken = read_safetensors(dir.path("prior.safetensors"));
    ASSERT_EQ(broken.tensors.erase("decoder.out.3.bias"), 1u);
    write_safetensors(dir.path("broken.safetensors"), broken);
    EXPECT_THROW(load_prior_model(dir.path("broken.safetensors")), Error);
    broken.tensors["decoder.out.3.bias"] = make_f32_tensor({4}, std::vector<float>(4, 0.f).data());
    write_safetensors(dir.path("broken.safetensors"), broken);
    EXPECT_THROW(load_prior_model(dir.path("broken.safetensors")), Error);
    const Camera cam = Room::view(24);
    int conductors = 0;
    struct Case {
        float theta;
        int levels;
        BounceIrradiance bounce;
    };
    for (const Case c : {Case{0.f, 1, BounceIrradiance::decode}, Case{0.5f, 2, BounceIrradiance::nodes}}) {
        set_prior_theta(model, c.theta);
        NeuralRenderOptions opt;
        opt.direct_spp = 4, opt.seed = 3, opt.glossy = GlossyShading::trace, opt.glossy_samples = 4, opt.bounce = c.bounce;
        opt.gi.stride = c.levels, opt.gi.levels = c.levels;
        const NeuralRender a = render_neural(model, pt, cam, opt);
        const NeuralRender b = render_prior(model->cfg, pt, cam, opt);
        ASSERT_EQ(a.n_decoded, b.n_decoded);
        conductors = int(a.n_conductor);
        int same = 0;
        for (size_t i = 0; i < a.image.color.pixels.size(); ++i)
            same += a.image.color.pixels[i] == b.image.color.pixels[i] && a.image.irradiance.pixels[i] == b.image.irradiance.pixels[i] &&
                    a.image.direct.pixels[i] == b.image.direct.pixels[i];
        EXPECT_EQ(same, int(a.image.color.pixels.size())) << "θ " << c.theta << ", " << c.levels << " levels";
    }
    EXPECT_GT(conductors, 20) << "conductor pixels in view";
    // The tensor decoder itself, not folded: its zeroed output through libtorch's softplus and expm1
    // gives the same prior to float rounding (the folded path above shares the prior's code).
    model->fold_prior = false;
    NeuralRenderOptions opt;
    opt.direct_spp = 4, opt.seed = 3, opt.glossy = GlossyShading::diffuse;
    const NeuralRender a = render_neural(model, pt, cam, opt), b = render_prior(model->cfg, pt, cam, opt);
    double worst = 0;
    for (size_t i = 0; i < a.image.irradiance.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, double(std::abs(a.image.irradiance.pixels[i][c] - b.image.irradiance.pixels[i][c])) /
                                        (double(b.image.irradiance.pixels[i][c]) + 1e-12));
    EXPECT_LT(worst, 1e-6) << "relative, at the worst pixel";
    model->fold_prior = true;
    NeuralRenderOptions head;
    head.glossy = GlossyShading::head;
    EXPECT_THROW(render_prior(model->cfg, pt, cam, head), Error);
}

namespace {
// A tiny traced-queries model whose body is silent and whose skip is `skip` (the regathered prior as
// weights, as v0.14 and v0.15), saved and read back as a PriorModel; the Room's view at 132² (17 424
// pixels, every one decoded: two chunks of k_decode_chunk) with the options both paths render with.
struct FoldedModel {
    Room r;
    LtmModel model{nullptr};
    test::TempDir dir;
    PriorModel pm;
    const Camera cam = Room::view(132);
    NeuralRenderOptions opt;
    explicit FoldedModel(Vec3f skip) {
        ModelConfig cfg = ModelConfig::from_file(test::source_path("configs/model/tiny-pi.json"));
        cfg.traced_inputs = 4, cfg.traced_queries = true;
        cfg.physics.prior_rays = true, cfg.physics.prior_theta = 0.5f;
        torch::manual_seed(5);
        model = LtmModel(cfg);
        model->eval();
        model->decoder->start_at_prior();
        {
            torch::NoGradGuard g;
            model->decoder->skip.copy_(torch::tensor({skip.x, skip.y, skip.z}));
        }
        save_weights(dir.path("folded.safetensors"), model);
        pm = load_prior_model(dir.path("folded.safetensors"));
        opt.direct_spp = 1, opt.seed = 3, opt.glossy = GlossyShading::diffuse, opt.gi.stride = 1, opt.gi.levels = 1;
    }
};

// max over pixels and channels of |a − b| / b (b the torch-free render).
double worst_relative(const NeuralRender &a, const NeuralRender &b) {
    double worst = 0;
    for (size_t i = 0; i < b.image.irradiance.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const double x = b.image.irradiance.pixels[i][c];
            worst = std::max(worst, std::abs(double(a.image.irradiance.pixels[i][c]) - x) / (x + 1e-12));
        }
    return worst;
}
}  // namespace

// A silent body with a skip (the regathered prior as weights: v0.14): the file reads as folded, not
// silenced, and rendered without libtorch (render_prior with the file's skip) it is the tensor model's
// fold to float rounding (libm against libtorch's log, exp) — with the prior's visibility by rays, whose
// neighbouring receivers share answers within a gather call, over more pixels than one chunk
// (k_decode_chunk: both paths gather alike); the skip moves it off the prior alone; a config without
// traced inputs cannot fold a skip.
TEST(NeuralRenderer, AFoldedSkipWithoutTorchIsTheTensorModelsFold) {
    FoldedModel f(Vec3f(0.7f, 1.f, 1.3f));
    const PriorModel &pm = f.pm;
    EXPECT_FALSE(pm.silenced);
    EXPECT_TRUE(pm.folded() && pm.torch_free());
    EXPECT_TRUE(pm.skip == Vec3f(0.7f, 1.f, 1.3f));
    const NeuralRender a = render_neural(f.model, f.r.pt, f.cam, f.opt), b = render_prior(pm.cfg, f.r.pt, f.cam, f.opt, pm.skip);
    ASSERT_GT(a.n_decoded, int64_t(k_decode_chunk));
    const NeuralRender prior = render_prior(pm.cfg, f.r.pt, f.cam, f.opt);
    ASSERT_EQ(a.n_decoded, b.n_decoded);
    EXPECT_LT(worst_relative(a, b), 1e-5) << "relative, at the worst pixel";
    EXPECT_GT(worst_relative(prior, b), 1e-2) << "the skip moves the prior";
    ModelConfig untraced = pm.cfg;
    untraced.traced_inputs = 0;
    EXPECT_THROW(render_prior(untraced, f.r.pt, f.cam, f.opt, pm.skip), Error);
}

// At w = 1 the fold is R: Ê · expm1(softplus(ln(R/Ê))) = R, so the torch-free path solves the frame for
// its regather alone (no prior bounces, SceneFrame::prior_solved false) and gathers R alone — the tensor
// model's fold through the full solve to float rounding. Such a frame refuses the prior and any other skip.
TEST(NeuralRenderer, AFoldAtOneIsTheRegatherWithoutThePriorsBounces) {
    FoldedModel f(Vec3f(1.f));
    const PriorModel &pm = f.pm;
    ASSERT_TRUE(pm.skip == Vec3f(1.f));
    const NeuralRender a = render_neural(f.model, f.r.pt, f.cam, f.opt), b = render_prior(pm.cfg, f.r.pt, f.cam, f.opt, pm.skip);
    ASSERT_EQ(a.n_decoded, b.n_decoded);
    double level = 0;
    for (const Vec3f &e : b.image.irradiance.pixels) level += double(e.x + e.y + e.z);
    EXPECT_GT(level, 0.0);
    EXPECT_LT(worst_relative(a, b), 1e-5) << "relative, at the worst pixel";
    const PriorScene ps = encode_prior_scene(pm.cfg, f.r.pt.accel(), f.opt.seed, true, pm.skip);
    EXPECT_FALSE(ps.frame.prior_solved);
    ASSERT_TRUE(ps.frame.regather);
    for (const Vec3f &e : ps.frame.transport->exitance) ASSERT_EQ(e, Vec3f(0.f)) << "the prior's bounces were solved";
    const std::vector<float> q(ps.points.values.begin(), ps.points.values.begin() + 9);   // a scene point's p, n, ρ as a query
    Vec3f out;
    EXPECT_NO_THROW(folded_irradiance(ps.frame, Vec3f(1.f), q.data(), 1, &out));
    EXPECT_THROW(prior_irradiance(ps.frame, q.data(), 1, &out), Error);
    EXPECT_THROW(folded_irradiance(ps.frame, Vec3f(0.7f, 1.f, 1.f), q.data(), 1, &out), Error);
    EXPECT_TRUE(encode_prior_scene(pm.cfg, f.r.pt.accel(), f.opt.seed, true, Vec3f(0.7f, 1.f, 1.f)).frame.prior_solved);
}

// physics.prior_regathered at its prior (𝓦_out zero): the file reads as silenced, and `ltm` renders it
// without libtorch by tracing the scene for R (encode_prior_scene) — the tensor model's render to float
// rounding, and the same R a traced-queries file at skip 1 folds to.
TEST(NeuralRenderer, ASilencedRegatheredPriorRendersRWithoutTorch) {
    FoldedModel at_one(Vec3f(1.f));
    ModelConfig cfg = at_one.pm.cfg;
    cfg.traced_queries = false, cfg.physics.prior_regathered = true;
    cfg.directional.reset();   // its prior_cells split the solved prior's gather: refused with R as the prior
    torch::manual_seed(5);
    LtmModel model(cfg);
    model->eval();
    model->decoder->start_at_prior();
    test::TempDir dir;
    save_weights(dir.path("rp.safetensors"), model);
    const PriorModel pm = load_prior_model(dir.path("rp.safetensors"));
    EXPECT_TRUE(pm.silenced && pm.torch_free());
    const NeuralRender plain = render_prior(pm.cfg, at_one.r.pt, at_one.cam, at_one.opt);
    const NeuralRender tensor = render_neural(model, at_one.r.pt, at_one.cam, at_one.opt);
    const NeuralRender r = render_prior(at_one.pm.cfg, at_one.r.pt, at_one.cam, at_one.opt, Vec3f(1.f));
    ASSERT_EQ(plain.n_decoded, tensor.n_decoded);
    EXPECT_LT(worst_relative(tensor, plain), 1e-5) << "the tensor model, relative at the worst pixel";
    EXPECT_LT(worst_relative(r, plain), 1e-5) << "the skip-1 fold's R";
    EXPECT_GT(worst_relative(render_prior(at_one.pm.cfg, at_one.r.pt, at_one.cam, at_one.opt), plain), 1e-2) << "not the solved prior";
}

// The node field holds each scene point's own decoded value: a decoder that answers each query
// row with its position gives every point its own position back (the group_order permutation
// and its inverse), and a point set without the query columns is refused.
TEST(NeuralRenderer, NodeIrradianceIsEachPointsOwnDecode) {
    PointSet points(scene_point_columns(), 300);
    Pcg32 rng(17);
    for (size_t j = 0; j < points.size(); ++j) {
        points.set_vec3(j, 0, Vec3f(rng.next_float(), rng.next_float(), rng.next_float()) * 4.f);
        points.set_vec3(j, 3, normalize(Vec3f(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f)));
        points.set_vec3(j, 6, Vec3f(0.5f));
    }
    const IrradianceDecoder echo = [](const std::vector<float> &q) {
        std::vector<Vec3f> out(q.size() / 9);
        for (size_t i = 0; i < out.size(); ++i) out[i] = Vec3f(q[i * 9], q[i * 9 + 1], q[i * 9 + 2]);
        return out;
    };
    const NodeIrradiance nodes = decode_node_irradiance(echo, points, 0.3f);
    ASSERT_EQ(nodes.irradiance.size(), points.size());
    for (size_t j = 0; j < points.size(); ++j) EXPECT_EQ(nodes.irradiance[j], points.vec3(j, 0)) << "point " << j;
    EXPECT_EQ(nodes.interpolator.size(), points.size());
    EXPECT_THROW(decode_node_irradiance(echo, PointSet({"x", "y", "z"}, 3), 0.3f), Error);
    const IrradianceDecoder wrong = [&](const std::vector<float> &q) {
        std::vector<Vec3f> out = echo(q);
        out.pop_back();
        return out;
    };
    EXPECT_ANY_THROW(decode_node_irradiance(wrong, points, 0.3f)) << "a decoder answering the wrong number of rows";
}

// BounceIrradiance::automatic interpolates exactly when the bounce has at least 2·M rays.
TEST(NeuralRenderer, AutomaticBounceInterpolatesOnlyWithEnoughRays) {
    const Scene scene = room_with_metal();
    LtmModel model = tiny_model();
    const EmbreeAccel accel(scene);
    const PathTracer pt(accel, PathTracerConfig{});
    const Camera cam = looking_at({1.f, 1.5f, 3.5f}, {2.5f, 0.3f, 1.5f}, 24);
    std::set<BounceIrradiance> seen;
    for (int K : {1, 64}) {
        NeuralRenderOptions opt;
        opt.direct_spp = 4, opt.seed = 3, opt.glossy_samples = K, opt.glossy = GlossyShading::trace;
        const NeuralRender r = render_neural(model, pt, cam, opt);
        ASSERT_GT(r.n_conductor, 40);
        const bool nodes = r.n_conductor * K >= k_bounce_nodes_per_point * r.n_scene_points;
        EXPECT_EQ(r.bounce, nodes ? BounceIrradiance::nodes : BounceIrradiance::decode) << K;
        seen.insert(r.bounce);
    }
    EXPECT_EQ(seen.size(), 2u) << "both ways occur";
    EXPECT_EQ(parse_bounce_irradiance("auto"), BounceIrradiance::automatic);
    EXPECT_THROW(parse_bounce_irradiance("nearest"), Error);
}

// F16 export halves the file and predicts within half precision of the F32 weights.
TEST(NeuralRenderer, HalfWeightsLoadAndPredictClose) {
    test::TempDir dir;
    LtmModel model = tiny_model();
    save_weights(dir.path("w32.safetensors"), model);
    save_weights(dir.path("w16.safetensors"), model, {}, /*half=*/true);
    const auto s32 = std::filesystem::file_size(dir.path("w32.safetensors"));
    const auto s16 = std::filesystem::file_size(dir.path("w16.safetensors"));
    EXPECT_LT(double(s16), 0.55 * double(s32));
    LoadedModel m16 = load_model(dir.path("w16.safetensors"));
    const Scene scene = load_scene("builtin:quad-light-room");
    const EmbreeAccel accel(scene);
    const GBuffer gb = render_gbuffer(accel, looking_at({1.f, 1.5f, 3.5f}, {2.5f, 0.8f, 1.5f}, 16));
    const auto a = predict_gbuffer(model, encode_scene(model, accel, 1), gb);
    const auto b = predict_gbuffer(m16.model, encode_scene(m16.model, accel, 1), gb);
    double err = 0, ref = 0;
    for (size_t k = 0; k < a.size(); ++k)
        for (int c = 0; c < 3; ++c) err += std::pow(a[k][c] - b[k][c], 2), ref += std::pow(a[k][c], 2);
    EXPECT_LT(std::sqrt(err / ref), 2e-2);
}

// With a GI lattice (--gi-stride 2), lattice pixels and pixels decoded on their own are the
// full-resolution predictions bit for bit, fewer queries are decoded, and interpolated pixels stay
// close to the full prediction (the tiny random model's E⁺ is smooth on the room's planes).
TEST(NeuralRenderer, GiLatticeMatchesFullDecodeWhereDecoded) {
    const Scene scene = load_scene("builtin:quad-light-room");
    const EmbreeAccel accel(scene);
    LtmModel model = tiny_model();
    const EncodedScene enc = encode_scene(model, accel, 1);
    const Camera cam = looking_at({1.f, 1.5f, 3.5f}, {2.5f, 0.8f, 1.5f}, 41);
    const GBuffer gb = render_gbuffer(accel, cam);
    const auto full = predict_gbuffer(model, enc, gb);
    GiUpsampleOptions opt;
    opt.stride = 2;
    int64_t n_decoded = 0;
    const auto up = predict_gbuffer_upsampled(model, enc, gb, cam, opt, nullptr, &n_decoded);
    ASSERT_EQ(up.size(), full.size());
    EXPECT_LT(n_decoded, int64_t(gb.n_hits()) / 2);
    EXPECT_GE(n_decoded, int64_t(lattice_hits(gb, 2).size()));
    for (size_t i : lattice_hits(gb, 2))
        for (int c = 0; c < 3; ++c) EXPECT_EQ(up[i][c], full[i][c]);
    double err = 0, norm = 0;
    for (size_t i = 0; i < full.size(); ++i)
        for (int c = 0; c < 3; ++c) err += std::pow(up[i][c] - full[i][c], 2), norm += std::pow(full[i][c], 2);
    EXPECT_LT(err / norm, 1e-2) << "relative squared error of the interpolation";
    std::cout << "gi stride 2: decoded " << n_decoded << " of " << gb.n_hits() << ", relative squared error " << err / norm << "\n";
    opt.stride = 1;
    EXPECT_EQ(predict_gbuffer_upsampled(model, enc, gb, cam, opt, nullptr, &n_decoded), full);
    EXPECT_EQ(n_decoded, int64_t(gb.n_hits()));
    // Coarse to fine at stride 1 (3 levels: a lattice of stride 4 first): every pixel is the full
    // prediction or a blend of corners that agree within 5 %, so fewer are decoded (the tiny random
    // model's E⁺ is rough: most are) and the image is closer to the full one than stride 2's.
    opt.levels = 3;
    int64_t n_levels = 0;
    const auto coarse = predict_gbuffer_upsampled(model, enc, gb, cam, opt, nullptr, &n_levels);
    EXPECT_LT(n_levels, int64_t(gb.n_hits()));
    EXPECT_GE(n_levels, int64_t(lattice_hits(gb, 4).size()));
    for (size_t i : lattice_hits(gb, 4))
        for (int c = 0; c < 3; ++c) EXPECT_EQ(coarse[i][c], full[i][c]);
    double err3 = 0;
    for (size_t i = 0; i < full.size(); ++i)
        for (int c = 0; c < 3; ++c) err3 += std::pow(coarse[i][c] - full[i][c], 2);
    EXPECT_LT(err3, err / 2) << "relative squared error of the coarse-to-fine lattice";
    std::cout << "gi stride 1, 3 levels: decoded " << n_levels << " of " << gb.n_hits() << ", relative squared error " << err3 / norm << "\n";
}

// The default direct light for constant-radiance emitters is the ratio estimator, bit for bit
// the same as render/direct_light's image for the same seed.
TEST(NeuralRenderer, AutomaticDirectLightIsTheRatioEstimator) {
    Room room;
    const Camera cam = Room::view(16);
    NeuralRenderOptions opt;
    opt.direct_spp = 2, opt.seed = 9;
    const NeuralRender r = render_neural(room.model, room.pt, cam, opt);
    EXPECT_EQ(r.direct, DirectEstimator::ratio);
    const Image want = direct_images_ratio(RatioDirectLight(room.accel, 9), render_gbuffer(room.accel, cam), 2).direct;
    EXPECT_EQ(r.image.direct.pixels, want.pixels);
    EXPECT_EQ(parse_direct_estimator("mis"), DirectEstimator::mis);
    EXPECT_THROW(parse_direct_estimator("fast"), Error);
}

// A scene in centimetres with z up predicts what its metric y-up twin predicts (issue #12): the
// pbrt reader turns it y-up, and the shipped model's normalisations divide out the unit (exact
// emission scale Φ/A, lengths in units of the point spacing ℓ, the enclosure filter's ray offset
// relative to the scene's extent) — so only float rounding in the resampled points remains.
TEST(NeuralRenderer, CentimetreZUpTwinPredictsWhatTheMetricSceneDoes) {
    const Scene metric = parse_pbrt(test::pbrt_text(cornell_box()), "metric.pbrt", ".");
    const Scene twin = parse_pbrt(test::pbrt_text(cornell_box(), 100.f, /*z_up=*/true), "twin.pbrt", ".");
    // Mean relative difference of E⁺ over the camera's pixels between the two scenes.
    const auto difference = [&](LtmModel &model) {
        std::vector<Vec3f> e[2];
        const Scene *scenes[2] = {&metric, &twin};
        for (int i = 0; i < 2; ++i) {
            const EmbreeAccel accel(*scenes[i]);
            Camera cam = scenes[i]->cameras[0];
            cam.width = cam.height = 24;
            e[i] = predict_gbuffer(model, encode_scene(model, accel, /*seed=*/1), render_gbuffer(accel, cam));
        }
        EXPECT_EQ(e[0].size(), e[1].size());
        EXPECT_GT(e[0].size(), 100u);
        double diff = 0, mean = 0;
        for (size_t k = 0; k < std::min(e[0].size(), e[1].size()); ++k)
            for (int c = 0; c < 3; ++c) diff += std::abs(e[1][k][c] - e[0][k][c]), mean += e[0][k][c];
        EXPECT_GT(mean, 0.0);
        return diff / mean;
    };
    LtmModel shipped = load_weights(test::source_path("models/ltm-cpu.safetensors"));
    shipped->eval();
    const double d = difference(shipped);
    std::cout << "cm z-up twin: mean relative E⁺ difference " << d << " (shipped model)\n";
    EXPECT_LT(d, 0.02);
    // The test can tell: a model without the physics normalisations (v0.3's configuration) sees
    // positions in the file's unit and moves.
    ModelConfig legacy = ModelConfig::from_file(test::source_path("configs/model/tiny.json"));
    legacy.physics = PhysicsConfig::legacy();
    torch::manual_seed(5);
    LtmModel old(legacy);
    {
        torch::NoGradGuard g;
        for (auto &p : old->parameters()) p.add_(torch::randn_like(p) * 0.2);
    }
    old->eval();
    EXPECT_GT(difference(old), 0.05);
}

// The prior's visibility by rays (--prior-rays, physics.prior_rays): it follows the scene under a
// change of unit and axes as the points' visibility does (rays are lifted relative to the points'
// spacing, the segments' ends trimmed relative to their length); it changes the answer (the test can
// tell it is used); and scene points without meshes (a record) are refused with a one-line error.
TEST(NeuralRenderer, PriorRaysFollowTheSceneAndNeedItsMeshes) {
    const Scene metric = parse_pbrt(test::pbrt_text(cornell_box()), "metric.pbrt", ".");
    const Scene twin = parse_pbrt(test::pbrt_text(cornell_box(), 100.f, /*z_up=*/true), "twin.pbrt", ".");
    LtmModel rays = load_weights(test::source_path("models/ltm-cpu.safetensors"));
    LtmModel points = load_weights(test::source_path("models/ltm-cpu.safetensors"));
    rays->eval(), points->eval();
    points->cfg.physics.prior_rays = false;   // the shipped model's visibility is by rays; the points' clusters here
    set_prior_rays(rays);
    EXPECT_TRUE(rays->cfg.physics.prior_rays);
    EXPECT_EQ(rays->cfg.physics.prior_theta, 0.5f);   // rays test the tree's terms
    set_prior_theta(points, 0.5);
    std::vector<Vec3f> e[3];
    const Scene *scenes[3] = {&metric, &twin, &metric};
    for (int i = 0; i < 3; ++i) {
        const EmbreeAccel accel(*scenes[i]);
        Camera cam = scenes[i]->cameras[0];
        cam.width = cam.height = 24;
        LtmModel &model = i < 2 ? rays : points;
        e[i] = predict_gbuffer(model, encode_scene(model, accel, /*seed=*/1), render_gbuffer(accel, cam));
    }
    ASSERT_EQ(e[0].size(), e[1].size());
    ASSERT_EQ(e[0].size(), e[2].size());
    double twin_diff = 0, ray_diff = 0, mean = 0;
    for (size_t k = 0; k < e[0].size(); ++k)
        for (int c = 0; c < 3; ++c)
            twin_diff += std::abs(e[1][k][c] - e[0][k][c]), ray_diff += std::abs(e[2][k][c] - e[0][k][c]), mean += e[0][k][c];
    EXPECT_GT(mean, 0.0);
    std::cout << "prior rays: cm z-up twin differs by " << twin_diff / mean << ", the points' visibility by " << ray_diff / mean << "\n";
    EXPECT_LT(twin_diff / mean, 0.02);
    EXPECT_GT(ray_diff / mean, 0.03);
    // Scene points alone (no meshes to trace): a one-line error, not an unoccluded prior.
    const EmbreeAccel accel(metric);
    const ScenePoints sp = sample_scene_points(accel, rays->cfg.scene_points, 1);
    const auto pts = point_tensor(sp.points);
    EXPECT_THROW(rays->encode(pts, rays->scene_geometry(pts)), Error);
}

// Conductors with a directional head (paper Fig. 11): direct light by NEE + BSDF sampling, the
// indirect part from the head's L̂⁺ in GGX-sampled directions. Diffuse pixels are untouched, the
// conductor pixels are finite and non-negative, and the whole image is linear in emission.
TEST(NeuralRenderer, ConductorsAreShadedWithTheDirectionalHead) {
    const Scene scene = room_with_metal();
    ModelConfig cfg = ModelConfig::from_file(test::source_path("configs/model/tiny.json"));
    DirectionalConfig d;
    d.dim = 16, d.groups = 4, d.n_layers = 1, d.direction_frequencies = 2, d.bin_resolution = 4;
    LtmModel plain = tiny_model();
    cfg.directional = d;
    torch::manual_seed(5);
    LtmModel headed(cfg);
    {
        // The same encoder and irradiance decoder as `plain`, a random (non-uniform) head.
        torch::NoGradGuard g;
        const auto src = plain->named_parameters();
        for (auto &p : headed->named_parameters()) {
            if (src.contains(p.key())) p.value().copy_(src[p.key()]);
            else p.value().normal_(0.0, 0.3);
        }
        headed->eval();
    }
    const Camera cam = looking_at({1.f, 1.5f, 3.5f}, {2.5f, 0.3f, 1.5f}, 24);
    NeuralRenderOptions opt;
    opt.direct_spp = 4, opt.seed = 2, opt.direct = DirectEstimator::mis, opt.glossy_samples = 8;
    auto render = [&](const Scene &s, LtmModel &m, GlossyShading g) {
        const EmbreeAccel accel(s);
        const PathTracer pt(accel, PathTracerConfig{});
        NeuralRenderOptions o = opt;
        o.glossy = g;
        return render_neural(m, pt, cam, o);
    };
    const NeuralRender a = render(scene, plain, GlossyShading::diffuse), b = render(scene, headed, GlossyShading::head);
    ASSERT_GT(b.n_conductor, 10);
    EXPECT_EQ(a.glossy, GlossyShading::diffuse);
    EXPECT_EQ(b.glossy, GlossyShading::head);
    // Weights without a head cannot shade through one: a one-line error, not a diffuse image.
    EXPECT_THROW(render(scene, plain, GlossyShading::head), Error);
    const EmbreeAccel accel(scene);
    const GBuffer gb = render_gbuffer(accel, cam);
    int changed = 0;
    for (size_t k = 0; k < gb.n_hits(); ++k) {
        const size_t i = size_t(gb.hit_pixels[k]);
        const Vec3f ca = a.image.color.pixels[i], cb = b.image.color.pixels[i];
        if (gb.diffuse[k]) {
            EXPECT_EQ(ca, cb) << "diffuse pixel " << i;
        } else {
            EXPECT_TRUE(std::isfinite(cb.x) && std::isfinite(cb.y) && std::isfinite(cb.z) && cb.x >= 0.f && cb.y >= 0.f && cb.z >= 0.f);
            changed += !(ca == cb);
        }
    }
    EXPECT_GT(changed, b.n_conductor / 2);
    // Emission ×4: the image ×4 (direct light and the head's L̂⁺ are both linear in emission).
    Scene bright = scene;
    for (auto &m : bright.materials) m.emission.color_a = m.emission.color_a * 4.f;
    const NeuralRender c = render(bright, headed, GlossyShading::head);
    for (size_t k = 0; k < gb.n_hits(); ++k) {
        const size_t i = size_t(gb.hit_pixels[k]);
        for (int ch = 0; ch < 3; ++ch)
            EXPECT_NEAR(c.image.color.pixels[i][ch], 4.f * b.image.color.pixels[i][ch], 1e-4f * std::max(1.f, 4.f * b.image.color.pixels[i][ch]));
    }
}

// Conductors by one traced bounce (GlossyShading::trace): each GGX sample's hit y contributes the
// radiance leaving it, ρ/π·(E_direct(y) + Ê⁺(y)). With the decoder's output layer silenced (Ê⁺ ≈ 0)
// that is exactly what a path tracer with two scattering events computes at a conductor pixel
// (direct light at the conductor, then one bounce and direct light at y), so the two agree in the
// mean over the conductor pixels within their noise; the render is linear in emission, needs no
// directional head, and leaves diffuse pixels as they were.
TEST(NeuralRenderer, TracedConductorsAreTwoBouncePathTracingWhenThereIsNoIndirectLight) {
    Scene scene = room_with_metal();
    LtmModel model = tiny_model();
    {
        torch::NoGradGuard g;
        for (auto &p : model->named_parameters())
            if (p.key() == "decoder.out.3.weight") p.value().zero_();
            else if (p.key() == "decoder.out.3.bias") p.value().fill_(-60.f);   // z = softplus(−60) ≈ 1e-26: Ê⁺ ≈ 0
        model->eval();
    }
    const Camera cam = looking_at({1.f, 1.5f, 3.5f}, {2.5f, 0.3f, 1.5f}, 24);
    PathTracerConfig cfg;
    cfg.max_depth = 1;   // a conductor seen from a conductor: one more scattering event, as the reference
    auto render = [&](const Scene &s, GlossyShading glossy) {
        const EmbreeAccel accel(s);
        const PathTracer pt(accel, cfg);
        NeuralRenderOptions opt;
        opt.direct_spp = 256, opt.seed = 3, opt.direct = DirectEstimator::mis, opt.glossy_samples = 256, opt.glossy = glossy;
        return render_neural(model, pt, cam, opt);
    };
    const NeuralRender traced = render(scene, GlossyShading::trace), diffuse = render(scene, GlossyShading::diffuse);
    EXPECT_EQ(traced.glossy, GlossyShading::trace);
    const EmbreeAccel accel(scene);
    const PathTracer pt(accel, cfg);
    const GBuffer gb = render_gbuffer(accel, cam);
    double sum_diff = 0, sum_sq = 0, sum_ref = 0, sum_direct_only = 0;
    int n = 0;
    for (size_t k = 0; k < gb.n_hits(); ++k) {
        const size_t i = size_t(gb.hit_pixels[k]);
        ASSERT_LT(max_component(traced.image.irradiance.pixels[i]), 1e-12f) << "the silenced decoder predicts Ê⁺ ≈ 0";
        if (gb.diffuse[k]) {
            EXPECT_EQ(traced.image.color.pixels[i], diffuse.image.color.pixels[i]) << "diffuse pixel " << i;
            continue;
        }
        const Ray ray{cam.eye, cam.ray_direction(float(i % size_t(cam.width)) + 0.5f, float(i / size_t(cam.width)) + 0.5f)};
        const SurfaceInteraction si = make_interaction(scene, ray, *accel.intersect(ray));
        Vec3f ref(0.f);
        constexpr int spp = 2048;
        for (int s = 0; s < spp; ++s) {
            Pcg32 rng(pt.stream_key(uint64_t(i), uint64_t(s)));
            ref += pt.reflected_radiance(si, -ray.d, 2, rng);
        }
        ref = ref / float(spp) + si.emitted();
        Vec3f one(0.f);   // one scattering event: the conductor's direct light alone
        for (int s = 0; s < 256; ++s) {
            Pcg32 rng(pt.stream_key(uint64_t(i) | 1ull << 40, uint64_t(s)));
            one += pt.reflected_radiance(si, -ray.d, 1, rng);
        }
        sum_direct_only += luminance(one / 256.f + si.emitted());
        const double d = double(luminance(traced.image.color.pixels[i])) - double(luminance(ref));
        sum_diff += d, sum_sq += d * d, sum_ref += luminance(ref), ++n;
    }
    ASSERT_GT(n, 40);
    const double mean = sum_diff / n, sd = std::sqrt(std::max(0.0, sum_sq / n - mean * mean));
    EXPECT_LT(std::abs(mean), 4.0 * sd / std::sqrt(double(n)) + 1e-3 * sum_ref / n) << "mean luminance difference " << mean;
    // The agreement tests the bounce: it is a large share of the conductors' radiance here.
    EXPECT_GT(sum_ref - sum_direct_only, 0.3 * sum_ref) << "bounce share " << (sum_ref - sum_direct_only) / sum_ref;
    // And the traced path ran: shading the conductors as diffuse gives another image.
    double traced_sum = 0, diffuse_like = 0;
    for (size_t k = 0; k < gb.n_hits(); ++k)
        if (!gb.diffuse[k]) {
            const size_t i = size_t(gb.hit_pixels[k]);
            traced_sum += luminance(traced.image.color.pixels[i]);
            diffuse_like += luminance(diffuse.image.color.pixels[i]);
        }
    EXPECT_GT(std::abs(traced_sum - diffuse_like), 0.05 * traced_sum);
    // Linear in emission: emission ×4, the conductor pixels ×4.
    Scene bright = scene;
    for (auto &m : bright.materials) m.emission.color_a = m.emission.color_a * 4.f;
    const NeuralRender c = render(bright, GlossyShading::trace);
    for (size_t k = 0; k < gb.n_hits(); ++k) {
        const size_t i = size_t(gb.hit_pixels[k]);
        for (int ch = 0; ch < 3; ++ch)
            EXPECT_NEAR(c.image.color.pixels[i][ch], 4.f * traced.image.color.pixels[i][ch],
                        1e-4f * std::max(1.f, 4.f * traced.image.color.pixels[i][ch]));
    }
}

// Conductors' bounce hits with Ê⁺ interpolated from the scene points (BounceIrradiance::nodes, the
// default) against Ê⁺ decoded at each hit: diffuse pixels are the same bits, conductor pixels
// differ only in that term, by a few per cent of their radiance, and the interpolation did run.
TEST(NeuralRenderer, BounceIrradianceFromTheScenePointsIsCloseToDecodingEachHit) {
    Scene scene = room_with_metal();
    LtmModel model = tiny_model();
    const EmbreeAccel accel(scene);
    const PathTracer pt(accel, PathTracerConfig{});
    const Camera cam = looking_at({1.f, 1.5f, 3.5f}, {2.5f, 0.3f, 1.5f}, 24);
    auto render = [&](BounceIrradiance bounce) {
        NeuralRenderOptions opt;
        opt.direct_spp = 16, opt.seed = 3, opt.direct = DirectEstimator::mis, opt.glossy_samples = 16, opt.glossy = GlossyShading::trace;
        opt.bounce = bounce;
        return render_neural(model, pt, cam, opt);
    };
    const NeuralRender nodes = render(BounceIrradiance::nodes), decoded = render(BounceIrradiance::decode);
    const GBuffer gb = render_gbuffer(accel, cam);
    double sum_nodes = 0, sum_decoded = 0, sum_sq = 0;
    int n = 0, differ = 0;
    for (size_t k = 0; k < gb.n_hits(); ++k) {
        const size_t i = size_t(gb.hit_pixels[k]);
        const Vec3f a = nodes.image.color.pixels[i], b = decoded.image.color.pixels[i];
        if (gb.diffuse[k]) {
            EXPECT_EQ(a, b) << "diffuse pixel " << i;
            continue;
        }
        ASSERT_TRUE(is_finite(a) && a.x >= 0.f && a.y >= 0.f && a.z >= 0.f) << a;
        sum_nodes += luminance(a), sum_decoded += luminance(b), ++n, differ += a != b;
        sum_sq += (double(luminance(a)) - luminance(b)) * (double(luminance(a)) - luminance(b));
    }
    ASSERT_GT(n, 40);
    EXPECT_GT(differ, n / 4) << "the interpolated Ê⁺ reached the conductor pixels";
    EXPECT_LT(std::abs(sum_nodes - sum_decoded), 0.03 * sum_decoded) << sum_nodes << " vs " << sum_decoded;
    EXPECT_LT(std::sqrt(sum_sq / n), 0.1 * sum_decoded / n) << "per-pixel RMS difference";
}
