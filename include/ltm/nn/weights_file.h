// weights_file.h: an `ltm export` weights file read without libtorch — its format checks, its model
// config, and whether its body is silent (its decoder's output layer zero) and with what skip. The
// tensor model's load_weights (nn/checkpoint.h) reads through it; a render of a silent body
// (infer/prior_model.h) needs nothing more.
#pragma once

#include <map>
#include <optional>
#include <string>

#include "ltm/core/math.h"
#include "ltm/nn/model_config.h"
#include "ltm/points/safetensors.h"

namespace ltm {

inline constexpr int k_weights_format_version = 1;
inline constexpr int k_arch_version = 1;   ///< bump when parameter names or shapes change meaning

struct WeightsFile {
    SafetensorsFile file;   ///< tensors (F32 or F16) and metadata
    ModelConfig config;     ///< from the metadata's "config"
};
/// Reads and checks: metadata format "ltm-weights", this build's format and architecture versions,
/// a valid config, tensors of F32 or F16. Throws "path: ..." naming what is wrong.
WeightsFile read_weights_file(const std::string &path);

/// The skip's weights w ("decoder.skip") when the decoder's output layer (the last "decoder.out.<i>"
/// Linear) is exactly zero — a silent body; (0, 0, 0) without a skip —, nullopt when it is not (the
/// network is active). w = 0: the network is silenced and the model is its closed-form prior wherever
/// it is asked (QueryDecoder::at_prior, --start-at-prior); w ≠ 0: the regathered prior
/// softplus(w ⊙ ln(R / Ê)) · Ê at every query (LtmModelImpl::fold_prior). Either renders from the
/// config and these tensors alone, without libtorch (infer/prior_model.h). A file without that layer,
/// or with it in another shape than the config's, a skip without traced_queries (or missing with it)
/// and a non-finite skip are refused ("path: ...").
std::optional<Vec3f> silent_body_skip(const WeightsFile &w, const std::string &path);

}  // namespace ltm
