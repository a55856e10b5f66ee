// frame_cache.cpp: one safetensors file per (record, point set), named by a fingerprint (header).
#include "ltm/train/frame_cache.h"

#include <cstring>
#include <filesystem>

#include "ltm/core/error.h"
#include "ltm/core/log.h"
#include "ltm/points/safetensors.h"
#include "ltm/train/distributed.h"

namespace ltm {

namespace fs = std::filesystem;

namespace {
constexpr int k_cache_version = 1;   // bump when the entry's contents change meaning

// A file's identity for the fingerprint: size and modification time (ns since the epoch).
std::string file_identity(const fs::path &p) {
    std::error_code ec;
    const auto size = fs::file_size(p, ec);
    if (ec) LTM_THROW(p.string(), ": cannot read its size (", ec.message(), ")");
    const auto time = fs::last_write_time(p, ec);
    if (ec) LTM_THROW(p.string(), ": cannot read its modification time (", ec.message(), ")");
    return std::to_string(size) + "@" + std::to_string(time.time_since_epoch().count());
}

StTensor to_st(const torch::Tensor &t) {
    const auto c = t.detach().to(torch::kCPU).contiguous();
    StTensor s;
    if (c.scalar_type() == torch::kFloat32) s.dtype = "F32";
    else if (c.scalar_type() == torch::kInt64) s.dtype = "I64";
    else LTM_THROW("frame cache: cannot store a tensor of type ", c.scalar_type());
    s.shape.assign(c.sizes().begin(), c.sizes().end());
    s.data.resize(size_t(c.numel()) * c.element_size());
    if (!s.data.empty()) std::memcpy(s.data.data(), c.data_ptr(), s.data.size());
    return s;
}

torch::Tensor from_st(const StTensor &s, const std::string &where) {
    const auto type = s.dtype == "F32" ? torch::kFloat32 : s.dtype == "I64" ? torch::kInt64 : torch::kUInt8;
    if (type == torch::kUInt8) LTM_THROW(where, ": dtype ", s.dtype, " is not F32 or I64");
    auto t = torch::empty(s.shape, torch::TensorOptions().dtype(type));
    if (size_t(t.numel()) * t.element_size() != s.data.size()) LTM_THROW(where, ": ", s.data.size(), " bytes do not fit its shape");
    if (!s.data.empty()) std::memcpy(t.data_ptr(), s.data.data(), s.data.size());
    return t;
}
}  // namespace

FrameCache::FrameCache(const std::string &dir) : m_dir(dir) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir)) LTM_THROW(dir, ": cannot create the frame cache folder (", ec.message(), ")");
    // The running program's inode (the link is followed: a binary replaced since it started still
    // names the one that runs).
    m_program = file_identity("/proc/self/exe");
}

std::string FrameCache::path_for(const ModelConfig &cfg, const std::string &record_path, int set) const {
    const Json model = cfg.to_json();
    Json key = {{"version", k_cache_version},
                {"program", m_program},
                {"record", fs::path(record_path).filename().string()},
                {"record_file", file_identity(record_path)},
                {"set", set},
                {"scene_points", cfg.scene_points},
                {"prior_inputs", cfg.prior_inputs},
                {"point_prior", cfg.prior_inputs || cfg.decoder.level_points > 0},   // stored with the frame
                {"traced_inputs", cfg.traced_inputs},
                {"traced_queries", cfg.traced_queries},
                {"embedding", model.value("embedding", Json())},
                {"physics", model.value("physics", Json())}};
    return (fs::path(m_dir) / (fs::path(record_path).stem().string() + ".set" + std::to_string(set) + "." +
                               fingerprint_of(key.dump()) + ".safetensors")).string();
}

std::optional<FrameCacheEntry> FrameCache::load(const std::string &path, int64_t n_queries, bool traced, bool traced_queries) const {
    if (!fs::exists(path)) return std::nullopt;
    try {
        const SafetensorsFile f = read_safetensors(path);
        auto get = [&](const char *name, bool required) -> torch::Tensor {
            const auto it = f.tensors.find(name);
            if (it == f.tensors.end()) {
                if (required) LTM_THROW(path, ": no tensor '", name, "'");
                return {};
            }
            return from_st(it->second, path + " (" + name + ")");
        };
        FrameCacheEntry e;
        e.scene_points = get("scene_points", true), e.centers = get("centers", true), e.groups = get("groups", true);
        e.emission_scale = get("emission_scale", false);
        e.center = get("center", true), e.length = get("length", true), e.emission = get("emission", true);
        e.output = get("output", true), e.point_prior = get("point_prior", false), e.query_scale = get("query_scale", true);
        e.point_traced = get("point_traced", false);
        e.query_regathered = get("query_regathered", false);
        const int64_t m = e.scene_points.dim() == 2 ? e.scene_points.size(0) : -1;
        const bool ok = m > 0 && e.scene_points.size(1) == 12 && e.scene_points.scalar_type() == torch::kFloat32 &&
                        e.centers.dim() == 1 && e.centers.scalar_type() == torch::kInt64 && e.groups.dim() == 2 &&
                        e.groups.scalar_type() == torch::kInt64 && e.groups.size(0) == e.centers.size(0) &&
                        (e.centers.numel() == 0 || (e.centers.min().item<int64_t>() >= 0 && e.centers.max().item<int64_t>() < m)) &&
                        (e.groups.numel() == 0 || (e.groups.min().item<int64_t>() >= 0 && e.groups.max().item<int64_t>() < m)) &&
                        (!e.point_prior.defined() || (e.point_prior.dim() == 2 && e.point_prior.size(0) == m && e.point_prior.size(1) == 3)) &&
                        (!e.point_traced.defined() || (e.point_traced.dim() == 2 && e.point_traced.size(0) == m && e.point_traced.size(1) == 6 &&
                                                       e.point_traced.scalar_type() == torch::kFloat32)) &&
                        (!e.query_regathered.defined() || e.query_regathered.scalar_type() == torch::kFloat32) &&
                        e.query_scale.dim() >= 1 && e.query_scale.size(-1) == 3;
        if (!ok) LTM_THROW(path, ": tensor types or shapes do not fit together");
        if (traced && !e.point_traced.defined()) LTM_THROW(path, ": no traced inputs, and the model has them");
        if (traced_queries && !(e.query_regathered.dim() == 2 && e.query_regathered.size(0) == n_queries && e.query_regathered.size(1) == 3))
            LTM_THROW(path, ": no regathered prior at the record's ", n_queries, " queries, and the model reads it");
        if (e.query_scale.dim() == 2 && e.query_scale.size(0) != n_queries)
            LTM_THROW(path, " holds the prior at ", e.query_scale.size(0), " queries, the record has ", n_queries);
        return e;
    } catch (const std::exception &err) {
        log_warn("frame cache: ", err.what(), " — computing it again");
        return std::nullopt;
    }
}

void FrameCache::store(const std::string &path, const FrameCacheEntry &e) const {
    SafetensorsFile f;
    auto put = [&](const char *name, const torch::Tensor &t) {
        if (t.defined()) f.tensors[name] = to_st(t);
    };
    put("scene_points", e.scene_points), put("centers", e.centers), put("groups", e.groups);
    put("emission_scale", e.emission_scale), put("center", e.center), put("length", e.length);
    put("emission", e.emission), put("output", e.output), put("point_prior", e.point_prior), put("query_scale", e.query_scale);
    put("point_traced", e.point_traced), put("query_regathered", e.query_regathered);
    f.metadata["format"] = "ltm-frame-cache";
    try {
        write_safetensors(path, f);
    } catch (const std::exception &err) {   // a full disk or a read-only folder costs speed, not the run
        log_warn("frame cache: ", err.what(), " — not kept");
    }
}

}  // namespace ltm
