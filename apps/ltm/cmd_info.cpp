// cmd_info.cpp: `ltm info <scene>`: what a scene file holds (counts, bounds, lights, cameras).
#include <iostream>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "delegate.h"
#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/points/safetensors.h"
#include "ltm/procgen/training_range.h"
#include "ltm/scene/scene_loader.h"
#ifdef LTM_WITH_TORCH
#include "ltm/nn/checkpoint.h"
#endif

namespace ltm::cli {

namespace {
// Weights, dataset records, bake outputs: list tensors and the ltm metadata.
void describe_safetensors(const std::string &path) {
    const SafetensorsFile f = read_safetensors(path);
    int64_t n_values = 0;
    for (const auto &[name, t] : f.tensors) n_values += int64_t(t.numel());
    std::string fmt = "unknown";
    if (f.metadata.count("format")) fmt = f.metadata.at("format");                 // weights
    else if (f.metadata.count("ltm")) fmt = "ltm-record";                          // dataset record
    else if (f.metadata.count("settings")) fmt = "ltm-bake (ground-truth irradiance)";   // ltm bake
    std::cout << "file       " << path << " (safetensors, " << fmt << ")\n"
              << "tensors    " << f.tensors.size() << " with " << n_values << " values\n";
    if (fmt == "ltm-weights") {
        std::cout << "config     " << f.metadata.at("config") << "\n";
        for (const char *k : {"format_version", "arch_version", "step", "best_val_loss"})
            if (f.metadata.count(k)) std::cout << k << "  " << f.metadata.at(k) << "\n";
        return;
    }
    for (const auto &[name, t] : f.tensors) {
        std::cout << "  " << name << " " << t.dtype << " [";
        for (size_t i = 0; i < t.shape.size(); ++i) std::cout << (i ? ", " : "") << t.shape[i];
        std::cout << "]\n";
    }
    for (const auto &[k, v] : f.metadata) std::cout << "meta " << k << "  " << v.substr(0, 400) << "\n";
}

struct InfoArgs {
    std::string input;
};

void declare(CLI::App &sub, InfoArgs &a) {
    sub.add_option("input", a.input, "Scene file")->required();
}

void run(const InfoArgs &a, const CommonOptions &) {
    const std::string ext = file_extension(a.input);
    if (ext == "safetensors") return describe_safetensors(a.input);
    if (ext == "ltmckpt") {
#ifdef LTM_WITH_TORCH
        const TrainState st = read_checkpoint_state(a.input);
        std::cout << "checkpoint " << a.input << "\nstep       " << st.step << "\nbest val   " << st.best_val
                  << "\nmodel      " << st.model_config << "\ntraining   " << st.train_config << "\n";
        return;
#else
        throw NeedsLibtorch(a.input + ": checkpoints are libtorch archives");
#endif
    }
    ValidateOptions opt;
    opt.require_emitter = false;
    const Scene s = load_scene(a.input, opt);
    const Bounds3f b = s.bounds();
    double emissive_area = 0;
    for (const auto &m : s.meshes)
        if (s.materials[size_t(m.material)].is_emissive())
            for (size_t t = 0; t < m.n_triangles(); ++t) emissive_area += m.area(t);
    std::cout << "scene      " << s.name << "\n"
              << "meshes     " << s.meshes.size() << "\n"
              << "triangles  " << s.n_triangles() << "\n"
              << "materials  " << s.materials.size() << "\n"
              << "area       " << s.total_area() << " m² (" << emissive_area << " m² emissive)\n"
              << "bounds     " << b.lo << " - " << b.hi << " m\n"
              << "cameras    " << s.cameras.size() << "\n";
    if (!s.has_emitter()) std::cout << "warning    no emitter: this scene renders black\n";
    // The shipped models are unit-invariant: only the proportions are compared.
    const auto range = scene_range_warnings(s, /*unit_free=*/true);
    std::cout << "range      " << (range.empty() ? "inside the training houses' proportions (footprint / height 0.75-4.6, y up)" : range[0])
              << "\n";
    if (!s.metadata.empty()) std::cout << "metadata   " << s.metadata.dump().substr(0, 200) << "\n";
}
}  // namespace

Command make_info_command() {
    return make_command(
        "info", "Describe a scene (json, obj, builtin:<name>), weights/records (.safetensors) or a checkpoint (.ltmckpt)",
        declare, run);
}

}  // namespace ltm::cli
