// json_util_test.cpp: strict reading: located errors for syntax, unknown keys, types, NaN.
#include <gtest/gtest.h>

#include "ltm/core/error.h"
#include "ltm/core/json_util.h"

using namespace ltm;

namespace {
std::string error_of(const std::function<void()> &f) {
    try {
        f();
    } catch (const Error &e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(JsonUtil, SyntaxErrorNamesFileLineAndColumn) {
    const std::string msg = error_of([] { parse_json("{\n  \"a\": 1,\n  \"b\": ]\n}", "x.json"); });
    EXPECT_NE(msg.find("x.json:3:"), std::string::npos) << msg;
}

TEST(JsonUtil, UnknownKeyIsAnErrorNamingIt) {
    const Json j = parse_json(R"({"width": 3, "widht": 4})", "c.json");
    const std::string msg = error_of([&] {
        JsonObject o(j, "c.json");
        o.get_int("width", 1);
        o.finish();
    });
    EXPECT_NE(msg.find("unknown key 'widht'"), std::string::npos) << msg;
}

TEST(JsonUtil, WrongTypeNamesThePointer) {
    const Json j = parse_json(R"({"cam": {"eye": [1, "two", 3]}})", "s.json");
    const std::string msg = error_of([&] {
        JsonObject o(j, "s.json");
        o.require_object("cam").require_vec3("eye");
    });
    EXPECT_NE(msg.find("s.json: /cam/eye/1"), std::string::npos) << msg;
}

TEST(JsonUtil, RangeWithLoAboveHiIsRejected) {
    const Json j = parse_json(R"({"r": [3, 1]})", "g.json");
    EXPECT_THROW(JsonObject(j, "g.json").get_range("r", {0, 1}), Error);
}

TEST(JsonUtil, NanLiteralIsASyntaxError) {
    EXPECT_THROW(parse_json(R"({"x": NaN})", "n.json"), Error);
}

TEST(JsonUtil, OverrideSetsNestedKeys) {
    Json j = parse_json(R"({"plan": {"rooms": [1, 2]}})", "o.json");
    apply_json_override(j, "plan.rooms=[2,4]");
    apply_json_override(j, "name=hello");
    EXPECT_EQ(j["plan"]["rooms"][1].get<int>(), 4);
    EXPECT_EQ(j["name"].get<std::string>(), "hello");
    EXPECT_THROW(apply_json_override(j, "novalue"), Error);
}

TEST(JsonUtil, CompactDumpIsStableAndParsesBack) {
    OrderedJson j;
    j["a"] = OrderedJson::array({0.1f, 2, 3});
    j["b"]["c"] = "x";
    const std::string s = dump_json_compact(j);
    EXPECT_EQ(s, dump_json_compact(j));
    EXPECT_NE(s.find("[0.10000000149011612, 2, 3]"), std::string::npos) << s;
    EXPECT_EQ(Json::parse(s)["b"]["c"], "x");
}
