// active_weights.h: test weights made from the shipped file. With their network set going — the
// decoder's last output layer (the highest "decoder.out.<i>.weight", by its index) given a first
// weight of 1 — for tests of what an active network needs (libtorch) beside weights whose body is
// silent; or with their physics changed (the prior's visibility by the points' clusters, the dense
// rows), for tests of those paths.
#pragma once

#include <cstdlib>
#include <string>

#include "ltm/core/json_util.h"
#include "ltm/points/safetensors.h"

namespace ltm::test {

inline void write_active_weights(const std::string &from, const std::string &to) {
    SafetensorsFile w = read_safetensors(from);
    const std::string prefix = "decoder.out.";
    std::string last;
    long best = -1;
    for (const auto &[name, t] : w.tensors) {
        if (name.rfind(prefix, 0) != 0 || name.size() < 7 || name.substr(name.size() - 7) != ".weight") continue;
        const long i = std::strtol(name.c_str() + prefix.size(), nullptr, 10);
        if (i > best) best = i, last = name;
    }
    StTensor &out = w.tensors.at(last);
    if (out.dtype == "F16")
        out.data[1] = char(0x3c);   // 1.0 in binary16 (0x3c00, little-endian)
    else
        out.data[3] = char(0x3f), out.data[2] = char(0x80);   // 1.0f (0x3f800000)
    write_safetensors(to, w);
}

/// The weights `from` with their config's physics keys set as in `physics` (e.g. {"prior_rays": false}).
inline void write_weights_with_physics(const std::string &from, const std::string &to, const Json &physics) {
    SafetensorsFile w = read_safetensors(from);
    Json cfg = Json::parse(w.metadata.at("config"));
    for (const auto &[key, value] : physics.items()) cfg["physics"][key] = value;
    w.metadata["config"] = cfg.dump();
    write_safetensors(to, w);
}

}  // namespace ltm::test
