// weights_file.cpp: the metadata checks and the output layer's test, on the file's bytes.
#include "ltm/nn/weights_file.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>

#include "ltm/core/error.h"
#include "ltm/core/json_util.h"

namespace ltm {

namespace {
std::string shape_string(const std::vector<int64_t> &shape) {
    std::string s = "[";
    for (size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
    return s + "]";
}
}  // namespace

WeightsFile read_weights_file(const std::string &path) {
    WeightsFile w;
    w.file = read_safetensors(path);
    auto meta = [&](const std::string &k) {
        const auto it = w.file.metadata.find(k);
        if (it == w.file.metadata.end()) LTM_THROW(path, ": not ltm weights (metadata '", k, "' missing)");
        return it->second;
    };
    if (meta("format") != "ltm-weights") LTM_THROW(path, ": not ltm weights (format '", meta("format"), "')");
    if (meta("format_version") != std::to_string(k_weights_format_version))
        LTM_THROW(path, ": weights format version ", meta("format_version"), ", this build reads ", k_weights_format_version);
    if (meta("arch_version") != std::to_string(k_arch_version))
        LTM_THROW(path, ": architecture version ", meta("arch_version"), ", this build has ", k_arch_version);
    w.config = ModelConfig::from_json(parse_json(meta("config"), path + " (config)"), path + " (config)");
    for (const auto &[name, t] : w.file.tensors)   // F32 as trained, or F16 (`ltm export --half`, for shipping)
        if (t.dtype != "F32" && t.dtype != "F16")
            LTM_THROW(path, ": tensor '", name, "' has dtype ", t.dtype, " (weights are F32 or F16)");
    return w;
}

std::optional<Vec3f> silent_body_skip(const WeightsFile &w, const std::string &path) {
    // The decoder's output MLP is "decoder.out.<i>.*" (LayerNorm, Linear, GELU, Linear: nn/query_decoder.h);
    // its last Linear is the highest i with a weight.
    const std::string prefix = "decoder.out.";
    long last = -1;
    for (const auto &[name, t] : w.file.tensors) {
        if (name.rfind(prefix, 0) != 0) continue;
        const std::string rest = name.substr(prefix.size());
        const size_t dot = rest.find('.');
        if (dot == std::string::npos || rest.substr(dot) != ".weight") continue;
        char *end = nullptr;
        const long i = std::strtol(rest.c_str(), &end, 10);
        if (end == rest.c_str() + dot) last = std::max(last, i);
    }
    if (last < 0) LTM_THROW(path, ": missing tensor '", prefix, "<i>.weight': weights of another architecture");
    // The shapes the decoder's last Linear has (dim -> 3): what the tensor model's loader checks for it.
    const std::vector<std::vector<int64_t>> shapes = {{3, int64_t(w.config.decoder.dim)}, {3}};
    const char *parts[2] = {".weight", ".bias"};
    bool zero = true;
    for (int k = 0; k < 2; ++k) {
        const std::string name = prefix + std::to_string(last) + parts[k];
        const auto it = w.file.tensors.find(name);
        if (it == w.file.tensors.end()) LTM_THROW(path, ": missing tensor '", name, "': weights of another architecture");
        if (it->second.shape != shapes[size_t(k)])
            LTM_THROW(path, ": tensor '", name, "' has shape ", shape_string(it->second.shape), ", the model expects ", shape_string(shapes[size_t(k)]));
        std::vector<float> v(it->second.numel());
        it->second.copy_f32(v.data(), path + ": tensor '" + name + "'");
        for (const float x : v) zero &= x == 0.f;
    }
    // ModelConfig::traced_queries: the skip carries ln(R / Ê) past the output layer, so a zero layer
    // with a nonzero skip is the regathered prior, not the prior (QueryDecoderImpl::at_prior).
    const auto skip = w.file.tensors.find("decoder.skip");
    if (w.config.traced_queries && skip == w.file.tensors.end())
        LTM_THROW(path, ": missing tensor 'decoder.skip': the config has traced_queries");
    Vec3f weights(0.f);
    if (skip != w.file.tensors.end()) {
        if (skip->second.shape != std::vector<int64_t>{3})
            LTM_THROW(path, ": tensor 'decoder.skip' has shape ", shape_string(skip->second.shape), ", the model expects [3]");
        if (!w.config.traced_queries) LTM_THROW(path, ": tensor 'decoder.skip' without traced_queries in the config");
        float v[3];
        skip->second.copy_f32(v, path + ": tensor 'decoder.skip'");
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(v[c])) LTM_THROW(path, ": tensor 'decoder.skip' is not finite");
        weights = Vec3f(v[0], v[1], v[2]);
    }
    if (!zero) return std::nullopt;
    return weights;
}

}  // namespace ltm
