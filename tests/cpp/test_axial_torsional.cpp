// The axial-torsional model with the Richard-Germay-Detournay bit (axial_torsional.hpp, rgd_bit.hpp):
// steady drilling is an equilibrium of the scheme with RGD's balance of forces, its delay is
// 2 pi / (N Omega), a bounce gives W = 0 without NaN, stick-slip arises from the coupling at low
// speed (RGD's result), runs repeat bit for bit, and bad input is one error naming the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "drill/presets.hpp"
#include "drill/simulation.hpp"
#include "coupled_trace.hpp"
#include "error_text.hpp"

using namespace drill;

namespace {

Config rgd(double duration = 5.0) {
  Config c = preset("rgd-field");
  c.sim.duration = duration;
  c.transient = 0.5 * duration;
  return c;
}

using Trace = test::CoupledTrace;

Trace trace(const Config& c, const ModelState* start = nullptr) { return test::coupled_trace(Simulation(c), start); }

}  // namespace

TEST(AxialTorsional, SteadyDrillingIsAnEquilibriumWithRgdBalance) {
  for (AxialTop top : {AxialTop::hook_load, AxialTop::feed}) {
    Config c = rgd(2.0);
    test::steady_start(c, top);
    Simulation sim(c);
    const AxialTorsional& m = *sim.coupled();
    const double om = c.top_speed;
    const AxialTorsional::Steady st = m.steady(om);
    const RgdBit& b = c.axial.rgd.bit;
    // RGD's steady drilling: W = a zeta eps d + a l sigma, T = a^2 eps d / 2 + gamma mu a^2 l sigma / 2
    EXPECT_NEAR(st.wob, test::rgd_steady_wob(b, st.depth), 1e-9 * st.wob);
    EXPECT_NEAR(st.torque, 0.5 * b.radius * b.radius * b.specific_energy * st.depth +
                               0.5 * b.geometry * b.friction * b.radius * b.radius * b.wear_flat * b.contact_strength,
                1e-9 * st.torque);
    EXPECT_NEAR(st.rop, om * st.depth / (2.0 * M_PI), 1e-12);
    const ModelState s0 = m.steady_torsion(om, 0.0);
    const Trace tr = trace(c, &s0);
    const double tN = 2.0 * M_PI / (b.blades * om);
    for (std::size_t i = 0; i < tr.a.size(); i += 97) {
      const AxialStep& a = tr.a[i];
      ASSERT_NEAR(a.wob, st.wob, 1e-7 * st.wob) << to_string(top) << " t = " << a.t;
      ASSERT_NEAR(tr.s[i].torque_on_bit, st.torque, 1e-7 * st.torque) << to_string(top) << " t = " << a.t;
      ASSERT_NEAR(a.rop, st.rop, 1e-7 * st.rop) << to_string(top) << " t = " << a.t;
      ASSERT_NEAR(a.delay, tN, 1e-9 * tN) << to_string(top) << " t = " << a.t;
      // the depth of cut is the advance over the delay: d = N ROP t_N
      ASSERT_NEAR(a.depth, b.blades * a.rop * a.delay, 1e-7 * st.depth) << to_string(top) << " t = " << a.t;
      ASSERT_NEAR(tr.s[i].bit_speed, om, 1e-9 * om);
    }
  }
}

TEST(AxialTorsional, AxialMomentumBalancesTheTopForceAndTheWob) {
  // hook load: the string is free axially, so its momentum P = 1^T M U' (the rigid mode's) changes
  // only by the force at the top and the WOB, P(T) - P(0) = sum over steps dt (F_top - W_i), through
  // stick-slip and whatever the axial modes do (the scheme's Eq. A.5 conserves it step by step)
  Config c = rgd(10.0);
  Simulation sim(c);
  const AxialTorsional& m = *sim.coupled();
  const double dt = c.sim.dt, F = c.axial.rgd.top_force;
  double impulse = 0.0;
  long steps = 0;
  const CoupledState end = m.run(sim.inputs(), [&](const StepState& s, const AxialStep& a) {
    if (s.step < c.sim.steps()) impulse += dt * (F - a.wob);  // the last observed step is not integrated
    steps = s.step;
  });
  ASSERT_EQ(steps, c.sim.steps());
  Eigen::VectorXd eta0, eta_dot0;
  m.steady_axial(c.top_speed, eta0, eta_dot0);
  const Eigen::VectorXd& u = m.axial().uniform;
  const double P0 = u.dot(eta_dot0), P1 = u.dot(end.eta_dot);
  EXPECT_NEAR(P1 - P0, impulse, 1e-6 * F * c.sim.duration);
  EXPECT_GT(std::fabs(impulse), 1e-3 * F * dt);  // not trivially zero: the WOB did move
}

TEST(AxialTorsional, StickSlipArisesAtLowSpeedWithThePublishedBit) {
  // RGD (J. Sound Vib. 2007): the steady drilling state of the coupled model is unstable; the
  // disturbance grows into stick-slip (full sticks of the bit) at the preset's 60 RPM
  Config c = rgd(40.0);  // 4 rad/s, 150 kN
  Simulation sim(c);
  const RunReport r = sim.run(sim.inputs(), false);
  EXPECT_GT(r.severity, 0.5);
  EXPECT_GT(r.stick_fraction, 0.05);
  EXPECT_GT(r.axial.wob_std, 0.01 * r.axial.steady_wob);  // the WOB swings with the cycle
  EXPECT_TRUE(std::isfinite(r.axial.mean_rop));
}

TEST(AxialTorsional, BitBounceGivesZeroWobAndNoNaN) {
  // the bit thrown up at 49 V0: it leaves the rock (d < 0, W = T = 0), flies and lands again
  Config c = rgd(3.0);
  c.axial.rgd.disturbance = 50.0;
  const Trace tr = trace(c);
  long off = 0, back = 0;
  for (std::size_t i = 0; i < tr.a.size(); ++i) {
    const AxialStep& a = tr.a[i];
    ASSERT_TRUE(std::isfinite(a.wob) && std::isfinite(a.depth) && std::isfinite(tr.s[i].bit_speed)) << a.t;
    ASSERT_GE(a.wob, 0.0);
    if (!a.contact) {
      ++off;
      ASSERT_EQ(a.wob, 0.0);
      ASSERT_EQ(tr.s[i].torque_on_bit, 0.0);
      ASSERT_LE(a.depth, 0.0);
    } else if (off > 0) {
      ++back;
    }
  }
  EXPECT_GT(off, 10);
  EXPECT_GT(back, 10);  // it lands
}

TEST(AxialTorsional, SameNumbersForTheSameRun) {
  Config c = rgd(4.0);
  Simulation sim(c);
  const RunReport a = sim.run(sim.inputs()), b = sim.run(sim.inputs());
  EXPECT_EQ(a.axial.wob, b.axial.wob);
  EXPECT_EQ(a.series.bit_speed, b.series.bit_speed);
  EXPECT_EQ(a.axial.bounce_fraction, b.axial.bounce_fraction);
}

TEST(AxialTorsional, SweepRunsEveryGridPointAsASingleRun) {
  // sweep and map on the coupled model: point (w, s) is the run at speeds[s] under the hook load
  // wobs[w] (the net force at the top, operation.wob_n), whatever the thread count
  const Config c = rgd(6.0);
  Simulation sim(c);
  const std::vector<double> speeds{3.0, 6.0}, wobs{120e3, 180e3};
  const std::vector<double> ss = sim.sweep_severity(speeds, wobs, nullptr, 2);
  ASSERT_EQ(ss.size(), 4u);
  EXPECT_EQ(ss, sim.sweep_severity(speeds, wobs, nullptr, 1));
  for (std::size_t w = 0; w < wobs.size(); ++w) {
    for (std::size_t k = 0; k < speeds.size(); ++k) {
      Config one = c;
      one.top_speed = speeds[k];
      one.wob = wobs[w];
      one.axial.rgd.top_force = wobs[w];
      Simulation single(one);
      EXPECT_EQ(ss[w * speeds.size() + k], single.run(single.inputs(), false).severity) << w << " " << k;
    }
  }
}

// A controlled top drive (drives/controlled.hpp) on the coupled model: from RGD's steady drilling
// without a disturbance the top turns at the command and the motor carries the string's top torque
// (J Omega' = u - T_top = 0), the integral action's steady state, on both top boundaries.
TEST(AxialTorsional, ControlledDriveHoldsSteadyDrillingAtItsCommand) {
  for (AxialTop top : {AxialTop::hook_load, AxialTop::feed}) {
    Config c = rgd(2.0);
    test::steady_start(c, top);
    c.top_drive.kind = TopDrive::Kind::controlled;
    c.top_drive.inertia = 2000.0;  // [kg m^2] an assumed field drive, as tests/cpp/test_controller.cpp
    c.top_drive.controller.kind = Controller::Kind::soft_speed;
    Simulation sim(c);
    const AxialTorsional& m = *sim.coupled();
    const double om = c.top_speed;
    const AxialTorsional::Steady st = m.steady(om);
    const ModelState s0 = m.steady_torsion(om, 0.0);
    const Trace tr = test::coupled_trace(sim, &s0);
    ASSERT_EQ(tr.s.size(), static_cast<std::size_t>(c.sim.steps() + 1));
    for (std::size_t i = 0; i < tr.s.size(); i += 97) {
      const StepState& s = tr.s[i];
      ASSERT_NEAR(s.top_speed, om, 1e-9 * om) << to_string(top) << " t = " << s.t;
      ASSERT_NEAR(s.bit_speed, om, 1e-9 * om) << to_string(top) << " t = " << s.t;
      ASSERT_NEAR(s.drive_torque, s.top_torque, 1e-7 * st.torque) << to_string(top) << " t = " << s.t;
      ASSERT_NEAR(tr.a[i].wob, st.wob, 1e-7 * st.wob) << to_string(top) << " t = " << s.t;
      ASSERT_NEAR(s.torque_on_bit, st.torque, 1e-7 * st.torque) << to_string(top) << " t = " << s.t;
    }
    // the string's top torque of the static twist is the bit's steady torque to the modal truncation
    // (20 torsional modes: 1.3 % below it on this string, both tops)
    EXPECT_NEAR(tr.s[0].top_torque, st.torque, 2e-2 * st.torque);
  }
}

// The controlled drive turns the coupled model away from its ideal-drive run: a drive that gives way
// moves the top (its speed is a state), and a sweep gives the same numbers on 1 and 2 threads.
TEST(AxialTorsional, ControlledDriveSweepIsTheSameForAnyThreadCount) {
  Config c = rgd(6.0);
  c.top_drive.kind = TopDrive::Kind::controlled;
  c.top_drive.inertia = 2000.0;
  c.top_drive.controller.kind = Controller::Kind::z_torque;
  Simulation sim(c);
  const std::vector<double> speeds{3.0, 4.0, 6.0};
  const std::vector<double> ss = sim.sweep_severity(speeds, {}, nullptr, 2);
  ASSERT_EQ(ss.size(), 3u);
  EXPECT_EQ(ss, sim.sweep_severity(speeds, {}, nullptr, 1));
  const RunReport r = sim.run(sim.inputs(), true);
  double lo = INFINITY, hi = -INFINITY;
  for (double v : r.series.top_speed) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  EXPECT_GT(hi - lo, 1e-3 * c.top_speed);  // the top moves: not the ideal drive
  EXPECT_TRUE(std::isfinite(r.severity));
}

// The rig's open-loop motor (drives/motor.hpp) on the coupled model. On a string reduced with all its
// modes (the static twist's top torque is then the bit's torque to round-off), steady drilling at the
// motor's drooped speed is an equilibrium of the scheme on both top boundaries and both schemes: the
// top and the bit turn at Omega_s = Omega_c - T0(Omega_s) / c_m, the WOB and the torque stay RGD's at
// Omega_s. With the feed top T0 = A + B / Omega (d0 = 2 pi V0 / Omega), so Omega_s is the larger root
// of c_m Omega^2 - (c_m Omega_c - A) Omega + B = 0.
namespace {
Config rgd_full_modes(AxialTop top, Scheme scheme) {
  Config c = rgd(2.0);
  test::steady_start(c, top);
  c.string.sections[0].elements = 8;
  c.string.sections[1].elements = 2;
  c.modes = 10;
  c.axial.rgd.modes = 10;
  c.sim.scheme = scheme;
  c.top_drive.kind = TopDrive::Kind::motor;
  c.top_drive.inertia = 2000.0;  // [kg m^2] an assumed field drive, as the controlled drive's tests
  c.top_drive.max_torque = 5e4;
  return c;
}
}  // namespace

TEST(AxialTorsional, MotorDriveDrillsSteadilyAtTheSpeedItsCharacteristicCarries) {
  for (Scheme scheme : {Scheme::modified_euler, Scheme::exact_modal}) {
    for (AxialTop top : {AxialTop::hook_load, AxialTop::feed}) {
      Config c = rgd_full_modes(top, scheme);
      {  // the slope that droops the top by 20 % under the torque at the command
        Config ic = c;
        ic.top_drive.kind = TopDrive::Kind::ideal;
        const Simulation ideal(ic);
        c.top_drive.slope = ideal.coupled()->steady(c.top_speed).torque / (0.2 * c.top_speed);
      }
      const Simulation sim(c);
      const AxialTorsional& m = *sim.coupled();
      const double om_c = c.top_speed, cm = c.top_drive.slope;
      const double om = m.steady_speed(c.top_drive, om_c);
      const AxialTorsional::Steady st = m.steady(om);
      EXPECT_NEAR(om, om_c - st.torque / cm, 1e-11 * om_c) << to_string(top);
      EXPECT_LT(om, 0.85 * om_c);
      if (top == AxialTop::feed) {
        const RgdBit& b = c.axial.rgd.bit;
        const double A = 0.5 * b.geometry * b.friction * b.radius * b.radius * b.wear_flat * b.contact_strength;
        const double B = 0.5 * b.radius * b.radius * b.specific_energy * 2.0 * M_PI * c.axial.rgd.feed_rate;
        const double p = cm * om_c - A;
        EXPECT_NEAR(om, (p + std::sqrt(p * p - 4.0 * cm * B)) / (2.0 * cm), 1e-9 * om_c);
      }
      c.axial.rgd.disturbance = 0.0;
      const Simulation still(c);
      const ModelState s0 = still.steady_state(om_c, c.wob, 0.0);
      EXPECT_DOUBLE_EQ(s0.top_speed, om);
      const Trace tr = test::coupled_trace(still, &s0);
      ASSERT_EQ(tr.s.size(), static_cast<std::size_t>(c.sim.steps() + 1));
      const std::string what = to_string(top) + " " + to_string(scheme);
      for (std::size_t i = 0; i < tr.s.size(); i += 97) {
        const StepState& s = tr.s[i];
        ASSERT_NEAR(s.top_speed, om, 1e-9 * om) << what << " t = " << s.t;
        ASSERT_NEAR(s.bit_speed, om, 1e-9 * om) << what << " t = " << s.t;
        ASSERT_NEAR(s.top_torque, cm * (om_c - om), 1e-7 * st.torque) << what << " t = " << s.t;
        ASSERT_NEAR(tr.a[i].wob, st.wob, 1e-7 * st.wob) << what << " t = " << s.t;
        ASSERT_NEAR(s.torque_on_bit, st.torque, 1e-7 * st.torque) << what << " t = " << s.t;
      }
    }
  }
}

// A controller without integral action (P only, ki = 0) droops like the motor: steady drilling at
// Omega_s = Omega_c - T0(Omega_s) / kp, the controller's integral zero and its proportional part
// carrying T0, is an equilibrium of the scheme on both tops (the string with all its modes, as above).
TEST(AxialTorsional, ControllerWithoutIntegralActionDrillsSteadilyAtItsDroopedSpeed) {
  for (AxialTop top : {AxialTop::hook_load, AxialTop::feed}) {
    Config c = rgd_full_modes(top, Scheme::modified_euler);
    c.top_drive.kind = TopDrive::Kind::controlled;
    c.top_drive.controller.kind = Controller::Kind::pi;
    {
      Config ic = c;
      ic.top_drive.kind = TopDrive::Kind::ideal;
      c.top_drive.controller.kp_given = Simulation(ic).coupled()->steady(c.top_speed).torque / (0.1 * c.top_speed);
    }
    c.top_drive.controller.ki_given = 0.0;
    c.axial.rgd.disturbance = 0.0;
    const Simulation sim(c);
    const AxialTorsional& m = *sim.coupled();
    const double om_c = c.top_speed, kp = sim.config().top_drive.controller.kp;
    const double om = m.steady_speed(sim.config().top_drive, om_c);
    const AxialTorsional::Steady st = m.steady(om);
    EXPECT_NEAR(om, om_c - st.torque / kp, 1e-11 * om_c) << to_string(top);
    EXPECT_LT(om, 0.92 * om_c);
    const ModelState s0 = sim.steady_state(om_c, c.wob, 0.0);
    EXPECT_EQ(s0.drive_integral, 0.0);
    const Trace tr = test::coupled_trace(sim, &s0);
    for (std::size_t i = 0; i < tr.s.size(); i += 97) {
      const StepState& s = tr.s[i];
      ASSERT_NEAR(s.top_speed, om, 1e-9 * om) << to_string(top) << " t = " << s.t;
      ASSERT_NEAR(s.bit_speed, om, 1e-9 * om) << to_string(top) << " t = " << s.t;
      ASSERT_NEAR(s.drive_torque, st.torque, 1e-7 * st.torque) << to_string(top) << " t = " << s.t;
      ASSERT_NEAR(tr.a[i].wob, st.wob, 1e-7 * st.wob) << to_string(top) << " t = " << s.t;
    }
  }
}

// The rig's jack as the top boundary (axial.top = jack): the top fed at V0 less kappa per N of the
// string's force on it above the set force W_s. Steady drilling balances the jack's feed with the cut,
// Omega d0 / (2 pi) = V0 + kappa (W_s - W0(d0)), and is an equilibrium of both schemes (the string with
// all its modes: the static string's force on the top is W0 to round-off); with an ideal drive and with
// the rig's open-loop motor (Omega_s from both balances).
TEST(AxialTorsional, JackTopDrillsSteadilyWhereItsFeedBalancesTheCut) {
  for (Scheme scheme : {Scheme::modified_euler, Scheme::exact_modal}) {
    for (bool motor : {false, true}) {
      Config c = rgd_full_modes(AxialTop::jack, scheme);
      c.axial.rgd.feed_rate = 0.01;      // 36 m/h free feed
      c.axial.rgd.top_force = 150e3;     // the set force [N]
      c.axial.rgd.jack_admittance = 1e-7;  // m/s per N: 10 mm/s less per 100 kN above the set force
      if (!motor) c.top_drive.kind = TopDrive::Kind::ideal;
      else c.top_drive.slope = 1e4;
      c.axial.rgd.disturbance = 0.0;
      const Simulation sim(c);
      const AxialTorsional& m = *sim.coupled();
      const double om = m.steady_speed(c.top_drive, c.top_speed);
      const AxialTorsional::Steady st = m.steady(om);
      const RgdBit& b = c.axial.rgd.bit;
      const double kap = c.axial.rgd.jack_admittance;
      const std::string what = std::string(motor ? "motor " : "ideal ") + to_string(scheme);
      EXPECT_NEAR(st.rop, c.axial.rgd.feed_rate + kap * (c.axial.rgd.top_force - st.wob), 1e-12) << what;
      EXPECT_NEAR(st.rop, om * st.depth / (2.0 * M_PI), 1e-15) << what;
      EXPECT_NEAR(st.wob, test::rgd_steady_wob(b, st.depth), 1e-9 * st.wob) << what;
      if (motor) EXPECT_NEAR(om, c.top_speed - st.torque / c.top_drive.slope, 1e-11 * c.top_speed) << what;
      const ModelState s0 = sim.steady_state(c.top_speed, 0.0, 0.0);
      const Trace tr = test::coupled_trace(sim, &s0);
      for (std::size_t i = 0; i < tr.s.size(); i += 97) {
        ASSERT_NEAR(tr.a[i].wob, st.wob, 1e-7 * st.wob) << what << " t = " << tr.a[i].t;
        ASSERT_NEAR(tr.a[i].rop, st.rop, 1e-7 * st.rop) << what << " t = " << tr.a[i].t;
        ASSERT_NEAR(tr.a[i].position - tr.a[0].position, st.rop * tr.a[i].t, 1e-12 + 1e-7 * st.rop * tr.a[i].t)
            << what;
        ASSERT_NEAR(tr.s[i].bit_speed, om, 1e-9 * om) << what << " t = " << tr.a[i].t;
        ASSERT_NEAR(tr.s[i].torque_on_bit, st.torque, 1e-7 * st.torque) << what << " t = " << tr.a[i].t;
      }
    }
  }
}

// The jack between its limits, from RGD's steady drilling disturbed (rgd-field, 4 rad/s): a vanishing
// admittance is the constant feed (the WOB series differs from the feed's in proportion to kappa), and a
// stiff one holds the mean WOB at the set force as a hook load would (within 2 %).
TEST(AxialTorsional, JackTopIsTheFeedAtZeroAdmittanceAndHoldsItsForceWhenStiff) {
  Config feed = rgd(20.0);
  test::steady_start(feed, AxialTop::feed);
  feed.axial.rgd.disturbance = 0.01;
  const RunReport rf = Simulation(feed).run(Simulation(feed).inputs(), true);
  Config jack = feed;
  jack.axial.rgd.top = AxialTop::jack;
  jack.axial.rgd.top_force = jack.wob = 150e3;
  auto wob_difference = [&](double kappa) {  // the largest difference of the WOB series from the feed's
    jack.axial.rgd.jack_admittance = kappa;
    const Simulation sj(jack);
    const RunReport rj = sj.run(sj.inputs(), true);
    EXPECT_EQ(rj.axial.wob.size(), rf.axial.wob.size());
    double dw = 0.0;
    for (std::size_t i = 0; i < rf.axial.wob.size(); ++i) dw = std::max(dw, std::fabs(rj.axial.wob[i] - rf.axial.wob[i]));
    return dw;
  };
  // first order in kappa (2.4e-2 and 2.5e-3 N on this run), 2.5e-8 of the steady WOB at 1e-16
  const double d15 = wob_difference(1e-15), d16 = wob_difference(1e-16);
  EXPECT_LT(d16, 1e-7 * rf.axial.steady_wob);
  EXPECT_GT(d15 / d16, 8.0);
  EXPECT_LT(d15 / d16, 12.0);
  EXPECT_GT(rf.axial.wob_std, 0.01 * rf.axial.steady_wob);  // the feed's WOB swings with the cycle
  // kappa a zeta eps = 39 >> Omega / (2 pi) = 0.64: the set force carries the cut (steady W0 149.2 kN);
  // kappa x the string's 4.7e5 N/m x dt = 2.3e-3: the explicit update is stable
  jack.axial.rgd.jack_admittance = 1e-5;
  const Simulation stiff(jack);
  const RunReport rs = stiff.run(stiff.inputs(), false);
  EXPECT_NEAR(rs.axial.mean_wob, 150e3, 0.02 * 150e3);
  EXPECT_TRUE(std::isfinite(rs.severity));
}

// The motor gives way: from steady drilling disturbed, at a speed where RGD's bit sticks and slips
// under the ideal drive, the motor's top swings with the cycle; a run has the same bits alone and in a
// batch, on 1 and 2 threads; under a torque limit below the steady torque there is no steady drilling
// and the run stalls; an inertia too small for the step is refused naming the field.
TEST(AxialTorsional, MotorDriveGivesWayWithTheCycleAndStallsBelowTheSteadyTorque) {
  Config c = rgd(40.0);  // 4 rad/s, 150 kN: stick-slip under the ideal drive (the test above)
  c.top_drive.kind = TopDrive::Kind::motor;
  c.top_drive.inertia = 2000.0;
  c.top_drive.slope = 5e4;  // N m s/rad: a stiff characteristic (0.19 rad/s of droop under RGD's 9394 N m)
  c.top_drive.max_torque = 5e4;
  const Simulation sim(c);
  const RunReport r = sim.run(sim.inputs(), true);
  const auto [lo, hi] = std::minmax_element(r.series.top_speed.begin(), r.series.top_speed.end());
  EXPECT_GT(r.severity, 0.5);  // it sticks and slips
  EXPECT_GT(*hi - *lo, 0.02 * c.top_speed);  // the top gives way with the cycle
  const std::vector<double> speeds{3.0, 4.0, 6.0};
  const std::vector<double> ss = sim.sweep_severity(speeds, {}, nullptr, 2);
  EXPECT_EQ(ss, sim.sweep_severity(speeds, {}, nullptr, 1));
  EXPECT_EQ(ss, sim.sweep_severity(speeds, {}, nullptr, 1, std::nullopt, false));
  EXPECT_DOUBLE_EQ(ss[1], r.severity);
  auto refused = [](Config x, const std::string& field) {
    try {
      const Simulation s(x);
      s.run(s.inputs(), false);
      ADD_FAILURE() << "accepted, expected an error naming " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  {  // a torque limit below RGD's steady 9394 N m: no steady drilling; the run starts from the command's and stalls
    Config stall = c;
    stall.top_drive.max_torque = 5000.0;
    const Simulation st(stall);
    EXPECT_TRUE(std::isnan(st.coupled()->steady_speed(stall.top_drive, stall.top_speed)));
    const RunReport s = st.run(st.inputs(), true);
    EXPECT_TRUE(std::isnan(s.axial.steady_speed));
    EXPECT_DOUBLE_EQ(r.axial.steady_speed, st.coupled()->steady_speed(c.top_drive, c.top_speed));
    EXPECT_GT(s.stick_fraction, 0.99);  // the bit held at the motor's 5 kN m, below its static torque
    // the top no longer turns: it rocks on the string at the motor's saturated torque, its mean speed ~ 0
    EXPECT_LT(std::fabs(s.mean_top_speed), 0.05 * c.top_speed);
  }
  Config light = c;
  light.top_drive.inertia = 1e-3;  // the top's own mode far above pi / (5 dt)
  refused(light, "simulation.dt_s");
}

TEST(AxialTorsional, ConfigurationErrorsNameTheField) {
  json j = preset_json("rgd-field");
  auto refused = [](json x, const std::string& field) {
    try {
      parse_config(x);
      ADD_FAILURE() << "accepted; expected an error naming " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  {
    json x = j;
    x["law"] = preset_json("thesis-field")["law"];
    refused(x, "config.law");
  }
  {
    json x = j;
    x["axial"]["top"] = "feed";
    x["operation"].erase("wob_n");
    refused(x, "axial.rop_m_s");
  }
  {
    json x = j;
    x["operation"]["wob_n"] = 50e3;  // below a l sigma = 71.28 kN: the bit would not cut
    refused(x, "operation.wob_n");
  }
  {
    json x = j;
    x["axial"]["bit"]["blades"] = 0;
    refused(x, "axial.bit.blades");
  }
  {
    json x = j;
    x["axial"]["bit"].erase("zeta");
    refused(x, "axial.bit.zeta");
  }
  {
    json x = j;
    x["simulation"]["scheme"] = "bdf2";
    refused(x, "axial.type");
  }
  {
    json x = j;
    x["simulation"]["dt_s"] = 0.02;
    try {
      Simulation s(parse_config(x));
      ADD_FAILURE() << "dt accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("simulation.dt_s"), std::string::npos) << e.what();
    }
  }
  // a WOB grid with a constant feed is refused before it starts: the WOB is then the bit's response
  {
    json x = j;
    x["axial"]["top"] = "feed";
    x["axial"]["rop_m_s"] = 0.006;
    x["operation"].erase("wob_n");
    Simulation sim(parse_config(x));
    try {
      sim.sweep_severity({5.0, 6.0}, {100e3, 200e3});
      ADD_FAILURE() << "a WOB grid accepted with a constant feed";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("sweep.wobs_n"), std::string::npos) << e.what();
    }
  }
  // axial.damping: an unknown kind, distributed without its rate, with a negative one or with a modal
  // ratio beside it, modal with a rate, and a rate too large for the step are each refused naming the key
  {
    json x = j;
    x["axial"]["damping"] = "viscous";
    refused(x, "axial.damping");
  }
  json dist = j;
  dist["axial"]["damping"] = "distributed";
  dist["axial"].erase("damping_ratio");
  refused(dist, "axial.damping_rate_per_s");
  {
    json x = dist;
    x["axial"]["damping_rate_per_s"] = -1.0;
    refused(x, "axial.damping_rate_per_s");
  }
  {
    json x = dist;
    x["axial"]["damping_rate_per_s"] = 1.0;
    x["axial"]["damping_ratio"] = 0.05;
    refused(x, "axial.damping_ratio");
  }
  {
    json x = j;
    x["axial"]["damping_rate_per_s"] = 1.0;
    refused(x, "axial.damping_rate_per_s");
  }
  {
    json x = dist;
    x["axial"]["damping_rate_per_s"] = 2000.0;  // 2 k dt = 2 at dt = 0.5 ms
    try {
      Simulation s(parse_config(x));
      ADD_FAILURE() << "a damping rate accepted beyond the step's stability";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("axial.damping_rate_per_s"), std::string::npos) << e.what();
    }
  }
  {  // a distributed string round-trips without a modal ratio
    json x = dist;
    x["axial"]["damping_rate_per_s"] = 1.0;
    const Config c = parse_config(x);
    EXPECT_EQ(c.axial.rgd.damping, AxialDamping::distributed);
    EXPECT_FALSE(to_json(c)["axial"].contains("damping_ratio"));
    EXPECT_EQ(to_json(parse_config(to_json(c))), to_json(c));
  }
  // a controlled drive whose limit is too low, named
  {  // RGD's steady torque at 150 kN is 9394 N m: a 5 kN m limit cannot carry it
    json x = j;
    x["top_drive"] = {{"type", "controlled"},
                      {"inertia_kg_m2", 2000.0},
                      {"controller", {{"type", "stiff"}, {"torque_limit_nm", 5000.0}}}};
    refused(x, "top_drive.controller.torque_limit_nm");
  }
  // the jack top: its admittance and free feed required, the admittance refused on another top, the
  // set force named when it cannot advance the bit; and its configuration round-trips
  {
    json x = j;
    x["axial"]["top"] = "jack";
    x["axial"]["rop_m_s"] = 0.005;
    refused(x, "axial.jack_admittance_m_s_n");
    x["axial"]["jack_admittance_m_s_n"] = 1e-7;
    const Config c = parse_config(x);
    EXPECT_EQ(c.axial.rgd.top, AxialTop::jack);
    EXPECT_EQ(to_json(parse_config(to_json(c))), to_json(c));
    json y = x;
    y["operation"]["wob_n"] = 1e3;  // 5 mm/s + 1e-7 (1 kN - 71 kN) < 0: the jack would retract
    refused(y, "operation.wob_n");
    json z = j;
    z["axial"]["jack_admittance_m_s_n"] = 1e-7;  // on the hook load
    refused(z, "axial.jack_admittance_m_s_n");
    json w = x;
    w["axial"].erase("rop_m_s");
    refused(w, "axial.rop_m_s");
  }
  // the configuration round-trips through JSON
  const Config c = preset("rgd-field");
  const Config back = parse_config(to_json(c));
  EXPECT_EQ(to_json(back), to_json(c));
}
