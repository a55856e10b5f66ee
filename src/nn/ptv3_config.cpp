// ptv3_config.cpp: PTv3Config declared once (key, member, limits, doc) and its cross-field checks.
#include "ltm/nn/ptv3_config.h"

#include "ltm/core/error.h"

namespace ltm {

const ConfigFields<PTv3Config> &PTv3Config::fields() {
    using C = PTv3Config;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("in_channels", &C::in_channels, "width of the input features (set to `embedding.dim` by the model config)", at_least(1))
            .field("grid_size", &C::grid_size, "voxel edge (in units of ℓ with `physics.length_scale`, else metres); points sharing a voxel are merged", positive())
            .field("enc_depths", &C::enc_depths, "blocks per encoder stage; its length is the stage count S", at_least(1))
            .field("enc_channels", &C::enc_channels, "width per encoder stage [S]", at_least(1))
            .field("enc_heads", &C::enc_heads, "attention heads per encoder stage [S]; each divides its width", at_least(1))
            .field("enc_patch_size", &C::enc_patch_size, "patch size K per encoder stage [S]", at_least(1))
            .field("dec_depths", &C::dec_depths, "blocks per decoder (U-Net) stage [S − 1]", at_least(1))
            .field("dec_channels", &C::dec_channels, "width per decoder stage [S − 1]; the latents have `dec_channels[0]` channels", at_least(1))
            .field("dec_heads", &C::dec_heads, "attention heads per decoder stage [S − 1]; each divides its width", at_least(1))
            .field("dec_patch_size", &C::dec_patch_size, "patch size K per decoder stage [S − 1]", at_least(1))
            .field("orders", &C::orders, "serialization orders; block i of a stage attends along order i mod (count)", {},
                   {"z", "z-trans", "hilbert", "hilbert-trans"})
            .field("shuffle_orders", &C::shuffle_orders, "permute the orders per stage in training (fixed in eval)")
            .field("mlp_ratio", &C::mlp_ratio, "block MLP hidden width = mlp_ratio · width", at_least(1))
            .field("attention", &C::attention, "serialized patch attention, or global attention over all tokens (Fig. 14 ablation, O(n²) memory)", {},
                   {"patch", "vanilla"})
            .field("drop_path", &C::drop_path, "maximum stochastic-depth rate (per point), linear over the blocks", from_below(0, 1))
            .field("enable_cpe", &C::enable_cpe, "xCPE (submanifold 3×3×3 conv as gather + GEMM) in every block");
    return f;
}

PTv3Config PTv3Config::from_json(const Json &j, const std::string &where) {
    PTv3Config c = fields().read(j, where);
    c.validate(where);
    return c;
}

OrderedJson PTv3Config::to_json() const { return fields().write(*this); }

void PTv3Config::validate(const std::string &where) const {
    fields().check(*this, where);
    const size_t S = enc_depths.size();
    if (S == 0) LTM_THROW(where, ": enc_depths must list at least one stage");
    auto check_length = [&](const char *name, const std::vector<int64_t> &v, size_t n) {
        if (v.size() != n) LTM_THROW(where, ": ", name, " must have ", n, " entries (", S, " encoder stages), got ", v.size());
    };
    check_length("enc_channels", enc_channels, S);
    check_length("enc_heads", enc_heads, S);
    check_length("enc_patch_size", enc_patch_size, S);
    check_length("dec_depths", dec_depths, S - 1);
    check_length("dec_channels", dec_channels, S - 1);
    check_length("dec_heads", dec_heads, S - 1);
    check_length("dec_patch_size", dec_patch_size, S - 1);
    for (size_t s = 0; s < S; ++s)
        if (enc_channels[s] % enc_heads[s] != 0)
            LTM_THROW(where, ": enc_channels[", s, "] = ", enc_channels[s], " is not a multiple of enc_heads[", s, "] = ", enc_heads[s]);
    for (size_t s = 0; s + 1 < S; ++s)
        if (dec_channels[s] % dec_heads[s] != 0)
            LTM_THROW(where, ": dec_channels[", s, "] = ", dec_channels[s], " is not a multiple of dec_heads[", s, "] = ", dec_heads[s]);
    if (orders.empty()) LTM_THROW(where, ": orders must not be empty");
}

}  // namespace ltm
