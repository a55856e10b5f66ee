// config_fields_test.cpp: one description reads, validates, writes and documents a config.
#include <gtest/gtest.h>

#include "ltm/core/config_fields.h"

using namespace ltm;

namespace {
struct Toy {
    int n = 3;
    float rate = 0.5f;
    bool on = true;
    std::string mode = "a";
    uint64_t seed = 7;
    float eps = 1.f;
    static const ConfigFields<Toy> &fields() {
        static const ConfigFields<Toy> f = ConfigFields<Toy>()
                                               .field("n", &Toy::n, "a count", at_least(1))
                                               .field("rate", &Toy::rate, "a share", from_below(0, 1))
                                               .field("on", &Toy::on, "a switch")
                                               .field("mode", &Toy::mode, "a choice", {}, {"a", "b"})
                                               .field("seed", &Toy::seed, "a seed")
                                               .field("eps", &Toy::eps, "a positive number", positive())
                                               .omit_default();
        return f;
    }
};
std::string error_of(const std::string &json) {
    try {
        Toy::fields().read(parse_json(json, "toy.json"), "toy.json");
    } catch (const Error &e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(ConfigFields, ReadsWhatIsGivenAndKeepsTheDefaults) {
    const Toy t = Toy::fields().read(parse_json(R"({"n": 5, "mode": "b", "seed": 9})", "toy.json"), "toy.json");
    EXPECT_EQ(t.n, 5);
    EXPECT_EQ(t.mode, "b");
    EXPECT_EQ(t.seed, 9u);
    EXPECT_EQ(t.rate, 0.5f);
    EXPECT_TRUE(t.on);
    // Written back in declaration order, floats in their shortest form; reading that is the identity.
    const OrderedJson j = Toy::fields().write(t);
    EXPECT_EQ(j.dump(), R"({"n":5,"rate":0.5,"on":true,"mode":"b","seed":9})");   // eps: default, omitted
    Toy v = t;
    v.eps = 2.f;
    EXPECT_EQ(Toy::fields().write(v)["eps"], 2.0);
    const Toy u = Toy::fields().read(Json::parse(j.dump()), "again");
    EXPECT_EQ(Toy::fields().write(u), j);
}

TEST(ConfigFields, BadValuesAreLocatedErrors) {
    EXPECT_EQ(error_of(R"({"n": 0})"), "toy.json: /n: 0 is outside >= 1");
    EXPECT_EQ(error_of(R"({"rate": 1.0})"), "toy.json: /rate: 1.0 is outside [0, 1)");
    EXPECT_EQ(error_of(R"({"mode": "c"})"), "toy.json: /mode: 'c' is not one of a, b");
    EXPECT_NE(error_of(R"({"n": "x"})").find("toy.json: /n"), std::string::npos);
    EXPECT_NE(error_of(R"({"m": 1})").find("unknown key 'm'"), std::string::npos);
    EXPECT_NE(error_of(R"({"seed": -1})").find("must be >= 0"), std::string::npos);
    EXPECT_EQ(error_of(R"({"eps": 0.0})"), "toy.json: /eps: 0.0 is outside > 0");   // a float's smallest step is not 0
    EXPECT_EQ(error_of(R"({"eps": 1e-30})"), "");
}

TEST(ConfigFields, TableShowsDefaultsLimitsAndDocs) {
    EXPECT_EQ(Toy::fields().markdown_table(),
              "| key | default | allowed | meaning |\n|---|---|---|---|\n"
              "| `n` | `3` | >= 1 | a count |\n"
              "| `rate` | `0.5` | [0, 1) | a share |\n"
              "| `on` | `true` | true, false | a switch |\n"
              "| `mode` | `\"a\"` | `a`, `b` | a choice |\n"
              "| `seed` | `7` | any | a seed |\n"
              "| `eps` | `1.0` | > 0 | a positive number |\n");
}

// Seeds use the whole uint64 range (the CLI's --seed does): what write() emits, read() takes back.
TEST(ConfigFields, Uint64FieldsRoundTripTheirWholeRange) {
    Toy t;
    t.seed = (uint64_t(1) << 63) + 12345;
    const Toy back = Toy::fields().read(parse_json(Toy::fields().write(t).dump(), "toy.json"), "toy.json");
    EXPECT_EQ(back.seed, t.seed);
    EXPECT_NE(error_of(R"({"seed": -1})").find("/seed"), std::string::npos);
    EXPECT_NE(error_of(R"({"seed": 1.5})").find("/seed"), std::string::npos);
}

// Integer limits compare without casting the bound into the value's type.
TEST(ConfigFields, IntegerLimitsOutsideTheTypesRangeHoldExactly) {
    EXPECT_TRUE(at_least(-1).contains(uint64_t(0)));
    EXPECT_FALSE(between(-5e9, -4e9).contains(int(0)));
    EXPECT_TRUE(between(-5e9, 5e9).contains(int(7)));
    EXPECT_FALSE(positive().contains(int(0)));
    EXPECT_TRUE(positive().contains(int(1)));
}
