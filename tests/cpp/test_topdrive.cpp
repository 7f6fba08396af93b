// Top-drive models: the motor's speed droop under a steady torque, the coupled motor-string
// oscillation frequency, the steady-drilling state with a motor, the stability bound, the stiff
// motor limit (the ideal drive), and the configuration's errors.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "drill/presets.hpp"
#include "drill/simulation.hpp"
#include "error_text.hpp"

using namespace drill;

namespace {

/// The rig preset with a Coulomb-like law of constant torque c0 for v > 0 (tanh saturated).
Config rig_with_constant_torque(double c0) {
  Config c = preset("thesis-rig");
  c.law = thesis_tucker_wang();
  c.law.speed_unit = SpeedUnit::rad_s;
  c.law.c0 = c0;
  c.law.alpha0 = 100.0;
  c.law.alpha1 = 0.0;
  c.law.wob_ref = c.wob;
  return c;
}

TopDrive motor(double slope, double inertia) {
  TopDrive t;
  t.kind = TopDrive::Kind::motor;
  t.slope = slope;
  t.inertia = inertia;
  return t;
}

}  // namespace

TEST(TopDrive, MotorSpeedDroopsByTorqueOverSlope) {
  // J_m Omega' = c_m (Omega_c - Omega) - T_top: under a steady torque of 1.5 N m a motor commanded at
  // 10 rad/s with c_m = 0.5 N m s/rad settles at 10 - 1.5 / 0.5 = 7 rad/s, and so does the bit.
  Config c = rig_with_constant_torque(1.5);
  c.top_speed = 10.0;
  c.top_drive = motor(0.5, 0.02);
  c.sim.duration = 20.0;
  c.transient = 15.0;
  const Simulation sim(c);
  const RunReport r = sim.run(sim.inputs());
  const double Ttop = r.series.top_torque.back();
  // the motor carries the torque on bit (to the one-mode model's static truncation, 1.5e-5 relative)
  EXPECT_NEAR(Ttop, 1.5, 1e-4);
  EXPECT_NEAR(r.series.top_speed.back(), 10.0 - Ttop / 0.5, 1e-9);  // the motor's characteristic, exactly
  EXPECT_NEAR(r.series.top_speed.back(), 7.0, 1e-4);
  EXPECT_NEAR(r.series.bit_speed.back(), r.series.top_speed.back(), 1e-9);
  EXPECT_DOUBLE_EQ(r.final_state.top_speed, r.series.top_speed.back());
}

TEST(TopDrive, MotorAndStringOscillateAtTheCoupledFrequency) {
  // No bit torque, no damping, a free motor inertia (negligible slope): the string's first mode and
  // the motor form a two-inertia oscillator with omega^2 = omega_1^2 - top_load top_torque / J_m
  // (= k (1 / J_m + 1 / I_bit) for the rig's one mode).
  Config c = rig_with_constant_torque(0.0);
  c.damping.ratios = {0.0};
  const double J = 0.005;
  c.top_drive = motor(1e-9, J);
  c.sim.duration = 5.0;
  c.transient = 0.0;
  c.output_stride = 1;
  const Simulation sim(c);
  const ReducedModel& rm = sim.rom().model;
  const double w1 = sim.rom().omega(0);
  const double expected = std::sqrt(w1 * w1 - rm.top_load(0) * rm.top_torque(0) / J) / (2.0 * M_PI);
  ModelState s0{Eigen::VectorXd::Constant(1, 0.01), Eigen::VectorXd::Zero(1)};
  s0.top_speed = c.top_speed;
  const RunReport r = sim.run(sim.inputs(), true, &s0);
  // frequency from the upward zero crossings of the top torque (linear interpolation)
  std::vector<double> up;
  const auto& T = r.series.top_torque;
  const auto& t = r.series.t;
  for (std::size_t i = 1; i < T.size(); ++i)
    if (T[i - 1] < 0.0 && T[i] >= 0.0) up.push_back(t[i - 1] + (t[i] - t[i - 1]) * (-T[i - 1]) / (T[i] - T[i - 1]));
  ASSERT_GE(up.size(), 10u);
  const double f = (up.size() - 1) / (up.back() - up.front());
  EXPECT_NEAR(f / expected, 1.0, 2e-3) << f << " Hz vs " << expected << " Hz";
  // the two-inertia oscillator is stiffer than the string alone clamped at the top
  EXPECT_GT(expected, 1.3 * w1 / (2.0 * M_PI));
}

TEST(TopDrive, SteadyStateWithMotorCarriesTheTorqueOnBit) {
  Config c = preset("thesis-rig");
  c.top_drive = motor(0.2, 0.02);
  const Simulation sim(c);
  const ModelState s = sim.steady_state(c.top_speed, c.wob);
  const double om = s.top_speed;
  ASSERT_TRUE(std::isfinite(om));
  EXPECT_LT(om, c.top_speed);
  // Omega = Omega_c - T(Omega) / c_m, and the string's twist carries T(Omega) (to the one-mode
  // model's static truncation: the first mode alone gives the top 1.5e-5 more than the bit)
  const double T = c.law.torque(om, 0.0, c.wob);
  EXPECT_NEAR(om, c.top_speed - T / 0.2, 1e-9);
  EXPECT_NEAR(sim.integrator().top_torque(s) / T, 1.0, 1e-4);
}

TEST(TopDrive, StiffMotorApproachesTheIdealDrive) {
  Config c = preset("thesis-rig");
  c.sim.duration = 1.5;
  c.transient = 0.5;
  const Simulation ideal(c);
  c.top_drive = motor(1e4, 0.05);
  const Simulation stiff(c);
  const RunReport a = ideal.run(ideal.inputs()), b = stiff.run(stiff.inputs());
  ASSERT_EQ(a.series.bit_speed.size(), b.series.bit_speed.size());
  double dv = 0.0, dtop = 0.0;
  for (std::size_t i = 0; i < a.series.bit_speed.size(); ++i) {
    dv = std::max(dv, std::fabs(a.series.bit_speed[i] - b.series.bit_speed[i]));
    dtop = std::max(dtop, std::fabs(b.series.top_speed[i] - c.top_speed));
  }
  EXPECT_LT(dtop, 1e-3);  // droop T / c_m below 4e-4 rad/s
  EXPECT_LT(dv, 0.05);    // bit speeds of 0 to 20 rad/s agree to a few hundredths
}

TEST(TopDrive, RefusesUnstableStepsAndBdf2) {
  Config c = preset("thesis-rig");
  c.top_drive = motor(0.2, 1e-9);  // a tiny motor inertia makes the coupled system very stiff
  const Simulation sim(c);
  const std::string e = error_of([&] { sim.run(sim.inputs()); });
  EXPECT_NE(e.find("simulation.dt_s"), std::string::npos) << e;
  EXPECT_NE(e.find("top_drive.inertia_kg_m2"), std::string::npos) << e;
  c.top_drive = motor(0.2, 0.02);
  c.sim.scheme = Scheme::bdf2;
  const std::string b = error_of([&] { Simulation s(c); });
  EXPECT_NE(b.find("top_drive.type = motor"), std::string::npos) << b;
  EXPECT_NE(b.find("modified_euler"), std::string::npos) << b;
}

TEST(TopDrive, ConfigParsesRoundTripsAndNamesBadFields) {
  json j = preset_json("thesis-rig");
  j["top_drive"] = {{"type", "motor"}, {"slope_nms_rad", 0.25}, {"inertia_kg_m2", 0.03}};
  const Config c = parse_config(j);
  EXPECT_EQ(c.top_drive.kind, TopDrive::Kind::motor);
  EXPECT_DOUBLE_EQ(c.top_drive.slope, 0.25);
  EXPECT_DOUBLE_EQ(c.top_drive.inertia, 0.03);
  const Config back = parse_config(to_json(c));
  EXPECT_DOUBLE_EQ(back.top_drive.slope, 0.25);
  EXPECT_FALSE(to_json(preset("thesis-rig")).contains("top_drive"));  // the ideal default is not written

  json bad = j;
  bad["top_drive"]["slope_nms_rad"] = -1.0;
  EXPECT_NE(error_of([&] { parse_config(bad); }).find("top_drive.slope_nms_rad = -1"), std::string::npos);
  bad = j;
  bad["top_drive"]["type"] = "diesel";
  EXPECT_NE(error_of([&] { parse_config(bad); }).find("top_drive.type = \"diesel\""), std::string::npos);
  bad = j;
  bad["top_drive"]["droop"] = 1.0;
  EXPECT_NE(error_of([&] { parse_config(bad); }).find("top_drive.droop"), std::string::npos);
  bad = j;
  bad["top_drive"] = {{"type", "ideal"}, {"slope_nms_rad", 1.0}};
  EXPECT_NE(error_of([&] { parse_config(bad); }).find("unknown key"), std::string::npos);
}

TEST(TopDrive, TorqueLimitStallsTheMotorBelowTheTorqueItCannotOvercome) {
  // A bit held by a static torque Ts = 5 N m: an unlimited motor commanded at 14 rad/s with
  // c_m = 0.5 reaches up to c_m Omega_c = 7 N m and breaks the stick; with T_max = 2 N m it cannot:
  // the bit never moves and the top comes to rest where the string's top torque balances T_max.
  Config c = preset("thesis-rig");
  c.law.kind = BitRockLaw::Kind::polynomial;
  c.law.speed_unit = SpeedUnit::rad_s;
  c.law.a = {5.0 / 1.36, 0.0, 2.0 / 1.36, 0.0, 2.0 / 1.36, 0.0, 0.0, 0.0};
  c.law.ref_speed = 10.0;
  c.law.wob_ref = c.wob;
  c.top_speed = 14.0;
  c.top_drive = motor(0.5, 0.002);
  c.sim.duration = 10.0;
  c.transient = 5.0;
  {
    const Simulation sim(c);
    const RunReport r = sim.run(sim.inputs());
    EXPECT_GT(*std::max_element(r.series.bit_speed.begin(), r.series.bit_speed.end()), 1.0);  // broke away
  }
  c.top_drive.max_torque = 2.0;
  const Simulation sim(c);
  const RunReport r = sim.run(sim.inputs());
  EXPECT_LT(*std::max_element(r.series.bit_speed.begin(), r.series.bit_speed.end()), 1e-9);  // stalled
  const std::size_t half = r.series.t.size() / 2, n = r.series.t.size() - half;
  double T = 0.0, om = 0.0;
  for (std::size_t i = half; i < r.series.t.size(); ++i) T += r.series.top_torque[i] / n, om += r.series.top_speed[i] / n;
  EXPECT_NEAR(T, 2.0, 0.02);  // the string holds the motor's limit
  EXPECT_LT(std::fabs(om), 0.01 * c.top_speed);  // the top stopped (it swings about the balance)
  EXPECT_DOUBLE_EQ(sim.steady_speed(14.0, c.wob), 0.0);  // 2 N m of law torque at any speed >= T_max
  // the limit round-trips and is range-checked
  json j = to_json(c);
  EXPECT_DOUBLE_EQ(j["top_drive"]["max_torque_nm"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(parse_config(j).top_drive.max_torque, 2.0);
  j["top_drive"]["max_torque_nm"] = 0.0;
  EXPECT_NE(error_of([&] { parse_config(j); }).find("top_drive.max_torque_nm = 0"), std::string::npos);
}
