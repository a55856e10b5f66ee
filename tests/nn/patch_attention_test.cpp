// patch_attention_test.cpp: pad/unpad arithmetic (notes §7.2) and serialized patch attention
// against plain multi-head attention written out in the test (notes §7.3).
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <set>

#include "ltm/nn/patch_attention.h"

using namespace ltm;

namespace {

std::vector<int64_t> to_vector(const torch::Tensor &t) {
    const auto c = t.to(torch::kCPU).contiguous();
    return std::vector<int64_t>(c.data_ptr<int64_t>(), c.data_ptr<int64_t>() + c.numel());
}

// Invariants for a batch of scenes: own slot holds itself, every patch has min(n, K) distinct
// tokens of one scene, padded length = Σ n_pad.
void check_layout(const std::vector<int64_t> &counts, int64_t K) {
    const PatchLayout layout = patch_layout(counts, K);
    const auto pad = to_vector(layout.pad), unpad = to_vector(layout.unpad);
    int64_t n_total = 0, n_pad_total = 0;
    std::vector<int64_t> scene_of;  // sorted position -> scene
    for (size_t i = 0; i < counts.size(); ++i) {
        n_total += counts[i];
        n_pad_total += counts[i] > K ? (counts[i] + K - 1) / K * K : counts[i];
        scene_of.insert(scene_of.end(), size_t(counts[i]), int64_t(i));
    }
    ASSERT_EQ(int64_t(unpad.size()), n_total);
    ASSERT_EQ(int64_t(pad.size()), n_pad_total);
    for (int64_t t = 0; t < n_total; ++t) ASSERT_EQ(pad[size_t(unpad[size_t(t)])], t);
    const auto &cu = layout.cu_seqlens;
    ASSERT_EQ(cu.back(), n_pad_total);
    for (size_t j = 0; j + 1 < cu.size(); ++j) {
        std::set<int64_t> tokens(pad.begin() + cu[j], pad.begin() + cu[j + 1]);
        const int64_t len = cu[j + 1] - cu[j];
        ASSERT_EQ(int64_t(tokens.size()), len) << "duplicate token in patch " << j;
        const int64_t scene = scene_of[size_t(*tokens.begin())];
        ASSERT_EQ(scene_of[size_t(*tokens.rbegin())], scene) << "patch " << j << " spans scenes";
        ASSERT_EQ(len, std::min(counts[size_t(scene)], K));
    }
}

}  // namespace

TEST(PatchLayout, MatchesTheNotesExample) {
    const PatchLayout layout = patch_layout({10}, 4);
    EXPECT_EQ(to_vector(layout.pad), (std::vector<int64_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 6, 7}));
    EXPECT_EQ(to_vector(layout.unpad), (std::vector<int64_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
    EXPECT_EQ(layout.cu_seqlens, (std::vector<int64_t>{0, 4, 8, 12}));
}

TEST(PatchLayout, InvariantsHoldForSizesAroundThePatchSize) {
    const int64_t K = 8;
    for (int64_t n : {int64_t(1), K - 1, K, K + 1, 2 * K, 2 * K + 3}) {
        SCOPED_TRACE("n = " + std::to_string(n));
        check_layout({n}, K);
    }
}

// A small scene forms one short patch and does not shrink the others' patches (pitfall 6).
TEST(PatchLayout, MultiSceneBatchKeepsScenesApart) {
    check_layout({10, 3, 8, 17, 1, 4}, 4);
    const PatchLayout layout = patch_layout({10, 3}, 4);
    EXPECT_EQ(to_vector(layout.pad),
              (std::vector<int64_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 6, 7, 10, 11, 12}));
    EXPECT_EQ(to_vector(layout.unpad),
              (std::vector<int64_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 12, 13, 14}));
}

namespace {

// Plain multi-head self-attention over all n tokens with the module's own weights.
//   x [n, C] -> [n, C]
torch::Tensor full_attention_reference(SerializedAttention &attn, const torch::Tensor &x) {
    const int64_t C = attn->channels, H = attn->n_heads, d = C / H;
    const auto qkv = attn->qkv->forward(x);
    std::vector<torch::Tensor> heads;
    for (int64_t h = 0; h < H; ++h) {
        const auto q = qkv.slice(1, h * d, (h + 1) * d);
        const auto k = qkv.slice(1, C + h * d, C + (h + 1) * d);
        const auto v = qkv.slice(1, 2 * C + h * d, 2 * C + (h + 1) * d);
        const auto logits = torch::matmul(q, k.t()) / std::sqrt(double(d));
        heads.push_back(torch::matmul(torch::softmax(logits, 1), v));
    }
    return attn->proj->forward(torch::cat(heads, 1));
}

}  // namespace

// With K >= n the scene is one patch, so any serialization gives full attention.
TEST(SerializedAttention, OnePatchEqualsFullMultiHeadAttention) {
    torch::manual_seed(3);
    const int64_t n = 37, C = 16;
    const auto x = torch::randn({n, C});
    const auto order = torch::randperm(n, torch::kLong);
    const auto inverse =
        torch::empty_like(order).index_put_({order}, torch::arange(n, torch::kLong));
    for (int64_t K : {int64_t(64), int64_t(37), int64_t(0)}) {
        SerializedAttention attn(C, /*n_heads=*/2, /*patch_size=*/K);
        torch::NoGradGuard no_grad;
        const auto expected = full_attention_reference(attn, x);
        EXPECT_TRUE(torch::allclose(attn->forward(x, order, inverse), expected, 1e-5, 1e-5)) << K;
        attn->kernel = AttentionKernel::batched;
        EXPECT_TRUE(torch::allclose(attn->forward(x, order, inverse), expected, 1e-5, 1e-5)) << K;
    }
}

// Small patches: the CPU loop kernel and the batched (GPU) kernel compute the same thing, and
// each token attends exactly to the tokens of its patch.
TEST(SerializedAttention, LoopAndBatchedKernelsAgreeOnSmallPatches) {
    torch::manual_seed(4);
    const int64_t n = 37, C = 24, K = 8;
    const auto x = torch::randn({n, C});
    const auto order = torch::randperm(n, torch::kLong);
    const auto inverse =
        torch::empty_like(order).index_put_({order}, torch::arange(n, torch::kLong));
    SerializedAttention attn(C, /*n_heads=*/3, K);
    torch::NoGradGuard no_grad;
    attn->kernel = AttentionKernel::loop;
    const auto loop = attn->forward(x, order, inverse);
    attn->kernel = AttentionKernel::batched;
    const auto batched = attn->forward(x, order, inverse);
    EXPECT_TRUE(torch::allclose(loop, batched, 1e-5, 1e-5));
    // The first patch holds the first K tokens in serialized order: full attention among them.
    const auto first = order.slice(0, 0, K);
    const auto expected = full_attention_reference(attn, x.index_select(0, first));
    EXPECT_TRUE(torch::allclose(loop.index_select(0, first), expected, 1e-5, 1e-5));
}

TEST(SerializedAttention, RejectsMismatchedShapes) {
    SerializedAttention attn(8, 2, 4);
    const auto order = torch::arange(5, torch::kLong);
    EXPECT_THROW(attn->forward(torch::randn({5, 6}), order, order), c10::Error);
    EXPECT_THROW(attn->forward(torch::randn({6, 8}), order, order), c10::Error);
    EXPECT_THROW(SerializedAttention(10, 3, 4), c10::Error);
}
