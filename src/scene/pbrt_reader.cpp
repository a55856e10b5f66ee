// pbrt_reader.cpp: pbrt-v4 directives → graphics state → world-space triangle meshes.
#include "ltm/scene/pbrt_reader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <vector>

#include "ltm/core/color.h"
#include "ltm/core/error.h"
#include "ltm/core/file_util.h"
#include "ltm/core/image.h"
#include "ltm/core/log.h"
#include "ltm/scene/material.h"
#include "ltm/scene/mesh_builder.h"
#include "ltm/scene/pbrt_tokenizer.h"
#include "ltm/scene/ply_mesh.h"

namespace fs = std::filesystem;

namespace ltm {

namespace {

using Kind = PbrtToken::Kind;

// Affine 4×4 (row-major, last row 0 0 0 1) in double: pbrt composes many transforms.
struct Mat4 {
    double m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
    Mat4 operator*(const Mat4 &b) const {
        Mat4 r;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) {
                double s = 0;
                for (int k = 0; k < 4; ++k) s += m[i][k] * b.m[k][j];
                r.m[i][j] = s;
            }
        return r;
    }
    double det3() const {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    }
    // Inverse of an affine matrix; nullopt if its linear part is singular.
    std::optional<Mat4> inverse() const {
        const double d = det3();
        if (!(std::abs(d) > 1e-300) || !std::isfinite(d)) return std::nullopt;
        Mat4 r;
        r.m[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) / d;
        r.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / d;
        r.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / d;
        r.m[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) / d;
        r.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / d;
        r.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / d;
        r.m[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) / d;
        r.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / d;
        r.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / d;
        for (int i = 0; i < 3; ++i) r.m[i][3] = -(r.m[i][0] * m[0][3] + r.m[i][1] * m[1][3] + r.m[i][2] * m[2][3]);
        return r;
    }
    Vec3f point(Vec3f p) const {
        return Vec3f(float(m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3]),
                     float(m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3]),
                     float(m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]));
    }
    Vec3f vector(Vec3f v) const {
        return Vec3f(float(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z), float(m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z),
                     float(m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z));
    }
    Transform to_transform() const {
        Transform t;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 4; ++j) t.m[i][j] = float(m[i][j]);
        return t;
    }
    static Mat4 from(const Transform &t) {
        Mat4 r;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 4; ++j) r.m[i][j] = t.m[i][j];
        return r;
    }
};

Vec3f vec3_at(const std::vector<double> &v, size_t i) { return {float(v[i]), float(v[i + 1]), float(v[i + 2])}; }

struct Param {
    std::string type, name, where;
    std::vector<double> nums;
    std::vector<std::string> strs;   // strings and bare words (true/false)
    bool used = false;
};

struct PbrtMaterial {
    std::string type = "diffuse", name;
    Material mat;
    bool drop = false;   // shapes with it are dropped (glass, media boundaries, unsupported)
};

struct AreaLight {
    Vec3f le{0.f};
};

struct State {
    Mat4 ctm;
    bool reverse = false;
    int material = 0;   // index into Reader::m_materials
    std::optional<AreaLight> light;
    bool transform_only = false;   // pushed by TransformBegin
};

class Reader {
public:
    Reader(std::string base_dir, bool allow_files) : m_base(std::move(base_dir)), m_allow_files(allow_files) {
        PbrtMaterial def;
        def.name = "pbrt_default";
        def.mat.name = def.name;
        def.mat.albedo = Texture::constant(Vec3f(0.5f));
        m_materials.push_back(def);
    }

    void parse(const std::string &text, const std::string &file) {
        m_files.push_back(std::make_unique<PbrtTokenizer>(text, file));
        while (!m_files.empty()) {
            PbrtToken t = m_files.back()->next();
            if (t.kind == Kind::end) {
                m_files.pop_back();
                continue;
            }
            if (t.kind != Kind::word) LTM_THROW(t.where(), ": expected a directive, got '", t.text, "'");
            directive(t);
        }
        if (!m_stack.empty()) LTM_THROW(file, ": ", m_stack.size(), " AttributeBegin without AttributeEnd at the end of the file");
        if (m_in_object) LTM_THROW(file, ": ObjectBegin without ObjectEnd at the end of the file");
    }

    Scene finish(const std::string &file) {
        if (!m_scene.has_emitter() && m_skipped_lights > 0)
            LTM_THROW(file, ": no area lights; its ", m_skipped_lights,
                      " LightSource(s) (point, spot, infinite, distant, ...) are out of scope: ltm supports area lights only "
                      "(AreaLightSource \"diffuse\")");
        // Handedness and up axis (see pbrt_reader.h), decided by the camera.
        Mat4 fix;
        bool mirror = true;
        std::string up_axis = "+y";
        std::optional<Camera> cam;
        if (m_camera_from_world) {
            const auto wfc = m_camera_from_world->inverse();
            if (!wfc) LTM_THROW(m_camera_where, ": the camera transform is singular");
            const Vec3f eye = wfc->point(Vec3f(0.f)), fwd = normalize(wfc->vector({0, 0, 1})), up = normalize(wfc->vector({0, 1, 0}));
            const Vec3f right = wfc->vector({1, 0, 0});
            mirror = dot(right, cross(up, fwd)) > 0.f;   // pbrt's left-handed camera: right = up × forward
            if (mirror) fix.m[0][0] = -1;
            const Vec3f up_m = fix.vector(up);
            const Vec3f a(std::abs(up_m.x), std::abs(up_m.y), std::abs(up_m.z));
            Transform turn;
            if (a.z >= a.x && a.z >= a.y) {
                up_axis = up_m.z > 0 ? "+z" : "-z";
                turn = Transform::rotate({1, 0, 0}, up_m.z > 0 ? -90.f : 90.f);
            } else if (a.x >= a.y) {
                up_axis = up_m.x > 0 ? "+x" : "-x";
                turn = Transform::rotate({0, 0, 1}, up_m.x > 0 ? 90.f : -90.f);
            } else if (up_m.y < 0) {
                up_axis = "-y";
                turn = Transform::rotate({1, 0, 0}, 180.f);
            }
            fix = Mat4::from(turn) * fix;
            Camera c;
            c.name = "pbrt";
            c.eye = fix.point(eye);
            c.target = c.eye + fix.vector(fwd);
            c.up = normalize(fix.vector(up));
            c.width = m_film_w, c.height = m_film_h;
            const double half = 0.5 * m_fov_deg * double(k_pi) / 180.0;
            c.fov_y_deg = float(m_film_w >= m_film_h ? m_fov_deg
                                                      : 2.0 * std::atan(std::tan(half) * double(m_film_h) / double(m_film_w)) * 180.0 / double(k_pi));
            cam = c;
        } else if (mirror) {
            fix.m[0][0] = -1;
        }
        for (auto &mesh : m_scene.meshes) transform_mesh(mesh, fix.to_transform());
        // Real files hold slivers and specks (a kitchen of 1.4 M triangles: one of 2e-11 m²) that
        // pbrt-v4 renders past: dropped by the rule validation checks, after the last transform (the
        // up-axis turn rounds every vertex again, and a sliver kept before it could fail after).
        if (const std::string dropped = drop_degenerate_triangles(m_scene); !dropped.empty()) warn(dropped);
        for (const auto &[msg, count] : m_warnings) log_warn(file, ": ", msg, count > 1 ? detail::concat(" (", count, "×)") : "");
        if (cam) m_scene.cameras.push_back(*cam);
        m_scene.metadata["pbrt"] = {{"file", file}, {"mirrored_x", mirror}, {"up_axis", up_axis},
                                    {"unit", "unspecified (pbrt has no unit of length)"}};
        return std::move(m_scene);
    }

private:
    // ---- tokens and parameters ----
    PbrtTokenizer &tok() const { return *m_files.back(); }

    PbrtToken expect(Kind k, const char *what) {
        PbrtToken t = tok().next();
        if (t.kind != k) LTM_THROW(t.where(), ": expected ", what, ", got '", t.kind == Kind::end ? "end of file" : t.text, "'");
        return t;
    }

    // The next token, a quoted name (`what`), looked up in `named`; else "<unknown> '<name>'".
    template <class V> const V &lookup(const std::map<std::string, V> &named, const char *what, const char *unknown) {
        const PbrtToken s = expect(Kind::string, what);
        const auto it = named.find(s.text);
        if (it == named.end()) LTM_THROW(s.where(), ": ", unknown, " '", s.text, "'");
        return it->second;
    }
    double number() { return expect(Kind::number, "a number").number; }
    std::string string() { return expect(Kind::string, "a quoted string").text; }

    // Numbers either bracketed or bare (pbrt accepts both for Transform/ConcatTransform).
    std::vector<double> numbers(size_t n) {
        std::vector<double> v;
        const bool bracket = tok().peek().kind == Kind::open;
        if (bracket) tok().next();
        for (size_t i = 0; i < n; ++i) v.push_back(number());
        if (bracket) expect(Kind::close, "']'");
        return v;
    }

    std::vector<Param> params() {
        std::vector<Param> out;
        while (tok().peek().kind == Kind::string) {
            const PbrtToken decl = tok().next();
            Param p;
            p.where = decl.where();
            std::istringstream in(decl.text);
            std::string extra;
            if (!(in >> p.type >> p.name) || (in >> extra))
                LTM_THROW(decl.where(), ": expected a parameter \"type name\", got \"", decl.text, "\"");
            auto value = [&](const PbrtToken &v) {
                if (v.kind == Kind::number) p.nums.push_back(v.number);
                else if (v.kind == Kind::string || (v.kind == Kind::word && (v.text == "true" || v.text == "false")))
                    p.strs.push_back(v.text);
                else LTM_THROW(v.where(), ": bad value '", v.text, "' for parameter '", p.name, "'");
            };
            if (tok().peek().kind == Kind::open) {
                tok().next();
                while (tok().peek().kind != Kind::close) {
                    const PbrtToken v = tok().next();
                    if (v.kind == Kind::end) LTM_THROW(decl.where(), ": '[' of parameter '", p.name, "' is never closed");
                    value(v);
                }
                tok().next();
            } else {
                value(tok().next());
            }
            for (const Param &q : out)
                if (q.name == p.name) LTM_THROW(p.where, ": parameter '", p.name, "' given twice");
            out.push_back(std::move(p));
        }
        return out;
    }

    static Param *find(std::vector<Param> &ps, const std::string &name) {
        for (auto &p : ps)
            if (p.name == name) return p.used = true, &p;
        return nullptr;
    }
    static double get_float(std::vector<Param> &ps, const std::string &name, double def) {
        Param *p = find(ps, name);
        if (!p) return def;
        if (p->type != "float" && p->type != "integer") LTM_THROW(p->where, ": parameter '", name, "' must be float, not ", p->type);
        if (p->nums.size() != 1) LTM_THROW(p->where, ": parameter '", name, "' needs one value, got ", p->nums.size());
        return p->nums[0];
    }
    static std::vector<double> get_numbers(std::vector<Param> &ps, const std::string &name, const char *type, size_t group) {
        Param *p = find(ps, name);
        if (!p) return {};
        const std::string want = type;
        if (p->type != want && !(want == "point3" && p->type == "point") && !(want == "point2" && p->type == "float") &&
            !(want == "normal" && p->type == "normal3"))
            LTM_THROW(p->where, ": parameter '", name, "' must be ", type, ", not ", p->type);
        if (!p->strs.empty() || p->nums.size() % group != 0)
            LTM_THROW(p->where, ": parameter '", name, "' needs a multiple of ", group, " numbers, got ", p->nums.size());
        return p->nums;
    }
    static std::string get_string(std::vector<Param> &ps, const std::string &name, const std::string &def) {
        Param *p = find(ps, name);
        if (!p) return def;
        if (p->strs.size() != 1 || !p->nums.empty()) LTM_THROW(p->where, ": parameter '", name, "' needs one string");
        return p->strs[0];
    }
    static bool get_bool(std::vector<Param> &ps, const std::string &name, bool def) {
        Param *p = find(ps, name);
        if (!p) return def;
        if (p->type != "bool" || p->strs.size() != 1 || (p->strs[0] != "true" && p->strs[0] != "false"))
            LTM_THROW(p->where, ": parameter '", name, "' must be a bool (true or false)");
        return p->strs[0] == "true";
    }

    // A colour parameter: rgb, blackbody (luminance 1, as pbrt-v4 normalises it), or a spectrum
    // (sampled pairs or a named one: approximated by a grey of its mean, with a warning).
    std::optional<Vec3f> get_color(std::vector<Param> &ps, const std::string &name) {
        Param *p = find(ps, name);
        if (!p) return std::nullopt;
        if (p->type == "rgb") {
            if (p->nums.size() != 3) LTM_THROW(p->where, ": rgb parameter '", name, "' needs 3 values");
            const Vec3f c{float(p->nums[0]), float(p->nums[1]), float(p->nums[2])};
            if (c.x < 0 || c.y < 0 || c.z < 0) LTM_THROW(p->where, ": rgb parameter '", name, "' is negative");
            return c;
        }
        if (p->type == "blackbody") {
            if (p->nums.size() != 1 || !(p->nums[0] > 0)) LTM_THROW(p->where, ": blackbody '", name, "' needs one temperature > 0 K");
            return blackbody_rgb(float(std::clamp(p->nums[0], 1000.0, 40000.0)));
        }
        if (p->type == "spectrum") {
            if (!p->strs.empty()) {
                warn("named spectrum '" + p->strs[0] + "' approximated by grey 0.5 (only rgb and blackbody are exact)");
                return Vec3f(0.5f);
            }
            if (p->nums.size() < 2 || p->nums.size() % 2) LTM_THROW(p->where, ": spectrum '", name, "' needs (wavelength, value) pairs");
            double s = 0;
            for (size_t i = 1; i < p->nums.size(); i += 2) s += p->nums[i];
            warn("sampled spectrum parameter '" + name + "' approximated by the grey of its mean value");
            return Vec3f(float(s / double(p->nums.size() / 2)));
        }
        LTM_THROW(p->where, ": parameter '", name, "' must be rgb, blackbody or spectrum, not ", p->type);
    }

    void warn_unused(std::vector<Param> &ps, const std::string &what) {
        for (const auto &p : ps)
            if (!p.used) warn("ignored parameter '" + p.name + "' of " + what);
    }
    void warn(const std::string &msg) { ++m_warnings[msg]; }

    std::string resolve(const std::string &file) const {
        if (!m_allow_files) LTM_THROW(tok().peek().where(), ": file '", file, "' not read (file access disabled)");
        return fs::path(file).is_absolute() ? file : (fs::path(m_base) / file).string();
    }

    // ---- directives ----
    void apply(const Mat4 &t) { m_state.ctm = m_state.ctm * t; }

    void directive(const PbrtToken &d) {
        const std::string &n = d.text;
        if (n == "Include" || n == "Import") {
            const PbrtToken f = expect(Kind::string, "a file name");
            if (m_files.size() > 32) LTM_THROW(f.where(), ": Include nested more than 32 deep (a cycle?)");
            const std::string path = resolve(f.text);
            if (!fs::is_regular_file(path)) LTM_THROW(f.where(), ": included file '", path, "' not found");
            m_files.push_back(std::make_unique<PbrtTokenizer>(read_file(path), path));
        } else if (n == "AttributeBegin" || n == "TransformBegin") {
            m_stack.push_back(m_state);
            m_stack_kind.push_back(n == "AttributeBegin" ? 'A' : 'T');
            m_state.transform_only = n == "TransformBegin";
        } else if (n == "AttributeEnd" || n == "TransformEnd") {
            // Each End closes its own kind of Begin (an ObjectBegin's state is ObjectEnd's to pop).
            if (m_stack.empty() || m_stack_kind.back() != (n == "AttributeEnd" ? 'A' : 'T'))
                LTM_THROW(d.where(), ": unbalanced ", n, " (no matching ", n == "AttributeEnd" ? "AttributeBegin" : "TransformBegin", ")");
            m_stack_kind.pop_back();
            if (m_state.transform_only) {
                const Mat4 ctm = m_stack.back().ctm;
                m_stack.pop_back();
                m_state.ctm = ctm;
            } else {
                m_state = m_stack.back();
                m_stack.pop_back();
            }
        } else if (n == "Identity") {
            m_state.ctm = Mat4();
        } else if (n == "Translate") {
            const auto v = numbers(3);
            apply(Mat4::from(Transform::translate(vec3_at(v, 0))));
        } else if (n == "Scale") {
            const auto v = numbers(3);
            Mat4 s;
            s.m[0][0] = v[0], s.m[1][1] = v[1], s.m[2][2] = v[2];
            apply(s);
        } else if (n == "Rotate") {
            const auto v = numbers(4);
            const Vec3f axis = vec3_at(v, 1);
            if (!(length(axis) > 0.f)) LTM_THROW(d.where(), ": Rotate about a zero axis");
            apply(Mat4::from(Transform::rotate(normalize(axis), float(v[0]))));
        } else if (n == "LookAt") {
            const auto v = numbers(9);
            const Vec3f eye = vec3_at(v, 0), look = vec3_at(v, 3), up = vec3_at(v, 6);
            const Vec3f dir = look - eye;
            if (!(length(dir) > 0.f) || !(length(cross(normalize(up), normalize(dir))) > 1e-6f))
                LTM_THROW(d.where(), ": LookAt with eye == look or up parallel to the view direction");
            const Vec3f f = normalize(dir), r = normalize(cross(normalize(up), f)), u = cross(f, r);
            Mat4 w;   // world from camera: columns right, up, forward, eye
            const Vec3f cols[4] = {r, u, f, eye};
            for (int c = 0; c < 4; ++c) w.m[0][c] = cols[c].x, w.m[1][c] = cols[c].y, w.m[2][c] = cols[c].z;
            apply(*w.inverse());
        } else if (n == "Transform" || n == "ConcatTransform") {
            const auto v = numbers(16);
            Mat4 t;   // pbrt lists the matrix column by column (translation in elements 12–14)
            for (int i = 0; i < 4; ++i)
                for (int j = 0; j < 4; ++j) t.m[i][j] = v[size_t(j * 4 + i)];
            if (std::abs(t.m[3][0]) + std::abs(t.m[3][1]) + std::abs(t.m[3][2]) > 1e-9 || std::abs(t.m[3][3] - 1) > 1e-9)
                LTM_THROW(d.where(), ": projective ", n, " matrices are not supported (last row must be 0 0 0 1)");
            if (n == "Transform") m_state.ctm = t;
            else apply(t);
        } else if (n == "CoordinateSystem") {
            m_coord[string()] = m_state.ctm;
        } else if (n == "CoordSysTransform") {
            m_state.ctm = lookup(m_coord, "a coordinate system name", "unknown coordinate system");
        } else if (n == "ReverseOrientation") {
            m_state.reverse = !m_state.reverse;
        } else if (n == "WorldBegin") {
            m_state.ctm = Mat4();
            m_coord["world"] = Mat4();
        } else if (n == "WorldEnd" || n == "TransformTimes") {
            if (n == "TransformTimes") numbers(2);
        } else if (n == "ActiveTransform") {
            expect(Kind::word, "StartTime, EndTime or All");
            warn("ActiveTransform ignored (no motion blur): every transform applies at all times");
        } else if (n == "Camera") {
            camera(d);
        } else if (n == "Film") {
            string();
            auto ps = params();
            const double w = get_float(ps, "xresolution", 1280), h = get_float(ps, "yresolution", 720);
            if (!(w >= 1 && h >= 1 && w <= 16384 && h <= 16384))   // checked before the cast (found by the fuzzer)
                LTM_THROW(d.where(), ": Film resolution ", w, "x", h, " out of range (1–16384)");
            m_film_w = int(w), m_film_h = int(h);
        } else if (n == "Sampler" || n == "Integrator" || n == "PixelFilter" || n == "Accelerator" || n == "Option" ||
                   n == "ColorSpace" || n == "MakeNamedMedium" || n == "Attribute") {
            // Renderer settings: ltm's own renderers decide these.
            if (n == "Option") {
                params();
                return;
            }
            const std::string what = string();
            params();
            if (n == "ColorSpace" && what != "srgb") warn("ColorSpace '" + what + "' ignored: colours are read as linear sRGB");
            if (n == "MakeNamedMedium") warn("participating media ignored (MakeNamedMedium)");
            if (n == "Attribute") warn("Attribute defaults ignored");
        } else if (n == "MediumInterface") {
            string();
            if (tok().peek().kind == Kind::string) string();
            warn("MediumInterface ignored (no participating media)");
        } else if (n == "Texture") {
            texture(d);
        } else if (n == "Material") {
            const std::string type = string();
            auto ps = params();
            m_state.material = add_material(type, ps, "", d);
        } else if (n == "MakeNamedMaterial") {
            const std::string name = string();
            auto ps = params();
            const std::string type = get_string(ps, "type", "");
            if (type.empty()) LTM_THROW(d.where(), ": MakeNamedMaterial '", name, "' has no \"string type\"");
            m_named_materials[name] = add_material(type, ps, name, d);
        } else if (n == "NamedMaterial") {
            m_state.material = lookup(m_named_materials, "a material name", "undefined named material");
        } else if (n == "LightSource") {
            const std::string type = string();
            params();
            ++m_skipped_lights;
            warn("LightSource '" + type + "' ignored: ltm supports area lights only (out of scope)");
        } else if (n == "AreaLightSource") {
            area_light(d);
        } else if (n == "Shape") {
            shape(d);
        } else if (n == "ObjectBegin") {
            if (m_in_object) LTM_THROW(d.where(), ": ObjectBegin inside ObjectBegin");
            m_object_name = string();
            m_stack.push_back(m_state);
            m_stack_kind.push_back('O');
            m_in_object = true;
            m_objects[m_object_name].clear();
        } else if (n == "ObjectEnd") {
            if (!m_in_object || m_stack.empty() || m_stack_kind.back() != 'O')
                LTM_THROW(d.where(), ": ObjectEnd without a matching ObjectBegin");
            m_in_object = false;
            m_state = m_stack.back();
            m_stack.pop_back();
            m_stack_kind.pop_back();
        } else if (n == "ObjectInstance") {
            const PbrtToken s = expect(Kind::string, "an object name");
            const auto it = m_objects.find(s.text);
            if (it == m_objects.end()) LTM_THROW(s.where(), ": undefined object '", s.text, "'");
            for (TriangleMesh mesh : it->second) {
                transform_mesh(mesh, m_state.ctm.to_transform());
                m_scene.meshes.push_back(std::move(mesh));
            }
        } else {
            LTM_THROW(d.where(), ": unknown directive '", n, "'");
        }
    }

    void camera(const PbrtToken &d) {
        const std::string type = string();
        auto ps = params();
        if (type != "perspective") warn("Camera '" + type + "' read as a perspective camera");
        m_fov_deg = get_float(ps, "fov", 90.0);
        if (!(m_fov_deg > 0 && m_fov_deg < 180)) LTM_THROW(d.where(), ": Camera fov ", m_fov_deg, " out of (0, 180)");
        warn_unused(ps, "Camera");
        m_camera_from_world = m_state.ctm;
        m_camera_where = d.where();
        const auto inv = m_state.ctm.inverse();
        if (!inv) LTM_THROW(d.where(), ": the camera transform is singular");
        m_coord["camera"] = *inv;
    }

    void texture(const PbrtToken &d) {
        const std::string name = string(), kind = string(), cls = string();
        auto ps = params();
        if (kind == "float") {
            warn("float textures ignored (roughness/bump maps)");
            return;
        }
        if (kind != "spectrum") LTM_THROW(d.where(), ": texture '", name, "' of unknown kind '", kind, "' (spectrum or float)");
        Texture t = Texture::constant(Vec3f(0.5f));
        if (cls == "imagemap") {
            const std::string file = get_string(ps, "filename", "");
            if (file.empty()) LTM_THROW(d.where(), ": imagemap texture '", name, "' has no filename");
            const std::string enc = get_string(ps, "encoding", "sRGB");
            t.kind = TextureKind::image;
            t.image_path = resolve(file);
            t.image_srgb = enc == "sRGB";
            try {
                t.image = std::make_shared<const Image>(read_image(t.image_path, t.image_srgb));
            } catch (const Error &e) {
                LTM_THROW(d.where(), ": texture '", name, "': ", e.what());
            }
            if (get_float(ps, "scale", 1.0) != 1.0) warn("imagemap 'scale' ignored");
            if (get_bool(ps, "invert", false)) warn("imagemap 'invert' ignored");
        } else {
            warn("texture class '" + cls + "' approximated by grey 0.5 (only imagemap is read)");
        }
        m_textures[name] = t;
    }

    // Reflectance-like parameter: rgb/spectrum/blackbody or "texture name".
    Texture reflectance(std::vector<Param> &ps, const std::string &name, Vec3f def) {
        if (Param *p = find(ps, name); p && p->type == "texture") {
            if (p->strs.size() != 1) LTM_THROW(p->where, ": texture parameter '", name, "' needs one name");
            const auto it = m_textures.find(p->strs[0]);
            if (it == m_textures.end()) LTM_THROW(p->where, ": undefined texture '", p->strs[0], "'");
            return it->second;
        } else if (p) {
            p->used = false;   // read again below as a colour
        }
        Vec3f c = get_color(ps, name).value_or(def);
        if (max_component(c) > 1.f) {
            warn("reflectance above 1 clamped to 1");
            c = min(c, Vec3f(1.f));
        }
        return Texture::constant(c);
    }

    int add_material(const std::string &type, std::vector<Param> &ps, const std::string &name, const PbrtToken &d) {
        PbrtMaterial m;
        m.type = type;
        m.name = name.empty() ? detail::concat("pbrt_", type, "_", m_materials.size()) : name;
        m.mat.name = m.name;
        get_string(ps, "type", "");   // MakeNamedMaterial's own key
        if (type == "diffuse" || type == "coateddiffuse" || type == "diffusetransmission") {
            m.mat.albedo = reflectance(ps, "reflectance", Vec3f(type == "diffusetransmission" ? 0.25f : 0.5f));
            if (type != "diffuse") warn("material '" + type + "' read as diffuse with its reflectance");
            if (type != "diffuse") for (auto &p : ps) p.used = true;
        } else if (type == "conductor") {
            m.mat.bsdf = BsdfKind::conductor;
            double r = get_float(ps, "roughness", 0.0);
            const double ur = get_float(ps, "uroughness", r), vr = get_float(ps, "vroughness", r);
            r = 0.5 * (ur + vr);
            if (ur != vr) warn("anisotropic conductor roughness averaged");
            if (get_bool(ps, "remaproughness", true)) r = std::sqrt(std::max(r, 0.0));   // pbrt-v4 RoughnessToAlpha
            m.mat.roughness = float(std::clamp(r, 0.001, 1.0));
            if (const auto refl = get_color(ps, "reflectance")) {
                m.mat.specular = min(*refl, Vec3f(1.f));
            } else {
                Param *eta = find(ps, "eta"), *k = find(ps, "k");
                if (eta && k && eta->type == "rgb" && k->type == "rgb" && eta->nums.size() == 3 && k->nums.size() == 3) {
                    for (int c = 0; c < 3; ++c) {
                        const double n = eta->nums[size_t(c)], kk = k->nums[size_t(c)];
                        m.mat.specular[c] = float(((n - 1) * (n - 1) + kk * kk) / ((n + 1) * (n + 1) + kk * kk));
                    }
                } else {
                    std::string metal = "Cu";   // pbrt-v4's default: metal-Cu-eta / metal-Cu-k
                    if (eta && eta->type == "spectrum" && eta->strs.size() == 1) {
                        const std::string &s = eta->strs[0];
                        if (s.rfind("metal-", 0) == 0 && s.size() > 10) metal = s.substr(6, s.size() - 10);
                    }
                    const auto it = named_metal_f0().find(metal);
                    if (it == named_metal_f0().end()) LTM_THROW(d.where(), ": conductor of unknown metal '", metal, "'");
                    m.mat.specular = it->second;
                }
            }
        } else {
            m.drop = true;
            for (auto &p : ps) p.used = true;
        }
        warn_unused(ps, "material '" + type + "'");
        m_materials.push_back(m);
        return int(m_materials.size()) - 1;
    }

    void area_light(const PbrtToken &d) {
        const std::string type = string();
        auto ps = params();
        if (type != "diffuse") LTM_THROW(d.where(), ": AreaLightSource '", type, "' unknown (diffuse)");
        AreaLight l;
        l.le = get_color(ps, "L").value_or(Vec3f(1.f)) * float(get_float(ps, "scale", 1.0));
        if (get_bool(ps, "twosided", false)) warn("two-sided area light emits on its front side only");
        if (find(ps, "power")) warn("area light 'power' ignored (radiance L × scale is used)");
        if (find(ps, "filename")) warn("area light image 'filename' ignored");
        warn_unused(ps, "AreaLightSource");
        if (!is_finite(l.le)) LTM_THROW(d.where(), ": area light radiance is not finite");
        m_state.light = l;
    }

    // Scene material index for the current (material, area light) pair.
    int scene_material() {
        const PbrtMaterial &pm = m_materials[size_t(m_state.material)];
        const Vec3f le = m_state.light ? m_state.light->le : Vec3f(0.f);
        const std::string key = detail::concat(m_state.material, "|", le.x, ",", le.y, ",", le.z);
        const auto it = m_scene_materials.find(key);
        if (it != m_scene_materials.end()) return it->second;
        Material m = pm.mat;
        if (max_component(le) > 0.f) {
            m.name = detail::concat(pm.name, "_light", m_scene_materials.size());
            m.emission = Texture::constant(le);
        }
        while (m_scene.find_material(m.name) >= 0) m.name += "_";
        const int idx = m_scene.add_material(m);
        m_scene_materials[key] = idx;
        return idx;
    }

    void shape(const PbrtToken &d) {
        const std::string type = string();
        auto ps = params();
        const PbrtMaterial &pm = m_materials[size_t(m_state.material)];
        if (pm.drop) {
            for (auto &p : ps) p.used = true;
            warn("shape with material '" + pm.type + "' dropped (unsupported material; glass lets light through)");
            return;
        }
        TriangleMesh mesh;
        mesh.name = detail::concat("pbrt_", type, "_", m_scene.meshes.size());
        std::vector<Vec3f> normals;   // object-space vertex normals, if given (orientation only)
        if (type == "trianglemesh" || type == "bilinearmesh") {
            const auto P = get_numbers(ps, "P", "point3", 3);
            const auto uv = get_numbers(ps, "uv", "point2", 2);
            const auto N = get_numbers(ps, "N", "normal", 3);
            auto idx = get_numbers(ps, "indices", "integer", 1);
            const size_t nv = P.size() / 3, per = type == "trianglemesh" ? 3 : 4;
            if (nv == 0) LTM_THROW(d.where(), ": ", type, " has no \"point3 P\"");
            if (idx.empty() && nv == per)
                for (size_t i = 0; i < per; ++i) idx.push_back(double(i));
            if (idx.empty() || idx.size() % per) LTM_THROW(d.where(), ": ", type, " needs \"integer indices\" in groups of ", per);
            if (!uv.empty() && uv.size() / 2 != nv) LTM_THROW(d.where(), ": ", type, " has ", uv.size() / 2, " uvs for ", nv, " vertices");
            if (!N.empty() && N.size() / 3 != nv) LTM_THROW(d.where(), ": ", type, " has ", N.size() / 3, " normals for ", nv, " vertices");
            for (size_t i = 0; i < nv; ++i) mesh.positions.push_back(Vec3f(float(P[3 * i]), float(P[3 * i + 1]), float(P[3 * i + 2])));
            for (size_t i = 0; i < uv.size() / 2; ++i) mesh.uvs.push_back(Vec2f{float(uv[2 * i]), float(uv[2 * i + 1])});
            for (size_t i = 0; i < N.size() / 3; ++i) normals.push_back(Vec3f(float(N[3 * i]), float(N[3 * i + 1]), float(N[3 * i + 2])));
            std::vector<uint32_t> ix;
            for (double v : idx) {
                if (!(v >= 0 && v < double(nv)) || v != std::floor(v))
                    LTM_THROW(d.where(), ": ", type, " index ", v, " out of range (", nv, " vertices)");
                ix.push_back(uint32_t(v));
            }
            if (per == 3) {
                mesh.indices = ix;
            } else {   // bilinear patch p00 p10 p01 p11 → (p00 p10 p11), (p00 p11 p01): normal dp/du × dp/dv
                for (size_t q = 0; q < ix.size(); q += 4)
                    mesh.indices.insert(mesh.indices.end(), {ix[q], ix[q + 1], ix[q + 3], ix[q], ix[q + 3], ix[q + 2]});
            }
        } else if (type == "plymesh") {
            const std::string file = get_string(ps, "filename", "");
            if (file.empty()) LTM_THROW(d.where(), ": plymesh has no filename");
            const std::string path = resolve(file);
            if (!fs::is_regular_file(path)) LTM_THROW(d.where(), ": PLY file '", path, "' not found");
            PlyMesh ply = read_ply_mesh(path);
            if (ply.n_polygons > 0) warn("PLY faces with more than 4 vertices triangulated as fans");
            mesh.positions = std::move(ply.positions);
            mesh.uvs = std::move(ply.uvs);
            mesh.indices = std::move(ply.indices);
            normals = std::move(ply.normals);
            if (find(ps, "displacement")) warn("plymesh displacement ignored");
        } else if (type == "sphere") {
            const float r = float(get_float(ps, "radius", 1.0));
            if (!(r > 0)) LTM_THROW(d.where(), ": sphere radius must be > 0");
            if (find(ps, "zmin") || find(ps, "zmax") || find(ps, "phimax")) warn("partial spheres (zmin/zmax/phimax) read as whole spheres");
            const int nu = 48, nv = 24;   // outward winding, poles along z as in pbrt
            for (int j = 0; j <= nv; ++j)
                for (int i = 0; i <= nu; ++i) {
                    const float th = k_pi * float(j) / float(nv), ph = 2.f * k_pi * float(i) / float(nu);
                    mesh.positions.push_back(Vec3f(r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th)));
                    mesh.uvs.push_back(Vec2f{float(i) / float(nu), float(j) / float(nv)});
                }
            for (int j = 0; j < nv; ++j)
                for (int i = 0; i < nu; ++i) {
                    const uint32_t a = uint32_t(j * (nu + 1) + i), b = a + 1, c = a + uint32_t(nu + 1), e = c + 1;
                    if (j > 0) mesh.indices.insert(mesh.indices.end(), {a, c, b});
                    if (j < nv - 1) mesh.indices.insert(mesh.indices.end(), {b, c, e});
                }
        } else if (type == "disk") {
            const float h = float(get_float(ps, "height", 0.0)), r = float(get_float(ps, "radius", 1.0)),
                        ri = float(get_float(ps, "innerradius", 0.0));
            if (!(r > 0) || !(ri >= 0 && ri < r)) LTM_THROW(d.where(), ": disk needs radius > innerradius >= 0");
            if (find(ps, "phimax")) warn("partial disks (phimax) read as whole disks");
            const int nu = 48;   // normal +z (pbrt's disk)
            for (int i = 0; i <= nu; ++i) {
                const float ph = 2.f * k_pi * float(i) / float(nu);
                mesh.positions.push_back(Vec3f(r * std::cos(ph), r * std::sin(ph), h));
                mesh.positions.push_back(Vec3f(ri * std::cos(ph), ri * std::sin(ph), h));
            }
            for (int i = 0; i < nu; ++i) {
                const uint32_t o0 = uint32_t(2 * i), i0 = o0 + 1, o1 = o0 + 2, i1 = o0 + 3;
                mesh.indices.insert(mesh.indices.end(), {o0, o1, i1});
                if (ri > 0) mesh.indices.insert(mesh.indices.end(), {o0, i1, i0});
            }
        } else {
            for (auto &p : ps) p.used = true;
            warn("Shape '" + type + "' not supported, skipped");
            return;
        }
        warn_unused(ps, "Shape '" + type + "'");
        // Orientation (pbrt-v4): with vertex normals the surface faces them; without, the winding
        // normal, flipped by ReverseOrientation. Decided in object space, kept by transform_mesh.
        for (size_t t = 0; t < mesh.n_triangles(); ++t) {
            bool flip = m_state.reverse;
            if (!normals.empty()) {
                const Vec3f nsum = normals[mesh.indices[3 * t]] + normals[mesh.indices[3 * t + 1]] + normals[mesh.indices[3 * t + 2]];
                flip = dot(mesh.cross_normal(t), nsum) < 0.f;
            }
            if (flip) std::swap(mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]);
        }
        if (mesh.indices.empty()) return;
        if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size()) mesh.uvs.clear();
        if (m_state.ctm.det3() == 0 || !std::isfinite(m_state.ctm.det3())) LTM_THROW(d.where(), ": shape transform is singular or not finite");
        transform_mesh(mesh, m_state.ctm.to_transform());
        for (const Vec3f &p : mesh.positions)
            if (!is_finite(p)) LTM_THROW(d.where(), ": shape has a non-finite vertex after its transform");
        mesh.material = scene_material();
        if (m_in_object) {
            // pbrt: an instance applies the CTM of ObjectInstance on top of the shapes' own.
            m_objects[m_object_name].push_back(std::move(mesh));
        } else {
            m_scene.meshes.push_back(std::move(mesh));
        }
    }

    std::string m_base;
    bool m_allow_files = true;
    std::vector<std::unique_ptr<PbrtTokenizer>> m_files;
    State m_state;
    std::vector<State> m_stack;
    std::vector<char> m_stack_kind;   // what pushed each entry: 'A'ttribute, 'T'ransform, 'O'bject
    std::vector<PbrtMaterial> m_materials;
    std::map<std::string, int> m_named_materials;
    std::map<std::string, Texture> m_textures;
    std::map<std::string, Mat4> m_coord;
    std::map<std::string, std::vector<TriangleMesh>> m_objects;
    std::map<std::string, int> m_scene_materials;
    std::map<std::string, int64_t> m_warnings;
    std::string m_object_name, m_camera_where;
    bool m_in_object = false;
    std::optional<Mat4> m_camera_from_world;
    double m_fov_deg = 90.0;
    int m_film_w = 1280, m_film_h = 720;
    int64_t m_skipped_lights = 0;
    Scene m_scene;
};

}  // namespace

Scene parse_pbrt(const std::string &text, const std::string &file, const std::string &base_dir, bool allow_files) {
    Reader r(base_dir, allow_files);
    r.parse(text, file);
    Scene s = r.finish(file);
    s.name = fs::path(file).stem().string();
    return s;
}

Scene load_pbrt(const std::string &path) {
    if (!fs::is_regular_file(path)) LTM_THROW(path, ": file not found");
    const std::string dir = parent_dir(path);
    return parse_pbrt(read_file(path), path, dir.empty() ? "." : dir);
}

}  // namespace ltm
