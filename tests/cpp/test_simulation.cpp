// Configured simulations: the thesis-field SS curve and threshold (Fig. 4.8), the 3-cycle periodic
// regime (section 4.2.1), thread-count invariance of sweeps, and the test rig's stick-slip cycle.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "drill/presets.hpp"
#include "drill/simulation.hpp"

using namespace drill;

TEST(Simulation, FieldSeverityCurveAndThreshold) {
  const Simulation sim(preset("thesis-field"));
  const auto& sp = sim.config().sweep_speeds;
  const std::vector<double> ss = sim.sweep_severity(sp, {});
  ASSERT_EQ(ss.size(), 22u);
  EXPECT_GT(ss.front(), 1.0);   // full stick-slip at 6 rad/s
  EXPECT_LT(ss.back(), 0.1);    // smooth drilling at 27 rad/s
  const double thr = severity_threshold(sp, ss);
  EXPECT_GT(thr, 15.0);         // the thesis reports 16 rad/s (docs/validation.md explains
  EXPECT_LT(thr, 21.0);         // why this model gives about 18 rad/s)
}

TEST(Simulation, SweepIsIdenticalForOneAndTwoThreads) {
  const Simulation sim(preset("thesis-field"));
  const std::vector<double> sp = {8, 15, 18, 19, 25};
  const std::vector<double> w = {100e3, 245e3};
  const auto a = sim.sweep_severity(sp, w, nullptr, 1);
  const auto b = sim.sweep_severity(sp, w, nullptr, 2);
  ASSERT_EQ(a.size(), 10u);
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << i;  // bit-identical
  // lower WOB is more stable at the same speed
  EXPECT_LE(a[2], a[7] + 1e-12);
}

TEST(Simulation, SweepCanBeCancelled) {
  const Simulation sim(preset("thesis-field"));
  std::size_t calls = 0;
  const auto out = sim.sweep_severity({6, 7, 8, 9, 10, 11, 12, 13, 14, 15}, {}, [&](std::size_t, std::size_t) {
    ++calls;
    return false;
  }, 1);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(calls, 1u);
}

TEST(Simulation, ThreeCyclePeriodicRegimeOfTheDeterministicModel) {
  // Section 4.2.1: stick (1.34, 2.53, 2.48) s and slip (5.4, 6.28, 6.41) s. Converged setting:
  // all 100 modes and the BDF2 scheme (docs/validation.md).
  Config c = preset("thesis-field");
  c.modes = 100;
  c.sim.scheme = Scheme::bdf2;
  c.sim.duration = 400;
  c.transient = 200;
  const Simulation sim(c);
  const RunReport r = sim.run(sim.inputs(16.0, 245e3), false);
  ASSERT_EQ(r.periodic.period_cycles, 3);
  std::vector<double> st = r.periodic.stick, sl = r.periodic.slip;
  std::sort(st.begin(), st.end());
  std::sort(sl.begin(), sl.end());
  const double thesis_st[3] = {1.34, 2.48, 2.53}, thesis_sl[3] = {5.4, 6.28, 6.41};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(st[k], thesis_st[k], 0.25) << "stick " << k;
    EXPECT_NEAR(sl[k], thesis_sl[k], 0.15) << "slip " << k;
  }
}

TEST(Simulation, TestRigStickSlipNearItsTorsionalFrequency) {
  const Simulation sim(preset("thesis-rig"));
  const RunReport r = sim.run(sim.inputs(), false);
  ASSERT_GT(r.stick.size(), 20u);
  double period = 0;
  const std::size_t n = std::min(r.stick.size(), r.slip.size());
  for (std::size_t j = 0; j < n; ++j) period += r.stick[j] + r.slip[j];
  period /= n;
  // the record shows 2.6-2.9 Hz cycles (data README); the rig's first mode is 2.89 Hz
  EXPECT_GT(1.0 / period, 2.0);
  EXPECT_LT(1.0 / period, 3.2);
  EXPECT_GT(r.severity, 0.5);
}

TEST(Simulation, StartModesSetTheInitialBitSpeed) {
  // rest (Eq. 2.10): the bit starts at rest; rigid (Eq. 2.3): it turns with the top, untwisted;
  // steady: at the top speed with the static twist (a 1 % disturbance of the relative velocity).
  Config c = preset("thesis-field");
  c.modes = 10;
  c.sim.duration = 1.0;
  c.transient = 0.5;
  const Simulation sim(c);
  const Inputs in = sim.inputs(15.0, 245e3);
  auto first_speed = [&](StartMode m) {
    double v0 = NAN;
    const std::optional<ModelState> s0 = sim.start_state(m, 15.0, 245e3);
    sim.integrator().run(in, [&](const StepState& s) { if (s.step == 0) v0 = s.bit_speed; }, s0 ? &*s0 : nullptr);
    return v0;
  };
  // Eq. (2.10) projected on 10 modes leaves the bit nearly at rest; the steady start's relative
  // velocity is 1 % of Eq. (2.10)'s, so its bit speed is 15 - 0.01 (15 - v_rest) exactly.
  const double v_rest = first_speed(StartMode::rest);
  EXPECT_LT(std::fabs(v_rest), 0.05 * 15.0);
  EXPECT_NEAR(first_speed(StartMode::rigid), 15.0, 1e-12);
  EXPECT_NEAR(first_speed(StartMode::steady), 15.0 - 0.01 * (15.0 - v_rest), 1e-9);
  const std::optional<ModelState> rigid = sim.start_state(StartMode::rigid, 15.0, 245e3);
  EXPECT_EQ(rigid->q.norm(), 0.0);  // untwisted
  EXPECT_GT(sim.start_state(StartMode::steady, 15.0, 245e3)->q.norm(), 0.0);
  EXPECT_THROW(parse_start("spinning"), std::invalid_argument);
}

TEST(Simulation, RunsAndSweepsStartAsTheConfigurationSays) {
  Config c = preset("thesis-field");
  c.modes = 6;
  c.sim.duration = 4.0;
  c.transient = 2.0;
  Config steady = c;
  steady.start = StartMode::steady;
  const Simulation rest_sim(c), steady_sim(steady);
  const std::vector<double> speeds{8.0, 14.0};
  // sweeps: the configured start unless one is given
  EXPECT_EQ(steady_sim.sweep_severity(speeds, {}), rest_sim.sweep_severity(speeds, {}, nullptr, 0, StartMode::steady));
  EXPECT_EQ(steady_sim.sweep_severity(speeds, {}, nullptr, 0, StartMode::rest), rest_sim.sweep_severity(speeds, {}));
  // runs: the configured start unless an initial state is given
  const Inputs in = rest_sim.inputs(14.0, 245e3);
  const std::optional<ModelState> s0 = rest_sim.start_state(StartMode::steady, 14.0, 245e3);
  EXPECT_EQ(steady_sim.run(in, false).severity, rest_sim.run(in, false, &*s0).severity);
  EXPECT_EQ(steady_sim.run(in, false).stick_fraction, rest_sim.run(in, false, &*s0).stick_fraction);
}

TEST(Simulation, NegativeThreadCountIsRefused) {
  Config c = preset("thesis-field");
  c.modes = 4;
  c.sim.duration = 1.0;
  c.transient = 0.5;
  const Simulation sim(c);
  std::string e = "no error";
  try {
    sim.sweep_severity({10.0}, {}, nullptr, -4);
  } catch (const std::invalid_argument& x) {
    e = x.what();
  }
  EXPECT_NE(e.find("threads = -4"), std::string::npos) << e;
  EXPECT_THROW(parallel_for(3, [](std::size_t) {}, nullptr, -1), std::invalid_argument);
}
