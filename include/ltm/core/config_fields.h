// config_fields.h: a config struct described once — key, member, limits or choices, one-line
// doc — and that description reads it from JSON (types checked, limits enforced, unknown keys
// rejected, every error naming the file and key), writes it back, and prints the table of
// docs/config.md (a test keeps the docs equal to it). Adding a key is one line plus its use, as
// with pbrt-v4's parameter dictionaries or tiny-cuda-nn's JSON configs.
//
//   static const ConfigFields<TrainConfig> fields = ConfigFields<TrainConfig>()
//       .field("steps", &TrainConfig::steps, "optimizer steps", at_least(1))
//       .field("loss", &TrainConfig::loss, "training loss", {}, {"relative-l2", "level-l2"});
//   TrainConfig c = fields.read(json, "train.json");
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "ltm/core/error.h"
#include "ltm/core/json_util.h"
#include "ltm/core/math.h"

namespace ltm {

/// Allowed values of a numeric field: lo <= v <= hi; lo < v when lo_open, v < hi when hi_open.
struct FieldLimits {
    double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    bool hi_open = false, lo_open = false;
    /// Floats compare in their own type (a float field's bound 1e-4 is the float 1e-4f); integers
    /// in long double, so a bound outside the type's range (a negative bound of a uint64_t) is
    /// never cast into it.
    template <class V>
    bool contains(V v) const {
        if constexpr (std::is_floating_point_v<V>) {
            const V l = std::isfinite(lo) ? V(lo) : std::numeric_limits<V>::lowest();
            const V h = std::isfinite(hi) ? V(hi) : std::numeric_limits<V>::max();
            return (lo_open ? v > l : v >= l) && (hi_open ? v < h : v <= h);
        } else {
            const long double x = static_cast<long double>(v), l = lo, h = hi;
            return (lo_open ? x > l : x >= l) && (hi_open ? x < h : x <= h);
        }
    }
    bool bounded() const { return std::isfinite(lo) || std::isfinite(hi); }
};
inline FieldLimits at_least(double lo) { return {lo}; }
inline FieldLimits between(double lo, double hi) { return {lo, hi}; }
inline FieldLimits from_below(double lo, double hi) { return {lo, hi, true}; }     ///< [lo, hi)
inline FieldLimits above_up_to(double lo, double hi) { return {lo, hi, false, true}; }   ///< (lo, hi]
/// Strictly positive (written "> 0").
inline FieldLimits positive() { return {0.0, std::numeric_limits<double>::infinity(), false, true}; }

template <class T>
class ConfigFields {
public:
    /// Reads what the fields do not: keys of nested objects, cross-field checks (before finish()).
    using Rest = std::function<void(JsonObject &, T &)>;
    struct Field {
        std::string key;
        std::string doc;
        FieldLimits limits;
        std::vector<std::string> choices;   ///< string fields: the allowed values (empty: any)
        bool omit_default = false;          ///< write() leaves the key out while it has T{}'s value
        std::string allowed;                ///< the docs table's "allowed" column
        /// Reads the key (present in o) into its member of t, checking type, limits and choices.
        std::function<void(JsonObject &o, const Field &f, T &t)> read;
        /// Checks the member of t against the limits and choices; errors name `at` (a key path).
        std::function<void(const Field &f, const T &t, const std::string &at)> check;
        /// The member of t as JSON.
        std::function<OrderedJson(const T &t)> value;
    };

    /// Field types: int, float, bool, std::string, uint64_t, the [lo, hi] ranges Vec2f and IntRange
    /// (lo <= hi; the limits bound both ends) and the lists std::vector<int64_t> (the limits bound
    /// every entry) and std::vector<std::string> (the choices hold for every entry). Each member's
    /// reader, checker and writer are built here for its own type only.
    template <class V>
    ConfigFields &field(std::string key, V T::*member, std::string doc, FieldLimits limits = {},
                        std::vector<std::string> choices = {}) {
        static_assert(std::is_same_v<V, int> || std::is_same_v<V, float> || std::is_same_v<V, bool> ||
                          std::is_same_v<V, std::string> || std::is_same_v<V, uint64_t> ||
                          std::is_same_v<V, Vec2f> || std::is_same_v<V, IntRange> ||
                          std::is_same_v<V, std::vector<int64_t>> || std::is_same_v<V, std::vector<std::string>>,
                      "ConfigFields: unsupported field type");
        Field f{std::move(key), std::move(doc), limits, std::move(choices)};
        if constexpr (std::is_same_v<V, bool>) f.allowed = "true, false";
        else if constexpr (std::is_same_v<V, std::string>) f.allowed = f.choices.empty() ? "text" : join(f.choices, ", ", "`");
        else if constexpr (std::is_same_v<V, std::vector<std::string>>)
            f.allowed = f.choices.empty() ? "texts" : "each of " + join(f.choices, ", ", "`");
        else if constexpr (std::is_same_v<V, std::vector<int64_t>>) f.allowed = limits.bounded() ? "each " + limits_text(limits) : "any";
        else f.allowed = limits.bounded() ? limits_text(limits) : "any";
        f.read = [member](JsonObject &o, const Field &fd, T &t) {
            read_value(o, fd, t.*member);
            check_value(fd, t.*member, o.where(fd.key));
        };
        f.check = [member](const Field &fd, const T &t, const std::string &at) { check_value(fd, t.*member, at); };
        f.value = [member](const T &t) { return json_value(t.*member); };
        m_fields.push_back(std::move(f));
        return *this;
    }
    /// The last field is written only when it differs from T{}'s value: files and checkpoints
    /// from before a key existed keep their exact JSON.
    ConfigFields &omit_default() {
        m_fields.back().omit_default = true;
        return *this;
    }
    const std::vector<Field> &fields() const { return m_fields; }

    /// `out` (the defaults) with the keys present in j; throws ltm::Error naming where/key.
    T read(const Json &j, const std::string &where, T out = T{}, const Rest &rest = {}) const {
        JsonObject o(j, where);
        for (const Field &f : m_fields)
            if (o.has(f.key)) f.read(o, f, out);
        if (rest) rest(o, out);
        o.finish();
        return out;
    }

    /// Checks every field of an in-memory c (e.g. built in code, not read) against its limits and
    /// choices; errors name where/key as read() does.
    void check(const T &c, const std::string &where) const {
        for (const Field &f : m_fields) f.check(f, c, JsonObject(Json::object(), where).where(f.key));
    }

    /// Every field, in declaration order.
    OrderedJson write(const T &c) const {
        OrderedJson j = OrderedJson::object();
        const T d{};
        for (const Field &f : m_fields) {
            OrderedJson v = f.value(c);
            if (!f.omit_default || v != f.value(d)) j[f.key] = std::move(v);
        }
        return j;
    }

    /// | key | default | allowed | meaning | — the defaults are T{}'s; keys shown as prefix + key
    /// (e.g. "decoder." for a nested section).
    std::string markdown_table(const std::string &prefix = "") const {
        const T d{};
        std::ostringstream s;
        s << "| key | default | allowed | meaning |\n|---|---|---|---|\n";
        for (const Field &f : m_fields)
            s << "| `" << prefix << f.key << "` | `" << range_text(f.value(d)) << "` | " << f.allowed << " | " << f.doc << " |\n";
        return s.str();
    }

private:
    /// Reads f.key from o into v (V is the member's type); types and range order only.
    template <class V>
    static void read_value(JsonObject &o, const Field &f, V &v) {
        if constexpr (std::is_same_v<V, bool>) v = o.get_bool(f.key, v);
        else if constexpr (std::is_same_v<V, std::string>) v = o.get_string(f.key, v);
        else if constexpr (std::is_same_v<V, float>) v = o.get_float(f.key, v);
        else if constexpr (std::is_same_v<V, int>) v = o.get_int(f.key, v);
        else if constexpr (std::is_same_v<V, uint64_t>) {   // the full range (seeds), not int's
            const Json &x = o.require(f.key);
            if (!x.is_number_integer() || (!x.is_number_unsigned() && x.get<int64_t>() < 0))
                LTM_THROW(o.where(f.key), ": must be >= 0 (an integer)");
            v = x.get<uint64_t>();
        } else if constexpr (std::is_same_v<V, Vec2f>) v = o.get_range(f.key, v);   // checks lo <= hi
        else if constexpr (std::is_same_v<V, IntRange>) {
            const Json &r = o.require(f.key);
            if (!r.is_array() || r.size() != 2 || !r[0].is_number_integer() || !r[1].is_number_integer())
                LTM_THROW(o.where(f.key), ": expected an integer range [lo, hi]");
            const int64_t a = r[0].get<int64_t>(), b = r[1].get<int64_t>();
            if (a > b) LTM_THROW(o.where(f.key), ": range has lo > hi: [", a, ", ", b, "]");
            if (!f.limits.contains(a) || !f.limits.contains(b))   // before narrowing to int
                LTM_THROW(o.where(f.key), ": range [", a, ", ", b, "] must lie in ", limits_text(f.limits));
            v = {int(a), int(b)};
        } else if constexpr (std::is_same_v<V, std::vector<int64_t>>) v = o.require_int_array(f.key);
        else if constexpr (std::is_same_v<V, std::vector<std::string>>) {
            const Json &a = o.require(f.key);
            if (!a.is_array()) LTM_THROW(o.where(f.key), ": expected an array of strings");
            v.clear();
            for (size_t i = 0; i < a.size(); ++i) {
                if (!a[i].is_string()) LTM_THROW(o.where(f.key), "/", i, ": expected a string");
                v.push_back(a[i].get<std::string>());
            }
        }
    }

    /// Limits (numbers, both ends of ranges, every list entry) and choices; `at` names the key.
    template <class V>
    static void check_value(const Field &f, const V &v, const std::string &at) {
        if constexpr (std::is_same_v<V, std::string>) {
            if (!f.choices.empty() && std::find(f.choices.begin(), f.choices.end(), v) == f.choices.end())
                LTM_THROW(at, ": '", v, "' is not one of ", join(f.choices, ", "));
        } else if constexpr (std::is_same_v<V, std::vector<std::string>>) {
            for (size_t i = 0; i < v.size(); ++i)
                if (!f.choices.empty() && std::find(f.choices.begin(), f.choices.end(), v[i]) == f.choices.end())
                    LTM_THROW(at, "/", i, ": '", v[i], "' is not one of ", join(f.choices, ", "));
        } else if constexpr (std::is_same_v<V, std::vector<int64_t>>) {
            for (size_t i = 0; i < v.size(); ++i)
                if (!f.limits.contains(v[i])) LTM_THROW(at, "/", i, ": ", v[i], " is outside ", limits_text(f.limits));
        } else if constexpr (std::is_same_v<V, Vec2f>) {
            if (!f.limits.contains(v.x) || !f.limits.contains(v.y))
                LTM_THROW(at, ": range ", range_text(json_value(v)), " must lie in ", limits_text(f.limits));
        } else if constexpr (std::is_same_v<V, IntRange>) {
            if (!f.limits.contains(v.lo) || !f.limits.contains(v.hi))
                LTM_THROW(at, ": range [", v.lo, ", ", v.hi, "] must lie in ", limits_text(f.limits));
        } else if constexpr (!std::is_same_v<V, bool>) {
            if (!f.limits.contains(v)) LTM_THROW(at, ": ", json_value(v), " is outside ", limits_text(f.limits));
        }
    }

    template <class V>
    static OrderedJson json_value(const V &v) {
        if constexpr (std::is_same_v<V, float>) return json_float(v);
        else if constexpr (std::is_same_v<V, std::vector<int64_t>> || std::is_same_v<V, std::vector<std::string>>) {
            OrderedJson a = OrderedJson::array();
            for (const auto &x : v) a.push_back(x);
            return a;
        }
        else if constexpr (std::is_same_v<V, Vec2f>) return OrderedJson::array({json_float(v.x), json_float(v.y)});
        else if constexpr (std::is_same_v<V, IntRange>) return OrderedJson::array({v.lo, v.hi});
        else return v;
    }
    /// A value as the docs show it: "[0.8, 1.0]" for ranges and lists (JSON with a space after commas).
    static std::string range_text(const OrderedJson &j) {
        if (!j.is_array()) return j.dump();
        std::string s = "[";
        for (size_t i = 0; i < j.size(); ++i) s += (i ? ", " : "") + j[i].dump();
        return s + "]";
    }
    static std::string number(double x) {
        std::ostringstream s;
        s.precision(12);   // 50000000, not 5e+07
        s << x;
        return s.str();
    }
    static std::string limits_text(const FieldLimits &l) {
        if (!std::isfinite(l.hi)) return (l.lo_open ? "> " : ">= ") + number(l.lo);
        if (!std::isfinite(l.lo)) return (l.hi_open ? "< " : "<= ") + number(l.hi);
        return (l.lo_open ? "(" : "[") + number(l.lo) + ", " + number(l.hi) + (l.hi_open ? ")" : "]");
    }
    static std::string join(const std::vector<std::string> &v, const char *sep, const char *quote = "") {
        std::string s;
        for (size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + std::string(quote) + v[i] + quote;
        return s;
    }
    std::vector<Field> m_fields;
};

}  // namespace ltm
