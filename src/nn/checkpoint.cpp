// checkpoint.cpp: safetensors weights and torch-archive training checkpoints.
#include "ltm/nn/checkpoint.h"

#include <cstring>
#include <filesystem>

#include "ltm/core/error.h"
#include "ltm/points/safetensors.h"

namespace ltm {

namespace {
std::map<std::string, torch::Tensor> state_dict(LtmModel &model) {
    std::map<std::string, torch::Tensor> out;
    for (const auto &p : model->named_parameters()) out[p.key()] = p.value();
    for (const auto &b : model->named_buffers()) out[b.key()] = b.value();
    return out;
}

void atomic_rename(const std::string &tmp, const std::string &path) {
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) LTM_THROW(path, ": cannot rename into place: ", ec.message());
}
}  // namespace

void save_weights(const std::string &path, LtmModel &model, const std::map<std::string, std::string> &extra, bool half) {
    SafetensorsFile f;
    for (const auto &[name, t] : state_dict(model)) {
        const auto c = t.detach().to(torch::kCPU, half ? torch::kHalf : torch::kFloat32).contiguous();
        StTensor st;
        st.dtype = half ? "F16" : "F32";
        st.shape.assign(c.sizes().begin(), c.sizes().end());
        const char *bytes = static_cast<const char *>(c.data_ptr());
        st.data.assign(bytes, bytes + c.numel() * int64_t(c.element_size()));
        f.tensors[name] = std::move(st);
    }
    f.metadata = extra;
    f.metadata["format"] = "ltm-weights";
    f.metadata["format_version"] = std::to_string(k_weights_format_version);
    f.metadata["arch_version"] = std::to_string(k_arch_version);
    f.metadata["config"] = model->cfg.to_json().dump();
    write_safetensors(path, f);
}

namespace {
// The model's parameters and buffers against named sources: the same names on both sides and equal
// shapes, else a one-line error naming `where`; then fill(name, dst, source) for each, without autograd.
// load_state copies tensors, load_weights widens a file's bytes in place: one set of checks for both.
template <class Source, class ShapeOf, class Fill>
void fill_state(LtmModel &model, const std::map<std::string, Source> &sources, const std::string &where, ShapeOf shape_of, Fill fill) {
    torch::NoGradGuard no_grad;
    auto own = state_dict(model);
    for (const auto &[name, s] : sources)
        if (!own.count(name)) LTM_THROW(where, ": unexpected tensor '", name, "': weights of another architecture");
    for (auto &[name, dst] : own) {
        const auto it = sources.find(name);
        if (it == sources.end()) LTM_THROW(where, ": missing tensor '", name, "': weights of another architecture");
        const c10::IntArrayRef shape = shape_of(it->second);
        if (shape != dst.sizes()) LTM_THROW(where, ": tensor '", name, "' has shape ", shape, ", the model expects ", dst.sizes());
        fill(name, dst, it->second);
    }
}
}  // namespace

void load_state(LtmModel &model, const std::map<std::string, torch::Tensor> &tensors, const std::string &where) {
    fill_state(
        model, tensors, where, [](const torch::Tensor &t) { return t.sizes(); },
        [](const std::string &, torch::Tensor &dst, const torch::Tensor &t) { dst.copy_(t); });
}

LtmModel load_weights(const std::string &path, std::map<std::string, std::string> *metadata) {
    const WeightsFile w = read_weights_file(path);   // the format, versions, config and dtypes checked
    const SafetensorsFile &f = w.file;
    const ModelConfig &cfg = w.config;
    LtmModel model(cfg);
    // Each tensor goes from the mapped file's bytes straight into the parameter the model already
    // holds (F16 widened on the way; computation is always F32): no second set of tensors to fault in.
    fill_state(
        model, f.tensors, path, [](const StTensor &t) { return c10::IntArrayRef(t.shape); },
        [&](const std::string &name, torch::Tensor &dst, const StTensor &t) {
            const std::string where = path + ": tensor '" + name + "'";
            if (dst.is_contiguous() && dst.scalar_type() == torch::kFloat32) return t.copy_f32(dst.data_ptr<float>(), where);
            auto wide = torch::empty(t.shape, torch::kFloat32);
            t.copy_f32(wide.data_ptr<float>(), where);
            dst.copy_(wide);
        });
    if (metadata) *metadata = f.metadata;
    return model;
}

void save_checkpoint(const std::string &path, LtmModel &model, torch::optim::Optimizer &opt, const TrainState &s) {
    torch::serialize::OutputArchive archive, model_archive, opt_archive;
    model->save(model_archive);
    opt.save(opt_archive);
    archive.write("model", model_archive);
    archive.write("optimizer", opt_archive);
    archive.write("format", c10::IValue(std::string("ltm-checkpoint")));
    archive.write("format_version", c10::IValue(int64_t(k_weights_format_version)));
    archive.write("arch_version", c10::IValue(int64_t(k_arch_version)));
    archive.write("step", c10::IValue(s.step));
    archive.write("best_val", c10::IValue(s.best_val));
    archive.write("model_config", c10::IValue(s.model_config));
    archive.write("train_config", c10::IValue(s.train_config));
    const std::string tmp = path + ".tmp";
    archive.save_to(tmp);
    atomic_rename(tmp, path);
}

namespace {
torch::serialize::InputArchive open_checkpoint(const std::string &path) {
    if (!std::filesystem::is_regular_file(path)) LTM_THROW(path, ": checkpoint not found");
    torch::serialize::InputArchive archive;
    try {
        archive.load_from(path);
    } catch (const std::exception &e) {
        LTM_THROW(path, ": not a readable checkpoint (", std::string(e.what()).substr(0, 120), ")");
    }
    c10::IValue v;
    if (!archive.try_read("format", v) || !v.isString() || v.toStringRef() != "ltm-checkpoint")
        LTM_THROW(path, ": not an ltm checkpoint");
    if (!archive.try_read("arch_version", v) || v.toInt() != k_arch_version)
        LTM_THROW(path, ": checkpoint of another architecture version");
    return archive;
}
}  // namespace

TrainState read_checkpoint_state(const std::string &path) {
    auto archive = open_checkpoint(path);
    TrainState s;
    c10::IValue v;
    archive.read("step", v);
    s.step = v.toInt();
    archive.read("best_val", v);
    s.best_val = v.toDouble();
    archive.read("model_config", v);
    s.model_config = v.toStringRef();
    archive.read("train_config", v);
    s.train_config = v.toStringRef();
    return s;
}

namespace {
void load_model_archive(const std::string &path, torch::serialize::InputArchive &archive, LtmModel &model) {
    torch::serialize::InputArchive model_archive;
    archive.read("model", model_archive);
    try {
        model->load(model_archive);
    } catch (const std::exception &e) {
        LTM_THROW(path, ": checkpoint does not fit this model (", std::string(e.what()).substr(0, 160), ")");
    }
}
}  // namespace

void load_checkpoint(const std::string &path, LtmModel &model, torch::optim::Optimizer &opt) {
    auto archive = open_checkpoint(path);
    load_model_archive(path, archive, model);
    torch::serialize::InputArchive opt_archive;
    archive.read("optimizer", opt_archive);
    opt.load(opt_archive);
}

void load_checkpoint_model(const std::string &path, LtmModel &model) {
    auto archive = open_checkpoint(path);
    load_model_archive(path, archive, model);
}

}  // namespace ltm
