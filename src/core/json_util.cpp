// json_util.cpp: strict typed access to nlohmann::json with located errors.
#include "ltm/core/json_util.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"

namespace ltm {

namespace {
std::string type_name(const Json &v) {
    if (v.is_number_integer()) return "integer";
    if (v.is_number()) return "number";
    return v.type_name();
}
}  // namespace

Json parse_json(const std::string &text, const std::string &where) {
    try {
        return Json::parse(text, /*cb=*/nullptr, /*allow_exceptions=*/true,
                           /*ignore_comments=*/false);
    } catch (const Json::parse_error &e) {
        // Convert the byte offset into line:col for the message.
        size_t line = 1, col = 1;
        for (size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
            if (text[i] == '\n') ++line, col = 1;
            else ++col;
        }
        std::string what = e.what();
        const size_t colon = what.find(": ", what.find("parse error"));
        if (colon != std::string::npos) what = what.substr(colon + 2);
        LTM_THROW(where, ":", line, ":", col, ": invalid JSON: ", what);
    } catch (const Json::exception &e) {   // e.g. out_of_range for 1e999
        std::string what = e.what();
        const size_t bracket = what.find("] ");
        LTM_THROW(where, ": invalid JSON: ", bracket == std::string::npos ? what : what.substr(bracket + 2));
    }
}

Json parse_json_file(const std::string &path) { return parse_json(read_file(path), path); }

namespace {
bool is_scalar_array(const OrderedJson &j) {
    for (const auto &v : j)
        if (v.is_structured()) return false;
    return true;
}

void dump_rec(const OrderedJson &j, int indent, int step, std::string &out) {
    const std::string pad(size_t(indent + step), ' ');
    if (j.is_object() && !j.empty()) {
        out += "{\n";
        size_t i = 0;
        for (auto it = j.begin(); it != j.end(); ++it, ++i) {
            out += pad + OrderedJson(it.key()).dump() + ": ";
            dump_rec(it.value(), indent + step, step, out);
            out += i + 1 < j.size() ? ",\n" : "\n";
        }
        out += std::string(size_t(indent), ' ') + "}";
    } else if (j.is_array() && !j.empty() && !is_scalar_array(j)) {
        out += "[\n";
        for (size_t i = 0; i < j.size(); ++i) {
            out += pad;
            dump_rec(j[i], indent + step, step, out);
            out += i + 1 < j.size() ? ",\n" : "\n";
        }
        out += std::string(size_t(indent), ' ') + "]";
    } else if (j.is_array()) {
        out += "[";
        for (size_t i = 0; i < j.size(); ++i) out += (i ? ", " : "") + j[i].dump();
        out += "]";
    } else {
        out += j.dump();
    }
}
}  // namespace

std::string dump_json_compact(const OrderedJson &j, int indent_step) {
    std::string out;
    dump_rec(j, 0, indent_step, out);
    out += "\n";
    return out;
}

JsonObject::JsonObject(const Json &j, std::string where) : m_json(j), m_where(std::move(where)) {
    if (!j.is_object()) LTM_THROW(m_where, ": expected an object, got ", type_name(j));
}

std::string JsonObject::where(const std::string &key) const {
    // where() is "file: /pointer" or "file"; append the key as a JSON pointer component.
    return m_where + (m_where.find(": /") == std::string::npos ? ": /" : "/") + key;
}

const Json &JsonObject::at(const std::string &key) {
    m_used.insert(key);
    return m_json.at(key);
}

const Json &JsonObject::require(const std::string &key) {
    if (!has(key)) LTM_THROW(m_where, ": missing required key '", key, "'");
    return at(key);
}

double json_float(float f) {
    char buf[40];
    for (int prec = 6; prec <= 9; ++prec) {
        std::snprintf(buf, sizeof buf, "%.*g", prec, double(f));
        if (std::strtof(buf, nullptr) == f) break;
    }
    return std::strtod(buf, nullptr);
}

float json_to_float(const Json &v, const std::string &where) {
    if (!v.is_number()) LTM_THROW(where, ": expected a number, got ", type_name(v));
    const double d = v.get<double>();
    if (!std::isfinite(d) || std::abs(d) > 3.0e38) LTM_THROW(where, ": number is not finite");
    return float(d);
}

Vec3f json_to_vec3(const Json &v, const std::string &where) {
    if (!v.is_array() || v.size() != 3)
        LTM_THROW(where, ": expected an array of 3 numbers, got ", type_name(v),
                  v.is_array() ? " of size " + std::to_string(v.size()) : "");
    return {json_to_float(v[0], where + "/0"), json_to_float(v[1], where + "/1"),
            json_to_float(v[2], where + "/2")};
}

float JsonObject::get_float(const std::string &key, float fallback) {
    return has(key) ? json_to_float(at(key), where(key)) : fallback;
}
float JsonObject::require_float(const std::string &key) {
    return json_to_float(require(key), where(key));
}

int JsonObject::require_int(const std::string &key) {
    const Json &v = require(key);
    if (!v.is_number_integer()) LTM_THROW(where(key), ": expected an integer, got ", type_name(v));
    const int64_t i = v.get<int64_t>();
    if (i < INT32_MIN || i > INT32_MAX) LTM_THROW(where(key), ": integer out of range: ", i);
    return int(i);
}
int JsonObject::get_int(const std::string &key, int fallback) {
    return has(key) ? require_int(key) : fallback;
}

bool JsonObject::get_bool(const std::string &key, bool fallback) {
    if (!has(key)) return fallback;
    const Json &v = at(key);
    if (!v.is_boolean()) LTM_THROW(where(key), ": expected true or false, got ", type_name(v));
    return v.get<bool>();
}

std::string JsonObject::require_string(const std::string &key) {
    const Json &v = require(key);
    if (!v.is_string()) LTM_THROW(where(key), ": expected a string, got ", type_name(v));
    return v.get<std::string>();
}
std::string JsonObject::get_string(const std::string &key, const std::string &fallback) {
    return has(key) ? require_string(key) : fallback;
}

Vec3f JsonObject::require_vec3(const std::string &key) { return json_to_vec3(require(key), where(key)); }
Vec3f JsonObject::get_vec3(const std::string &key, Vec3f fallback) {
    return has(key) ? require_vec3(key) : fallback;
}

Vec2f JsonObject::get_range(const std::string &key, Vec2f fallback) {
    if (!has(key)) return fallback;
    const Json &v = at(key);
    if (!v.is_array() || v.size() != 2)
        LTM_THROW(where(key), ": expected a range [lo, hi], got ", type_name(v));
    const Vec2f r{json_to_float(v[0], where(key) + "/0"), json_to_float(v[1], where(key) + "/1")};
    if (r.x > r.y) LTM_THROW(where(key), ": range has lo > hi: [", r.x, ", ", r.y, "]");
    return r;
}

namespace {
// The array `v` at `at`, each element accepted by `is` (else "expected <one>") and read by `get`.
template <class T, class Is, class Get>
std::vector<T> read_array(const Json &v, const std::string &at, const char *many, const char *one, Is is, Get get) {
    if (!v.is_array()) LTM_THROW(at, ": expected an array of ", many, ", got ", type_name(v));
    std::vector<T> out;
    out.reserve(v.size());
    for (size_t i = 0; i < v.size(); ++i) {
        if (!is(v[i])) LTM_THROW(at, "/", i, ": expected ", one, ", got ", type_name(v[i]));
        out.push_back(get(v[i]));
    }
    return out;
}
}  // namespace

std::vector<float> JsonObject::require_float_array(const std::string &key) {
    // is_number() is the fast path check; json_to_float repeats it with the location.
    return read_array<float>(require(key), where(key), "numbers", "a number", [](const Json &x) { return x.is_number(); },
                             [&](const Json &x) { return json_to_float(x, where(key)); });
}

std::vector<int64_t> JsonObject::require_int_array(const std::string &key) {
    return read_array<int64_t>(require(key), where(key), "integers", "an integer",
                               [](const Json &x) { return x.is_number_integer(); },
                               [](const Json &x) { return x.get<int64_t>(); });
}

JsonObject JsonObject::require_object(const std::string &key) {
    return JsonObject(require(key), where(key));
}

void JsonObject::finish() const {
    for (auto it = m_json.begin(); it != m_json.end(); ++it) {
        if (m_used.count(it.key())) continue;
        std::string known;
        for (const auto &k : m_used) known += (known.empty() ? "" : ", ") + k;
        LTM_THROW(m_where, ": unknown key '", it.key(), "'",
                  known.empty() ? "" : " (this object uses: " + known + ")");
    }
}

void apply_json_override(Json &config, const std::string &assignment) {
    const size_t eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0)
        LTM_THROW("--set ", assignment, ": expected key=value (e.g. rooms.count=[1,4])");
    const std::string key = assignment.substr(0, eq), text = assignment.substr(eq + 1);
    Json value;
    try {
        value = Json::parse(text);
    } catch (const Json::parse_error &) {
        value = text;   // bare words are strings
    }
    Json *node = &config;
    std::stringstream ss(key);
    std::string part;
    std::vector<std::string> parts;
    while (std::getline(ss, part, '.')) parts.push_back(part);
    for (size_t i = 0; i < parts.size(); ++i) {
        if (!node->is_object()) LTM_THROW("--set ", key, ": '", parts[i - 1], "' is not an object");
        node = &(*node)[parts[i]];
    }
    *node = value;
}

}  // namespace ltm
