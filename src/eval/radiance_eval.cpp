// radiance_eval.cpp: rendered images (direct + GI; conductors by a traced bounce, the directional head, or as diffuse)
// against path tracing; see radiance_eval.h.
#include "ltm/eval/radiance_eval.h"

#include <algorithm>
#include <cmath>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/core/log.h"
#include "ltm/eval/field_metrics.h"
#include "ltm/eval/image_grid.h"
#include "ltm/eval/metrics.h"
#include "ltm/infer/neural_renderer.h"
#include "ltm/render/gbuffer.h"
#include "ltm/render/image_renderer.h"

namespace ltm {

namespace {

// The values of `img` at the pixels where mask != 0, in pixel order.
std::vector<Vec3f> masked_pixels(const Image &img, const std::vector<uint8_t> &mask) {
    std::vector<Vec3f> out;
    for (size_t i = 0; i < mask.size(); ++i)
        if (mask[i]) out.push_back(img.pixels[i]);
    return out;
}

}  // namespace

RadianceEvalReport run_radiance_evaluation(const std::vector<EvalScene> &scenes, std::vector<EvalModel> &models,
                                           const RadianceEvalOptions &opt) {
    const EvalOptions &o = opt.base;
    if (o.views < 1) LTM_THROW("eval: views must be >= 1, got ", o.views);
    if (o.ref_spp < 1 || o.baseline_spp < 1 || opt.direct_spp < 1) LTM_THROW("eval: samples per pixel must be >= 1");
    if (opt.glossy_samples < 0) LTM_THROW("eval: glossy samples per pixel must be >= 0 (0: automatic), got ", opt.glossy_samples);
    RadianceEvalReport report;
    for (EvalReport *r : {&report.all, &report.conductors}) {
        r->options = o;
        for (const auto &m : models) r->models.push_back(m.name);
    }
    report.all.quantity = "Radiance towards the eye (the rendered image: emission + direct + indirect, conductors by "
                          "their BRDF) at every pixel's centre ray";
    report.conductors.quantity = "The same radiance at conductor pixels only (SSIM: windows centred on them)";
    if (!o.out_dir.empty()) create_directories(o.out_dir);
    for (size_t si = 0; si < scenes.size(); ++si) {
        const EvalScene &es = scenes[si];
        const EmbreeAccel accel(es.scene);
        for (auto &m : models) m.fit_scene_points(es.scene);
        auto tracer = [&](EvalRole role) { return PathTracer(accel, eval_tracer_config(o.seed, role)); };
        const PathTracer pt_ref = tracer(EvalRole::reference), pt_base = tracer(EvalRole::baseline),
                         pt_eq = tracer(EvalRole::equal_time), pt_neural = tracer(EvalRole::neural_direct);
        for (int v = 0; v < o.views; ++v) {
            const auto view = eval_view(accel, es.name, v, o.views, o.width, o.height);
            if (!view) continue;
            const Camera &cam = view->camera;
            const GBuffer &gb = view->gbuffer;
            log_info("eval --radiance: ", es.name, " / ", cam.name, " (", si + 1, "/", scenes.size(), ")");
            std::vector<uint8_t> conductor(size_t(cam.width) * size_t(cam.height), 0);
            for (size_t k = 0; k < gb.n_hits(); ++k) conductor[size_t(gb.hit_pixels[k])] = !gb.diffuse[k];
            const int64_t n_conductor = std::count(conductor.begin(), conductor.end(), uint8_t(1));
            report.conductor_pixels += n_conductor;
            const RenderedImage ref = render_pathtraced(pt_ref, cam, o.ref_spp, /*jitter=*/false);
            ViewResult all, cond;
            all.scene = cond.scene = es.name, all.view = cond.view = cam.name;
            all.pixels = int64_t(gb.n_hits()), cond.pixels = n_conductor;
            all.reference_seconds = cond.reference_seconds = ref.seconds;
            const std::vector<Vec3f> ref_hits = gather_hits(gb, ref.color), ref_cond = masked_pixels(ref.color, conductor);
            auto add = [&](const std::string &method, const Image &img, double secs, int spp) {
                all.methods.push_back({method, compare_images(img, ref.color), secs, spp, compare_fields(gather_hits(gb, img), ref_hits)});
                if (n_conductor > 0)
                    cond.methods.push_back({method, compare_images_masked(img, ref.color, conductor), secs, spp,
                                            compare_fields(masked_pixels(img, conductor), ref_cond)});
            };
            std::vector<Image> tiles{scatter_to_image(gb, gb.albedo), ref.color};
            double first_model_seconds = 0;
            Image first_model;
            for (size_t mi = 0; mi < models.size(); ++mi) {
                NeuralRenderOptions no;
                no.direct_spp = opt.direct_spp, no.seed = o.seed, no.exclude_enclosed = o.exclude_enclosed;
                no.glossy_samples = opt.glossy_samples, no.glossy = GlossyShading::trace, no.bounce = opt.bounce;
                const NeuralRender traced = render_neural(models[mi].model, pt_neural, cam, no);
                add("model:" + models[mi].name, traced.image.color, traced.timings.total, 0);
                if (mi == 0) first_model_seconds = traced.timings.total, first_model = traced.image.color;
                if (mi == 0) tiles.push_back(traced.image.color);
                {
                    // The bounce's Ê⁺ the other way: decoded at each hit (the reference), or with
                    // --bounce-irradiance decode interpolated from the points. Where the render
                    // already took that way (auto with few rays), or the view shows no conductor
                    // (only conductor pixels differ), the row repeats the render's image and time:
                    // every row summarises the same views.
                    NeuralRenderOptions other = no;
                    other.bounce = opt.bounce == BounceIrradiance::decode ? BounceIrradiance::nodes : BounceIrradiance::decode;
                    const std::string row = "model:" + models[mi].name + "/bounce-" + bounce_irradiance_name(other.bounce);
                    if (n_conductor > 0 && traced.bounce != other.bounce) {
                        const NeuralRender alt = render_neural(models[mi].model, pt_neural, cam, other);
                        add(row, alt.image.color, alt.timings.total, 0);
                    } else {
                        add(row, traced.image.color, traced.timings.total, 0);
                    }
                }
                {
                    // The model's own prior, the network silenced, at the pixels and the bounce's
                    // hits: what the network adds to the rendered image is the model row against
                    // this one. Its time leaves out the encoder (a prior needs none).
                    NeuralRenderOptions po = no;
                    po.prior_only = true;
                    const NeuralRender prior = render_neural(models[mi].model, pt_neural, cam, po);
                    add("model-prior:" + models[mi].name, prior.image.color,
                        prior.timings.total - prior.timings.encode + prior.timings.prior_solve, 0);
                }
                if (models[mi].model->directional) {
                    // Conductors through the directional head (paper Fig. 11): the same render but
                    // for L⁺ along the GGX samples; the same image where the view shows no conductor.
                    no.glossy = GlossyShading::head;
                    const NeuralRender head = render_neural(models[mi].model, pt_neural, cam, no);
                    add("model:" + models[mi].name + "/head-conductors", head.image.color, head.timings.total, 0);
                    if (mi == 0) tiles.push_back(head.image.color);
                }
                // Conductors as diffuse (--glossy diffuse), composed from the render's E_direct and
                // Ê⁺ (its AOVs), so it costs the render less the conductor pass.
                const Image diffuse = compose_image(gb, traced.image.direct, traced.image.irradiance).color;
                add("model:" + models[mi].name + "/diffuse-conductors", diffuse, traced.timings.total - traced.timings.glossy, 0);
                if (mi == 0) tiles.push_back(diffuse);
            }
            const RenderedImage base = render_pathtraced(pt_base, cam, o.baseline_spp, /*jitter=*/false);
            add("pt" + std::to_string(o.baseline_spp), base.color, base.seconds, o.baseline_spp);
            tiles.push_back(base.color);
            if (!models.empty()) {
                // PT at the neural render's wall time: spp scaled from the baseline's measured rate.
                const int spp_eq = std::max(1, int(std::lround(double(o.baseline_spp) * first_model_seconds / base.seconds)));
                const RenderedImage eq = render_pathtraced(pt_eq, cam, spp_eq, /*jitter=*/false);
                add("pt-equal-time", eq.color, eq.seconds, spp_eq);
                tiles.push_back(eq.color);
            }
            // The floor: every hit pixel the reference's own mean colour over hit pixels.
            const Color3d mc = mean_color(ref_hits);
            add("flat-oracle", scatter_to_image(gb, std::vector<Vec3f>(gb.n_hits(), Vec3f{float(mc[0]), float(mc[1]), float(mc[2])})),
                0.0, 0);
            if (!o.out_dir.empty()) {
                const float scale = tonemap_scale(ref.color);
                for (size_t t = 1; t < tiles.size(); ++t) tiles[t] = tonemap(tiles[t], scale);
                if (!models.empty()) tiles.push_back(error_map(first_model, ref.color, scale));
                write_png(o.out_dir + "/radiance_" + es.name + "_" + cam.name + ".png", hconcat(tiles), 1.f);
            }
            report.all.views.push_back(std::move(all));
            if (n_conductor > 0) report.conductors.views.push_back(std::move(cond));
        }
    }
    return report;
}

OrderedJson RadianceEvalReport::to_json() const {
    return {{"all_pixels", all.to_json()}, {"conductor_pixels", conductors.to_json()}, {"n_conductor_pixels", conductor_pixels}};
}

std::string RadianceEvalReport::table_markdown() const {
    std::string s = "### All pixels\n\n" + all.table_markdown();
    s += "\n### Conductor pixels (" + std::to_string(conductor_pixels) + " over " +
         std::to_string(conductors.views.size()) + " views)\n\n";
    s += conductors.views.empty() ? std::string("No view shows a conductor.\n") : conductors.table_markdown();
    return s;
}

}  // namespace ltm
