// delegate.h: the torch-free `ltm` hands what needs libtorch to `ltm-torch` beside it.
//
// libtorch's ~290 shared libraries take 0.4–0.6 s to load on the 2-core machine, before main: more
// than a quarter of a 512² frame (docs/performance.md). So a libtorch build makes two programs from
// the same commands: `ltm`, without libtorch — every command that does not need a network, and
// render/bake-gi of weights at their prior (infer/prior_model.h) — and `ltm-torch`, the whole CLI.
// `ltm` replaces itself by `ltm-torch` (exec: same pid, arguments, streams and exit code) for
// train, export, eval, eval-directional and --version, and where a command finds it needs a network
// (NeedsLibtorch). A build without libtorch has no `ltm-torch`: the same places then say in one line
// that libtorch is needed.
#pragma once

#include <string>
#include <vector>

#include "ltm/core/error.h"

namespace ltm::cli {

/// Thrown where a command finds that it needs libtorch (an active network, a directional head, a
/// checkpoint) in a program without it, before it has written anything: run_cli hands the whole
/// command line to ltm-torch, or reports the message when there is none.
class NeedsLibtorch : public Error {
public:
    explicit NeedsLibtorch(const std::string &what) : Error(what) {}
};

/// The commands that exist only with libtorch, and their one-line help (every build lists them).
inline constexpr const char *k_train_help = "Train the light transport model on a dataset (checkpoints, validation, exact resume)";
inline constexpr const char *k_export_help = "Export a checkpoint's (or convert a weights file's) weights to safetensors, config in the metadata";
inline constexpr const char *k_eval_help = "Evaluate the model against path tracing on held-out scenes (report.json, table.md, grids)";
inline constexpr const char *k_eval_directional_help =
    "Evaluate a directional head on held-out records with L_in bins, beside spherical-harmonics fits";
struct LibtorchCommand {
    const char *name, *help;
};
inline constexpr LibtorchCommand k_libtorch_commands[] = {
    {"train", k_train_help}, {"export", k_export_help}, {"eval", k_eval_help}, {"eval-directional", k_eval_directional_help}};
bool is_libtorch_command(const std::string &name);

/// Set in the environment of the ltm-torch that `ltm` hands a command to: a program that finds it
/// set does not hand anything on again (a loop of links), and ltm-torch clears it for its children.
inline constexpr const char *k_delegated_env = "LTM_DELEGATED";

/// Replaces this process by `ltm-torch` (beside /proc/self/exe) with `args`; returns only when that
/// is impossible, with why (no such file, the same program, exec failed).
std::string exec_libtorch_program(const std::vector<std::string> &args);

}  // namespace ltm::cli
