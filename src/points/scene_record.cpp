// scene_record.cpp: record files — safetensors tensors + "ltm" JSON metadata, checked on reading.
#include "ltm/points/scene_record.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "ltm/core/error.h"
#include "ltm/points/safetensors.h"

namespace fs = std::filesystem;

namespace ltm {

std::string record_file_name(uint64_t seed) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "scene-%06llu.safetensors", (unsigned long long)seed);
    return buf;
}

void write_record(const std::string &path, const SceneRecord &r) {
    const int64_t m = int64_t(r.scene_points.size()), n = int64_t(r.query_points.size());
    LTM_CHECK_EQ(r.scene_points.n_columns(), size_t(12));
    LTM_CHECK_EQ(r.query_points.n_columns(), size_t(9));
    LTM_CHECK_EQ(r.e_direct.size(), size_t(3 * n));
    LTM_CHECK_EQ(r.e_indirect.size(), size_t(3 * n));
    SafetensorsFile f;
    f.tensors["scene_points"] = make_f32_tensor({m, 12}, r.scene_points.values.data());
    f.tensors["query_points"] = make_f32_tensor({n, 9}, r.query_points.values.data());
    f.tensors["E_direct"] = make_f32_tensor({n, 3}, r.e_direct.data());
    f.tensors["E_indirect"] = make_f32_tensor({n, 3}, r.e_indirect.data());
    if (r.emission_scale) {
        const float s[3] = {r.emission_scale->x, r.emission_scale->y, r.emission_scale->z};
        f.tensors["emission_scale"] = make_f32_tensor({3}, s);
    }
    if (r.bin_resolution > 0) {
        const int64_t nb = int64_t(r.bin_resolution) * r.bin_resolution;
        LTM_CHECK_EQ(r.l_in.size(), size_t(n * nb * 3));
        f.tensors["L_in"] = make_f32_tensor({n, nb, 3}, r.l_in.data());
    }
    f.metadata["ltm"] = r.metadata.dump();
    write_safetensors(path, f);
}

SceneRecord read_record(const std::string &path) {
    const SafetensorsFile f = read_safetensors(path);
    SceneRecord r;
    r.path = path;
    const auto it = f.metadata.find("ltm");
    if (it == f.metadata.end()) LTM_THROW(path, ": not an ltm dataset record (no 'ltm' metadata)");
    r.metadata = OrderedJson::parse(parse_json(it->second, path + " (metadata)").dump());
    const int version = r.metadata.value("format_version", 0);
    if (version != k_record_format_version)
        LTM_THROW(path, ": record format version ", version, ", this build reads ", k_record_format_version);
    r.seed = r.metadata.value("seed", uint64_t(0));
    const auto &sp = f.require("scene_points", "F32", {-1, 12}, path);
    const auto &qp = f.require("query_points", "F32", {-1, 9}, path);
    const int64_t n = qp.shape[0];
    r.scene_points = PointSet(scene_point_columns(), size_t(sp.shape[0]));
    r.scene_points.values = sp.as_f32(path);
    r.query_points = PointSet(query_point_columns(), size_t(n));
    r.query_points.values = qp.as_f32(path);
    r.e_direct = f.require("E_direct", "F32", {n, 3}, path).as_f32(path);
    r.e_indirect = f.require("E_indirect", "F32", {n, 3}, path).as_f32(path);
    for (const auto *v : {&r.scene_points.values, &r.query_points.values, &r.e_direct, &r.e_indirect})
        for (float x : *v)
            if (!std::isfinite(x)) LTM_THROW(path, ": record contains NaN or Inf");
    if (f.tensors.count("emission_scale")) {
        const auto s = f.require("emission_scale", "F32", {3}, path).as_f32(path);
        for (float x : s)
            if (!(std::isfinite(x) && x >= 0.f)) LTM_THROW(path, ": emission_scale must be finite and >= 0");
        r.emission_scale = Vec3f(s[0], s[1], s[2]);
    }
    if (f.tensors.count("L_in")) {
        const auto &t = f.tensors.at("L_in");
        const int64_t nb = t.shape.size() == 3 ? t.shape[1] : 0;
        const int res = int(std::lround(std::sqrt(double(nb))));
        if (nb <= 0 || int64_t(res) * res != nb)
            LTM_THROW(path, ": L_in must be [N, R², 3] with a square bin count, got ", t.shape.size() == 3 ? nb : -1, " bins");
        r.l_in = f.require("L_in", "F32", {n, nb, 3}, path).as_f32(path);
        for (float x : r.l_in)
            if (!(std::isfinite(x) && x >= 0.f)) LTM_THROW(path, ": L_in must be finite and >= 0");
        r.bin_resolution = res;
    }
    return r;
}

std::vector<std::string> list_records(const std::string &dir) {
    if (!fs::is_directory(dir)) LTM_THROW(dir, ": dataset directory not found");
    std::vector<std::string> out;
    for (const auto &e : fs::directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        if (name.rfind("scene-", 0) == 0 && e.path().extension() == ".safetensors") out.push_back(e.path().string());
    }
    std::sort(out.begin(), out.end());   // zero-padded seeds: lexicographic = numeric
    return out;
}

std::vector<std::string> list_records(const std::vector<std::string> &dirs) {
    if (dirs.empty()) LTM_THROW("no dataset directory given");
    std::vector<std::pair<std::string, std::string>> named;   // (file name = seed order, path)
    for (const auto &dir : dirs)
        for (auto &path : list_records(dir)) named.emplace_back(fs::path(path).filename().string(), std::move(path));
    std::sort(named.begin(), named.end());
    std::vector<std::string> out;
    for (size_t i = 0; i < named.size(); ++i) {
        if (i > 0 && named[i].first == named[i - 1].first)
            LTM_THROW(named[i].second, ": seed also present as ", named[i - 1].second, " (one record per seed)");
        out.push_back(std::move(named[i].second));
    }
    return out;
}

}  // namespace ltm
