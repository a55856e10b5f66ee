// model_config.cpp: strict JSON (de)serialisation of the model config.
#include "ltm/nn/model_config.h"

#include "ltm/core/error.h"

namespace ltm {

ModelConfig ModelConfig::from_json(const Json &j, const std::string &where) {
    JsonObject o(j, where);
    ModelConfig c;
    c.name = o.get_string("name", c.name);
    c.scene_points = o.get_int("scene_points", c.scene_points);
    if (c.scene_points < 16) LTM_THROW(o.where("scene_points"), ": must be >= 16");
    if (o.has("embedding")) {
        JsonObject e = o.require_object("embedding");
        c.embedding.dim = e.get_int("dim", c.embedding.dim);
        c.embedding.k = e.get_int("k", c.embedding.k);
        c.embedding.sample_ratio = e.get_float("sample_ratio", c.embedding.sample_ratio);
        c.embedding.relative_position = e.get_bool("relative_position", c.embedding.relative_position);
        e.finish();
        if (c.embedding.dim < 1) LTM_THROW(e.where("dim"), ": must be >= 1");
        if (c.embedding.k < 1) LTM_THROW(e.where("k"), ": must be >= 1");
        if (!(c.embedding.sample_ratio > 0.f && c.embedding.sample_ratio <= 1.f))
            LTM_THROW(e.where("sample_ratio"), ": must be in (0, 1]");
    }
    if (o.has("decoder")) {
        JsonObject d = o.require_object("decoder");
        c.decoder.type = d.get_string("type", c.decoder.type);
        c.decoder.dim = d.get_int("dim", c.decoder.dim);
        c.decoder.n_neighbors = d.get_int("n_neighbors", c.decoder.n_neighbors);
        c.decoder.n_layers = d.get_int("n_layers", c.decoder.n_layers);
        c.decoder.groups = d.get_int("groups", c.decoder.groups);
        c.decoder.ffn_ratio = d.get_int("ffn_ratio", c.decoder.ffn_ratio);
        d.finish();
        if (c.decoder.type != "attention" && c.decoder.type != "knn-mean")
            LTM_THROW(d.where("type"), ": must be \"attention\" or \"knn-mean\", got \"", c.decoder.type, "\"");
        if (c.decoder.dim < 1 || c.decoder.n_neighbors < 1 || c.decoder.n_layers < 1 || c.decoder.groups < 1)
            LTM_THROW(d.where("dim"), ": dim, n_neighbors, n_layers and groups must be >= 1");
        if (c.decoder.ffn_ratio < 1 || c.decoder.ffn_ratio > 64) LTM_THROW(d.where("ffn_ratio"), ": must be in [1, 64]");
        if (c.decoder.dim % c.decoder.groups != 0)
            LTM_THROW(d.where("groups"), ": dim ", c.decoder.dim, " is not divisible by groups ", c.decoder.groups);
    }
    if (o.has("encoder")) {
        Json enc = o.require("encoder");
        if (enc.is_object()) enc["in_channels"] = c.embedding.dim;   // forced: the embedding feeds the encoder
        c.encoder = PTv3Config::from_json(enc, o.where("encoder"));
    }
    c.encoder.in_channels = c.embedding.dim;
    c.physics = PhysicsConfig::legacy();   // v0.3 configs and weights have no "physics" object
    if (o.has("physics")) {
        JsonObject ph = o.require_object("physics");
        c.physics = PhysicsConfig{};
        c.physics.emission_scale = ph.get_bool("emission_scale", c.physics.emission_scale);
        c.physics.length_scale = ph.get_bool("length_scale", c.physics.length_scale);
        c.physics.prior_bounces = ph.get_int("prior_bounces", c.physics.prior_bounces);
        c.physics.translation_invariant = ph.get_bool("translation_invariant", c.physics.translation_invariant);
        c.physics.prior_field = ph.get_string("prior_field", c.physics.prior_field);
        c.physics.prior_nodes = ph.get_string("prior_nodes", c.physics.prior_nodes);
        c.physics.prior_visibility = ph.get_float("prior_visibility", c.physics.prior_visibility);
        ph.finish();
        if (!(c.physics.prior_visibility >= 0.f && c.physics.prior_visibility <= 64.f))
            LTM_THROW(ph.where("prior_visibility"), ": must be in [0, 64] (voxel edge / point spacing), got ", c.physics.prior_visibility);
        if (c.physics.prior_visibility > 0.f && c.physics.prior_field != "transport")
            LTM_THROW(ph.where("prior_visibility"), ": only the \"transport\" prior has visibility");
        if (c.physics.prior_nodes != "anchors" && c.physics.prior_nodes != "points")
            LTM_THROW(ph.where("prior_nodes"), ": must be \"anchors\" or \"points\", got \"", c.physics.prior_nodes, "\"");
        if (c.physics.prior_nodes != "anchors" && c.physics.prior_field != "transport")
            LTM_THROW(ph.where("prior_nodes"), ": only the \"transport\" prior has nodes");
        if (c.physics.prior_field != "flat" && c.physics.prior_field != "transport")
            LTM_THROW(ph.where("prior_field"), ": must be \"flat\" or \"transport\", got \"", c.physics.prior_field, "\"");
        if (c.physics.prior_field == "transport" && (c.physics.prior_bounces < 1 || !c.physics.length_scale))
            LTM_THROW(ph.where("prior_field"), ": \"transport\" needs prior_bounces >= 1 and length_scale");
        if (c.physics.prior_bounces < 0 || c.physics.prior_bounces > 64)
            LTM_THROW(ph.where("prior_bounces"), ": must be in [0, 64]");
        if (c.physics.prior_bounces > 0 && !c.physics.emission_scale)
            LTM_THROW(ph.where("prior_bounces"), ": the power-balance prior needs emission_scale");
    }
    o.finish();
    if (c.n_anchors() < c.decoder.n_neighbors)
        LTM_THROW(where, ": ", c.n_anchors(), " anchors are fewer than decoder.n_neighbors = ", c.decoder.n_neighbors);
    if (c.embedding.k > c.scene_points) LTM_THROW(where, ": embedding.k exceeds scene_points");
    return c;
}

ModelConfig ModelConfig::from_file(const std::string &path) { return from_json(parse_json_file(path), path); }

OrderedJson ModelConfig::to_json() const {
    OrderedJson j;
    j["name"] = name;
    j["scene_points"] = scene_points;
    j["embedding"] = {{"dim", embedding.dim}, {"k", embedding.k}, {"sample_ratio", json_float(embedding.sample_ratio)},
                      {"relative_position", embedding.relative_position}};
    OrderedJson enc = encoder.to_json();
    enc.erase("in_channels");   // derived from embedding.dim
    j["encoder"] = enc;
    j["decoder"] = {{"type", decoder.type}, {"dim", decoder.dim}, {"n_neighbors", decoder.n_neighbors},
                    {"n_layers", decoder.n_layers}, {"groups", decoder.groups}};
    // Written only when not the default: weights and checkpoints from before the key keep their
    // exact JSON (checkpoints compare it on resume).
    if (decoder.ffn_ratio != DecoderConfig{}.ffn_ratio) j["decoder"]["ffn_ratio"] = decoder.ffn_ratio;
    if (physics.any()) {
        j["physics"] = {{"emission_scale", physics.emission_scale}, {"length_scale", physics.length_scale},
                        {"prior_bounces", physics.prior_bounces}};
        // Written only when on: configs and weights from before the key keep their exact JSON
        // (checkpoints compare it on resume).
        if (physics.translation_invariant) j["physics"]["translation_invariant"] = true;
        if (physics.prior_field != "flat") j["physics"]["prior_field"] = physics.prior_field;
        if (physics.prior_nodes != "anchors") j["physics"]["prior_nodes"] = physics.prior_nodes;
        if (physics.prior_visibility > 0.f) j["physics"]["prior_visibility"] = json_float(physics.prior_visibility);
    }
    return j;
}

}  // namespace ltm
