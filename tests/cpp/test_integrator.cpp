// Time integration (appendix A and the BDF2 scheme): stability bound, convergence orders against
// an exact solution and a reference solution, rotating-frame forcing, stick without chatter.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstring>
#include <string>
#include <vector>

#include "drill/integrator.hpp"
#include "drill/metrics.hpp"
#include "drill/presets.hpp"
#include "drill/simulation.hpp"

using namespace drill;

namespace {

BitRockLaw zero_law() {
  BitRockLaw l = thesis_tucker_wang();
  l.c0 = 0.0;
  return l;
}

ModalROM field_rom(int modes) {
  const Config c = preset("thesis-field");
  return build_modal_rom(c.string, modes, c.damping);
}

/// Bit speed at time t of the free (zero bit torque) response from Eq. (2.10), exact per mode.
double exact_free_bit_speed(const ModalROM& rom, const DampingSpec& d, double omega, double t) {
  const Eigen::VectorXd p0 = -omega * rom.model.init_velocity;  // modal velocities at t = 0
  double v = omega;
  for (int j = 0; j < rom.omega.size(); ++j) {
    const double w = rom.omega(j), z = d.modal_ratio(j), wd = w * std::sqrt(1 - z * z);
    // q = p0/wd e^{-z w t} sin(wd t);  q' = p0 e^{-z w t} (cos(wd t) - z w / wd sin(wd t))
    const double qd = p0(j) * std::exp(-z * w * t) * (std::cos(wd * t) - z * w / wd * std::sin(wd * t));
    v += rom.model.bit(j) * qd;
  }
  return v;
}

/// |bit speed at T - target| for dt = 4, 2, 1, 0.5 ms with one scheme.
std::vector<double> errors_by_dt(Scheme sch, const ModalROM& rom, const BitRockLaw& law, const Inputs& in,
                                 double T, double target, const ModelState* start = nullptr) {
  std::vector<double> err;
  for (double dt : {4e-3, 2e-3, 1e-3, 5e-4}) {
    SimOptions o;
    o.scheme = sch;
    o.dt = dt;
    o.duration = T;
    double v = 0;
    Integrator(rom.model, law, o).run(in, [&](const StepState& s) { v = s.bit_speed; }, start);
    err.push_back(std::fabs(v - target));
  }
  return err;
}

}  // namespace

TEST(Integrator, ModifiedEulerRefusesTimeStepAboveBoundA7) {
  const ModalROM rom = field_rom(20);
  SimOptions o;
  o.dt = 0.02;
  try {
    Integrator integ(rom.model, thesis_hysteretic(0.14, SpeedUnit::rpm), o);
    FAIL() << "dt above the bound was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    const double bound = M_PI / (5.0 * rom.omega.maxCoeff());
    EXPECT_NE(msg.find("simulation.dt_s = 0.02"), std::string::npos) << msg;
    EXPECT_NE(msg.find(show(bound)), std::string::npos) << msg;
  }
  o.dt = 0.99 * M_PI / (5.0 * rom.omega.maxCoeff());
  EXPECT_NO_THROW(Integrator(rom.model, thesis_hysteretic(0.14, SpeedUnit::rpm), o));
  o.scheme = Scheme::bdf2;  // L-stable: no bound
  o.dt = 0.02;
  EXPECT_NO_THROW(Integrator(rom.model, thesis_hysteretic(0.14, SpeedUnit::rpm), o));
}

TEST(Integrator, OrdersOneAndTwoAgainstTheExactLinearSolution) {
  const Config c = preset("thesis-field");
  const ModalROM rom = field_rom(5);
  Inputs in;
  in.top_speed = Signal::constant(10.0);
  const double T = 4.0, exact = exact_free_bit_speed(rom, c.damping, 10.0, T);
  for (Scheme sch : {Scheme::modified_euler, Scheme::bdf2}) {
    const std::vector<double> err = errors_by_dt(sch, rom, zero_law(), in, T, exact);
    const double expected = sch == Scheme::bdf2 ? 2.0 : 1.0;
    for (std::size_t i = 1; i < err.size(); ++i)
      EXPECT_NEAR(std::log2(err[i - 1] / err[i]), expected, 0.25) << to_string(sch) << " refinement " << i;
  }
}

TEST(Integrator, OrdersOneAndTwoOnTheNonlinearSlipRegime) {
  // Tucker-Wang law at 20 rad/s starting from the rigidly rotating, untwisted string: the bit
  // slips throughout, so the solution is smooth. Reference: BDF2 with a 16x smaller step.
  const ModalROM rom = field_rom(8);
  Inputs in;
  in.top_speed = Signal::constant(20.0);
  const ModelState start{Eigen::VectorXd::Zero(8), Eigen::VectorXd::Zero(8)};
  const double T = 6.0;
  SimOptions ref;
  ref.scheme = Scheme::bdf2;
  ref.dt = 5e-4 / 16;
  ref.duration = T;
  double vmin = 1e9;
  double v_ref = 0;
  Integrator(rom.model, thesis_tucker_wang(), ref).run(in, [&](const StepState& s) {
    vmin = std::min(vmin, s.bit_speed);
    v_ref = s.bit_speed;
  }, &start);
  ASSERT_GT(vmin, 1.0) << "the reference run is expected to slip throughout";
  for (Scheme sch : {Scheme::modified_euler, Scheme::bdf2}) {
    const std::vector<double> err = errors_by_dt(sch, rom, thesis_tucker_wang(), in, T, v_ref, &start);
    const double expected = sch == Scheme::bdf2 ? 2.0 : 1.0;
    const double order = std::log2(err.front() / err.back()) / 3.0;
    EXPECT_NEAR(order, expected, 0.3) << to_string(sch);
  }
}

TEST(Integrator, SteadySlipBalancesTopAndBitTorque) {
  // Far above the stick-slip threshold the reversible law (model 1) lets the string settle to a
  // steady twist: the top torque equals the torque on bit and the bit turns at the top speed.
  // (With beta1 > 0 a small limit cycle remains at 50 rad/s: docs/numerics.md.)
  const Config c = preset("thesis-field");
  const ModalROM rom = build_modal_rom(c.string, 100, c.damping);
  SimOptions o;
  o.scheme = Scheme::bdf2;
  o.dt = 2e-3;
  o.duration = 400;
  Inputs in;
  in.top_speed = Signal::constant(50.0);
  StepState last;
  Integrator(rom.model, thesis_hysteretic(0.0, SpeedUnit::rpm), o).run(in, [&](const StepState& s) { last = s; });
  EXPECT_NEAR(last.bit_speed, 50.0, 1e-3);
  EXPECT_NEAR(last.top_torque / last.torque_on_bit, 1.0, 1e-4);
  // and the twist is the static one: T = k_eff * twist with 1/k_eff = sum L / (G J)
  double compliance = 0;
  for (const auto& s : c.string.sections) compliance += s.length / (s.shear_modulus() * s.polar_moment());
  const double twist = 50.0 * last.t - last.bit_angle;
  EXPECT_NEAR(twist, last.torque_on_bit * compliance, 1e-3 * twist);
}

TEST(Integrator, AcceleratingTopDriveLoadsTheStringQuasiStatically) {
  // Top speed ramp Omega = 5 + alpha t with no bit torque: the rotating-frame load -M 1 alpha gives
  // a steady relative twist u = -alpha K^-1 (M_ff 1 + M_f0); the bit angle is
  // theta_top(t) + u_bit with theta_top = 5 t + alpha t^2 / 2.
  Config c = preset("thesis-field");
  c.set_total_elements(20);
  const ModalROM rom = build_modal_rom(c.string, 20, c.damping);
  const ClampedMatrices cm = clamp_top(assemble(c.string));
  const double alpha = 0.05, T = 200.0;
  const Eigen::VectorXd u = -alpha * cm.K.ldlt().solve(cm.M * Eigen::VectorXd::Ones(20) + cm.m_top);
  std::vector<double> ramp;
  for (int k = 0; k <= 2100; ++k) ramp.push_back(5.0 + alpha * 0.1 * k);
  Inputs in;
  in.top_speed = Signal::sampled(ramp, 0.0, 0.1);
  SimOptions o;
  o.scheme = Scheme::bdf2;
  o.dt = 1e-3;
  o.duration = T;
  StepState last;
  Integrator(rom.model, zero_law(), o).run(in, [&](const StepState& s) { last = s; });
  const double theta_top = 5.0 * T + 0.5 * alpha * T * T;
  EXPECT_NEAR(last.bit_angle - theta_top, u(19), 1e-3 * std::fabs(u(19)));
  EXPECT_NEAR(last.bit_speed, 5.0 + alpha * T, 1e-4);
  EXPECT_NEAR(last.top_speed, 5.0 + alpha * T, 1e-9);
}

TEST(Integrator, Bdf2SticksWithoutChatteringWhileModifiedEulerChatters) {
  const Config c = preset("thesis-field");
  const ModalROM rom = build_modal_rom(c.string, 100, c.damping);
  Inputs in;
  in.top_speed = Signal::constant(10.0);
  for (Scheme sch : {Scheme::bdf2, Scheme::exact_modal, Scheme::modified_euler}) {
    SimOptions o;
    o.scheme = sch;
    o.duration = 120;
    double vmin = 1e9, vmax_stuck = 0;
    long stuck = 0;
    Integrator(rom.model, thesis_hysteretic(0.14, SpeedUnit::rpm), o).run(in, [&](const StepState& s) {
      if (s.t < 60) return;
      vmin = std::min(vmin, s.bit_speed);
      if (s.bit_speed < 0.5) ++stuck;
    });
    ASSERT_GT(stuck, 1000) << to_string(sch) << ": the bit should stick at 10 rad/s";
    if (sch != Scheme::modified_euler) EXPECT_GT(vmin, -1e-3) << to_string(sch);  // stick is a true zero-speed phase
    else EXPECT_LT(vmin, -0.05);                      // the explicit torque chatters around zero
    (void)vmax_stuck;
  }
}

TEST(Integrator, BadInputsAreRefused) {
  const ModalROM rom = field_rom(5);
  SimOptions o;
  o.duration = -1;
  EXPECT_THROW(Integrator(rom.model, thesis_tucker_wang(), o), std::invalid_argument);
  o.duration = 1;
  Integrator integ(rom.model, thesis_tucker_wang(), o);
  Inputs in;
  in.top_speed = Signal::constant(std::nan(""));
  try {
    integ.run(in, [](const StepState&) {});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("operation.top_speed_rad_s"), std::string::npos);
  }
}

namespace {

/// Eq. (5.1) with a static torque Ts at rest and a constant kinetic torque Tk while slipping
/// (a0 = Ts / gain; a2 = a4 = Tk / gain; the other coefficients zero), in rad/s, at W = W_ref.
BitRockLaw coulomb_law(double Ts, double Tk) {
  BitRockLaw l;
  l.kind = BitRockLaw::Kind::polynomial;
  l.speed_unit = SpeedUnit::rad_s;
  l.wob_ref = 500.0;
  l.ref_speed = 1.0;
  l.a = {Ts / l.gain, 0.0, Tk / l.gain, 0.0, Tk / l.gain, 0.0, 0.0, 0.0};
  return l;
}

ModalROM rig_rom(double zeta) {
  Config c = preset("thesis-rig");
  c.damping.ratios = {zeta};
  return build_modal_rom(c.string, 1, c.damping);
}

}  // namespace

TEST(Integrator, StuckBitBreaksAwayWhenTheStringTorqueReachesTheStaticTorque) {
  // One mode, bit at rest at t = 0 with an untwisted string, top at Omega: while stuck the
  // coordinate is z = -Omega t / b, so the string holds the bit with T(t) = Omega (d + w^2 t) / b^2
  // (d = 2 zeta w); it breaks away at t_b = (Ts b^2 / Omega - d) / w^2.
  const ModalROM rom = rig_rom(0.1);
  const double b = rom.model.bit(0), w = rom.omega(0), d = 2 * 0.1 * w, Om = 8.0, Ts = 3.0;
  const double t_b = (Ts * b * b / Om - d) / (w * w);
  ASSERT_GT(t_b, 0.05);
  ModelState start{Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, -Om / b)};
  Inputs in;
  in.top_speed = Signal::constant(Om);
  in.wob = Signal::constant(500.0);
  for (Scheme sch : {Scheme::modified_euler, Scheme::bdf2, Scheme::exact_modal}) {
    SimOptions o;
    o.scheme = sch;
    o.dt = 1e-4;
    o.duration = 1.5 * t_b;
    double t_move = -1, worst_T = 0, worst_v = 0;
    Integrator(rom.model, coulomb_law(Ts, 0.6 * Ts), o).run(in, [&](const StepState& s) {
      if (t_move >= 0) return;
      if (s.bit_speed > 1e-9) {
        t_move = s.t;
        return;
      }
      worst_v = std::max(worst_v, std::fabs(s.bit_speed));
      const double T_exact = Om * (d + w * w * s.t) / (b * b);  // the break-away step reports Ts itself
      if (s.step > 0 && T_exact < Ts) worst_T = std::max(worst_T, std::fabs(s.torque_on_bit - T_exact));
    }, &start);
    EXPECT_LT(worst_v, 1e-9) << to_string(sch);
    // exact_modal holds a stuck step's torque constant over the step: off by half a step of the
    // torque's rise here (BDF2 is off by the same order)
    EXPECT_LT(worst_T, (sch == Scheme::modified_euler ? 1e-9 : 1e-3) * Ts) << to_string(sch);
    EXPECT_NEAR(t_move, t_b, 2.5 * o.dt) << to_string(sch);
  }
}

TEST(Integrator, AgedStaticTorqueHoldsTheStuckBitUntilTheStringExceedsItsAgedValue) {
  // The case above with law.static_ageing A, tau_a: after t stuck the static torque is
  // Ts (1 + A t / (t + tau_a)), so the bit breaks away where Omega (d + w^2 t) / b^2 first exceeds
  // it (bisection), later than without ageing; A = 0 is the law without ageing, bit for bit.
  const ModalROM rom = rig_rom(0.1);
  const double b = rom.model.bit(0), w = rom.omega(0), d = 2 * 0.1 * w, Om = 8.0, Ts = 3.0, A = 0.5, ta = 0.05;
  const auto excess = [&](double t) { return Om * (d + w * w * t) / (b * b) - Ts * (1.0 + A * t / (t + ta)); };
  const double t_b0 = (Ts * b * b / Om - d) / (w * w);
  double lo = 0.0, hi = 20.0 * t_b0;
  ASSERT_LT(excess(lo), 0.0);
  ASSERT_GT(excess(hi), 0.0);
  for (int k = 0; k < 100; ++k) (excess(0.5 * (lo + hi)) < 0.0 ? lo : hi) = 0.5 * (lo + hi);
  const double t_b = hi;
  ASSERT_GT(t_b, 1.3 * t_b0);  // the ageing holds the bit markedly longer
  ModelState start{Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, -Om / b)};
  Inputs in;
  in.top_speed = Signal::constant(Om);
  in.wob = Signal::constant(500.0);
  SimOptions o;
  o.dt = 1e-4;
  o.duration = 1.5 * t_b;
  const auto run = [&](const BitRockLaw& law) {
    std::vector<double> v;
    Integrator(rom.model, law, o).run(in, [&](const StepState& s) { v.push_back(s.bit_speed); }, &start);
    return v;
  };
  BitRockLaw aged = coulomb_law(Ts, 0.6 * Ts);
  aged.static_ageing = A;
  aged.static_ageing_s = ta;
  const std::vector<double> v = run(aged);
  const long moved = std::find_if(v.begin(), v.end(), [](double x) { return x > 1e-9; }) - v.begin();
  EXPECT_NEAR(moved * o.dt, t_b, 2.5 * o.dt);
  BitRockLaw none = coulomb_law(Ts, 0.6 * Ts);
  const std::vector<double> v0 = run(none);
  none.static_ageing = 0.0;
  none.static_ageing_s = ta;
  EXPECT_EQ(run(none), v0);
  const long moved0 = std::find_if(v0.begin(), v0.end(), [](double x) { return x > 1e-9; }) - v0.begin();
  EXPECT_NEAR(moved0 * o.dt, t_b0, 2.5 * o.dt);
}

TEST(Integrator, StaticTorqueAboveKineticTorqueGivesTrueStickPhasesCappedByTheStaticTorque) {
  const ModalROM rom = rig_rom(0.05);
  const double Ts = 3.0;
  Inputs in;
  in.top_speed = Signal::constant(5.0);
  in.wob = Signal::constant(500.0);
  for (Scheme sch : {Scheme::modified_euler, Scheme::bdf2, Scheme::exact_modal}) {
    SimOptions o;
    o.scheme = sch;
    o.dt = 1e-4;
    o.duration = 20.0;
    long stuck = 0, n = 0, breaks = 0;
    double vmin = 1e9, Tmax_stuck = 0, prev_v = 1.0;
    Integrator(rom.model, coulomb_law(Ts, 0.6 * Ts), o).run(in, [&](const StepState& s) {
      if (s.t < 5) return;
      ++n;
      vmin = std::min(vmin, s.bit_speed);
      if (std::fabs(s.bit_speed) <= 1e-9) {
        ++stuck;
        Tmax_stuck = std::max(Tmax_stuck, s.torque_on_bit);
      } else if (std::fabs(prev_v) <= 1e-9) {
        ++breaks;
      }
      prev_v = s.bit_speed;
    });
    EXPECT_GT(breaks, 5) << to_string(sch) << ": a stick-slip limit cycle";
    EXPECT_GT(stuck, n / 20) << to_string(sch);
    EXPECT_GT(vmin, -1e-9) << to_string(sch) << ": no backward motion, no chatter";
    EXPECT_LE(Tmax_stuck, Ts * (1 + 1e-12)) << to_string(sch);
    EXPECT_GT(Tmax_stuck, 0.99 * Ts) << to_string(sch) << ": it breaks away at the static torque";
  }
}

// Coulomb string friction T_sf sign(v) (operation.string_friction_nm, an extension not in the
// thesis): set-valued at rest, it adds to the stick capacity; it acts outside the bit's torque
// sensor, so the reported torque on bit leaves it out.

namespace {

/// The bit at rest under an untwisted string with the top at Om (as in the static-torque test
/// above): the string torque at the bit is T(t) = Om (d + w^2 t) / b^2 while stuck, and the bit
/// breaks away when it reaches Ts + Tsf. Checks the reported (contact) torque while stuck against
/// min(T(t), Ts) (the contact takes the string torque up to the static torque, the string friction
/// the rest) and the break-away time.
void expect_stick_and_break_away(const BitRockLaw& law, double Ts, double Tsf, const std::string& what) {
  const ModalROM rom = rig_rom(0.1);
  const double b = rom.model.bit(0), w = rom.omega(0), d = 2 * 0.1 * w, Om = 8.0;
  const double t_b = ((Ts + Tsf) * b * b / Om - d) / (w * w);
  ASSERT_GT(t_b, 0.05) << what;
  ASSERT_DOUBLE_EQ(law.static_torque(500.0), Ts) << what;
  const ModelState start{Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, -Om / b)};
  Inputs in;
  in.top_speed = Signal::constant(Om);
  in.wob = Signal::constant(500.0);
  in.string_friction = Tsf;
  for (Scheme sch : {Scheme::modified_euler, Scheme::bdf2, Scheme::exact_modal}) {
    SimOptions o;
    o.scheme = sch;
    o.dt = 1e-4;
    o.duration = t_b + 50 * o.dt;
    double t_move = -1, worst_T = 0, worst_v = 0;
    long stuck_steps = 0;
    Integrator(rom.model, law, o).run(in, [&](const StepState& s) {
      if (t_move >= 0) return;
      if (s.bit_speed > 1e-9) {
        t_move = s.t;
        return;
      }
      worst_v = std::max(worst_v, std::fabs(s.bit_speed));
      const double T_exact = Om * (d + w * w * s.t) / (b * b);
      if (s.step > 0 && T_exact < Ts + Tsf) {
        ++stuck_steps;
        worst_T = std::max(worst_T, std::fabs(s.torque_on_bit - std::min(T_exact, Ts)));
      }
    }, &start);
    EXPECT_GT(stuck_steps, 100) << what << " " << to_string(sch);
    EXPECT_LT(worst_v, 1e-9) << what << " " << to_string(sch);
    EXPECT_LT(worst_T, (sch == Scheme::modified_euler ? 1e-9 : 1e-3) * (Ts + Tsf)) << what << " " << to_string(sch);
    EXPECT_NEAR(t_move, t_b, 2.5 * o.dt) << what << " " << to_string(sch);
  }
}

}  // namespace

TEST(Integrator, StringFrictionAloneSticksTheLawsWithoutStaticTorqueAndBreaksAwayAtTsf) {
  const double Tsf = 2.0;
  BitRockLaw hys = thesis_hysteretic(0.14, SpeedUnit::rpm);
  hys.wob_ref = 500.0;
  hys.b[0] = 1.0;
  BitRockLaw tw = thesis_tucker_wang();
  tw.c0 = 1.0;
  expect_stick_and_break_away(coulomb_law(0.0, 0.6 * Tsf), 0.0, Tsf, "polynomial a0 = 0");
  expect_stick_and_break_away(hys, 0.0, Tsf, "hysteretic");
  expect_stick_and_break_away(tw, 0.0, Tsf, "tucker_wang");
  expect_stick_and_break_away(zero_law(), 0.0, Tsf, "zero law");
}

TEST(Integrator, StringFrictionAddsToTheStaticTorqueOfTheStickCondition) {
  expect_stick_and_break_away(coulomb_law(3.0, 1.8), 3.0, 1.5, "polynomial a0 > 0");
}

TEST(Integrator, SteadySlipStringTorqueIsTheReportedTorqueOnBitPlusTheStringFriction) {
  // One mode, constant kinetic torque Tk above 0.01 rad/s: started with the twist of the contact
  // torque alone, the string settles to steady slip at the top speed with the twist of Tk + T_sf,
  // while the reported torque on bit stays the contact torque Tk.
  const ModalROM rom = rig_rom(0.1);
  const double Om = 10.0, Tk = 2.0, Tsf = 0.5;
  Inputs in;
  in.top_speed = Signal::constant(Om);
  in.wob = Signal::constant(500.0);
  in.string_friction = Tsf;
  for (Scheme sch : {Scheme::modified_euler, Scheme::bdf2, Scheme::exact_modal}) {
    SimOptions o;
    o.scheme = sch;
    o.dt = 1e-4;
    o.duration = 20.0;
    const Integrator integ(rom.model, coulomb_law(0.0, Tk), o);
    const ModelState start = integ.state_from_bit(Om, 0.0, Tk, Om, 0.0);
    double vmin = 1e9;
    StepState last;
    integ.run(in, [&](const StepState& s) {
      vmin = std::min(vmin, s.bit_speed);
      last = s;
    }, &start);
    ASSERT_GT(vmin, 0.5) << to_string(sch) << ": the bit is expected to slip throughout";
    EXPECT_NEAR(last.bit_speed, Om, 1e-6) << to_string(sch);
    EXPECT_NEAR(last.torque_on_bit, Tk, 1e-9) << to_string(sch);
    // the string torque: the top torque of the static twist per N m at the bit (1 + 1.4e-5 with one mode)
    const double per_nm = integ.top_torque(integ.state_from_bit(Om, 0.0, 1.0, Om, 0.0));
    ASSERT_NEAR(per_nm, 1.0, 1e-4);
    EXPECT_NEAR(last.top_torque / per_nm, Tk + Tsf, 1e-6) << to_string(sch);
    EXPECT_NEAR(last.top_torque / per_nm - last.torque_on_bit, Tsf, 1e-6) << to_string(sch);
  }
}

TEST(Integrator, ZeroStringFrictionLeavesRunsBitIdentical) {
  // T_sf = 0 takes the code paths of the engine without string friction (checked at the change
  // against the previous headers on rig, field and motor runs); here: the default and an explicit
  // 0, from Inputs and from a configuration with and without the key, step for step.
  const ModalROM rom = rig_rom(0.05);
  for (Scheme sch : {Scheme::modified_euler, Scheme::bdf2, Scheme::exact_modal}) {
    SimOptions o;
    o.scheme = sch;
    o.dt = 1e-4;
    o.duration = 5.0;
    const Integrator integ(rom.model, coulomb_law(3.0, 1.8), o);
    Inputs a;
    a.top_speed = Signal::constant(5.0);
    a.wob = Signal::constant(500.0);
    a.bit_viscous = 0.01;
    Inputs b = a;
    b.string_friction = 0.0;
    std::vector<StepState> ra, rb;
    integ.run(a, [&](const StepState& s) { ra.push_back(s); });
    integ.run(b, [&](const StepState& s) { rb.push_back(s); });
    ASSERT_EQ(ra.size(), rb.size());
    long stuck = 0;
    for (std::size_t k = 0; k < ra.size(); ++k) {
      ASSERT_EQ(std::memcmp(&ra[k], &rb[k], sizeof(StepState)), 0) << to_string(sch) << " step " << k;
      stuck += std::fabs(ra[k].bit_speed) <= 1e-9;
    }
    EXPECT_GT(stuck, 1000) << to_string(sch) << ": the stick condition is exercised";
  }
  json with_key = preset_json("thesis-rig"), without = with_key;
  with_key["operation"]["string_friction_nm"] = 0.0;
  with_key["simulation"]["duration_s"] = without["simulation"]["duration_s"] = 6.0;
  const Simulation s1(parse_config(with_key)), s2(parse_config(without));
  const RunReport r1 = s1.run(s1.inputs()), r2 = s2.run(s2.inputs());
  EXPECT_EQ(r1.series.bit_speed, r2.series.bit_speed);
  EXPECT_EQ(r1.series.torque_on_bit, r2.series.torque_on_bit);
  EXPECT_EQ(r1.series.top_torque, r2.series.top_torque);
}

TEST(Integrator, NegativeOrNonFiniteStringFrictionIsRefused) {
  const ModalROM rom = rig_rom(0.1);
  SimOptions o;
  o.dt = 1e-4;
  o.duration = 0.01;
  const Integrator integ(rom.model, coulomb_law(0.0, 1.0), o);
  for (double bad : {-1.0, std::nan(""), HUGE_VAL}) {
    Inputs in;
    in.string_friction = bad;
    try {
      integ.run(in, [](const StepState&) {});
      FAIL() << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("operation.string_friction_nm = " + show(bad)), std::string::npos)
          << e.what();
    }
  }
}

TEST(Integrator, LaggedAccelerationEqualsImplicitWithoutHysteresis) {
  // Without hysteresis (beta1 = 0) the law does not depend on the acceleration: both readings of
  // Eq. (3.3) integrate the same equations.
  const ModalROM rom = field_rom(10);
  SimOptions o;
  o.duration = 30;
  Inputs in;
  in.top_speed = Signal::constant(12.0);
  std::vector<double> a, b;
  Integrator(rom.model, thesis_hysteretic(0.0, SpeedUnit::rpm), o).run(in, [&](const StepState& s) { a.push_back(s.bit_speed); });
  o.acceleration = Acceleration::lagged;
  Integrator(rom.model, thesis_hysteretic(0.0, SpeedUnit::rpm), o).run(in, [&](const StepState& s) { b.push_back(s.bit_speed); });
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); i += 997) EXPECT_NEAR(a[i], b[i], 1e-9 * (1 + std::fabs(a[i]))) << i;
}

TEST(Integrator, LaggedAccelerationFlipsTheHysteresisAtEveryStep) {
  // docs/numerics.md: the law's dT/da acts as an added inertia at the bit far larger than the bit's
  // modal inertia, so an explicit (lagged) acceleration alternates in sign from step to step in
  // slip at 50 rad/s, while the implicit one changes sign only at the turning points of the slow
  // oscillation that remains (a sign change every few hundred steps at most).
  const ModalROM rom = field_rom(20);
  SimOptions o;
  o.duration = 60;
  Inputs in;
  in.top_speed = Signal::constant(50.0);
  auto alternations = [&](Acceleration acc, double& amplitude) {
    o.acceleration = acc;
    std::vector<double> a;
    Integrator(rom.model, thesis_hysteretic(0.14, SpeedUnit::rpm), o).run(in, [&](const StepState& s) {
      if (s.t >= 50.0) a.push_back(s.bit_accel);
    });
    int flips = 0;
    amplitude = 0.0;
    for (std::size_t i = 1; i < a.size(); ++i) {
      flips += a[i] * a[i - 1] < 0.0;
      amplitude = std::max(amplitude, std::fabs(a[i]));
    }
    return static_cast<double>(flips) / static_cast<double>(a.size() - 1);
  };
  double amp_lag = 0.0, amp_imp = 0.0;
  const double lag = alternations(Acceleration::lagged, amp_lag), imp = alternations(Acceleration::implicit, amp_imp);
  EXPECT_GT(lag, 0.9);
  EXPECT_GT(amp_lag, 1.0);  // rad/s^2
  EXPECT_LT(imp, 0.01);
}

TEST(Integrator, LaggedAccelerationIsRefusedWithBdf2) {
  SimOptions o;
  o.scheme = Scheme::bdf2;
  o.acceleration = Acceleration::lagged;
  try {
    o.validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("simulation.acceleration"), std::string::npos);
  }
  EXPECT_THROW(parse_acceleration("explicit"), std::invalid_argument);
}
