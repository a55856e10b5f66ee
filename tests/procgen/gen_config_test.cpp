// gen_config_test.cpp: GenConfig JSON: the shipped defaults file, round trips, strictness.
#include "ltm/procgen/gen_config.h"

#include <gtest/gtest.h>

#include <string>

#include "ltm/core/error.h"
#include "ltm/core/file_util.h"

namespace ltm {
namespace {

// Runs from_json and returns the error message ("" if it did not throw).
std::string from_json_error(const std::string &text) {
    try {
        GenConfig::from_json(parse_json(text, "test.json"), "test.json");
    } catch (const Error &e) {
        return e.what();
    }
    return "";
}

TEST(GenConfig, DefaultsEqualTheShippedConfigFile) {
    const Json file = parse_json_file(LTM_SOURCE_DIR "/configs/gen/indoor.json");
    const Json defaults = Json::parse(GenConfig().to_json().dump());
    EXPECT_EQ(defaults, file) << "regenerate configs/gen/indoor.json from GenConfig().to_json():\n"
                              << dump_json_compact(GenConfig().to_json());
    // Reading the file gives back the defaults, key for key.
    EXPECT_EQ(GenConfig::from_json(file, "indoor.json").to_json(), GenConfig().to_json());
}

TEST(GenConfig, ToJsonFromJsonRoundTripsEveryKey) {
    GenConfig c;
    c.plan.weight_hallway = 0.7f;
    c.plan.n_rooms = {3, 7};
    c.rooms.ceiling_height = {2.4f, 2.9f};
    c.walls.thickness = 0.14f;
    c.doors.p_extra = 0.05f;
    c.furniture.archetypes["bed"].width = {1.1f, 1.3f};
    c.furniture.archetypes["plant"].weight = 0.f;
    c.textures.tile_scale = {0.31f, 0.33f};
    c.lights.temperature = {3000.f, 3100.f};
    c.lights.p_ajar = 1.f;
    c.camera.width = 640;
    const OrderedJson j = c.to_json();
    const GenConfig back = GenConfig::from_json(Json::parse(j.dump()), "roundtrip");
    EXPECT_EQ(back.to_json(), j);
    EXPECT_EQ(back.plan.n_rooms.hi, 7);
    EXPECT_EQ(back.furniture.archetypes.at("bed").width.x, 1.1f);
    EXPECT_EQ(back.walls.thickness, 0.14f);
    EXPECT_EQ(back.camera.width, 640);
}

TEST(GenConfig, MissingKeysKeepTheirDefaults) {
    const GenConfig c = GenConfig::from_json(parse_json(R"({"lights": {"p_ajar": 0.5}})", "t"), "t");
    EXPECT_EQ(c.lights.p_ajar, 0.5f);
    GenConfig expected;
    expected.lights.p_ajar = 0.5f;
    EXPECT_EQ(c.to_json(), expected.to_json());
}

TEST(GenConfig, UnknownKeysAreErrorsThatNameTheKey) {
    std::string e = from_json_error(R"({"bogus": 1})");
    EXPECT_NE(e.find("bogus"), std::string::npos) << e;
    e = from_json_error(R"({"plan": {"snapp": 0.05}})");
    EXPECT_NE(e.find("snapp"), std::string::npos) << e;
    EXPECT_NE(e.find("test.json: /plan"), std::string::npos) << e;
    e = from_json_error(R"({"furniture": {"archetypes": {"spaceship": {"weight": 1}}}})");
    EXPECT_NE(e.find("spaceship"), std::string::npos) << e;
    e = from_json_error(R"({"furniture": {"archetypes": {"bed": {"colour": 1}}}})");
    EXPECT_NE(e.find("colour"), std::string::npos) << e;
    EXPECT_NE(e.find("/furniture/archetypes/bed"), std::string::npos) << e;
}

TEST(GenConfig, InvalidValuesAreErrorsWithTheirJsonPointer) {
    struct Case {
        const char *json, *pointer;
    };
    const Case cases[] = {
        {R"({"rooms": {"size": [7.0, 2.5]}})", "/rooms/size"},                 // lo > hi
        {R"({"lights": {"p_ajar": 1.5}})", "/lights/p_ajar"},                   // probability > 1
        {R"({"lights": {"per_room": [0, 2]}})", "/lights/per_room"},            // count < 1
        {R"({"plan": {"n_rooms": [1, 3]}})", "/plan/n_rooms"},                  // a split needs 2
        {R"({"walls": {"thickness": -0.1}})", "/walls/thickness"},
        {R"({"plan": {"snap": "big"}})", "/plan/snap"},                         // wrong type
        {R"({"camera": {"width": 0}})", "/camera/width"},
        {R"({"lights": {"temperature": [500, 6500]}})", "/lights/temperature"}, // outside blackbody fit
        {R"({"plan": {"hallway_rooms_per_side": [1.5, 2]}})", "/plan/hallway_rooms_per_side"},
        {R"({"rooms": {"min_side": 1.0}})", "/rooms/min_side"},                 // no door fits
        {R"({"textures": {"p_floor_wood": 0.8, "p_floor_tiles": 0.5}})", "/textures/p_floor_tiles"},
        {R"({"plan": {"weight_single": 0, "weight_l_room": 0, "weight_bsp": 0, "weight_hallway": 0,
                     "weight_l_split": 0}})", "/plan"},
    };
    for (const Case &c : cases) {
        const std::string e = from_json_error(c.json);
        EXPECT_NE(e.find(std::string("test.json: ") + c.pointer), std::string::npos)
            << c.json << " gave: '" << e << "'";
    }
}

TEST(GenConfig, TopLevelMustBeAnObject) {
    EXPECT_THROW(GenConfig::from_json(Json::array({1, 2}), "t"), Error);
    EXPECT_THROW(GenConfig::from_json(parse_json(R"({"plan": 3})", "t"), "t"), Error);
}

}  // namespace
}  // namespace ltm

// docs/config.md shows each section's table as its description prints it (on failure: paste it).
TEST(GenConfig, GlossySectionIsCheckedWithLocatedErrors) {
    EXPECT_EQ(ltm::from_json_error(R"({"glossy": {"p_conductor": 0.5, "roughness": [0.05, 0.3], "metals": ["Au"]}})"), "");
    EXPECT_NE(ltm::from_json_error(R"({"glossy": {"archetypes": ["table", "piano"]}})").find("/glossy/archetypes/1"), std::string::npos);
    EXPECT_NE(ltm::from_json_error(R"({"glossy": {"metals": ["Unobtainium"]}})").find("/glossy/metals/0"), std::string::npos);
    EXPECT_NE(ltm::from_json_error(R"({"glossy": {"roughness": [0.0, 0.1]}})").find("/glossy/roughness"), std::string::npos);
    EXPECT_NE(ltm::from_json_error(R"({"glossy": {"p_walls": 1.5}})").find("/glossy/p_walls"), std::string::npos);
    EXPECT_NE(ltm::from_json_error(R"({"glossy": {"p_conductor": 0.5, "archetypes": []}})").find("/glossy/archetypes"), std::string::npos);
    EXPECT_NE(ltm::from_json_error(R"({"glossy": {"colour": 1}})"), "");
}

TEST(GenConfig, DocsTablesAreTheDescriptions) {
    const std::string doc = ltm::read_file(LTM_SOURCE_DIR "/docs/config.md");
    using G = ltm::GenConfig;
    for (const std::string &table : {G::Plan::fields().markdown_table(), G::Rooms::fields().markdown_table(),
                                     G::Walls::fields().markdown_table(), G::Doors::fields().markdown_table(),
                                     G::Furniture::fields().markdown_table(), G::Textures::fields().markdown_table(),
                                     G::Lights::fields().markdown_table(), G::CameraCfg::fields().markdown_table(),
                                     G::Glossy::fields().markdown_table(), G::Fixtures::fields().markdown_table()})
        EXPECT_NE(doc.find(table), std::string::npos) << "docs/config.md lacks this table:\n" << table;
}

// docs/config.md documents every key of the shipped config (docs drift otherwise).
TEST(GenConfig, EveryKeyIsDocumented) {
    const std::string doc = ltm::read_file(LTM_SOURCE_DIR "/docs/config.md");
    const ltm::Json cfg = ltm::parse_json_file(LTM_SOURCE_DIR "/configs/gen/indoor.json");
    for (auto it = cfg.begin(); it != cfg.end(); ++it) {
        EXPECT_NE(doc.find("`" + it.key() + "`"), std::string::npos) << it.key();
        for (auto kt = it->begin(); it->is_object() && kt != it->end(); ++kt)
            EXPECT_NE(doc.find("`" + kt.key() + "`"), std::string::npos) << it.key() << "." << kt.key();
    }
    for (const auto &[name, ranges] : ltm::default_archetypes())
        EXPECT_NE(doc.find("`" + name + "`"), std::string::npos) << name;
}

// Every shipped generator config parses (the glossy preset turns conductors on).
TEST(GenConfig, EveryShippedGeneratorConfigParses) {
    const ltm::GenConfig glossy = ltm::GenConfig::from_json(ltm::parse_json_file(LTM_SOURCE_DIR "/configs/gen/glossy.json"), "glossy.json");
    EXPECT_GT(glossy.glossy.p_conductor, 0.f);
    EXPECT_GT(glossy.glossy.p_walls, 0.f);
    EXPECT_EQ(glossy.glossy.roughness.x, 0.1f);   // the paper's α
    EXPECT_EQ(glossy.glossy.roughness.y, 0.1f);
    ltm::GenConfig rest = glossy;   // the rest is the default house
    rest.glossy = ltm::GenConfig().glossy;
    EXPECT_EQ(rest.to_json(), ltm::GenConfig().to_json());
}
