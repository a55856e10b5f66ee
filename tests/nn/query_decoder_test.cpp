// query_decoder_test.cpp: vector attention with κ = 1, finite-difference gradients, and
// batched = one-by-one decoding.
#include <gtest/gtest.h>
#include <torch/torch.h>

#include "ltm/nn/query_decoder.h"

using namespace ltm;

// With a single neighbour the softmax weight is 1: the output is G^v + P.
TEST(VectorCrossAttention, SingleNeighbourReturnsValuePlusPosition) {
    torch::manual_seed(3);
    VectorCrossAttention attn(/*dim=*/16, /*latent_dim=*/24, /*groups=*/4);
    const auto latents = torch::randn({10, 24});
    const auto [k, v] = attn->project_latents(latents);
    const auto h = torch::randn({7, 16});
    const auto idx = torch::randint(0, 10, {7, 1}, torch::kInt64);
    const auto pos = torch::randn({7, 1, 16});
    const auto out = attn->forward(h, k, v, idx, pos);
    const auto expect = v.index_select(0, idx.view(-1)) + pos.view({7, 16});
    EXPECT_TRUE(torch::allclose(out, expect, 1e-5, 1e-6));
}

// Autograd matches central finite differences (double precision) for the latents and the query.
TEST(QueryDecoder, GradientsMatchFiniteDifferences) {
    torch::manual_seed(4);
    DecoderConfig cfg;
    cfg.dim = 8, cfg.groups = 2, cfg.n_layers = 2, cfg.n_neighbors = 4;
    QueryDecoder dec(cfg, /*latent_dim=*/6);
    dec->to(torch::kFloat64);
    auto latents = torch::randn({12, 6}, torch::kFloat64).requires_grad_(true);
    const auto anchors = torch::randn({12, 3}, torch::kFloat64);
    auto query = torch::randn({5, 9}, torch::kFloat64).requires_grad_(true);
    const auto idx = torch::randint(0, 12, {5, 4}, torch::kInt64);
    const auto f = [&] { return dec->forward(query, latents, anchors, idx).pow(2).sum(); };
    f().backward();
    const auto g_lat = latents.grad().clone(), g_q = query.grad().clone();
    torch::NoGradGuard no_grad;
    const double h = 1e-6;
    for (auto [t, g] : {std::pair{latents, g_lat}, std::pair{query, g_q}}) {
        for (int64_t i = 0; i < std::min<int64_t>(t.numel(), 20); ++i) {
            const double orig = t.view(-1)[i].item<double>();
            t.view(-1)[i] = orig + h;
            const double up = f().item<double>();
            t.view(-1)[i] = orig - h;
            const double down = f().item<double>();
            t.view(-1)[i] = orig;
            EXPECT_NEAR(g.view(-1)[i].item<double>(), (up - down) / (2 * h), 1e-5 * (1.0 + std::abs((up - down) / (2 * h))));
        }
    }
}

TEST(QueryDecoder, BatchedEqualsOneByOne) {
    torch::manual_seed(5);
    for (const char *type : {"attention", "knn-mean"}) {
        DecoderConfig cfg;
        cfg.type = type;
        cfg.dim = 16, cfg.groups = 4, cfg.n_neighbors = 5;
        QueryDecoder dec(cfg, 8);
        const auto latents = torch::randn({20, 8}), anchors = torch::randn({20, 3});
        const auto q = torch::randn({9, 9});
        const auto idx = torch::randint(0, 20, {9, 5}, torch::kInt64);
        const auto all = dec->forward(q, latents, anchors, idx);
        EXPECT_TRUE((all >= 0).all().item<bool>()) << "z = log1p(E+) must be >= 0";
        for (int64_t i = 0; i < 9; ++i)
            EXPECT_TRUE(torch::allclose(dec->forward(q.slice(0, i, i + 1), latents, anchors, idx.slice(0, i, i + 1)),
                                        all.slice(0, i, i + 1), 1e-5, 1e-6))
                << type << " query " << i;
    }
}

TEST(QueryDecoder, WrongShapesAreErrorsNamingThem) {
    QueryDecoder dec(DecoderConfig{}, 8);
    try {
        dec->forward(torch::randn({4, 8}), torch::randn({40, 8}), torch::randn({40, 3}), torch::zeros({4, 32}, torch::kInt64));
        FAIL() << "expected an error";
    } catch (const c10::Error &e) {
        EXPECT_NE(std::string(e.what()).find("[N, 9]"), std::string::npos) << e.what();
    }
}
