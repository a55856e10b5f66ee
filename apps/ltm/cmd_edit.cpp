// cmd_edit.cpp: `ltm edit in.json --move light0=1,0,0 --albedo room0_walls=0.8,0.2,0.2 -o out.json`
// (scene/scene_edit.h). The result is validated as a scene before it is written.
#include <filesystem>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "ltm/core/file_util.h"
#include "ltm/core/log.h"
#include "ltm/scene/scene_edit.h"
#include "ltm/scene/scene_json.h"

namespace ltm::cli {

namespace {
struct EditArgs {
    std::string input, output;
    std::vector<std::string> moves, albedos, light_scales;
};

/// "NAME=v1,v2,..." → (NAME, values); exactly `n` finite numbers.
std::pair<std::string, std::vector<float>> parse_assignment(const std::string &s, size_t n, const char *option) {
    const size_t eq = s.rfind('=');
    if (eq == std::string::npos || eq == 0) LTM_THROW(option, " ", s, ": expected NAME=", n == 1 ? "k" : "x,y,z");
    std::vector<float> v;
    std::string rest = s.substr(eq + 1) + ",";
    for (size_t p = 0, c; (c = rest.find(',', p)) != std::string::npos; p = c + 1) {
        try {
            size_t used = 0;
            const std::string tok = rest.substr(p, c - p);
            v.push_back(std::stof(tok, &used));
            if (used != tok.size() || !std::isfinite(v.back())) throw std::invalid_argument("");
        } catch (const std::exception &) {
            LTM_THROW(option, " ", s, ": '", rest.substr(p, c - p), "' is not a finite number");
        }
    }
    if (v.size() != n) LTM_THROW(option, " ", s, ": expected ", n, " numbers, got ", v.size());
    return {s.substr(0, eq), v};
}
void declare(CLI::App &sub, EditArgs &a) {
    sub.add_option("scene", a.input, "Scene JSON")->required();
    sub.add_option("--move", a.moves, "NAME=dx,dy,dz: translate mesh NAME or object NAME_* (metres; repeatable)");
    sub.add_option("--albedo", a.albedos, "MATERIAL=r,g,b: constant albedo in [0,1] (repeatable)");
    sub.add_option("--scale-light", a.light_scales, "MATERIAL=k: multiply an emitter's radiance (repeatable)");
    add_output_option(sub, a.output, "Edited scene JSON");
}

void run(const EditArgs &a, const CommonOptions &) {
    if (a.moves.empty() && a.albedos.empty() && a.light_scales.empty())
        LTM_THROW("nothing to do: give --move, --albedo or --scale-light");
    Json j = parse_json_file(a.input);
    for (const auto &m : a.moves) {
        const auto [name, v] = parse_assignment(m, 3, "--move");
        const int n = translate_meshes(j, name, {v[0], v[1], v[2]}, a.input);
        log_info("moved ", n, " mesh", n == 1 ? "" : "es", " of '", name, "' by ", Vec3f{v[0], v[1], v[2]}, " m");
    }
    for (const auto &m : a.albedos) {
        const auto [name, v] = parse_assignment(m, 3, "--albedo");
        set_albedo(j, name, {v[0], v[1], v[2]}, a.input);
    }
    for (const auto &m : a.light_scales) {
        const auto [name, v] = parse_assignment(m, 1, "--scale-light");
        scale_radiance(j, name, v[0], a.input);
    }
    // Validate the edited scene (relative files resolve against the input's folder) before writing.
    const std::string base = std::filesystem::path(a.input).parent_path().string();
    validate_scene(scene_from_json(j, a.input + " (edited)", base.empty() ? "." : base), a.input + " (edited)");
    write_file_atomic(a.output, dump_json_compact(OrderedJson::parse(j.dump())) + "\n");
    log_info("wrote ", a.output);
}
}  // namespace

Command make_edit_command() {
    return make_command(
        "edit", "Edit a scene JSON: move a light or object, change an albedo, scale a light (no retraining needed)",
        declare, run);
}

}  // namespace ltm::cli
