// point_set.h: a table of points with named float columns (PLY properties), the in-memory form
// of scene points [M, 12] and query points [N, 9] (ARCHITECTURE.md §4).
#pragma once

#include <string>
#include <vector>

#include "ltm/core/math.h"

namespace ltm {

/// Column layout of scene points: p, n, albedo, emission (radiance).
const std::vector<std::string> &scene_point_columns();
/// Column layout of query points: p, n, albedo.
const std::vector<std::string> &query_point_columns();
/// Writes one query point in that layout: row[0..9) = p, n, albedo.
inline void write_query_row(float *row, Vec3f p, Vec3f n, Vec3f albedo) {
    const Vec3f cols[3] = {p, n, albedo};
    for (int c = 0; c < 3; ++c)
        for (int a = 0; a < 3; ++a) row[c * 3 + a] = cols[c][a];
}

struct PointSet {
    std::vector<std::string> columns;   ///< property names, e.g. "x", "albedo_r"
    std::vector<float> values;          ///< row-major [size(), columns.size()]

    PointSet() = default;
    PointSet(std::vector<std::string> cols, size_t n_points);
    size_t size() const { return columns.empty() ? 0 : values.size() / columns.size(); }
    size_t n_columns() const { return columns.size(); }
    /// Column index, or -1.
    int find_column(const std::string &name) const;
    /// Column index; throws "where: missing column 'name'".
    size_t require_column(const std::string &name, const std::string &where) const;
    float &at(size_t i, size_t c) { return values[i * columns.size() + c]; }
    float at(size_t i, size_t c) const { return values[i * columns.size() + c]; }
    Vec3f vec3(size_t i, size_t first_col) const {
        return {at(i, first_col), at(i, first_col + 1), at(i, first_col + 2)};
    }
    void set_vec3(size_t i, size_t first_col, Vec3f v) {
        at(i, first_col) = v.x, at(i, first_col + 1) = v.y, at(i, first_col + 2) = v.z;
    }
    /// The given columns in the given order (e.g. scene_point_columns()); throws if one is missing.
    PointSet select(const std::vector<std::string> &names, const std::string &where) const;
};

}  // namespace ltm
