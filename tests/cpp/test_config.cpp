// JSON configuration: presets, round trip, remeshing, and errors that name the field and value.
#include <gtest/gtest.h>

#include "drill/config.hpp"
#include "drill/presets.hpp"

using namespace drill;

namespace {
std::string error_of(const std::string& text) {
  try {
    parse_config_text(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}
std::string with(const std::string& path, const json& value) {
  json j = preset_json("thesis-field");
  j[json::json_pointer(path)] = value;
  return j.dump();
}
}  // namespace

TEST(Config, PresetsParseAndRoundTrip) {
  for (const auto& name : preset_names()) {
    const Config c = preset(name);
    const Config back = parse_config(to_json(c));
    EXPECT_EQ(to_json(back), to_json(c)) << name;
  }
  const Config f = preset("thesis-field");
  EXPECT_EQ(f.string.sections[0].elements, 91);
  EXPECT_EQ(f.string.sections[1].elements, 9);
  EXPECT_EQ(f.law.speed_unit, SpeedUnit::rpm);
  EXPECT_EQ(preset("thesis-ch6").cb_modes, (std::vector<int>{25, 25}));
}

TEST(Config, TotalElementsSplitInProportionToLength) {
  Config c = preset("thesis-field");
  c.set_total_elements(100);
  EXPECT_EQ(c.string.sections[0].elements, 91);
  EXPECT_EQ(c.string.sections[1].elements, 9);
  c.set_total_elements(13);
  EXPECT_EQ(c.string.n_elements(), 13);
  EXPECT_GE(c.string.sections[1].elements, 1);
  EXPECT_THROW(c.set_total_elements(1), std::invalid_argument);
}

TEST(Config, ErrorsNameTheFieldAndTheValue) {
  EXPECT_NE(error_of("{\"string\": ").find("malformed JSON"), std::string::npos);
  EXPECT_NE(error_of("[1, 2]").find("must be a JSON object"), std::string::npos);
  EXPECT_NE(error_of("{}").find("config.string: missing"), std::string::npos);
  json j = preset_json("thesis-field");
  j.erase("law");
  EXPECT_NE(error_of(j.dump()).find("config.law: missing"), std::string::npos);
  EXPECT_NE(error_of(with("/string/sections/0/length_m", -5.0)).find("string.sections[0].length_m = -5"), std::string::npos);
  EXPECT_NE(error_of(with("/string/sections/1/inner_radius_m", 0.1)).find("string.sections[1].inner_radius_m = 0.1"),
            std::string::npos);
  EXPECT_NE(error_of(with("/string/sections/0/elements", 0)).find("string.sections[0].elements = 0"), std::string::npos);
  EXPECT_NE(error_of(with("/string/sections/0/elements", 2.5)).find("must be an integer"), std::string::npos);
  EXPECT_NE(error_of(with("/string/sections/0/density_kg_m3", "heavy")).find("density_kg_m3 = \"heavy\""),
            std::string::npos);
  EXPECT_NE(error_of(with("/rom/modes", 500)).find("rom.modes = 500"), std::string::npos);
  EXPECT_NE(error_of(with("/law/type", "magic")).find("law.type = \"magic\""), std::string::npos);
  EXPECT_NE(error_of(with("/simulation/scheme", "rk45")).find("simulation.scheme = \"rk45\""), std::string::npos);
  EXPECT_NE(error_of(with("/simulation/transient_s", 500.0)).find("simulation.transient_s = 500"), std::string::npos);
  EXPECT_NE(error_of(with("/operation/colour", 3)).find("operation.colour = 3: unknown key"), std::string::npos);
  EXPECT_NE(error_of(with("/damping", json{{"type", "rayleigh"}, {"pairs", {1, 2}}})).find("damping.pairs"),
            std::string::npos);
  // JSON has no NaN or infinity literal; a huge number overflows to infinity in the parser
  EXPECT_NE(error_of(with("/string/sections/0/youngs_modulus_pa", 1e308 * 10)).find("youngs_modulus_pa"),
            std::string::npos);
  EXPECT_NE(error_of(with("/operation/top_speed_rad_s", nullptr)).find("operation.top_speed_rad_s = null"),
            std::string::npos);
}

TEST(Config, UnknownPresetListsTheKnownOnes) {
  try {
    preset("thesis-moon");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("thesis-field, thesis-ch4, thesis-rig, thesis-ch6"), std::string::npos);
  }
}
