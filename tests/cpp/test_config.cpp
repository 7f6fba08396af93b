// JSON configuration: presets, round trip, remeshing, and errors that name the field and value.
#include <gtest/gtest.h>

#include "drill/config.hpp"
#include "drill/presets.hpp"
#include "drill/simulation.hpp"

using namespace drill;

namespace {
std::string parse_error_of(const std::string& text) {
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
  EXPECT_NE(parse_error_of("{\"string\": ").find("malformed JSON"), std::string::npos);
  EXPECT_NE(parse_error_of("[1, 2]").find("must be a JSON object"), std::string::npos);
  EXPECT_NE(parse_error_of("{}").find("config.string: missing"), std::string::npos);
  json j = preset_json("thesis-field");
  j.erase("law");
  EXPECT_NE(parse_error_of(j.dump()).find("config.law: missing"), std::string::npos);
  EXPECT_NE(parse_error_of(with("/string/sections/0/length_m", -5.0)).find("string.sections[0].length_m = -5"), std::string::npos);
  EXPECT_NE(parse_error_of(with("/string/sections/1/inner_radius_m", 0.1)).find("string.sections[1].inner_radius_m = 0.1"),
            std::string::npos);
  EXPECT_NE(parse_error_of(with("/string/sections/0/elements", 0)).find("string.sections[0].elements = 0"), std::string::npos);
  EXPECT_NE(parse_error_of(with("/string/sections/0/elements", 2.5)).find("must be an integer"), std::string::npos);
  EXPECT_NE(parse_error_of(with("/string/sections/0/density_kg_m3", "heavy")).find("density_kg_m3 = \"heavy\""),
            std::string::npos);
  EXPECT_NE(parse_error_of(with("/rom/modes", 500)).find("rom.modes = 500"), std::string::npos);
  EXPECT_NE(parse_error_of(with("/law/type", "magic")).find("law.type = \"magic\""), std::string::npos);
  EXPECT_NE(parse_error_of(with("/simulation/scheme", "rk45")).find("simulation.scheme = \"rk45\""), std::string::npos);
  EXPECT_NE(parse_error_of(with("/simulation/transient_s", 500.0)).find("simulation.transient_s = 500"), std::string::npos);
  EXPECT_NE(parse_error_of(with("/operation/colour", 3)).find("operation.colour = 3: unknown key"), std::string::npos);
  EXPECT_NE(parse_error_of(with("/damping", json{{"type", "rayleigh"}, {"pairs", {1, 2}}})).find("damping.pairs"),
            std::string::npos);
  // JSON has no NaN or infinity literal; a huge number overflows to infinity in the parser
  EXPECT_NE(parse_error_of(with("/string/sections/0/youngs_modulus_pa", 1e308 * 10)).find("youngs_modulus_pa"),
            std::string::npos);
  EXPECT_NE(parse_error_of(with("/operation/top_speed_rad_s", nullptr)).find("operation.top_speed_rad_s = null"),
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

TEST(Config, StringFrictionRoundTripsAndDefaultsToZero) {
  // operation.string_friction_nm: Coulomb string friction T_sf at the bit [N m] (an extension, not in the thesis)
  EXPECT_EQ(preset("thesis-field").string_friction, 0.0);
  EXPECT_EQ(to_json(preset("thesis-field"))["operation"]["string_friction_nm"], 0.0);
  const Config c = parse_config_text(with("/operation/string_friction_nm", 1.25));
  EXPECT_EQ(c.string_friction, 1.25);
  EXPECT_EQ(c.bit_viscous, 0.0);
  const Config back = parse_config(to_json(c));
  EXPECT_EQ(back.string_friction, 1.25);
  EXPECT_EQ(to_json(back), to_json(c));
  EXPECT_EQ(Simulation(c).inputs().string_friction, 1.25);
}

TEST(Config, NegativeOrNonFiniteStringFrictionIsRefused) {
  EXPECT_NE(parse_error_of(with("/operation/string_friction_nm", -0.5))
                .find("operation.string_friction_nm = -0.5: must not be negative"),
            std::string::npos)
      << parse_error_of(with("/operation/string_friction_nm", -0.5));
  // JSON has no NaN or infinity literal (an infinite value is written as null); a Config set in
  // code is validated with the same message
  EXPECT_NE(parse_error_of(with("/operation/string_friction_nm", 1e308 * 10)).find("operation.string_friction_nm = null"),
            std::string::npos);
  EXPECT_NE(parse_error_of(with("/operation/string_friction_nm", "big")).find("operation.string_friction_nm = \"big\""),
            std::string::npos);
  Config c = preset("thesis-field");
  for (double bad : {std::nan(""), HUGE_VAL}) {
    c.string_friction = bad;
    try {
      c.validate();
      FAIL() << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("operation.string_friction_nm = " + show(bad) + ": must be a finite number"),
                std::string::npos)
          << e.what();
    }
  }
}
