// point_set.cpp: column bookkeeping.
#include "ltm/points/point_set.h"

#include "ltm/core/error.h"

namespace ltm {

const std::vector<std::string> &scene_point_columns() {
    static const std::vector<std::string> c = {"x", "y", "z", "nx", "ny", "nz",
                                               "albedo_r", "albedo_g", "albedo_b",
                                               "emission_r", "emission_g", "emission_b"};
    return c;
}

const std::vector<std::string> &query_point_columns() {
    static const std::vector<std::string> c = {"x", "y", "z", "nx", "ny", "nz",
                                               "albedo_r", "albedo_g", "albedo_b"};
    return c;
}

PointSet::PointSet(std::vector<std::string> cols, size_t n_points)
    : columns(std::move(cols)), values(columns.size() * n_points, 0.f) {}

int PointSet::find_column(const std::string &name) const {
    for (size_t i = 0; i < columns.size(); ++i)
        if (columns[i] == name) return int(i);
    return -1;
}

size_t PointSet::require_column(const std::string &name, const std::string &where) const {
    const int c = find_column(name);
    if (c < 0) LTM_THROW(where, ": missing column '", name, "'");
    return size_t(c);
}

PointSet PointSet::select(const std::vector<std::string> &names, const std::string &where) const {
    std::vector<size_t> src;
    for (const auto &n : names) src.push_back(require_column(n, where));
    PointSet out(names, size());
    for (size_t i = 0; i < size(); ++i)
        for (size_t c = 0; c < names.size(); ++c) out.at(i, c) = at(i, src[c]);
    return out;
}

}  // namespace ltm
