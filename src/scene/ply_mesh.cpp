// ply_mesh.cpp: PLY header + generic element reader (ASCII / binary LE / binary BE).
#include "ltm/scene/ply_mesh.h"

#include <cctype>
#include <cmath>
#include <cstring>
#include <sstream>

#include <zlib.h>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/core/ply_scalar.h"

namespace ltm {

namespace {

struct Property {
    std::string name;
    PlyType type = PlyType::f32;
    bool is_list = false;
    PlyType count_type = PlyType::u8;
};

struct Element {
    std::string name;
    int64_t count = 0;
    std::vector<Property> props;
};

// Reads scalars from the body in the file's encoding.
class BodyReader {
public:
    BodyReader(const std::string &bytes, size_t pos, int format, std::string where)
        : m_bytes(bytes), m_pos(pos), m_format(format), m_where(std::move(where)) {}

    double read(PlyType t) {
        if (m_format == 0) return read_ascii();
        const size_t n = ply_type_size(t);
        if (m_pos + n > m_bytes.size()) LTM_THROW(m_where, ": file is truncated (data ends early)");
        const double v = decode_ply_scalar(m_bytes.data() + m_pos, t, m_format == 2);
        m_pos += n;
        return v;
    }
    size_t remaining() const { return m_bytes.size() - m_pos; }

private:
    double read_ascii() {
        while (m_pos < m_bytes.size() && std::isspace(static_cast<unsigned char>(m_bytes[m_pos]))) ++m_pos;
        if (m_pos >= m_bytes.size()) LTM_THROW(m_where, ": file is truncated (data ends early)");
        const char *start = m_bytes.c_str() + m_pos;
        char *end = nullptr;
        const double v = std::strtod(start, &end);
        if (end == start) LTM_THROW(m_where, ": '", std::string(start, std::min<size_t>(16, m_bytes.size() - m_pos)), "' is not a number");
        m_pos += size_t(end - start);
        return v;
    }
    const std::string &m_bytes;
    size_t m_pos;
    int m_format;   // 0 ascii, 1 binary LE, 2 binary BE
    std::string m_where;
};

std::string gunzip_file(const std::string &path) {
    gzFile f = gzopen(path.c_str(), "rb");
    if (!f) LTM_THROW(path, ": cannot open");
    std::string out;
    char buf[1 << 16];
    int n;
    while ((n = gzread(f, buf, sizeof buf)) > 0) out.append(buf, size_t(n));
    const bool failed = n < 0;
    gzclose(f);
    if (failed) LTM_THROW(path, ": corrupt gzip data");
    return out;
}

}  // namespace

PlyMesh read_ply_mesh(const std::string &path) {
    const bool gz = path.size() > 3 && path.compare(path.size() - 3, 3, ".gz") == 0;
    return parse_ply_mesh(gz ? gunzip_file(path) : read_file(path), path);
}

PlyMesh parse_ply_mesh(const std::string &bytes, const std::string &where) {
    // Header: one line per statement up to "end_header".
    size_t pos = 0;
    int line_no = 0, format = -1;
    std::vector<Element> elements;
    auto next_line = [&](std::string &line) {
        const size_t e = bytes.find('\n', pos);
        if (e == std::string::npos) LTM_THROW(where, ": PLY header has no end_header");
        line = bytes.substr(pos, e - pos);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        pos = e + 1;
        ++line_no;
    };
    std::string line;
    next_line(line);
    if (line != "ply") LTM_THROW(where, ":1: not a PLY file (no 'ply' magic)");
    while (true) {
        next_line(line);
        std::istringstream in(line);
        std::string kw;
        in >> kw;
        const std::string at = detail::concat(where, ":", line_no);
        if (kw == "end_header") break;
        if (kw.empty() || kw == "comment" || kw == "obj_info") continue;
        if (kw == "format") {
            std::string f, v;
            in >> f >> v;
            if (f == "ascii") format = 0;
            else if (f == "binary_little_endian") format = 1;
            else if (f == "binary_big_endian") format = 2;
            else LTM_THROW(at, ": unknown PLY format '", f, "'");
        } else if (kw == "element") {
            Element e;
            if (!(in >> e.name >> e.count) || e.count < 0) LTM_THROW(at, ": bad element line '", line, "'");
            elements.push_back(e);
        } else if (kw == "property") {
            if (elements.empty()) LTM_THROW(at, ": property before any element");
            Property p;
            std::string t;
            in >> t;
            if (t == "list") {
                std::string ct, it;
                in >> ct >> it >> p.name;
                if (!parse_ply_type(ct, p.count_type) || !parse_ply_type(it, p.type)) LTM_THROW(at, ": bad list types in '", line, "'");
                p.is_list = true;
            } else {
                in >> p.name;
                if (!parse_ply_type(t, p.type)) LTM_THROW(at, ": unknown property type '", t, "'");
            }
            if (p.name.empty()) LTM_THROW(at, ": property without a name");
            elements.back().props.push_back(p);
        } else {
            LTM_THROW(at, ": unknown PLY header keyword '", kw, "'");
        }
    }
    if (format < 0) LTM_THROW(where, ": PLY header has no format line");
    // Every element instance takes at least one byte (binary) or one character (ASCII): a count
    // larger than the body is a corrupt header, refused before anything is allocated.
    for (const auto &e : elements)
        if (uint64_t(e.count) > bytes.size() - pos) LTM_THROW(where, ": element '", e.name, "' count ", e.count, " exceeds the file size");

    PlyMesh m;
    BodyReader r(bytes, pos, format, where);
    for (const auto &e : elements) {
        const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
        int ix = -1, iy = -1, iz = -1, inx = -1, iny = -1, inz = -1, iu = -1, iv = -1, iidx = -1;
        for (int k = 0; k < int(e.props.size()); ++k) {
            const std::string &n = e.props[size_t(k)].name;
            if (n == "x") ix = k;
            else if (n == "y") iy = k;
            else if (n == "z") iz = k;
            else if (n == "nx") inx = k;
            else if (n == "ny") iny = k;
            else if (n == "nz") inz = k;
            else if (n == "u" || n == "s" || n == "texture_u" || n == "texture_s") iu = k;
            else if (n == "v" || n == "t" || n == "texture_v" || n == "texture_t") iv = k;
            else if (n == "vertex_indices" || n == "vertex_index") iidx = k;
        }
        if (is_vertex && (ix < 0 || iy < 0 || iz < 0)) LTM_THROW(where, ": vertex element lacks x, y or z");
        if (is_face && (iidx < 0 || !e.props[size_t(iidx)].is_list)) LTM_THROW(where, ": face element lacks a vertex_indices list");
        const bool normals = inx >= 0 && iny >= 0 && inz >= 0, uvs = iu >= 0 && iv >= 0;
        std::vector<double> vals(e.props.size());
        std::vector<uint32_t> poly;
        for (int64_t i = 0; i < e.count; ++i) {
            for (size_t k = 0; k < e.props.size(); ++k) {
                const Property &p = e.props[k];
                if (!p.is_list) {
                    vals[k] = r.read(p.type);
                    continue;
                }
                const double n = r.read(p.count_type);
                if (!(n >= 0 && n <= 1e6) || n != std::floor(n)) LTM_THROW(where, ": ", e.name, " ", i, ": bad list length ", n);
                if (is_face && int(k) == iidx) poly.clear();
                for (int64_t j = 0; j < int64_t(n); ++j) {
                    const double v = r.read(p.type);
                    if (is_face && int(k) == iidx) {
                        if (!(v >= 0 && v < 4294967295.0) || v != std::floor(v)) LTM_THROW(where, ": face ", i, ": bad vertex index ", v);
                        poly.push_back(uint32_t(v));
                    }
                }
            }
            if (is_vertex) {
                const Vec3f p{float(vals[size_t(ix)]), float(vals[size_t(iy)]), float(vals[size_t(iz)])};
                if (!is_finite(p)) LTM_THROW(where, ": vertex ", i, " has a non-finite position");
                m.positions.push_back(p);
                if (normals) m.normals.push_back(Vec3f(float(vals[size_t(inx)]), float(vals[size_t(iny)]), float(vals[size_t(inz)])));
                if (uvs) m.uvs.push_back(Vec2f{float(vals[size_t(iu)]), float(vals[size_t(iv)])});
            } else if (is_face) {
                if (poly.size() < 3) LTM_THROW(where, ": face ", i, " has ", poly.size(), " vertices (at least 3)");
                if (poly.size() > 4) ++m.n_polygons;
                for (size_t j = 1; j + 1 < poly.size(); ++j)   // fan: a quad (0 1 2 3) → (0 1 2), (0 2 3)
                    m.indices.insert(m.indices.end(), {poly[0], poly[j], poly[j + 1]});
            }
        }
    }
    for (uint32_t idx : m.indices)
        if (idx >= m.positions.size()) LTM_THROW(where, ": face index ", idx, " out of range (", m.positions.size(), " vertices)");
    return m;
}

}  // namespace ltm
