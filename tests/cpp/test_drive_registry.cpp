// The top-drive registry (drives/registry.hpp): every registered drive has a unique name and keys,
// is parsed from its name and written back through the configuration, refuses a bad value of each
// of its keys (and the keys of the other drives) naming the field, and behaves as a drive: it turns
// at the command without torque, at the command whatever the torque when it does not droop, and a
// short run with it is finite, with the top at the command when the top has no inertia. The
// physics of each drive: test_topdrive.cpp (motor), test_controller.cpp (controlled).
#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <set>
#include <string>

#include "drill/config.hpp"
#include "drill/presets.hpp"
#include "drill/simulation.hpp"
#include "error_text.hpp"

using namespace drill;

namespace {

/// A "top_drive" block of kind k with every number of its variant at `value` and, for a drive with a
/// controller, a stiff controller with every key at 0.5 and a torque limit far above the rig's torques.
json drive_registry_json(TopDrive::Kind k, double value) {
  const std::string type = TopDrive::kind_name(k);
  json j = {{"type", type}};
  const schema::Block& block = schema::block("top_drive");
  for (const schema::Variant& v : block.variants)
    if (v.type == type)
      for (const schema::Field& f : v.fields) {
        if (f.type == schema::Field::Type::number) {
          j[f.key] = value;
        } else if (f.type == schema::Field::Type::object && f.block == "top_drive.controller") {
          json ctl = {{"type", "stiff"}, {"torque_limit_nm", 1e6}};
          for (const std::string& key : schema::keys("top_drive.controller", "stiff"))
            if (!ctl.contains(key)) ctl[key] = 0.5;
          j[f.key] = ctl;
        } else {
          ADD_FAILURE() << "top_drive." << f.key << " of " << type << ": a key the test does not fill";
        }
      }
  return j;
}

/// The test rig (Table 5.1, one mode) with the drive of kind k (every number 0.5), 2 s long.
json drive_registry_rig(TopDrive::Kind k) {
  json j = preset_json("thesis-rig");
  j["top_drive"] = drive_registry_json(k, 0.5);
  j["simulation"]["duration_s"] = 2.0;
  j["simulation"]["transient_s"] = 1.0;
  return j;
}

}  // namespace

TEST(DriveRegistry, NamesAndKeysAreUniqueAndInTheListsOrder) {
  const schema::Block& block = schema::block("top_drive");
  ASSERT_EQ(block.variants.size(), std::size(TopDrive::kinds));
  EXPECT_EQ(TopDrive{}.kind, TopDrive::kinds[0].value);  // the first of the list is the default
  std::set<std::string> names;
  for (std::size_t i = 0; i < std::size(TopDrive::kinds); ++i) {
    const Named<TopDrive::Kind>& k = TopDrive::kinds[i];
    EXPECT_TRUE(names.insert(k.name).second) << k.name;
    EXPECT_EQ(static_cast<std::size_t>(k.value), i) << k.name;
    EXPECT_EQ(TopDrive::parse_kind(k.name), k.value);
    EXPECT_EQ(TopDrive::kind_name(k.value), k.name);
    EXPECT_EQ(block.variants[i].type, k.name);
    std::set<std::string> keys;  // the block's keys ("type") and the variant's, none twice
    for (const schema::Field& f : block.fields) keys.insert(f.key);
    for (const schema::Field& f : block.variants[i].fields) EXPECT_TRUE(keys.insert(f.key).second) << k.name << "." << f.key;
    EXPECT_EQ(schema::keys("top_drive", k.name), keys) << k.name;
    // a drive with inertia says so in its keys; one with a controller has the controller block
    TopDrive d;
    d.kind = k.value;
    EXPECT_EQ(keys.count("inertia_kg_m2") == 1, d.has_inertia()) << k.name;
    EXPECT_EQ(keys.count("controller") == 1, d.has_controller()) << k.name;
  }
  EXPECT_NE(error_of([] { TopDrive::parse_kind("diesel"); }).find("top_drive.type = \"diesel\""), std::string::npos);
}

TEST(DriveRegistry, EveryDriveRoundTripsThroughTheConfiguration) {
  for (const Named<TopDrive::Kind>& k : TopDrive::kinds) {
    const json j = drive_registry_rig(k.value);
    const Config c = parse_config(j);
    EXPECT_EQ(c.top_drive.kind, k.value) << k.name;
    const json written = to_json(c);
    if (k.value == TopDrive{}.kind) {
      EXPECT_FALSE(written.contains("top_drive")) << k.name;  // the default is not written
    } else {
      EXPECT_EQ(written.at("top_drive"), j.at("top_drive")) << k.name;
    }
    const Config again = parse_config(written);
    EXPECT_EQ(again.top_drive.kind, k.value) << k.name;
    EXPECT_EQ(to_json(again), written) << k.name;
  }
}

TEST(DriveRegistry, EveryDriveRefusesABadValueOrAnotherDrivesKeyNamingTheField) {
  std::set<std::string> all;  // every key of every drive
  for (const schema::Variant& v : schema::block("top_drive").variants)
    for (const schema::Field& f : v.fields) all.insert(f.key);
  for (const Named<TopDrive::Kind>& k : TopDrive::kinds) {
    const json good = drive_registry_rig(k.value);
    const std::set<std::string> own = schema::keys("top_drive", k.name);
    for (const std::string& key : own) {
      if (key == "type") continue;
      json bad = good;
      bad["top_drive"][key] = good["top_drive"][key].is_number() ? json(-1.0) : json("no");
      const std::string e = error_of([&] { parse_config(bad); });
      EXPECT_NE(e.find("top_drive." + key + " = "), std::string::npos) << k.name << ": " << e;
      if (good["top_drive"][key].is_number()) {
        bad = good;  // a required number left out
        bad["top_drive"].erase(key);
        const std::string missing = error_of([&] { parse_config(bad); });
        if (missing != "no error") EXPECT_NE(missing.find("top_drive." + key), std::string::npos) << missing;
      }
    }
    for (const std::string& key : all) {
      if (own.count(key)) continue;
      json bad = good;
      bad["top_drive"][key] = 1.0;
      const std::string e = error_of([&] { parse_config(bad); });
      EXPECT_NE(e.find("top_drive." + key), std::string::npos) << k.name << ": " << e;
      EXPECT_NE(e.find("unknown key"), std::string::npos) << k.name << ": " << e;
    }
  }
}

TEST(DriveRegistry, EveryDriveTurnsAtTheCommandWithoutTorqueAndRuns) {
  for (const Named<TopDrive::Kind>& k : TopDrive::kinds) {
    const Simulation sim(parse_config(drive_registry_rig(k.value)));
    const TopDrive& d = sim.config().top_drive;  // tuned (a controlled drive)
    EXPECT_NO_THROW(d.validate()) << k.name;
    EXPECT_EQ(d.steady_speed(7.0, 0.0), 7.0) << k.name;  // no torque, no droop
    if (!d.droops())
      for (double T : {0.1, 1.0, 10.0}) EXPECT_EQ(d.steady_speed(7.0, T), 7.0) << k.name;
    if (!d.has_inertia()) EXPECT_FALSE(d.droops()) << k.name;  // the top turns at the command signal
    const double om = sim.steady_speed(sim.config().top_speed, sim.config().wob);
    EXPECT_TRUE(om >= 0.0 && om <= sim.config().top_speed) << k.name << ": " << om;
    const RunReport r = sim.run(sim.inputs());
    ASSERT_FALSE(r.series.top_speed.empty()) << k.name;
    for (std::size_t i = 0; i < r.series.top_speed.size(); ++i) {
      ASSERT_TRUE(std::isfinite(r.series.top_speed[i]) && std::isfinite(r.series.bit_speed[i])) << k.name << " " << i;
      if (!d.has_inertia()) ASSERT_EQ(r.series.top_speed[i], sim.config().top_speed) << k.name << " " << i;
    }
  }
}

TEST(DriveRegistry, SteadySpeedOfEachDrive) {
  // The drives' characteristics under a steady torque T at the command 10 rad/s.
  TopDrive d;
  d.kind = TopDrive::Kind::ideal;  // the thesis: the command whatever the torque
  EXPECT_EQ(d.steady_speed(10.0, 1e9), 10.0);
  EXPECT_FALSE(d.droops());
  d.kind = TopDrive::Kind::motor;  // Omega_c - T / c_m; stalled at and above T_max
  d.slope = 0.5;
  d.inertia = 0.02;
  d.max_torque = 4.0;
  EXPECT_TRUE(d.droops());
  EXPECT_DOUBLE_EQ(d.steady_speed(10.0, 1.5), 7.0);
  EXPECT_EQ(d.steady_speed(10.0, 4.0), 0.0);
  EXPECT_EQ(d.steady_speed(10.0, 5.0), 0.0);
  EXPECT_TRUE(d.accel_from_torque());
  d.kind = TopDrive::Kind::controlled;  // the integral carries the torque: the command; P only droops by T / kp
  d.controller.kp = 2.0;
  d.controller.ki = 3.0;
  EXPECT_FALSE(d.droops());
  EXPECT_EQ(d.steady_speed(10.0, 1.5), 10.0);
  d.controller.ki = 0.0;
  EXPECT_TRUE(d.droops());
  EXPECT_DOUBLE_EQ(d.steady_speed(10.0, 1.5), 9.25);
  EXPECT_FALSE(d.accel_from_torque());
  const std::string e = error_of([&] { d.top_accel(10.0, 9.0, 1e-3, 0.0, 0.0); });
  EXPECT_NE(e.find("top_drive.type = "), std::string::npos) << e;
  EXPECT_NE(e.find("controlled"), std::string::npos) << e;
}
