// ply_io.cpp: an in-house PLY reader/writer (no Debian package provides one). The reader is
// fuzzed (fuzz/ply_fuzzer.cpp): every length and count is checked before it is trusted.
#include "ltm/points/ply_io.h"

#include <cmath>
#include <cstring>
#include <sstream>

#include "ltm/core/color.h"
#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/core/ply_scalar.h"

namespace ltm {

namespace {

constexpr size_t k_max_points = size_t(1) << 31;

bool is_rgb_byte_column(const std::string &name) {
    return name == "red" || name == "green" || name == "blue";
}

struct Header {
    bool binary = false;
    size_t n_vertices = 0;
    std::vector<std::string> names;
    std::vector<PlyType> types;
    size_t data_offset = 0;   // byte offset of the first data byte
    size_t data_line = 0;     // line number of the first ASCII data line
};

Header parse_header(const std::string &bytes, const std::string &where) {
    Header h;
    size_t pos = 0, line_no = 0;
    bool seen_format = false, in_vertex = false, seen_vertex = false, seen_other = false;
    auto next_line = [&](std::string &line) {
        const size_t end = bytes.find('\n', pos);
        if (end == std::string::npos) LTM_THROW(where, ":", line_no + 1, ": truncated header (no end_header)");
        line = bytes.substr(pos, end - pos);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        pos = end + 1;
        ++line_no;
    };
    std::string line;
    next_line(line);
    if (line != "ply") LTM_THROW(where, ":1: not a PLY file (first line must be 'ply')");
    while (true) {
        next_line(line);
        std::istringstream ss(line);
        std::string kw;
        ss >> kw;
        const std::string at = where + ":" + std::to_string(line_no);
        if (kw.empty() || kw == "comment" || kw == "obj_info") continue;
        if (kw == "end_header") break;
        if (kw == "format") {
            std::string fmt, ver;
            ss >> fmt >> ver;
            if (fmt == "ascii") h.binary = false;
            else if (fmt == "binary_little_endian") h.binary = true;
            else if (fmt == "binary_big_endian") LTM_THROW(at, ": binary_big_endian PLY is not supported");
            else LTM_THROW(at, ": unknown PLY format '", fmt, "'");
            if (ver != "1.0") LTM_THROW(at, ": unsupported PLY version '", ver, "'");
            seen_format = true;
        } else if (kw == "element") {
            std::string name;
            long long count = -1;
            ss >> name >> count;
            if (ss.fail() || count < 0) LTM_THROW(at, ": malformed element line");
            in_vertex = name == "vertex";
            if (in_vertex) {
                if (seen_vertex) LTM_THROW(at, ": duplicate vertex element");
                if (seen_other) LTM_THROW(at, ": the vertex element must be the first element");
                if (size_t(count) > k_max_points) LTM_THROW(at, ": vertex count ", count, " is too large");
                h.n_vertices = size_t(count);
                seen_vertex = true;
            } else {
                seen_other = true;
            }
        } else if (kw == "property") {
            if (!seen_vertex && !seen_other) LTM_THROW(at, ": property before any element");
            std::string type, name;
            ss >> type;
            if (type == "list") {
                if (in_vertex) LTM_THROW(at, ": list properties in the vertex element are not supported");
                continue;
            }
            ss >> name;
            PlyType t;
            if (!parse_ply_type(type, t)) LTM_THROW(at, ": unknown property type '", type, "'");
            if (name.empty()) LTM_THROW(at, ": property without a name");
            if (in_vertex) {
                for (const auto &n : h.names)
                    if (n == name) LTM_THROW(at, ": duplicate property '", name, "'");
                h.names.push_back(name);
                h.types.push_back(t);
            }
        } else {
            LTM_THROW(at, ": unknown header keyword '", kw, "'");
        }
    }
    if (!seen_format) LTM_THROW(where, ": header has no format line");
    if (!seen_vertex) LTM_THROW(where, ": no vertex element");
    if (h.names.empty()) LTM_THROW(where, ": vertex element has no properties");
    h.data_offset = pos;
    h.data_line = line_no + 1;
    return h;
}

}  // namespace

PointSet parse_ply(const std::string &bytes, const std::string &where) {
    const Header h = parse_header(bytes, where);
    PointSet pts;
    pts.columns = h.names;
    const size_t nc = h.names.size();
    if (h.binary) {
        size_t stride = 0;
        for (PlyType t : h.types) stride += ply_type_size(t);
        const size_t available = bytes.size() - h.data_offset;
        if (h.n_vertices > available / stride)
            LTM_THROW(where, ": truncated: header declares ", h.n_vertices, " vertices of ", stride,
                      " bytes but only ", available, " data bytes follow");
        pts.values.resize(h.n_vertices * nc);
        const char *p = bytes.data() + h.data_offset;
        for (size_t i = 0; i < h.n_vertices; ++i)
            for (size_t c = 0; c < nc; ++c) {
                pts.values[i * nc + c] = float(decode_ply_scalar(p, h.types[c]));
                p += ply_type_size(h.types[c]);
            }
    } else {
        std::istringstream in(bytes.substr(h.data_offset));
        std::string line;
        pts.values.reserve(std::min(h.n_vertices, size_t(1) << 20) * nc);
        for (size_t i = 0; i < h.n_vertices; ++i) {
            const std::string at = where + ":" + std::to_string(h.data_line + i);
            if (!std::getline(in, line))
                LTM_THROW(at, ": truncated: expected ", h.n_vertices, " vertices, got ", i);
            std::istringstream ls(line);
            for (size_t c = 0; c < nc; ++c) {
                double v;
                if (!(ls >> v)) LTM_THROW(at, ": expected ", nc, " numbers, could not read '", h.names[c], "'");
                pts.values.push_back(float(v));
            }
        }
    }
    for (size_t i = 0; i < pts.values.size(); ++i)
        if (!std::isfinite(pts.values[i]))
            LTM_THROW(where, ": vertex ", i / nc, " property '", h.names[i % nc], "' is not finite");
    return pts;
}

PointSet read_ply(const std::string &path) { return parse_ply(read_file(path), path); }

void write_ply(const std::string &path, const PointSet &points, const PlyWriteOptions &opt) {
    AtomicFile f(path);
    write_ply(f.stream(), points, opt);
    f.commit();
}

void write_ply(std::ostream &out, const PointSet &points, const PlyWriteOptions &opt) {
    const size_t n = points.size(), nc = points.n_columns();
    LTM_CHECK(nc > 0);
    // Output columns: the set's own, plus rgb bytes derived from albedo if asked for.
    const int ar = points.find_column("albedo_r");
    const bool add_rgb = opt.add_rgb_from_albedo && ar >= 0 && points.find_column("red") < 0;
    std::ostringstream hdr;
    hdr << "ply\nformat " << (opt.binary ? "binary_little_endian" : "ascii") << " 1.0\n";
    if (!opt.comment.empty()) hdr << "comment " << opt.comment << "\n";
    hdr << "element vertex " << n << "\n";
    for (const auto &c : points.columns)
        hdr << "property " << (is_rgb_byte_column(c) ? "uchar " : "float ") << c << "\n";
    if (add_rgb) hdr << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    hdr << "end_header\n";

    out << hdr.str();
    std::string row;
    for (size_t i = 0; i < n; ++i) {
        row.clear();
        auto put_float = [&](float v) {
            if (opt.binary) row.append(reinterpret_cast<const char *>(&v), 4);
            else {
                char buf[32];
                std::snprintf(buf, sizeof buf, "%.9g ", double(v));
                row += buf;
            }
        };
        auto put_byte = [&](float v) {
            const uint8_t b = uint8_t(std::lround(clamp(v, 0.f, 255.f)));
            if (opt.binary) row.push_back(char(b));
            else row += std::to_string(int(b)) + " ";
        };
        for (size_t c = 0; c < nc; ++c) {
            if (is_rgb_byte_column(points.columns[c])) put_byte(points.at(i, c));
            else put_float(points.at(i, c));
        }
        if (add_rgb)
            for (int k = 0; k < 3; ++k) put_byte(255.f * linear_to_srgb(points.at(i, size_t(ar + k))));
        if (!opt.binary) row.back() = '\n';
        out.write(row.data(), std::streamsize(row.size()));
    }
}

}  // namespace ltm
