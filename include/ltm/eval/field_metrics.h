// field_metrics.h: does a predicted E⁺ field follow its reference the way physics says it must?
// Scene-level agreement of two RGB fields sampled at the same points (pixels or query points):
// level, colour, spatial structure, and the flat-oracle floor (issue #10, docs/results.md).
//
// The flat oracle is not a method: it fills every point with the reference's own mean colour.
// It knows the exact level and chroma, and nothing else; a model worth using must beat it.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "ltm/core/math.h"

namespace ltm {

/// An RGB colour accumulated in double (means over many points).
using Color3d = std::array<double, 3>;

/// Rec. 709 luminance Y = 0.2126 R + 0.7152 G + 0.0722 B.
double luminance(const Color3d &c);

/// Mean colour of n RGB rows (double accumulation).   rows [n, 3] -> Color3d
Color3d mean_color(const float *rows, size_t n);
Color3d mean_color(const std::vector<Vec3f> &rows);

/// Centred log channel values: log(c_i) − mean_j log(c_j), the colour with its level removed
/// (channels floored at 1e-6 · max so a black channel stays finite).
Color3d centred_log(const Color3d &c);

/// Chroma error between two colours: the RMS over channels of the difference of centred log
/// channel values, sqrt((1/3) Σ_c (log(a_c / ḡ(a)) − log(b_c / ḡ(b)))²), ḡ the geometric mean.
/// Invariant to the level of either colour; 0 iff a ∝ b. Channels are floored at 1e-6 · max so a
/// black channel gives a large, finite error.
double chroma_error(const Color3d &a, const Color3d &b);

/// Share of blue in a colour: B / (R + G + B) (0 for black).
double blue_share(const Color3d &c);

struct FieldMetrics {
    double level_ratio = 0;             ///< mean Y(pred) / mean Y(ref)  (inf if the reference is black)
    double chroma_error = 0;            ///< chroma_error(mean pred, mean ref)
    double luminance_correlation = 0;   ///< Pearson correlation of Y(pred) and Y(ref) over the points (0 if either is constant)
    double mse = 0;                     ///< mean over points and channels of (pred − ref)², / mean Y(ref)² (scale-free)
    double flat_mse = 0;                ///< the same for the flat oracle (every point = mean ref)
    /// Below the floor by more than rounding (the oracle itself, rounded to float, does not beat it).
    bool beats_flat() const { return mse < flat_mse * (1.0 - 1e-6); }
    /// Level within [0.8, 1.25] (the target band of issue #10).
    bool level_in_band() const { return level_ratio >= 0.8 && level_ratio <= 1.25; }
};

/// Compares a predicted field with its reference at the same n points.
///   pred [n, 3], ref [n, 3] (linear E⁺, row-major) -> FieldMetrics
/// Throws ltm::Error when n is 0 or a value is non-finite.
FieldMetrics compare_fields(const float *pred, const float *ref, size_t n);
FieldMetrics compare_fields(const std::vector<Vec3f> &pred, const std::vector<Vec3f> &ref);

}  // namespace ltm
