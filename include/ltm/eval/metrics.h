// metrics.h: image metrics for comparing neural renders with path-traced references
// (ARCHITECTURE.md §7): MSE, PSNR and SSIM on tone-mapped images, relMSE on linear HDR.
//
// Conventions. Images are linear RGB (ltm::Image). Two-image functions take the image under
// test first and the reference second; they throw ltm::Error when the sizes differ, when an
// image is empty, or when a pixel is NaN/Inf ("ssim(): test image has a non-finite pixel at
// (3, 4)"). Sums are accumulated in double.
#pragma once

#include <cstdint>
#include <vector>

#include "ltm/core/image.h"
#include "ltm/core/math.h"
#include "ltm/core/tonemap.h"

namespace ltm {

// Tone mapping (tonemap_scale, tonemap) lives in core/tonemap.h: `ltm render` uses it too.

// ---- pixel-wise errors -------------------------------------------------------------------------

/// Mean squared error over all pixels and the 3 channels: (1 / 3N) Σ_i Σ_c (a_ic − b_ic)².
/// Units: squared image units. Symmetric; 0 iff the images are equal.
double mse(const Image &test, const Image &reference);

/// Peak signal-to-noise ratio in dB: 10 · log10(peak² / mse(test, reference)).
/// +inf when the images are equal. peak = 1 for tone-mapped images in [0, 1].
double psnr(const Image &test, const Image &reference, double peak = 1.0);

/// Relative MSE on linear HDR values (not tone mapped):
///   (1 / 3N) Σ_i Σ_c (t_ic − r_ic)² / (r_ic² + eps).
/// eps keeps dark pixels from dominating; it is in squared image units (default 0.01).
inline constexpr double k_rel_mse_eps = 1e-2;   ///< the evaluation protocol's eps (compare_images)
double rel_mse(const Image &test, const Image &reference, double eps = k_rel_mse_eps);

// ---- structural similarity ---------------------------------------------------------------------

/// SSIM (Wang, Bovik, Sheikh & Simoncelli 2004) with an 11×11 Gaussian window, σ = 1.5 px
/// (weights normalised to sum 1), per channel, averaged over RGB:
///   SSIM(x, y) = (2 μx μy + C1)(2 σxy + C2) / ((μx² + μy² + C1)(σx² + σy² + C2)),
///   C1 = (0.01 L)², C2 = (0.03 L)², L = 1 (data range of tone-mapped images),
/// where μ, σ², σxy are Gaussian-weighted local means, population variances and covariance
/// (σx² = E_w[x²] − μx²). The map is averaged over the valid region only: pixels whose whole
/// 11×11 window lies inside the image, i.e. a 5-pixel border is dropped. This equals
/// scikit-image's structural_similarity(gaussian_weights=True, sigma=1.5,
/// use_sample_covariance=False, data_range=1, channel_axis=-1).
/// Inputs are expected in [0, 1] (tone-mapped) but not clamped here. Symmetric; SSIM(x, x) = 1.
/// Throws when either side is smaller than 11 pixels.
double ssim(const Image &test, const Image &reference);

/// The per-pixel, per-channel SSIM map over the valid region: (width − 10) × (height − 10),
/// pixel (x, y) of the map is the window centred on pixel (x + 5, y + 5) of the inputs.
/// ssim() is the mean of this map over pixels and channels (computed there in double).
Image ssim_map(const Image &test, const Image &reference);

// ---- the evaluation protocol -------------------------------------------------------------------

/// Metrics of one test image against its reference (ARCHITECTURE.md §7).
struct ImageMetrics {
    double mse = 0;       ///< on tonemap(·, tonemap_scale(reference))
    double psnr = 0;      ///< dB, peak 1, on the same tone-mapped pair (+inf if equal)
    double ssim = 0;      ///< on the same tone-mapped pair
    double rel_mse = 0;   ///< on the linear HDR pair, eps = 0.01
};

/// Tone-maps both images with the reference's scale s = tonemap_scale(reference), so the test
/// image cannot change its own exposure, then computes mse, psnr and ssim on the tone-mapped
/// pair and rel_mse on the linear pair. Not symmetric: swapping arguments changes s.
ImageMetrics compare_images(const Image &test, const Image &reference);

/// The reference's own noise in compare_images' MSE: from a twin of it (same spp, independent
/// samples), both tone-mapped at the reference's scale, MSE(reference, twin)/2 (E (a − b)² = 2σ² per
/// pixel; eval/experiment.h, ViewResult::reference_noise_mse).
double reference_noise_mse(const Image &reference, const Image &twin);

/// compare_images on a region: the pixels where mask[y·width + x] != 0 (e.g. the conductors of a
/// glossy scene). Both images are tone-mapped with the whole reference's scale (the region cannot
/// pick its own exposure); mse and rel_mse average over the region's pixels and channels, psnr
/// follows from mse, ssim is the mean of ssim_map over the windows centred on region pixels
/// (NaN when no region pixel lies in the map's valid region, i.e. all within 5 px of the border).
/// Throws ltm::Error when the mask's size differs from the images' or the region is empty.
ImageMetrics compare_images_masked(const Image &test, const Image &reference, const std::vector<uint8_t> &mask);

// ---- visualisation -----------------------------------------------------------------------------

/// Perceptual error ramp for t in [0, 1] (clamped): piecewise linear in display (sRGB) space
/// through black (t = 0), blue (0.25), red (0.5), yellow (0.75) and white (1).
/// Returned as linear RGB, so write_png (which sRGB-encodes) shows exactly these stops.
Vec3f error_ramp(float t);

/// Error image: pixel = error_ramp(clamp(Y(|test − reference|) · scale, 0, 1)), with |·| per
/// channel and Y the Rec. 709 luminance. Use scale = tonemap_scale(reference) so that an error
/// equal to the reference's 99th-percentile luminance is white. Identical images give black.
Image error_map(const Image &test, const Image &reference, float scale);

}  // namespace ltm
