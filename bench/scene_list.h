// scene_list.h: the benches' SCENES argument — scene files and builtin:NAME, comma-separated.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

namespace ltm::bench {

/// "a.pbrt,builtin:cornell-box" -> {"a.pbrt", "builtin:cornell-box"} (empty items kept).
inline std::vector<std::string> split_commas(const std::string &list) {
    std::vector<std::string> out;
    for (size_t b = 0; b <= list.size();) {
        const size_t e = std::min(list.find(',', b), list.size());
        out.push_back(list.substr(b, e - b));
        b = e + 1;
    }
    return out;
}

}  // namespace ltm::bench
