// directional_eval_test.cpp: `ltm eval-directional` on tiny records: a head at its uniform start
// integrates exactly to an irradiance head at its prior, SH errors never grow with the degree,
// and models or records that do not fit are refused with the reason.
#include <filesystem>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/data/dataset.h"
#include "ltm/eval/directional_eval.h"
#include "test_util.h"

using namespace ltm;

namespace {
std::string build_records(const std::string &d, int bin_resolution) {
    BuildOptions opt;
    opt.preset = DataPreset::from_file(test::source_path("configs/data/ci.json"));
    opt.preset.query_points = 32, opt.preset.spp = 16, opt.preset.bin_resolution = bin_resolution, opt.preset.bin_spp = 2;
    opt.preset.bin_radiance = "indirect";
    opt.seeds = {31};
    opt.out_dir = d;
    set_log_level(LogLevel::quiet);
    build_dataset(opt);
    return d;
}
ModelConfig tiny_with_head() {
    ModelConfig mc = ModelConfig::from_file(test::source_path("configs/model/tiny.json"));
    DirectionalConfig d;
    d.dim = 16, d.groups = 4, d.n_layers = 1, d.direction_frequencies = 2, d.bin_resolution = 4;
    mc.directional = d;
    return mc;
}
}  // namespace

TEST(DirectionalEval, UniformStartIntegratesToThePriorAndShErrorsFall) {
    test::TempDir tmp;
    const std::string dir = build_records(tmp.path("data"), 4);
    torch::manual_seed(2);
    LtmModel m(tiny_with_head());
    m->decoder->start_at_prior();   // Ê⁺ = prior; the fresh head's L = prior / π, so ∫ L cos = Ê⁺
    DirectionalEvalOptions opt;
    opt.points_per_record = 8, opt.l_max = 3, opt.tiles = 2;
    const DirectionalEvalResult r = evaluate_directional(m, dir, opt);
    EXPECT_EQ(r.records, 1);
    EXPECT_EQ(r.points, 8);
    EXPECT_LT(r.hemisphere_gap_vs_model, 1e-5);
    // ... and the head is then exactly the uniform radiance of the irradiance head: the same error.
    EXPECT_NEAR(r.head, r.uniform_model, 1e-5 * r.uniform_model);
    EXPECT_TRUE(std::isfinite(r.head) && std::isfinite(r.uniform) && std::isfinite(r.hemisphere_gap_vs_ref));
    ASSERT_EQ(r.sh.size(), 4u);
    for (size_t l = 1; l < r.sh.size(); ++l) EXPECT_LE(r.sh[l], r.sh[l - 1] * (1 + 1e-9)) << l;
    for (int n : r.head_beats_sh) EXPECT_LE(n, r.points);
    EXPECT_EQ(r.tiles.width, 4 * (4 * 4 + 2) - 2);
    EXPECT_EQ(r.tiles.height, 2 * (4 * 4 + 2) - 2);
    EXPECT_NE(r.markdown().find("SH best fit"), std::string::npos);
    // A head of another resolution, and a model without a head, are refused with the reason.
    ModelConfig other = tiny_with_head();
    other.directional->bin_resolution = 8;
    LtmModel m8(other);
    EXPECT_THROW(evaluate_directional(m8, dir, opt), Error);
    ModelConfig plain = tiny_with_head();
    plain.directional.reset();
    LtmModel p(plain);
    try {
        evaluate_directional(p, dir, opt);
        ADD_FAILURE() << "no error";
    } catch (const Error &e) {
        EXPECT_NE(std::string(e.what()).find("no directional head"), std::string::npos) << e.what();
    }
}

// The traced-bounce row (infer/traced_bounce.h) regenerates the record's scene and traces each
// bin: it resolves where the light comes from, so it is closer to the reference bins than the
// uniform radiance with the reference's own cosine integral; and it leaves every other row as it was.
TEST(DirectionalEval, TracedBounceRowResolvesDirections) {
    test::TempDir tmp;
    const std::string dir = build_records(tmp.path("data"), 4);
    torch::manual_seed(2);
    LtmModel m(tiny_with_head());
    m->decoder->start_at_prior();
    DirectionalEvalOptions opt;
    opt.points_per_record = 8, opt.l_max = 3, opt.tiles = 0;
    const DirectionalEvalResult plain = evaluate_directional(m, dir, opt);
    EXPECT_LT(plain.traced, 0.0) << "no row unless asked";
    opt.traced_samples = 16;
    const DirectionalEvalResult r = evaluate_directional(m, dir, opt);
    ASSERT_TRUE(std::isfinite(r.traced));
    EXPECT_GE(r.traced, 0.0);
    EXPECT_LT(r.traced, 0.8 * r.uniform) << "traced " << r.traced << ", uniform " << r.uniform;
    EXPECT_EQ(r.head, plain.head);
    EXPECT_EQ(r.sh, plain.sh);
    ASSERT_EQ(r.traced_beats_sh.size(), 4u);
    for (int n : r.traced_beats_sh) EXPECT_LE(n, r.points);
    EXPECT_NE(r.markdown().find("one traced bounce"), std::string::npos);
    opt.traced_samples = -1;
    EXPECT_THROW(evaluate_directional(m, dir, opt), Error);
}
