// cmd_generate.cpp: `ltm generate --seed S [--config FILE] [--set k=v] -o scene.json`.
#include <chrono>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "ltm/core/log.h"
#include "ltm/procgen/indoor_generator.h"
#include "ltm/scene/scene_json.h"

namespace ltm::cli {

namespace {
struct GenerateArgs {
    std::string config, output;
    std::vector<std::string> overrides;
};

void declare(CLI::App &sub, GenerateArgs &a) {
    sub.alias("gen");
    sub.add_option("--config", a.config, "Generator config JSON (default: built-in defaults = configs/gen/indoor.json)");
    sub.add_option("--set", a.overrides, "Override a config key, e.g. --set plan.room_count=[2,4]");
    add_output_option(sub, a.output, "Output scene JSON");
}

void run(const GenerateArgs &a, const CommonOptions &common) {
    Json cfg_json = a.config.empty() ? Json(GenConfig{}.to_json()) : parse_json_file(a.config);
    for (const auto &o : a.overrides) apply_json_override(cfg_json, o);
    const GenConfig cfg = GenConfig::from_json(cfg_json, a.config.empty() ? "--set" : a.config);
    const auto t0 = std::chrono::steady_clock::now();
    const GeneratedScene g = generate_indoor(cfg, common.seed);
    validate_scene(g.scene, a.output);
    save_scene_json(g.scene, a.output);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    log_info("generated '", g.scene.name, "': ", g.rooms.size(), " room(s), ", g.furniture.size(),
             " furniture pieces, ", g.lights.size(), " light(s)", g.ajar ? " (ajar lighting)" : "", ", ",
             g.scene.n_triangles(), " triangles, ", g.scene.total_area(), " m² in ", ms, " ms -> ", a.output);
}
}  // namespace

Command make_generate_command() {
    return make_command(
        "generate", "Generate a procedural indoor scene (rooms, furniture, ceiling lights)",
        declare, run);
}

}  // namespace ltm::cli
