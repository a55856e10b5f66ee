// ptv3_config.h: the PTv3 encoder's hyper-parameters, their JSON and their checks — torch-free,
// so a config can be read, validated and documented without the network (nn/ptv3.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ltm/core/config_fields.h"
#include "ltm/core/json_util.h"

namespace ltm {

/// PTv3 hyper-parameters. Defaults are the "cpu" preset (ARCHITECTURE.md §6). S = number of
/// encoder stages; stage s > 0 starts with a stride-2 grid pooling.
struct PTv3Config {
    int in_channels = 64;  ///< width of the input features (the NN embedding's D)
    float grid_size = 0.2f;  ///< voxel edge in metres (> 0); ≈ anchor spacing, extent/grid < 2^16
    std::vector<int64_t> enc_depths{1, 1, 1, 2};         ///< blocks per encoder stage [S]
    std::vector<int64_t> enc_channels{32, 64, 128, 256}; ///< widths per encoder stage [S]
    std::vector<int64_t> enc_heads{2, 4, 8, 16};         ///< attention heads per stage [S]
    std::vector<int64_t> enc_patch_size{256, 256, 256, 256};  ///< patch K per stage [S]
    std::vector<int64_t> dec_depths{1, 1, 1};            ///< blocks per decoder stage [S-1]
    std::vector<int64_t> dec_channels{64, 64, 128};      ///< widths per decoder stage [S-1]
    std::vector<int64_t> dec_heads{4, 4, 8};             ///< heads per decoder stage [S-1]
    std::vector<int64_t> dec_patch_size{256, 256, 256};  ///< patch K per decoder stage [S-1]
    /// Space-filling curves ("z", "z-trans", "hilbert", "hilbert-trans"); block i of a stage
    /// attends along order i % (number of orders).
    std::vector<std::string> orders{"z", "z-trans", "hilbert", "hilbert-trans"};
    /// Training mode: a random permutation of the orders per stage (torch's generator, so
    /// torch::manual_seed reproduces it). Eval mode always uses the listed order.
    bool shuffle_orders = true;
    int mlp_ratio = 4;              ///< MLP hidden width = mlp_ratio · C
    /// "patch": serialized patch attention; "vanilla": global attention over all tokens of the
    /// scene at every stage (the paper's Fig. 14 ablation; O(n²) memory).
    std::string attention = "patch";
    float drop_path = 0.f;          ///< max stochastic-depth rate (per point), linear over blocks
    bool enable_cpe = true;         ///< xCPE (submanifold 3×3×3 conv → Linear → LN) in blocks

    /// Each key once: reading, limits, writing, the docs table (core/config_fields.h).
    static const ConfigFields<PTv3Config> &fields();
    /// Strict parse (unknown keys are errors); missing keys keep the defaults above; validated.
    static PTv3Config from_json(const Json &j, const std::string &where);
    OrderedJson to_json() const;
    /// Throws ltm::Error naming `where` on out-of-range values (fields()) or inconsistent lists
    /// (lengths per stage, widths divisible by heads): the one place a PTv3Config is checked.
    void validate(const std::string &where) const;
    int64_t n_stages() const { return int64_t(enc_depths.size()); }
};

}  // namespace ltm
