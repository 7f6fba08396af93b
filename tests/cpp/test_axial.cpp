// The axial jack (axial.hpp): W' = g (Omega_f - v) - (W - W_s) / tau. Its step against the exact
// solution of the linear equation, the WOB rising while the bit is stuck and falling while it slips,
// steady drilling at the set force, lift-off at W = 0, and the configuration's errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "drill/presets.hpp"
#include "drill/simulation.hpp"
#include "error_text.hpp"

using namespace drill;

namespace {

Axial jack(double g, double tau, double feed) {
  Axial a;
  a.kind = Axial::Kind::jack;
  a.gain = g;
  a.relaxation = tau;
  a.feed_speed = feed;
  return a;
}

/// The rig with the Eq. (5.1) law scaled to sample 175's size (static 2.9 N m, 2 N m at 9 rad/s).
Config rig_with_jack(double g, double tau) {
  Config c = preset("thesis-rig");
  c.law.kind = BitRockLaw::Kind::polynomial;
  c.law.speed_unit = SpeedUnit::rpm;
  c.law.a = {2.09, -0.18, 1.93, 0.0, 1.94, -3.18e-3, -3.09e-5, 1.04e-7};
  c.law.ref_speed = 90.0;
  c.law.wob_ref = 563.0;
  c.wob = 563.0;
  c.top_speed = 8.9;
  c.damping.ratios = {0.03};
  c.axial.kind = Axial::Kind::jack;
  c.axial.gain = g;
  c.axial.relaxation = tau;
  c.sim.dt = 1e-4;
  c.sim.duration = 12.0;
  c.transient = 4.0;
  c.output_stride = 10;
  return c;
}

}  // namespace

TEST(Axial, StepIsExactForAConstantBitSpeed) {
  // With v constant the equation is linear with constant coefficients: W(t) = W_s + (W0 - W_s) e^{-t/tau}
  // + g (Omega_f - v) tau (1 - e^{-t/tau}); the step reproduces it at any dt (to rounding).
  const Axial a = jack(150.0, 0.2, 9.0);
  for (double dt : {1e-4, 1e-2, 0.1}) {
    double W = 500.0;
    const int n = static_cast<int>(std::lround(1.0 / dt));
    for (int i = 0; i < n; ++i) W = a.step(W, 4.0, 560.0, dt);
    const double e = std::exp(-1.0 / 0.2);
    EXPECT_NEAR(W, 560.0 + (500.0 - 560.0) * e + 150.0 * 5.0 * 0.2 * (1.0 - e), 1e-9) << dt;
  }
  EXPECT_DOUBLE_EQ(a.step(10.0, 1e3, 0.0, 0.01), 0.0);  // lift-off: no negative contact force
}

TEST(Axial, WobRisesWhileStuckAndFallsWhileSlipping) {
  // Figs. 5.6-5.7 of the thesis: in stick-slip the WOB is above its mean in the stick phases and
  // below it in the fast slip; its swing grows with g; without the jack it is the constant input.
  double swing_prev = 0.0;
  for (double g : {0.0, 60.0, 150.0}) {
    const Config c = rig_with_jack(g, 0.1);
    const Simulation sim(c);
    const RunReport r = sim.run(sim.inputs());
    const std::size_t k0 = static_cast<std::size_t>(c.transient / (c.sim.dt * c.output_stride));
    std::vector<double> w(r.series.wob.begin() + k0, r.series.wob.end()), v(r.series.bit_speed.begin() + k0,
                                                                            r.series.bit_speed.end());
    ASSERT_GT(r.stick_fraction, 0.02) << g;  // stick-slip
    const double wm = std::accumulate(w.begin(), w.end(), 0.0) / w.size();
    double stuck = 0.0, fast = 0.0;
    int ns = 0, nf = 0;
    for (std::size_t i = 0; i < w.size(); ++i) {
      if (v[i] < 1e-6) stuck += w[i] - wm, ++ns;
      if (v[i] > 1.5 * c.top_speed) fast += w[i] - wm, ++nf;
    }
    const double swing = *std::max_element(w.begin(), w.end()) - *std::min_element(w.begin(), w.end());
    if (g == 0.0) {
      EXPECT_NEAR(swing, 0.0, 1e-9);  // relaxes to, and stays at, the set force
      continue;
    }
    EXPECT_GT(stuck / ns, 0.0) << g;
    EXPECT_LT(fast / nf, 0.0) << g;
    EXPECT_GT(swing, swing_prev) << g;
    swing_prev = swing;
  }
}

TEST(Axial, SteadyDrillingHoldsTheSetForceAndTheFeedFollowsTheDrive) {
  // Started in steady drilling at a speed where the law is velocity-strengthening enough to be
  // stable, v = Omega_f and the WOB stays at the set force; with a motor the feed is the drive's
  // steady speed, below the command by T / c_m.
  Config c = rig_with_jack(100.0, 0.2);
  c.law.a = {0.0, 0.2, 0.0, 0.2, 1.94, 0.01, 0.0, 0.0};  // increasing with speed: stable drilling
  c.start = StartMode::steady;
  const Simulation sim(c);
  const RunReport r = sim.run(sim.inputs());
  EXPECT_NEAR(sim.inputs().axial.feed_speed, c.top_speed, 1e-12);
  EXPECT_NEAR(r.series.wob.back(), c.wob, 0.5);
  EXPECT_NEAR(r.series.bit_speed.back(), c.top_speed, 0.01);
  Config m = c;
  m.top_drive.kind = TopDrive::Kind::motor;
  m.top_drive.slope = 0.5;
  m.top_drive.inertia = 0.02;
  const Simulation ms(m);
  const double T = ms.steady_torque(ms.inputs().axial.feed_speed, m.wob);
  EXPECT_NEAR(ms.inputs().axial.feed_speed, m.top_speed - T / 0.5, 1e-9);
}

TEST(Axial, ConfigParsesRoundTripsAndNamesBadFields) {
  json j = preset_json("thesis-rig");
  j["axial"] = {{"type", "jack"}, {"gain_n_rad", 120.0}, {"relaxation_s", 0.3}};
  const Config c = parse_config(j);
  EXPECT_TRUE(c.axial.active());
  EXPECT_DOUBLE_EQ(c.axial.gain, 120.0);
  EXPECT_DOUBLE_EQ(parse_config(to_json(c)).axial.relaxation, 0.3);
  EXPECT_FALSE(to_json(preset("thesis-rig")).contains("axial"));  // none is the default, not written
  json bad = j;
  bad["axial"]["relaxation_s"] = 0.0;
  EXPECT_NE(error_of([&] { parse_config(bad); }).find("axial.relaxation_s = 0"), std::string::npos);
  bad = j;
  bad["axial"]["type"] = "spring";
  EXPECT_NE(error_of([&] { parse_config(bad); }).find("axial.type = \"spring\""), std::string::npos);
  bad = j;
  bad["simulation"]["scheme"] = "bdf2";
  EXPECT_NE(error_of([&] { parse_config(bad); }).find("axial.type = jack"), std::string::npos);
  // a run whose feed speed was never set is refused, not a silent NaN
  Config c2 = c;
  const Simulation sim(c2);
  Inputs in = sim.inputs();
  in.axial.feed_speed = NAN;
  EXPECT_NE(error_of([&] { sim.integrator().run(in, [](const StepState&) {}); }).find("axial.feed_speed"),
            std::string::npos);
  EXPECT_NO_THROW(sim.run(in));  // Simulation::run sets it
}
