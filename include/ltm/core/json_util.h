// json_util.h: strict JSON reading. Every config and scene file goes through JsonObject, which
// type-checks each value and rejects unknown keys, naming the file and the JSON pointer.
#pragma once

#include <cstdint>

#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ltm/core/math.h"

namespace ltm {

using Json = nlohmann::json;
using OrderedJson = nlohmann::ordered_json;

/// Parses text; a syntax error reads "where:line:col: <what>". Rejects NaN/Inf literals.
Json parse_json(const std::string &text, const std::string &where);
/// Reads and parses a file (errors name the file).
Json parse_json_file(const std::string &path);

/// Compact pretty printer: objects indented, arrays of numbers/strings on one line, numbers in
/// nlohmann's shortest round-trip form. Output is a pure function of the value (byte-stable).
std::string dump_json_compact(const OrderedJson &j, int indent_step = 2);

/// A view of one JSON object with its location ("scene.json: /materials/2").
class JsonObject {
public:
    JsonObject(const Json &j, std::string where);

    bool has(const std::string &key) const { return m_json.contains(key); }
    const std::string &where() const { return m_where; }
    /// "scene.json: /materials/2/albedo" (for error messages about one key).
    std::string where(const std::string &key) const;

    float get_float(const std::string &key, float fallback);
    float require_float(const std::string &key);
    int get_int(const std::string &key, int fallback);
    int require_int(const std::string &key);
    bool get_bool(const std::string &key, bool fallback);
    std::string get_string(const std::string &key, const std::string &fallback);
    std::string require_string(const std::string &key);
    Vec3f get_vec3(const std::string &key, Vec3f fallback);
    Vec3f require_vec3(const std::string &key);
    /// A [lo, hi] pair with lo <= hi.
    Vec2f get_range(const std::string &key, Vec2f fallback);
    std::vector<float> require_float_array(const std::string &key);
    std::vector<int64_t> require_int_array(const std::string &key);
    /// The raw value (marks the key as used).
    const Json &require(const std::string &key);
    JsonObject require_object(const std::string &key);
    /// Throws "where: unknown key 'k' (known: a, b, c)" for every key not read.
    void finish() const;

private:
    const Json &at(const std::string &key);
    const Json &m_json;
    std::string m_where;
    std::set<std::string> m_used;
};

/// The shortest decimal that reads back as the same float, as a JSON number: config files show
/// 0.1, not 0.10000000149011612.
double json_float(float f);

/// Parses a float with the error naming `where` (for values outside objects).
float json_to_float(const Json &v, const std::string &where);
Vec3f json_to_vec3(const Json &v, const std::string &where);

/// Applies "a.b.c=value" overrides (value parsed as JSON, or taken as a string) to a config.
void apply_json_override(Json &config, const std::string &assignment);

}  // namespace ltm
