// directional_eval.cpp: one encode per record, the head's bins of its points in one batch.
#include "ltm/eval/directional_eval.h"

#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/core/progress.h"
#include "ltm/core/rng.h"
#include "ltm/data/dataset.h"
#include "ltm/infer/neural_renderer.h"
#include "ltm/infer/traced_bounce.h"
#include "ltm/nn/point_tensor.h"
#include "ltm/points/scene_record.h"
#include "ltm/render/bake.h"
#include "ltm/render/embree_accel.h"
#include "ltm/render/hemisphere_bins.h"
#include "ltm/render/spherical_harmonics.h"

namespace ltm {

namespace {
// Every bin of every point: the mean of S one-traced-bounce samples uniform over the bin's square
// (equal projected solid angle: the measure of the reference bins' cosine-weighted samples), in
// the record's regenerated scene (its query points checked to lie on it), one light sample per
// hit; emitters seen directly count when the bins hold L_in (with_emission). Traced in chunks of
// whole points (≤ ~1 M rows at a time).  -> [points·R²]
std::vector<Vec3f> traced_bins(LtmModel &model, const SceneLatents &lat, const SceneRecord &r, const std::vector<int64_t> &pts,
                               int R, int S, bool with_emission) {
    const Scene scene = regenerate_scene(r);
    const EmbreeAccel accel(scene);
    check_points_match_scene(accel, r.query_points, r.path + " (regenerated for --traced)");
    PathTracerConfig cfg;
    cfg.seed = hash_keys({r.seed, 0x7ace5ull});
    cfg.max_depth = r.metadata.at("preset").value("max_depth", cfg.max_depth);
    const PathTracer pt(accel, cfg);
    std::optional<RatioDirectLight> ratio;
    if (RatioDirectLight::supports(scene)) ratio.emplace(accel, cfg.seed);
    const DirectIrradianceFn direct = direct_irradiance_fn(pt, ratio ? &*ratio : nullptr, 1);
    const size_t nb = size_t(R) * size_t(R), s_n = size_t(S), per_point = nb * s_n;
    const size_t chunk = std::max<size_t>(1, (size_t(1) << 20) / per_point);
    std::vector<Vec3f> bins(pts.size() * nb, Vec3f(0.f));
    for (size_t j0 = 0; j0 < pts.size(); j0 += chunk) {
        const size_t j1 = std::min(pts.size(), j0 + chunk), rows = (j1 - j0) * per_point;
        std::vector<Ray> rays(rows);
        std::vector<uint64_t> keys(rows);
        for (size_t j = j0; j < j1; ++j) {
            const size_t q = size_t(pts[j]);
            const Vec3f p(r.query_points.at(q, 0), r.query_points.at(q, 1), r.query_points.at(q, 2));
            const Vec3f n = normalize(Vec3f(r.query_points.at(q, 3), r.query_points.at(q, 4), r.query_points.at(q, 5)));
            const Frame frame(n);
            for (size_t b = 0; b < nb; ++b) {
                Pcg32 rng(hash_keys({cfg.seed, q, b}));
                for (size_t s = 0; s < s_n; ++s) {
                    const size_t row = ((j - j0) * nb + b) * s_n + s;
                    const Vec3f w = normalize(frame.to_world(square_to_direction(bin_to_square(int(b), R, {rng.next_float(), rng.next_float()}))));
                    rays[row] = Ray{offset_ray_origin(p, n, w), w};
                    keys[row] = (q * nb + b) * s_n + s;
                }
            }
        }
        const std::vector<Vec3f> l = traced_bounce_radiance(model_irradiance(model, lat), pt, rays, keys, direct, with_emission);
        for (size_t row = 0; row < rows; ++row) bins[j0 * nb + row / s_n] += l[row] / float(S);
    }
    return bins;
}

double sq_err(const Vec3f *a, const Vec3f *b, size_t n) {
    double e = 0;
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) e += double(a[i][c] - b[i][c]) * double(a[i][c] - b[i][c]);
    return e;
}
}  // namespace

DirectionalEvalResult evaluate_directional(LtmModel &model, const std::string &data_dir, const DirectionalEvalOptions &opt) {
    if (!model->directional) LTM_THROW("model '", model->cfg.name, "' has no directional head (train one: ltm train --head directional)");
    if (opt.points_per_record < 1 || opt.l_max < 0) LTM_THROW("directional eval: need points >= 1 and l_max >= 0");
    if (model->cfg.traced_inputs > 0)
        LTM_THROW("directional eval: model '", model->cfg.name, "' has traced inputs, which this evaluation of records does not trace");
    const DirectionalConfig &dc = *model->cfg.directional;
    const auto paths = list_records(data_dir);
    if (paths.empty()) LTM_THROW(data_dir, ": no dataset records (scene-*.safetensors)");
    torch::NoGradGuard no_grad;
    model->eval();
    const int R = dc.bin_resolution, nb = R * R;
    const BinShFit sh(R, opt.l_max);
    const bool indirect = dc.radiance == "indirect";
    const bool with_prior = opt.prior_cells > 0 && model->cfg.physics.prior_field == "transport";
    DirectionalEvalResult res;
    res.resolution = R, res.radiance = dc.radiance;
    res.sh.assign(size_t(opt.l_max + 1), 0.0);
    res.head_beats_sh.assign(size_t(opt.l_max + 1), 0);
    if (opt.traced_samples < 0) LTM_THROW("directional eval: traced samples per bin must be >= 0, got ", opt.traced_samples);
    const bool with_traced = opt.traced_samples > 0;
    if (with_traced) res.traced_beats_sh.assign(size_t(opt.l_max + 1), 0);
    double ref2 = 0, prior_err = 0, traced_err = 0, gap_m = 0, gap_r = 0, e_model_sum = 0, e_ref_sum = 0, seconds = 0;
    std::vector<std::vector<Vec3f>> tile_rows;   // per tiled point: ref, head, SH 2, SH l_max
    for (const std::string &path : paths) {
        const SceneRecord r = read_record(path);
        check_directional_record(r, dc);
        const int64_t nq = int64_t(r.query_points.size()), np = std::min<int64_t>(nq, opt.points_per_record);
        std::vector<int64_t> pts;
        for (int64_t j = 0; j < np; ++j) pts.push_back(j * nq / np);
        const HemisphereRows hemi = hemisphere_rows(r.query_points, pts, R);
        const auto t0 = std::chrono::steady_clock::now();
        const auto sp = point_tensor(r.scene_points);
        torch::Tensor es;
        if (r.emission_scale) es = torch::tensor({r.emission_scale->x, r.emission_scale->y, r.emission_scale->z});
        const SceneLatents lat = model->encode(sp, model->scene_geometry(sp), es);
        const auto pred = model->predict_radiance(rows_tensor(hemi.query, 9), rows_tensor(hemi.direction, 3), lat).contiguous();
        seconds += seconds_since(t0);
        std::vector<float> qp;
        for (int64_t q : pts)
            for (int c = 0; c < 9; ++c) qp.push_back(r.query_points.at(size_t(q), size_t(c)));
        const auto e_hat = model->predict_irradiance(rows_tensor(qp, 9), lat).contiguous();
        const Vec3f *head = reinterpret_cast<const Vec3f *>(pred.data_ptr<float>());
        torch::Tensor prior_l;   // the directional transport prior's bins, [P·R², 3]
        if (with_prior)
            prior_l = radiance_scale(rows_tensor(hemi.query, 9), rows_tensor(hemi.direction, 3), lat.norm, opt.prior_cells).contiguous();
        std::vector<Vec3f> traced;   // one traced bounce's bins, [P·R²]
        if (with_traced) traced = traced_bins(model, lat, r, pts, R, opt.traced_samples, /*with_emission=*/!indirect);
        for (int64_t j = 0; j < np; ++j) {
            const size_t q = size_t(pts[size_t(j)]);
            const std::vector<Vec3f> ref(reinterpret_cast<const Vec3f *>(r.l_in.data()) + q * size_t(nb),
                                         reinterpret_cast<const Vec3f *>(r.l_in.data()) + (q + 1) * size_t(nb));
            const Vec3f *h = head + size_t(j) * size_t(nb);
            Vec3f e_ref(0.f), e_model(0.f), integral(0.f);
            for (int c = 0; c < 3; ++c) {
                e_ref[c] = r.e_indirect[q * 3 + size_t(c)] + (indirect ? 0.f : r.e_direct[q * 3 + size_t(c)]);
                e_model[c] = e_hat.data_ptr<float>()[j * 3 + c] + (indirect ? 0.f : r.e_direct[q * 3 + size_t(c)]);
            }
            for (int b = 0; b < nb; ++b) integral += h[b] * (float(k_pi) / float(nb));
            const std::vector<Vec3f> uniform(size_t(nb), e_ref / float(k_pi)), uniform_model(size_t(nb), e_model / float(k_pi));
            for (const Vec3f &l : ref) ref2 += double(dot(l, l));
            const double eh = sq_err(h, ref.data(), size_t(nb));
            res.head += eh;
            res.uniform += sq_err(uniform.data(), ref.data(), size_t(nb));
            res.uniform_model += sq_err(uniform_model.data(), ref.data(), size_t(nb));
            if (with_prior) prior_err += sq_err(reinterpret_cast<const Vec3f *>(prior_l.data_ptr<float>()) + size_t(j) * size_t(nb), ref.data(), size_t(nb));
            const double et = with_traced ? sq_err(traced.data() + size_t(j) * size_t(nb), ref.data(), size_t(nb)) : 0.0;
            traced_err += et;
            std::vector<std::vector<Vec3f>> fits;
            for (int l = 0; l <= opt.l_max; ++l) {
                fits.push_back(sh.fit(ref, l));
                const double es_l = sq_err(fits.back().data(), ref.data(), size_t(nb));
                res.sh[size_t(l)] += es_l;
                res.head_beats_sh[size_t(l)] += eh < es_l;
                if (with_traced) res.traced_beats_sh[size_t(l)] += et < es_l;
            }
            for (int c = 0; c < 3; ++c) {
                gap_m += std::abs(double(integral[c] - e_model[c])), gap_r += std::abs(double(integral[c] - e_ref[c]));
                e_model_sum += std::abs(double(e_model[c])), e_ref_sum += std::abs(double(e_ref[c]));
            }
            if (int(tile_rows.size()) < opt.tiles * 4) {
                tile_rows.push_back(ref);
                tile_rows.emplace_back(h, h + nb);
                tile_rows.push_back(fits[size_t(std::min(2, opt.l_max))]);
                tile_rows.push_back(fits.back());
            }
            ++res.points;
        }
        ++res.records;
        log_info(path, ": ", np, " hemispheres");
    }
    const double norm = ref2 > 0 ? ref2 : 1.0;
    res.head /= norm, res.uniform /= norm, res.uniform_model /= norm;
    if (with_prior) res.prior = prior_err / norm, res.prior_cells = opt.prior_cells;
    if (with_traced) res.traced = traced_err / norm, res.traced_samples = opt.traced_samples;
    for (double &e : res.sh) e /= norm;
    res.hemisphere_gap_vs_model = gap_m / std::max(e_model_sum, 1e-30);
    res.hemisphere_gap_vs_ref = gap_r / std::max(e_ref_sum, 1e-30);
    res.seconds_per_point = seconds / std::max(1, res.points);
    // Tiles: one row per point, each tile R×R upscaled ×4, exposure per row from the reference's mean.
    const int n_rows = int(tile_rows.size()) / 4, px = 4, gap = 2;
    if (n_rows > 0) {
        res.tiles = Image(4 * (R * px + gap) - gap, n_rows * (R * px + gap) - gap);
        for (int row = 0; row < n_rows; ++row) {
            double mean = 0;
            for (const Vec3f &v : tile_rows[size_t(row * 4)]) mean += double(v.x + v.y + v.z) / (3.0 * nb);
            const float exposure = mean > 0 ? float(0.35 / mean) : 1.f;
            for (int t = 0; t < 4; ++t)
                for (int b = 0; b < nb; ++b)
                    for (int dy = 0; dy < px; ++dy)
                        for (int dx = 0; dx < px; ++dx) {
                            const Vec3f v = tile_rows[size_t(row * 4 + t)][size_t(b)] * exposure;
                            res.tiles.at(t * (R * px + gap) + (b % R) * px + dx, row * (R * px + gap) + (b / R) * px + dy) =
                                Vec3f(std::max(v.x, 0.f), std::max(v.y, 0.f), std::max(v.z, 0.f));
                        }
        }
    }
    return res;
}

OrderedJson DirectionalEvalResult::to_json() const {
    OrderedJson j = {{"records", records}, {"points", points}, {"bin_resolution", resolution}, {"radiance", radiance},
                     {"head_rel_mse", head}, {"uniform_rel_mse", uniform}, {"uniform_model_rel_mse", uniform_model}, {"prior_rel_mse", prior}, {"prior_cells", prior_cells}, {"traced_rel_mse", traced}, {"traced_samples", traced_samples},
                     {"traced_beats_sh_points", traced_beats_sh}, {"sh_rel_mse", sh}, {"head_beats_sh_points", head_beats_sh},
                     {"hemisphere_gap_vs_model", hemisphere_gap_vs_model}, {"hemisphere_gap_vs_ref", hemisphere_gap_vs_ref},
                     {"seconds_per_point", seconds_per_point}};
    return j;
}

std::string DirectionalEvalResult::markdown() const {
    std::ostringstream s;
    s << "| method | relative MSE of " << (radiance == "indirect" ? "L_in⁺" : "L_in") << " bins | points where the head is closer |\n"
      << "|---|---|---|\n";
    s << "| directional head (predicted) | " << head << " | |\n";
    s << "| uniform radiance of the irradiance head's Ê (a head's start without prior_cells) | " << uniform_model << " | |\n";
    if (prior >= 0)
        s << "| directional transport prior alone, " << prior_cells << "×" << prior_cells << " cells | " << prior << " | |\n";
    if (traced >= 0)
        s << "| one traced bounce into Ê⁺, " << traced_samples << " samples per bin (ray traced, not a decoder) | " << traced << " | |\n";
    s << "| uniform radiance, reference's ∫ L cos (oracle floor) | " << uniform << " | |\n";
    for (size_t l = 0; l < sh.size(); ++l)
        s << "| SH best fit to the reference, l ≤ " << l << " (" << (l + 1) * (l + 1) << " coefficients) | " << sh[l] << " | "
          << head_beats_sh[l] << " of " << points << " |\n";
    if (traced >= 0) {
        s << "\nOne traced bounce is closer than the SH fit of degree l = 0, 1, …, " << sh.size() - 1 << " at";
        for (size_t l = 0; l < traced_beats_sh.size(); ++l) s << (l ? ", " : " ") << traced_beats_sh[l];
        s << " of " << points << " points.\n";
    }
    return s.str();
}

}  // namespace ltm
