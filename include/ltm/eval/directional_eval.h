// directional_eval.h: the directional head against its ground truth and against spherical
// harmonics (paper Fig. 12, issue #11 items 2 and 4). On held-out records with L_in bins, at
// whole hemispheres of query points spread over each record: the head's bins (predicted at bin
// centres), the best SH fit of degree l = 0..l_max to the reference bins (render/
// spherical_harmonics.h: no SH of that degree is closer in the bins' metric, the plain
// projection included), the floor of a uniform radiance with the reference's cosine integral, and
// optionally the directional transport prior alone and one traced bounce into the model's Ê⁺.
#pragma once

#include <string>
#include <vector>

#include "ltm/core/image.h"
#include "ltm/core/json_util.h"
#include "ltm/nn/ltm_model.h"

namespace ltm {

struct DirectionalEvalOptions {
    int points_per_record = 16;   ///< hemispheres per record, spread evenly over its rows
    int l_max = 8;                ///< SH degrees 0..l_max are fitted
    int tiles = 4;                ///< points drawn as tiles (reference | head | SH 2 | SH l_max)
    /// R of the directional transport prior's row (radiance_scale with R×R cells; 0 = no row;
    /// needs a model with the transport prior).
    int prior_cells = 8;
    /// Samples per bin of a row for one traced bounce into the model's Ê⁺ (infer/traced_bounce.h:
    /// what `ltm render --glossy trace` shades conductors with; ray traced, not a decoder). Each
    /// record's scene is regenerated from its metadata. 0 = no row.
    int traced_samples = 0;
};

/// Errors are relative: Σ(x − L)² / Σ L² over every bin of every evaluated point.
struct DirectionalEvalResult {
    int records = 0, points = 0, resolution = 0;
    std::string radiance;                ///< "indirect" (L_in⁺) or "incident"
    double head = 0, uniform = 0;        ///< the head; a uniform radiance with the reference's ∫ L cos
    /// A uniform radiance with the irradiance head's Ê (its prior when the decoder is zeroed): the
    /// directional head's own start, so head < this means it learned where the light comes from.
    double uniform_model = 0;
    /// The directional transport prior alone (prior_cells × prior_cells cells; -1 when not evaluated).
    double prior = -1;
    int prior_cells = 0;
    /// One traced bounce (traced_samples per bin; -1 when not evaluated), and the points where it
    /// is closer than the SH fit of each degree.
    double traced = -1;
    int traced_samples = 0;
    std::vector<int> traced_beats_sh;
    std::vector<double> sh;              ///< [l_max + 1] best SH fit of degree l
    /// Points where the head's error is below the SH fit's, per degree (out of `points`).
    std::vector<int> head_beats_sh;
    double hemisphere_gap_vs_model = 0;  ///< mean |∫ L̂ cos − Ê| / mean Ê (Ê: the irradiance head, + E_direct if incident)
    double hemisphere_gap_vs_ref = 0;    ///< the same against the reference E
    double seconds_per_point = 0;        ///< the head's bins of one point (encode amortised over the record)
    Image tiles;                         ///< rows of R×R tiles; empty when tiles = 0
    OrderedJson to_json() const;
    std::string markdown() const;        ///< one table: method, relative MSE, points beaten
};

/// Evaluates `model` (with a directional head) on the records of `data_dir`. Throws ltm::Error on
/// a model without a head, records without bins or with another resolution or radiance.
DirectionalEvalResult evaluate_directional(LtmModel &model, const std::string &data_dir, const DirectionalEvalOptions &opt);

}  // namespace ltm
