// model_config.h: the whole model's hyper-parameters (ARCHITECTURE.md §6 presets), JSON-backed.
// configs/model/{tiny,cpu,paper}.json and the two ablations are instances of this struct.
#pragma once

#include <string>

#include "ltm/core/json_util.h"
#include "ltm/nn/ptv3.h"

namespace ltm {

/// Nearest-neighbour embedding (paper eqs. 5–7).
struct EmbeddingConfig {
    int dim = 64;                   ///< D: width of 𝓕 and 𝓖 and of the encoder's input
    int k = 16;                     ///< neighbours grouped around each FPS centre (paper: open)
    float sample_ratio = 0.5f;      ///< m = M·ratio FPS centres (paper: M → M/2)
    bool relative_position = true;  ///< also feed p_j − p̃_l to 𝓖 (PointNet++ style; eq. 6 omits it)
};

/// Local query decoder (paper eqs. 9–14) or the knn-mean ablation.
struct DecoderConfig {
    std::string type = "attention";  ///< "attention" (vector cross-attention) | "knn-mean" (Fig. 14 ablation)
    int dim = 64;                    ///< D of query features and attention values
    int n_neighbors = 32;            ///< κ nearest anchors per query (paper Tab. 2: 32)
    int n_layers = 2;                ///< stacked cross-attention blocks ("iteratively aggregate")
    int groups = 8;                  ///< G weight groups of grouped vector attention (PTv2)
};

struct ModelConfig {
    std::string name = "cpu";       ///< preset name, informational
    int scene_points = 8192;        ///< M scene points the model is trained with
    EmbeddingConfig embedding;
    PTv3Config encoder;             ///< in_channels is forced to embedding.dim
    DecoderConfig decoder;

    /// Strict: unknown keys and invalid values throw "where: /pointer: problem".
    static ModelConfig from_json(const Json &j, const std::string &where);
    static ModelConfig from_file(const std::string &path);
    OrderedJson to_json() const;
    int n_anchors() const { return std::max(1, int(float(scene_points) * embedding.sample_ratio)); }
};

}  // namespace ltm
