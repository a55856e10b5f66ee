// directional_head_test.cpp: the directional radiance head (issue #11 item 2): its config, its
// uniform start (L_in = prior / π, whose cosine integral is the prior), the exact symmetries it
// inherits from the irradiance head's frame, its weights, and its errors.
#include <cmath>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "ltm/core/error.h"
#include "ltm/core/sampling.h"
#include "ltm/nn/checkpoint.h"
#include "ltm/nn/ltm_model.h"
#include "test_util.h"
#include "tiny_scene_fixture.h"

using namespace ltm;

namespace {
struct Fixture : test::TinySceneFixture {
    Fixture() : TinySceneFixture(64) {
        DirectionalConfig d;
        d.dim = 16, d.groups = 4, d.n_layers = 1, d.direction_frequencies = 3, d.bin_resolution = 4;
        cfg.directional = d;
    }
    // Directions in each query's hemisphere: n tilted towards a fixed vector, normalised.
    torch::Tensor directions(double tilt) const {
        const auto n = qp.slice(1, 3, 6);
        const auto t = torch::tensor({0.3f, -0.5f, 0.8f}).expand_as(n);
        const auto d = n + tilt * (t - (t * n).sum(1, true) * n);
        return d / d.norm(2, 1, true);
    }
};

LtmModel random_head(const ModelConfig &cfg, uint64_t seed) { return test::model_with_random_part(cfg, seed, "directional"); }

torch::Tensor radiance(LtmModel &m, const torch::Tensor &sp, const torch::Tensor &qp, const torch::Tensor &d) {
    return m->predict_radiance(qp, d, m->encode(sp, m->scene_geometry(sp)));
}

using test::scaled;
}  // namespace

TEST(DirectionalHead, ConfigRoundTripsAndIsChecked) {
    Fixture f;
    const ModelConfig back = ModelConfig::from_json(f.cfg.to_json(), "t");
    ASSERT_TRUE(back.directional.has_value());
    EXPECT_EQ(back.directional->bin_resolution, 4);
    EXPECT_EQ(back.to_json().dump(), f.cfg.to_json().dump());
    // Irradiance-only configs keep their exact JSON (no "directional" key): old weights still load.
    ModelConfig plain = f.cfg;
    plain.directional.reset();
    EXPECT_FALSE(plain.to_json().contains("directional"));
    Json j = f.cfg.to_json();
    j["directional"]["groups"] = 5;
    EXPECT_THROW(ModelConfig::from_json(j, "t"), Error);
    j["directional"]["groups"] = 4;
    j["directional"]["bins"] = 32;   // unknown key
    EXPECT_THROW(ModelConfig::from_json(j, "t"), Error);
}

// A fresh head predicts the uniform radiance whose cosine integral is the irradiance head's
// prior: L_in = output_scale / π in every direction.
TEST(DirectionalHead, StartsAsTheUniformRadianceOfThePrior) {
    Fixture f;
    torch::manual_seed(1);
    LtmModel m(f.cfg);
    m->eval();
    const SceneLatents lat = m->encode(f.sp, m->scene_geometry(f.sp));
    const auto scale = output_scale(f.qp, lat.norm).expand({f.qp.size(0), 3});
    for (double tilt : {0.0, 0.7, 3.0}) {
        const auto l = m->predict_radiance(f.qp, f.directions(tilt), lat);
        EXPECT_TRUE(torch::allclose(l * k_pi, scale, 1e-5, 1e-7)) << tilt;
    }
}

// The head lives in the irradiance head's frame, so it inherits its exact symmetries: L_in is
// linear in emission (bit-exact for powers of two) and independent of the unit of length.
TEST(DirectionalHead, LinearInEmissionAndBlindToTheUnitOfLength) {
    Fixture f;
    LtmModel m = random_head(f.cfg, 7);
    const auto d = f.directions(0.6);
    const auto l = radiance(m, f.sp, f.qp, d);
    ASSERT_GT(l.abs().mean().item<double>(), 0.0);
    ASSERT_GT((l - l.mean(0)).abs().mean().item<double>(), 1e-3 * l.abs().mean().item<double>());   // not uniform
    for (double k : {0.25, 4.0}) EXPECT_TRUE(torch::equal(radiance(m, scaled(f.sp, 9, 12, k), f.qp, d), l * k)) << k;
    for (double s : {0.5, 2.0, 1024.0}) EXPECT_TRUE(torch::equal(radiance(m, scaled(f.sp, 0, 3, s), scaled(f.qp, 0, 3, s), d), l)) << s;
}

TEST(DirectionalHead, WeightsRoundTripAndIrradianceWeightsStillLoad) {
    Fixture f;
    test::TempDir dir;
    LtmModel m = random_head(f.cfg, 9);
    save_weights(dir.path("w.safetensors"), m);
    LtmModel back = load_weights(dir.path("w.safetensors"));
    ASSERT_TRUE(back->directional);
    const auto d = f.directions(0.3);
    EXPECT_TRUE(torch::equal(radiance(back, f.sp, f.qp, d), radiance(m, f.sp, f.qp, d)));
    // Irradiance-only weights: the same E⁺, no head, and asking for L_in is a one-line error.
    ModelConfig plain = f.cfg;
    plain.directional.reset();
    torch::manual_seed(9);
    LtmModel p(plain);
    save_weights(dir.path("p.safetensors"), p);
    LtmModel pb = load_weights(dir.path("p.safetensors"));
    EXPECT_FALSE(pb->directional);
    try {
        radiance(pb, f.sp, f.qp, d);
        ADD_FAILURE() << "no error";
    } catch (const Error &e) {
        EXPECT_NE(std::string(e.what()).find("no directional head"), std::string::npos) << e.what();
    }
}

// Directions must be unit vectors in the query's hemisphere: anything else is an error, never NaN.
TEST(DirectionalHead, DirectionsBelowTheSurfaceOrNotUnitAreErrors) {
    Fixture f;
    LtmModel m = random_head(f.cfg, 11);
    const SceneLatents lat = m->encode(f.sp, m->scene_geometry(f.sp));
    const auto n = f.qp.slice(1, 3, 6);
    auto expect_error = [&](const torch::Tensor &d, const std::string &what) {
        try {
            m->predict_radiance(f.qp, d, lat);
            ADD_FAILURE() << "no error for " << what;
        } catch (const Error &e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    expect_error(-n, "below the surface");
    expect_error(n * 2.0, "not a unit vector");
    auto nan = n.clone();
    nan[3][1] = NAN;
    expect_error(nan, "NaN");
    EXPECT_THROW(m->predict_radiance(f.qp, n.slice(0, 0, 5), lat), std::exception);   // wrong shape
    // Grazing directions (n·ω = 0) are in the hemisphere: finite.
    const auto grazing = f.directions(1e4);
    EXPECT_TRUE(torch::isfinite(m->predict_radiance(f.qp, grazing, lat)).all().item<bool>());
}

// With directional.prior_cells = R (and the transport prior) a fresh head predicts the prior's
// radiance split over R×R cells: its cosine integral over a hemisphere's cell centres is the
// irradiance prior, it is not uniform, and it keeps the exact symmetries.
TEST(DirectionalHead, StartsAsTheDirectionalTransportPrior) {
    Fixture f;
    f.cfg.physics = ModelConfig::from_file(test::source_path("configs/model/cpu-tp.json")).physics;
    const int R = 4;
    f.cfg.directional->prior_cells = R;
    const ModelConfig back = ModelConfig::from_json(f.cfg.to_json(), "t");
    EXPECT_EQ(back.directional->prior_cells, R);
    torch::manual_seed(1);
    LtmModel m(f.cfg);
    m->eval();
    const SceneLatents lat = m->encode(f.sp, m->scene_geometry(f.sp));
    // Every query's R² cell-centre directions, rows grouped by query (as hemisphere_rows).
    const int64_t nq = f.qp.size(0);
    std::vector<float> dirs;
    for (int64_t i = 0; i < nq; ++i) {
        const Frame frame(Vec3f(f.qp[i][3].item<float>(), f.qp[i][4].item<float>(), f.qp[i][5].item<float>()));
        for (int b = 0; b < R * R; ++b) {
            const Vec3f w = normalize(frame.to_world(sample_cosine_hemisphere({(float(b / R) + 0.5f) / R, (float(b % R) + 0.5f) / R})));
            dirs.insert(dirs.end(), {w.x, w.y, w.z});
        }
    }
    const auto q = f.qp.repeat_interleave(R * R, 0);
    const auto d = torch::from_blob(dirs.data(), {nq * R * R, 3}, torch::kFloat32).clone();
    const auto l = m->predict_radiance(q, d, lat);
    const auto e = output_scale(f.qp, lat.norm);
    const auto integral = l.view({nq, R * R, 3}).sum(1) * (k_pi / double(R * R));
    // Cells the prior leaves dark are floored (10⁻³ of the scene's scale): compare where it is lit.
    const auto lit = (e > 0.01 * e.mean()).all(1);
    ASSERT_GT(lit.sum().item<int64_t>(), nq / 2);
    EXPECT_TRUE(torch::allclose(integral.index({lit}), e.index({lit}), 2e-3, 1e-6));
    const auto per_query = l.view({nq, R * R, 3});
    EXPECT_GT((per_query - per_query.mean(1, true)).abs().mean().item<double>(), 0.1 * per_query.abs().mean().item<double>())
        << "the directional prior is not the uniform one";
    // Exact symmetries: emission ×k, the unit of length.
    auto predict = [&](const torch::Tensor &sp, const torch::Tensor &qp) { return m->predict_radiance(qp, d, m->encode(sp, m->scene_geometry(sp))); };
    EXPECT_TRUE(torch::equal(predict(scaled(f.sp, 9, 12, 4.0), q), l * 4.0));
    EXPECT_TRUE(torch::allclose(predict(scaled(f.sp, 0, 3, 8.0), scaled(q, 0, 3, 8.0)), l, 1e-4, 1e-7));
    // Only the transport prior has directions to split.
    Json j = f.cfg.to_json();
    j["physics"]["prior_field"] = "flat";
    j["physics"].erase("prior_visibility"), j["physics"].erase("prior_discs"), j["physics"].erase("prior_balance");
    j["physics"].erase("prior_blend"), j["physics"].erase("prior_patches"), j["physics"].erase("prior_nodes");
    EXPECT_THROW(ModelConfig::from_json(j, "t"), Error);
}

// A model at its prior with a directional head defers its encoder (the irradiance never reads the
// features): encode() leaves them undefined, the first radiance query runs the encoder once, and the
// radiance is the unfolded model's exactly.
TEST(DirectionalHead, AtThePriorTheEncoderRunsOnlyWhenTheHeadAsks) {
    Fixture f;
    LtmModel m = random_head(f.cfg, 3);
    m->decoder->start_at_prior();
    ASSERT_TRUE(m->decoder->at_prior());
    torch::NoGradGuard no_grad;
    const SceneGeometry g = m->scene_geometry(f.sp);
    const SceneLatents folded = m->encode(f.sp, g);
    EXPECT_FALSE(folded.features.defined()) << "deferred";
    ASSERT_TRUE(folded.deferred);
    const auto e = m->predict_irradiance(f.qp, folded);
    EXPECT_FALSE(folded.deferred->features.defined()) << "the irradiance does not run the encoder";
    const auto d = f.directions(0.5);
    const auto lazy = m->predict_radiance(f.qp, d, folded);
    EXPECT_TRUE(folded.deferred->features.defined());
    m->fold_prior = false;
    const SceneLatents full = m->encode(f.sp, g);
    ASSERT_TRUE(full.features.defined());
    EXPECT_TRUE(torch::equal(m->features(folded), full.features));
    EXPECT_TRUE(torch::allclose(m->predict_radiance(f.qp, d, full), lazy, 1e-6, 0.0));
    EXPECT_TRUE(torch::allclose(m->predict_irradiance(f.qp, full), e, 1e-6, 0.0));
}
