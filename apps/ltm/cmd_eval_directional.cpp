// cmd_eval_directional.cpp: `ltm eval-directional --model W --data DIR --out DIR`: the directional
// head against the reference bins of held-out records and against SH fits of degree 0..l_max
// (eval/directional_eval.h); writes report.json, report.md and tiles.png.
#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>

#include "cli.h"
#include "delegate.h"
#include "ltm/core/file_util.h"
#include "ltm/core/log.h"
#include "ltm/eval/directional_eval.h"
#include "ltm/nn/checkpoint.h"

namespace ltm::cli {

namespace {
struct EvalDirectionalArgs {
    std::string model, data, out;
    DirectionalEvalOptions opt;
};

void declare(CLI::App &sub, EvalDirectionalArgs &a) {
    sub.add_option("--model", a.model, "Weights with a directional head (.safetensors)")->required();
    sub.add_option("--data", a.data, "Dataset directory of held-out records with L_in bins (e.g. a glossy preset)")->required();
    sub.add_option("--out", a.out, "Output directory: report.json, report.md, tiles.png")->required();
    sub.add_option("--points", a.opt.points_per_record, "Hemispheres per record, spread over its rows")
        ->capture_default_str()->check(CLI::Range(1, 1 << 20));
    sub.add_option("--prior-cells", a.opt.prior_cells, "R of a row for the directional transport prior alone (R×R cells; 0: none)")
        ->capture_default_str()
        ->check(CLI::Range(0, 64));
    sub.add_option("--traced", a.opt.traced_samples,
                   "Samples per bin of a row for one traced bounce into the model's E+ (what --glossy trace renders; "
                   "regenerates each record's scene; 0: none)")
        ->capture_default_str()
        ->check(CLI::Range(0, 1024));
    sub.add_option("--lmax", a.opt.l_max, "Highest SH degree fitted")->capture_default_str()->check(CLI::Range(0, 16));
    sub.add_option("--tiles", a.opt.tiles, "Points drawn as tiles: reference | head | SH l=2 | SH l=lmax")
        ->capture_default_str()->check(CLI::Range(0, 64));
}

void run(const EvalDirectionalArgs &a, const CommonOptions &) {
    LtmModel model = load_weights(a.model);
    const DirectionalEvalResult r = evaluate_directional(model, a.data, a.opt);
    std::filesystem::create_directories(a.out);
    OrderedJson j = r.to_json();
    j["model"] = a.model, j["data"] = a.data;
    write_file_atomic(a.out + "/report.json", j.dump(2) + "\n");
    write_file_atomic(a.out + "/report.md", r.markdown());
    if (r.tiles.width > 0) write_png(a.out + "/tiles.png", r.tiles);
    std::cout << r.markdown() << "\nhemisphere integral vs the irradiance head " << r.hemisphere_gap_vs_model
              << ", vs the reference " << r.hemisphere_gap_vs_ref << " (" << r.points << " points of " << r.records
              << " records; head " << r.seconds_per_point << " s per hemisphere)\n";
}
}  // namespace

Command make_eval_directional_command() {
    return make_command(
        "eval-directional", k_eval_directional_help,
        declare, run);
}

}  // namespace ltm::cli
