// JSON configuration: presets, round trip, remeshing, errors that name the field and value, and the
// JSON Schema written from the parser's table of keys.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>

#include "drill/batched_integrator.hpp"
#include "drill/config.hpp"
#include "drill/config_schema.hpp"
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
  EXPECT_NE(parse_error_of("{\"string\": ").find("malformed JSON: parse error at line 1"), std::string::npos);
  EXPECT_EQ(parse_error_of("{\"string\": ").find("json.exception"), std::string::npos);  // no library tag
  {  // a key with a line break is shown escaped: still one line
    json j = preset_json("thesis-field");
    j["a\nb"] = 1;
    const std::string e = parse_error_of(j.dump());
    EXPECT_NE(e.find("config.\"a\\nb\" = 1: unknown key"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos);
  }
  EXPECT_NE(parse_error_of(with("/string/sections/0/elements", 6000)).find("exceeds 5000"), std::string::npos);
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

TEST(Config, StaticAgeingRoundTripsAndIsRefusedWhereItIsNotModelled) {
  json j = preset_json("thesis-rig");
  j["law"] = preset_json("rgd-rig")["law"];  // Eq. (5.1) with a0 > 0 (sample 175's): a static torque to age
  EXPECT_FALSE(j["law"].contains("static_ageing"));  // absent: no ageing, as before
  j["law"]["static_ageing"] = 0.5;
  EXPECT_NE(parse_error_of(j.dump()).find("law.static_ageing_s = nan: must be a positive time"), std::string::npos)
      << parse_error_of(j.dump());
  j["law"]["static_ageing_s"] = 0.05;
  const Config c = parse_config_text(j.dump());
  EXPECT_TRUE(c.law.ages());
  EXPECT_DOUBLE_EQ(c.law.ageing_factor(0.05), 1.25);
  EXPECT_EQ(to_json(c)["law"]["static_ageing"], 0.5);
  EXPECT_EQ(parse_config(to_json(c)).law, c.law);
  json b = j;
  b["simulation"]["scheme"] = "bdf2";
  EXPECT_NE(parse_error_of(b.dump()).find("law.static_ageing = 0.5: is implemented on the torsional engine's "
                                          "modified_euler scheme only"),
            std::string::npos)
      << parse_error_of(b.dump());
  b = j;
  b["law"]["static_ageing"] = -1.0;
  EXPECT_NE(parse_error_of(b.dump()).find("law.static_ageing = -1"), std::string::npos);
  json f = preset_json("thesis-field");  // Eqs. (3.2)-(3.3): no static torque
  f["law"]["static_ageing"] = 0.5;
  f["law"]["static_ageing_s"] = 0.05;
  EXPECT_NE(parse_error_of(f.dump()).find("needs a static torque to age"), std::string::npos) << parse_error_of(f.dump());
  EXPECT_FALSE(BatchedIntegrator(Simulation(c).integrator()).supports(Simulation(c).inputs()));
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

namespace {
// The preset as compact JSON text with `from` replaced once by `to` (for what a json value cannot
// hold: repeated keys, number literals as written).
std::string field_text_with(const std::string& from, const std::string& to) {
  std::string t = preset_json("thesis-field").dump();
  const std::size_t at = t.find(from);
  if (at == std::string::npos) return "pattern not found: " + from;
  return t.replace(at, from.size(), to);
}
bool mentions(const std::string& message, const std::string& part) { return message.find(part) != std::string::npos; }
}  // namespace

TEST(Config, IntegersOutOfRangeOrNotWholeAreRefusedNotWrapped) {
  std::string e = parse_error_of(with("/string/sections/0/elements", 4294967316LL));
  EXPECT_TRUE(mentions(e, "string.sections[0].elements = 4294967316")) << e;
  EXPECT_TRUE(mentions(e, "out of range")) << e;
  e = parse_error_of(with("/rom/modes", 4294967297LL));
  EXPECT_TRUE(mentions(e, "rom.modes = 4294967297")) << e;
  e = parse_error_of(with("/rom/modes", -4294967296LL));
  EXPECT_TRUE(mentions(e, "rom.modes = -4294967296")) << e;
  e = parse_error_of(field_text_with("\"modes\":20}", "\"modes\":1e12}"));
  EXPECT_TRUE(mentions(e, "rom.modes = 1000000000000")) << e;
  EXPECT_TRUE(mentions(e, "must be an integer")) << e;
  e = parse_error_of(with("/rom/modes", 2.5));
  EXPECT_TRUE(mentions(e, "rom.modes = 2.5: must be an integer")) << e;
  e = parse_error_of(with("/simulation/output_stride", 4294967316LL));
  EXPECT_TRUE(mentions(e, "simulation.output_stride = 4294967316")) << e;
  e = parse_error_of(with("/string/lumped_inertias", json::array({{{"node", 4294967295LL}, {"inertia_kg_m2", 1.0}}})));
  EXPECT_TRUE(mentions(e, "string.lumped_inertias[0].node = 4294967295")) << e;
  e = parse_error_of(with("/craig_bampton", {{"modes", {25, 2.5}}}));
  EXPECT_TRUE(mentions(e, "craig_bampton.modes[1] = 2.5: must be an integer")) << e;
  e = parse_error_of(with("/craig_bampton", {{"modes", {25, 4294967321LL}}}));
  EXPECT_TRUE(mentions(e, "craig_bampton.modes[1] = 4294967321")) << e;
  // in range: still accepted
  EXPECT_EQ(parse_config_text(with("/rom/modes", 12)).modes, 12);
}

TEST(Config, DuplicateKeysAreRefusedNamingTheKey) {
  std::string e = parse_error_of(field_text_with("\"modes\":20}", "\"modes\":20,\"modes\":12}"));
  EXPECT_TRUE(mentions(e, "rom.modes: duplicate key \"modes\"")) << e;
  e = parse_error_of(field_text_with("\"name\":", "\"name\":\"x\",\"name\":"));
  EXPECT_TRUE(mentions(e, "name: duplicate key \"name\"")) << e;
  e = parse_error_of(field_text_with("\"elements\":", "\"elements\":4,\"elements\":"));
  EXPECT_TRUE(mentions(e, "string.sections[].elements: duplicate key \"elements\"")) << e;
  // the same key in different objects is fine
  EXPECT_NO_THROW(parse_config_text(preset_json("thesis-field").dump()));
}

TEST(Config, MetricFractionsMustLieStrictlyBetweenZeroAndOne) {
  std::string e = parse_error_of(with("/metrics", {{"stick_threshold_fraction", 5}}));
  EXPECT_TRUE(mentions(e, "metrics.stick_threshold_fraction = 5: must be between 0 and 1")) << e;
  e = parse_error_of(with("/metrics", {{"stick_threshold_fraction", 0.0}}));
  EXPECT_TRUE(mentions(e, "metrics.stick_threshold_fraction = 0:")) << e;
  e = parse_error_of(with("/metrics", {{"slip_level_fraction", 1.0}}));
  EXPECT_TRUE(mentions(e, "metrics.slip_level_fraction = 1: must be between 0 and 1")) << e;
  e = parse_error_of(with("/metrics", {{"slip_level_fraction", -0.25}}));
  EXPECT_TRUE(mentions(e, "metrics.slip_level_fraction = -0.25:")) << e;
  EXPECT_NO_THROW(parse_config_text(with("/metrics", {{"stick_threshold_fraction", 0.1}, {"slip_level_fraction", 0.5}})));
}

TEST(Config, StartModeIsParsedValidatedAndSerialized) {
  EXPECT_EQ(preset("thesis-field").start, StartMode::rest);
  EXPECT_EQ(to_json(preset("thesis-field"))["simulation"]["start"], "rest");
  const Config c = parse_config_text(with("/simulation/start", "steady"));
  EXPECT_EQ(c.start, StartMode::steady);
  EXPECT_EQ(to_json(c)["simulation"]["start"], "steady");
  EXPECT_EQ(parse_config(to_json(c)).start, StartMode::steady);
  EXPECT_EQ(parse_config_text(with("/simulation/start", "rigid")).start, StartMode::rigid);
  const std::string e = parse_error_of(with("/simulation/start", "spinning"));
  EXPECT_TRUE(mentions(e, "simulation.start = \"spinning\"")) << e;
  EXPECT_TRUE(mentions(parse_error_of(with("/simulation/start", 1)), "simulation.start = 1")) << e;
}

namespace {
std::set<std::string> property_names(const json& properties) {
  std::set<std::string> names;
  for (auto it = properties.begin(); it != properties.end(); ++it) names.insert(it.key());
  return names;
}
// The JSON pointer of a block in a configuration: "string.sections" is each item of that array.
/// Where a block's object sits in a configuration: string.sections is an array of objects (its first
/// item), top_drive.controller an object inside the controlled top drive, axial.bit inside the rgd axial model.
std::string block_pointer(const std::string& name) {
  if (name == "config") return "";
  if (name == "top_drive.controller") return "/top_drive/controller";
  if (name == "axial.bit") return "/axial/bit";
  const std::size_t dot = name.find('.');
  return dot == std::string::npos ? "/" + name : "/" + name.substr(0, dot) + "/" + name.substr(dot + 1) + "/0";
}
}  // namespace

TEST(Config, SchemaPropertiesAreTheKeysTheParserAccepts) {
  const json s = config_schema();
  EXPECT_EQ(s["$schema"], "https://json-schema.org/draft/2020-12/schema");
  EXPECT_EQ(property_names(s["properties"]), schema::keys("config"));
  for (const schema::Block& b : schema::blocks()) {
    std::vector<std::string> types{""};  // a block without variants
    if (b.name != "config") {
      const json& d = s["$defs"][b.name];
      if (b.variants.empty()) {
        EXPECT_EQ(property_names(d["properties"]), schema::keys(b.name)) << b.name;
      } else {
        types.clear();
        ASSERT_EQ(d["allOf"].size(), b.variants.size()) << b.name;
        for (const json& c : d["allOf"]) {
          types.push_back(c["if"]["properties"]["type"]["const"]);
          EXPECT_EQ(property_names(c["then"]["properties"]), schema::keys(b.name, types.back()))
              << b.name << " " << types.back();
        }
      }
    }
    // the parser itself: in each block (and variant) it takes every key the schema names (a null value
    // is refused for another reason) and refuses any other
    for (const std::string& type : types) {
      const std::string at = block_pointer(b.name);
      // the axial-torsional model's blocks in its own preset (a "law" block is refused with it)
      const bool rgd = b.name == "axial.bit" || (b.name == "axial" && type == "rgd");
      json base = preset_json(rgd ? "rgd-field" : "thesis-field");
      if (b.name == "top_drive.controller") base["top_drive"] = {{"type", "controlled"}, {"inertia_kg_m2", 2000.0}};
      if (!at.empty()) base[json::json_pointer(at)] = type.empty() ? json::object() : json{{"type", type}};
      for (const std::string& key : schema::keys(b.name, type)) {
        json j = base;
        j[json::json_pointer(at)][key] = nullptr;
        const std::string e = parse_error_of(j.dump());
        EXPECT_FALSE(mentions(e, "unknown key")) << b.name << " " << type << " " << key << ": " << e;
      }
      json j = base;
      j[json::json_pointer(at)]["not_a_key"] = nullptr;
      EXPECT_TRUE(mentions(parse_error_of(j.dump()), "not_a_key = null: unknown key")) << b.name << " " << type;
    }
  }
}

TEST(Config, SchemaDefaultsAreWhatTheParserTakes) {
  const json field = preset_json("thesis-field");
  const json minimal{{"string", field["string"]}, {"law", field["law"]}};  // no simulation block either
  const json c = to_json(parse_config(minimal));
  for (const schema::Field& f : schema::block("config").fields) {
    if (!c.contains(f.key)) continue;  // sensors, sweep...: written only when not the default
    if (!f.dflt.is_null()) EXPECT_EQ(c[f.key], f.dflt) << f.key;
    if (f.type != schema::Field::Type::object || !schema::block(f.block).variants.empty()) continue;
    for (const schema::Field& g : schema::block(f.block).fields)
      if (!g.dflt.is_null()) EXPECT_EQ(c[f.key][g.key], g.dflt) << f.key << "." << g.key;
  }
  EXPECT_EQ(c["simulation"]["transient_s"], 50.0);  // half the default duration
}

TEST(Config, SchemaBoundsAreTheValidatorsBounds) {
  // every bound the table states for a number or an integer key (the schema's) is enforced: a value
  // just outside it is refused, naming the key; in the presets and in the variants they lack
  std::vector<json> bases;
  for (const auto& name : preset_names()) bases.push_back(preset_json(name));
  const json field = preset_json("thesis-field");
  auto variant = [&](const std::string& pointer, const json& value) {
    json j = field;
    j[json::json_pointer(pointer)] = value;
    bases.push_back(j);
  };
  for (const char* type : {"stiff", "pi", "soft_speed", "z_torque"})
    variant("/top_drive", {{"type", "controlled"},
                           {"inertia_kg_m2", 2000.0},
                           {"controller",
                            {{"type", type}, {"kp_nms_rad", 900.0}, {"ki_nm_rad", 250.0}, {"torque_limit_nm", 1e6},
                             {"sample_time_s", 1e-3}}}});
  variant("/top_drive", {{"type", "motor"}, {"slope_nms_rad", 1e4}, {"inertia_kg_m2", 2000.0}, {"max_torque_nm", 1e6}});
  variant("/axial", {{"type", "jack"}, {"gain_n_rad", 1e5}, {"relaxation_s", 1.0}});
  variant("/string/lumped_inertias", json::array({{{"node", -1}, {"inertia_kg_m2", 100.0}}}));
  variant("/law", {{"type", "tucker_wang"}, {"speed_unit", "rad_s"}, {"wob_ref_n", 245e3}, {"c0", 4700.0},
                   {"alpha0", 2.0}, {"alpha1", 0.5}, {"alpha2", 0.1}});
  int checked = 0;
  for (const json& base : bases)
    for (const schema::Block& b : schema::blocks()) {
      const std::string at = block_pointer(b.name);
      const json::json_pointer ptr(at);
      if (!base.contains(ptr) || !base.at(ptr).is_object()) continue;
      std::vector<schema::Field> fields = b.fields;
      for (const schema::Variant& v : b.variants)
        if (base.at(ptr).value("type", "") == v.type) fields.insert(fields.end(), v.fields.begin(), v.fields.end());
      std::string where = b.name == "config" ? "config" : b.name;
      if (at.size() > 2 && at.substr(at.size() - 2) == "/0") where += "[0]";
      for (const schema::Field& f : fields) {
        if (f.type != schema::Field::Type::number && f.type != schema::Field::Type::integer) continue;
        const double step = f.type == schema::Field::Type::integer ? 1.0 : 1e-3;
        std::vector<double> outside;
        if (f.min) outside.push_back(f.min->exclusive ? f.min->value : f.min->value - step);
        if (f.max) outside.push_back(f.max->exclusive ? f.max->value : f.max->value + step);
        for (const double value : outside) {
          json j = base;
          j[ptr][f.key] = f.type == schema::Field::Type::integer ? json(static_cast<int>(value)) : json(value);
          const std::string e = parse_error_of(j.dump());
          EXPECT_TRUE(mentions(e, where + "." + f.key + " = ")) << where << "." << f.key << " = " << value << ": " << e;
          ++checked;
        }
      }
    }
  EXPECT_GT(checked, 100);
}

TEST(Config, SchemaKeyIsAcceptedAndIgnored) {
  json j = preset_json("thesis-field");
  j["$schema"] = "../python/drillpy/model/config.schema.json";
  EXPECT_EQ(to_json(parse_config(j)), to_json(preset("thesis-field")));
  j["$schema"] = 3;
  EXPECT_TRUE(mentions(parse_error_of(j.dump()), "config.$schema = 3: must be a string"));
}

namespace {
int nesting_depth(const json& j) {  // levels of arrays and objects (a scalar: 0)
  int d = 0;
  if (j.is_structured())
    for (const auto& v : j) d = std::max(d, nesting_depth(v));
  return j.is_structured() ? d + 1 : 0;
}
}  // namespace

TEST(Config, NestingBeyondTheLimitIsRefusedAtOnceInOneShortLine) {
  for (const auto& name : preset_names()) EXPECT_LE(nesting_depth(preset_json(name)), 4) << name;  // the "(... has 4)"
  const std::string ok = std::string(max_json_depth, '[') + std::string(max_json_depth, ']');
  EXPECT_EQ(nesting_depth(parse_json_text(ok)), max_json_depth);  // the limit itself is read
  const std::string expected = "--config deep.json: JSON nested too deep: more than 64 levels of arrays and objects"
                               " (a configuration has 4)";
  for (const std::size_t n : {std::size_t(max_json_depth) + 1, std::size_t(200000)}) {
    const std::string deep = std::string(n, '[') + std::string(n, ']');
    const auto t0 = std::chrono::steady_clock::now();
    std::string e = "no error";
    try {
      parse_json_text(deep, "--config deep.json");
    } catch (const std::invalid_argument& x) {
      e = x.what();
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(e, expected) << n;
    EXPECT_LT(seconds, 5.0) << n;  // was 67 s for 200 000 levels (a path string rebuilt per level)
  }
  // objects count as levels too, and the whole-config parser refuses the same way
  std::string objs;
  for (int k = 0; k < 70; ++k) objs += "{\"a\": ";
  objs += "1" + std::string(70, '}');
  EXPECT_EQ(parse_error_of(objs),
            "config: JSON nested too deep: more than 64 levels of arrays and objects (a configuration has 4)");
}

TEST(Config, TooManyTimeStepsNamesTheTimeStepAndTheDuration) {
  std::string e = parse_error_of(with("/simulation/dt_s", 1e-12));
  EXPECT_EQ(e, "simulation.dt_s = 1e-12 with simulation.duration_s = 200: 2e+14 steps, at most 2e+09; "
               "a time step below 1 us: in ms or us typed as s?");
  e = parse_error_of(with("/simulation/duration_s", 1e300));
  EXPECT_EQ(e, "simulation.dt_s = 0.000512 with simulation.duration_s = 1e+300: 1.95e+303 steps, at most 2e+09; "
               "a duration over 100 days: in ms typed as s?");
  e = parse_error_of(with("/simulation/duration_s", 2e6));  // both plausible alone: no hint
  EXPECT_EQ(e, "simulation.dt_s = 0.000512 with simulation.duration_s = 2000000: 3.91e+09 steps, at most 2e+09");
}
