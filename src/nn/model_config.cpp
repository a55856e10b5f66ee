// model_config.cpp: strict JSON (de)serialisation of the model config.
#include "ltm/nn/model_config.h"

#include "ltm/core/error.h"

namespace ltm {

const ConfigFields<EmbeddingConfig> &EmbeddingConfig::fields() {
    using C = EmbeddingConfig;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("dim", &C::dim, "D: width of 𝓕 and 𝓖 and of the encoder's input", at_least(1))
            .field("k", &C::k, "neighbours grouped around each FPS centre (paper: open)", at_least(1))
            .field("sample_ratio", &C::sample_ratio, "m = M·ratio FPS centres, the anchors (paper: M → M/2)", above_up_to(0, 1))
            .field("relative_position", &C::relative_position, "also feed p_j − p̃_l to 𝓖 (PointNet++ style; eq. 6 omits it)");
    return f;
}

const ConfigFields<DecoderConfig> &DecoderConfig::fields() {
    using C = DecoderConfig;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("type", &C::type, "vector cross-attention, or the Fig. 14 ablation", {}, {"attention", "knn-mean"})
            .field("dim", &C::dim, "D of query features and attention values", at_least(1))
            .field("n_neighbors", &C::n_neighbors, "κ nearest anchors per query (paper Tab. 2: 32)", at_least(1))
            .field("n_layers", &C::n_layers, "stacked cross-attention blocks", at_least(1))
            .field("groups", &C::groups, "G weight groups of grouped vector attention (PTv2); divides dim", at_least(1))
            .field("ffn_ratio", &C::ffn_ratio, "hidden width of each block's FFN = ffn_ratio · dim", between(1, 64))
            .omit_default()
            .field("level_points", &C::level_points, "K > 0: the output keeps the prior's level over the K first anchors (with traced_queries, the regathered prior's; 0: free)", at_least(0))
            .omit_default();
    return f;
}

const ConfigFields<DirectionalConfig> &DirectionalConfig::fields() {
    using C = DirectionalConfig;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("dim", &C::dim, "D of the head's query features and attention values", at_least(1))
            .field("n_layers", &C::n_layers, "stacked cross-attention blocks", at_least(1))
            .field("groups", &C::groups, "G weight groups of grouped vector attention; divides dim", at_least(1))
            .field("ffn_ratio", &C::ffn_ratio, "hidden width of each block's FFN = ffn_ratio · dim", between(1, 64))
            .field("direction_frequencies", &C::direction_frequencies, "F octaves of the direction's Fourier features sin/cos(2^k π ω)", between(0, 12))
            .field("bin_resolution", &C::bin_resolution, "R of the R×R hemisphere bins it is trained on and renders/guides with (paper: 32)", between(1, 256))
            .field("radiance", &C::radiance, "what it predicts: L_in⁺ (scattered light only; direct light stays exact) or the paper's L_in (emitters included)", {}, {"indirect", "incident"})
            .field("prior_cells", &C::prior_cells, "the head predicts the ratio to the directional transport prior over R×R cells (0: to the uniform radiance Ê_prior/π)", between(0, 64))
            .omit_default();
    return f;
}

const ConfigFields<PhysicsConfig> &PhysicsConfig::fields() {
    using C = PhysicsConfig;
    static const ConfigFields<C> f =
        ConfigFields<C>()
            .field("emission_scale", &C::emission_scale, "emission enters divided by S = Φ/A and the output is multiplied back: E⁺ exactly linear in emission")
            .field("length_scale", &C::length_scale, "positions enter in units of the point spacing: E⁺ invariant to the unit of length")
            .field("prior_bounces", &C::prior_bounces, "bounces D of the power-balance prior the output is a ratio to (0 = none)", between(0, 64))
            .field("translation_invariant", &C::translation_invariant, "no layer sees an absolute position, only differences")
            .omit_default()
            .field("prior_field", &C::prior_field, "one level per scene, or the radiosity solve among the points (transport/transport_prior.h)", {}, {"flat", "transport"})
            .omit_default()
            .field("prior_nodes", &C::prior_nodes, "the transport prior's nodes: the FPS anchors or all scene points", {}, {"anchors", "points"})
            .omit_default()
            .field("prior_visibility", &C::prior_visibility, "occlusion in the transport prior: voxel edge in point spacings (0 = none)", between(0, 64))
            .omit_default()
            .field("prior_clusters", &C::prior_clusters, "occlusion clusters of the transport prior (visibility is decided between them)", between(16, 16384))
            .omit_default()
            .field("prior_discs", &C::prior_discs, "occlusion in the transport prior by the scene points as discs of this radius in point spacings (0 = by the voxels)", between(0, 8))
            .omit_default()
            .field("prior_balance", &C::prior_balance, "the occluded transport prior's power balance: a gain per channel, one grey gain, or none", {}, {"channel", "grey", "none"})
            .omit_default()
            .field("prior_blend", &C::prior_blend, "each receiver of the transport prior blends the visibility of its K nearest visible occlusion clusters (1 = its one cluster)", between(1, 7))
            .omit_default()
            .field("prior_patches", &C::prior_patches, "the transport prior's near field by the exact form factors of square patches (else the point formula)")
            .omit_default()
            .field("prior_open_rays", &C::prior_open_rays, "rows of the transport prior sum to each receiver's closure from R x R rays per occlusion cluster against the discs (0 = every receiver closed)", between(0, 64))
            .omit_default()
            .field("prior_theta", &C::prior_theta, "the transport prior through its cluster tree with this opening bound (0 = the dense rows)", between(0, 1))
            .omit_default()
            .field("prior_rays", &C::prior_rays, "the transport prior's visibility and closure by rays against the scene's meshes (needs prior_theta > 0)")
            .omit_default()
            .field("prior_regathered", &C::prior_regathered, "the prior is R, the transport's regather of the light traced at its nodes (no bounces solved); the points' prior input is their traced E⁺ (needs prior_inputs and traced_inputs; not with traced_queries or decoder.level_points)")
            .omit_default();
    return f;
}

const ConfigFields<ModelConfig> &ModelConfig::fields() {
    using C = ModelConfig;
    static const ConfigFields<C> f = ConfigFields<C>()
                                         .field("name", &C::name, "preset name (informational)")
                                         .field("scene_points", &C::scene_points, "M scene points the model is trained with (must match the dataset)", at_least(16))
                                         .field("prior_inputs", &C::prior_inputs, "scene points and queries also carry the transport prior's Ê⁺ there, log1p(Ê⁺ / S·Σρ̄^k): the network sees what it corrects")
                                         .omit_default()
                                         .field("traced_inputs", &C::traced_inputs, "> 0: paths traced per scene point (strata); every scene point also carries its traced E⁺ and the prior regathered from the traced light, in the prior inputs' normalisation (needs prior_inputs; inference and training trace the scene)", between(0, 4096))
                                         .omit_default()
                                         .field("traced_queries", &C::traced_queries, "with traced_inputs: every query also carries ln(R / Ê), the regathered prior's ratio to the prior there, as an input and through a learned per-channel skip to the output (needs traced_inputs; with decoder.level_points the level held is the regathered prior's)")
                                         .omit_default()
                                         .field("auto_scene_points", &C::auto_scene_points, "at inference the point count follows each scene as --scene-points auto does, unless --scene-points is given (training uses scene_points)")
                                         .omit_default();
    return f;
}

std::string ModelConfig::markdown_tables() {
    return fields().markdown_table() + "\n" + EmbeddingConfig::fields().markdown_table("embedding.") + "\n" +
           PTv3Config::fields().markdown_table("encoder.") + "\n" + DecoderConfig::fields().markdown_table("decoder.") + "\n" +
           PhysicsConfig::fields().markdown_table("physics.") + "\n" + DirectionalConfig::fields().markdown_table("directional.");
}

ModelConfig ModelConfig::from_json(const Json &j, const std::string &where) {
    ModelConfig c = fields().read(j, where, ModelConfig{}, [](JsonObject &o, ModelConfig &m) { read_sections(o, m); });
    if (c.n_anchors() < c.decoder.n_neighbors)
        LTM_THROW(where, ": ", c.n_anchors(), " anchors are fewer than decoder.n_neighbors = ", c.decoder.n_neighbors);
    if (c.embedding.k > c.scene_points) LTM_THROW(where, ": embedding.k exceeds scene_points");
    return c;
}

void ModelConfig::read_sections(JsonObject &o, ModelConfig &c) {
    if (o.has("embedding")) c.embedding = EmbeddingConfig::fields().read(o.require("embedding"), o.where("embedding"));
    if (o.has("decoder"))
        c.decoder = DecoderConfig::fields().read(o.require("decoder"), o.where("decoder"), DecoderConfig{}, [](JsonObject &d, DecoderConfig &dc) {
            if (dc.dim % dc.groups != 0) LTM_THROW(d.where("groups"), ": dim ", dc.dim, " is not divisible by groups ", dc.groups);
        });
    if (o.has("encoder")) {
        Json enc = o.require("encoder");
        if (enc.is_object()) enc["in_channels"] = c.embedding.dim;   // forced: the embedding feeds the encoder
        c.encoder = PTv3Config::from_json(enc, o.where("encoder"));
    }
    c.encoder.in_channels = c.embedding.dim;
    c.physics = PhysicsConfig::legacy();   // v0.3 configs and weights have no "physics" object
    if (o.has("physics"))
        c.physics = PhysicsConfig::fields().read(o.require("physics"), o.where("physics"), PhysicsConfig{}, [](JsonObject &ph, PhysicsConfig &p) {
            if (p.prior_clusters != PhysicsConfig{}.prior_clusters && !(p.prior_visibility > 0.f))
                LTM_THROW(ph.where("prior_clusters"), ": occlusion clusters need prior_visibility > 0");
            if (p.prior_balance != PhysicsConfig{}.prior_balance && !(p.prior_visibility > 0.f))
                LTM_THROW(ph.where("prior_balance"), ": the power balance applies only with prior_visibility > 0");
            if (p.prior_blend != PhysicsConfig{}.prior_blend && !(p.prior_visibility > 0.f))
                LTM_THROW(ph.where("prior_blend"), ": blending occlusion clusters needs prior_visibility > 0");
            if (p.prior_open_rays > 0 && p.prior_balance != "none")
                LTM_THROW(ph.where("prior_open_rays"), ": the power balance restores a closed room's level and would undo the open share: needs prior_balance \"none\"");
            if (p.prior_open_rays > 0 && !(p.prior_discs > 0.f))
                LTM_THROW(ph.where("prior_open_rays"), ": the open share is measured against the discs: needs prior_discs > 0");
            if (p.prior_discs > 0.f && !(p.prior_visibility > 0.f))
                LTM_THROW(ph.where("prior_discs"), ": occlusion discs need prior_visibility > 0");
            if (p.prior_rays && p.prior_field != "transport")
                LTM_THROW(ph.where("prior_rays"), ": only the \"transport\" prior has visibility");
            if (p.prior_visibility > 0.f && p.prior_field != "transport")
                LTM_THROW(ph.where("prior_visibility"), ": only the \"transport\" prior has visibility");
            if (p.prior_patches && p.prior_field != "transport")
                LTM_THROW(ph.where("prior_patches"), ": only the \"transport\" prior has a near field");
            if (p.prior_nodes != "anchors" && p.prior_field != "transport")
                LTM_THROW(ph.where("prior_nodes"), ": only the \"transport\" prior has nodes");
            if (p.prior_field == "transport" && (p.prior_bounces < 1 || !p.length_scale))
                LTM_THROW(ph.where("prior_field"), ": \"transport\" needs prior_bounces >= 1 and length_scale");
            if (p.prior_bounces > 0 && !p.emission_scale)
                LTM_THROW(ph.where("prior_bounces"), ": the power-balance prior needs emission_scale");
        });
    if (o.has("directional"))
        c.directional = DirectionalConfig::fields().read(o.require("directional"), o.where("directional"), DirectionalConfig{},
                                                         [](JsonObject &d, DirectionalConfig &dc) {
                                                             if (dc.dim % dc.groups != 0)
                                                                 LTM_THROW(d.where("groups"), ": dim ", dc.dim, " is not divisible by groups ", dc.groups);
                                                         });
    if (c.prior_inputs && c.physics.prior_field != "transport")
        LTM_THROW(o.where("prior_inputs"), ": prior inputs need physics.prior_field \"transport\" (the prior they carry)");
    if (c.traced_inputs > 0 && !c.prior_inputs)
        LTM_THROW(o.where("traced_inputs"), ": traced inputs need prior_inputs (they stand beside the prior's own, in its normalisation)");
    if (c.traced_queries && c.traced_inputs <= 0)
        LTM_THROW(o.where("traced_queries"), ": traced queries need traced_inputs > 0 (the traced light they regather)");
    if (c.physics.prior_regathered && (c.physics.prior_field != "transport" || !c.prior_inputs || c.traced_inputs <= 0))
        LTM_THROW(o.where("physics"), ": prior_regathered needs prior_field \"transport\", prior_inputs and traced_inputs > 0 (R regathers the traced light)");
    if (c.physics.prior_regathered && (c.traced_queries || c.decoder.level_points > 0))
        LTM_THROW(o.where("physics"), ": prior_regathered replaces traced_queries' ln(R / Ê) and holds no level (decoder.level_points): not with either");
    if (c.physics.prior_regathered && c.directional && c.directional->prior_cells > 0)
        LTM_THROW(o.where("directional"), ": prior_cells splits the solved prior's gather, and physics.prior_regathered solves none");
    if (c.directional && c.directional->prior_cells > 0 && c.physics.prior_field != "transport")
        LTM_THROW(o.where("directional"), ": prior_cells needs physics.prior_field \"transport\" (the directional prior splits its gather)");
}

ModelConfig ModelConfig::from_file(const std::string &path) { return from_json(parse_json_file(path), path); }

OrderedJson ModelConfig::to_json() const {
    OrderedJson j = fields().write(*this);
    j["embedding"] = EmbeddingConfig::fields().write(embedding);
    OrderedJson enc = encoder.to_json();
    enc.erase("in_channels");   // derived from embedding.dim
    j["encoder"] = enc;
    j["decoder"] = DecoderConfig::fields().write(decoder);
    // Keys marked omit_default are written only when set: configs, weights and checkpoints from
    // before them keep their exact JSON (checkpoints compare it on resume).
    if (physics.any()) j["physics"] = PhysicsConfig::fields().write(physics);
    if (directional) j["directional"] = DirectionalConfig::fields().write(*directional);
    return j;
}

}  // namespace ltm
