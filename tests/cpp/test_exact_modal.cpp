// The exact modal scheme (exact_modal.hpp, issue 33): the propagator of one mode is exact for a
// forcing linear over the step at any step, damped or not; a linear run is exact at a step 100x
// the thesis's; on the thesis's field configuration SS converges to a fine-step BDF2 reference at
// a step 10x the thesis's; the stick condition holds; the batched path gives a run the same bits in
// every lane, for any thread count and chunking, and the scalar path's results to rounding.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "drill/batched_integrator.hpp"
#include "drill/exact_modal.hpp"
#include "drill/integrator.hpp"
#include "drill/montecarlo.hpp"
#include "drill/presets.hpp"
#include "drill/process.hpp"
#include "drill/run_many.hpp"
#include "drill/simulation.hpp"
#include "error_text.hpp"
#include "rig_with_stick.hpp"
#include "varied_runs.hpp"

using namespace drill;

namespace {

/// z'' + d z' + w2 z = F0 + r t from (z0, p0), underdamped (d^2 < 4 w2): the exact (z, z') at t.
std::pair<double, double> em_exact_ramp(double w2, double d, double z0, double p0, double F0, double r, double t) {
  const double zp0 = F0 / w2 - d * r / (w2 * w2), zpd = r / w2;  // particular solution and its slope at 0
  const double s = 0.5 * d, wd = std::sqrt(w2 - s * s);
  const double A = z0 - zp0, B = (p0 - zpd + s * A) / wd;
  const double e = std::exp(-s * t), c = std::cos(wd * t), sn = std::sin(wd * t);
  const double z = e * (A * c + B * sn) + zp0 + zpd * t;
  const double p = e * ((-s * A + wd * B) * c + (-s * B - wd * A) * sn) + zpd;
  return {z, p};
}

Config em_field(int modes, double duration) {
  Config c = preset("thesis-field");
  c.modes = modes;
  c.sim.scheme = Scheme::exact_modal;
  c.sim.duration = duration;
  c.transient = duration / 3.0;
  return c;
}

std::vector<StepTrace> em_batched(const BatchedIntegrator& b, const std::vector<Inputs>& in) {
  std::vector<StepTrace> tr(in.size());
  const std::vector<const ModelState*> start(in.size(), nullptr);
  b.run(in.data(), start.data(), in.size(), tr.data());
  return tr;
}

/// A damping scan of the rig with a stick condition on the exact modal scheme: one simulation per
/// modal damping ratio, with its inputs (run_many's arguments).
struct DampingScan {
  std::vector<std::unique_ptr<Simulation>> owned;
  std::vector<const Simulation*> sims;
  std::vector<Inputs> in;
};
DampingScan em_damping_scan(BitRockLaw::Kind law, const std::vector<double>& ratios) {
  DampingScan scan;
  for (double z : ratios) {
    Config c = rig_with_stick(law);
    c.sim.scheme = Scheme::exact_modal;
    c.damping.kind = DampingSpec::Kind::modal;
    c.damping.ratios = {z};
    scan.owned.push_back(std::make_unique<Simulation>(c));
    scan.sims.push_back(scan.owned.back().get());
    scan.in.push_back(scan.sims.back()->inputs());
  }
  return scan;
}

}  // namespace

TEST(ExactModal, ThePropagatorIsExactForAForcingLinearOverTheStep) {
  // omega dt = 3 rad (half a period per step), undamped and 10 % damped, 20 steps of a ramp
  // forcing: the composed steps reproduce the closed-form solution to rounding.
  const double w2 = 900.0, dt = 0.1, z0 = 0.3, p0 = -2.0, F0 = 5.0, r = -120.0;
  for (double zeta : {0.0, 0.1}) {
    const double d = 2.0 * zeta * std::sqrt(w2);
    const std::array<double, 8> P = ExactModal::propagator(w2, d, dt);
    double z = z0, p = p0;
    double worst = 0.0;
    for (int i = 0; i < 20; ++i) {
      const double Fa = F0 + r * i * dt, Fb = F0 + r * (i + 1) * dt;
      const double zn = P[0] * z + P[1] * p + P[4] * Fa + P[6] * Fb;
      const double pn = P[2] * z + P[3] * p + P[5] * Fa + P[7] * Fb;
      z = zn;
      p = pn;
      const auto ex = em_exact_ramp(w2, d, z0, p0, F0, r, (i + 1) * dt);
      worst = std::max({worst, std::fabs(z - ex.first) / 1.0, std::fabs(p - ex.second) / 30.0});
    }
    EXPECT_LT(worst, 1e-12) << "zeta " << zeta;  // |z| ~ 1, |p| ~ 30 here
    // one step of the thesis's modified Euler (Eqs. A.5-A.6) at this step is off by O(1)
    const double pe = p0 + dt * (F0 - d * p0 - w2 * z0), ze = z0 + dt * pe;
    const auto ex1 = em_exact_ramp(w2, d, z0, p0, F0, r, dt);
    EXPECT_GT(std::fabs(ze - ex1.first), 0.1) << "zeta " << zeta;
  }
}

TEST(ExactModal, ALinearRunIsExactAtAStepOneHundredTimesTheThesis) {
  // No bit torque (a zero law): the free response of Eq. (2.10) at 5 modes with the thesis's
  // modal damping, exact per mode, at dt = 51.2 ms; BDF2 at that step is visibly off.
  const Config c = preset("thesis-field");
  const ModalROM rom = build_modal_rom(c.string, 5, c.damping);
  BitRockLaw zero = thesis_tucker_wang();
  zero.c0 = 0.0;
  Inputs in;
  in.top_speed = Signal::constant(10.0);
  const double T = 4.096;
  double exact = 10.0;
  const Eigen::VectorXd p0 = -10.0 * rom.model.init_velocity;
  for (int j = 0; j < rom.omega.size(); ++j) {
    const double w = rom.omega(j), z = c.damping.modal_ratio(j), wd = w * std::sqrt(1 - z * z);
    exact += rom.model.bit(j) * p0(j) * std::exp(-z * w * T) * (std::cos(wd * T) - z * w / wd * std::sin(wd * T));
  }
  auto end_speed = [&](Scheme s) {
    SimOptions o;
    o.scheme = s;
    o.dt = 100 * 5.12e-4;
    o.duration = T;
    double v = NAN;
    Integrator(rom.model, zero, o).run(in, [&](const StepState& st) { v = st.bit_speed; });
    return v;
  };
  ASSERT_GT(std::fabs(exact - 10.0), 1e-3);  // the free response has not died out
  EXPECT_NEAR(end_speed(Scheme::exact_modal), exact, 1e-9 * 10.0);
  EXPECT_GT(std::fabs(end_speed(Scheme::bdf2) - exact), 1e-4);
}

TEST(ExactModal, SeverityConvergesToAFineStepBdf2ReferenceAtATenTimesLargerStep) {
  // thesis-field, 20 modes (hysteretic law, Eqs. 3.2-3.3), 100 s: SS of the exact modal scheme at
  // 5.12 ms (10x the thesis's step) within 0.5 % of BDF2 at 51.2 us (10x finer than the thesis's),
  // in stick-slip (10 rad/s) and above the threshold (22 rad/s); measured 0.013 % and 0.19 %
  // (docs/numerics.md gives the full study: benchmarks/exact_modal_convergence.py).
  for (double om : {10.0, 22.0}) {
    Config ref = em_field(20, 100.0);
    ref.transient = 50.0;
    ref.sim.scheme = Scheme::bdf2;
    ref.sim.dt = 5.12e-5;
    Config big = ref;
    big.sim.scheme = Scheme::exact_modal;
    big.sim.dt = 5.12e-3;
    const Simulation a(ref), b(big);
    const RunReport ra = a.run(a.inputs(om, ref.wob), false), rb = b.run(b.inputs(om, big.wob), false);
    EXPECT_NEAR(rb.severity / ra.severity, 1.0, 5e-3) << om;
    EXPECT_NEAR(rb.stick_fraction, ra.stick_fraction, 2e-3) << om;
  }
}

TEST(ExactModal, TheStickConditionHoldsOnTheRig) {
  // the test rig with a static torque (Eq. 5.1 with a0 > 0) and string friction, 20 s at 0.1 ms:
  // true stick phases (zero speed, no backward motion) with the torque on bit within the static
  // torque, and the phases of BDF2's run (the same break-aways; a torque interpolated linearly
  // over a stuck step alternated from step to step and broke away 6x as often).
  struct Phases {
    long stuck = 0, breaks = 0, n = 0;
    double vmin = 1e9, Tmax = 0.0;
  };
  auto phases = [](Scheme s) {
    Config c = rig_with_stick(BitRockLaw::Kind::polynomial);
    c.sim.scheme = s;
    c.sim.duration = 20.0;
    const Simulation sim(c);
    Phases ph;
    double prev = 1.0;
    sim.integrator().run(sim.inputs(), [&](const StepState& st) {
      if (st.t < 5.0) return;
      ++ph.n;
      ph.vmin = std::min(ph.vmin, st.bit_speed);
      if (st.bit_speed == 0.0) {
        ++ph.stuck;
        ph.Tmax = std::max(ph.Tmax, std::fabs(st.torque_on_bit));
      } else if (prev == 0.0) {
        ++ph.breaks;
      }
      prev = st.bit_speed;
    });
    return ph;
  };
  const Config c = rig_with_stick(BitRockLaw::Kind::polynomial);
  const double Ts = c.law.static_torque(c.wob);
  ASSERT_GT(Ts, 0.0);
  const Phases em = phases(Scheme::exact_modal), ref = phases(Scheme::bdf2);
  EXPECT_GT(em.breaks, 20) << "a stick-slip limit cycle";
  EXPECT_GT(em.stuck, 1000);
  EXPECT_GT(em.vmin, -1e-9) << "no backward motion";
  EXPECT_LE(em.Tmax, Ts * (1.0 + 1e-12)) << "the contact takes at most the static torque";
  EXPECT_EQ(em.breaks, ref.breaks);
  EXPECT_NEAR(static_cast<double>(em.stuck), static_cast<double>(ref.stuck), 0.05 * ref.stuck);
}

TEST(ExactModal, ALandingBitThatTheStringPullsBackStaysAtRest) {
  // A large static torque (a0 3.3: about 4.5 N m against the sliding law's 2.7) makes the bit slip
  // past the top: when it stops, the string pulls it backwards with less than the static torque, so
  // it stays at rest. The torque of the landing step is held as the modified Euler holds it; ramped
  // from the sliding torque, the stopping torque fell beyond the capacity and the bit broke away
  // backwards for a step at every stop (1-step stick and slip phases, a validation case of the
  // loop lost its static friction: issue 33). Against BDF2 at a 40 x finer step (the modified Euler's
  // stuck bit is at rest only to rounding, so its phases are not counted on v == 0).
  struct Phases {
    long breaks = 0, shortest = 1L << 40;
    double vmin = 1e9, ss = 0.0;
  };
  auto phases = [](Scheme s, double dt) {
    Config c = rig_with_stick(BitRockLaw::Kind::polynomial);
    c.law.a[0] = 3.3;
    c.string_friction = 0.0;
    c.sim.scheme = s;
    c.sim.dt = dt;
    c.sim.duration = 20.0;
    c.transient = 5.0;
    const Simulation sim(c);
    Phases ph;
    bool prev = false;
    long run = 0;
    sim.integrator().run(sim.inputs(), [&](const StepState& st) {
      if (st.t < 5.0) return;
      ph.vmin = std::min(ph.vmin, st.bit_speed);
      const bool stuck = st.bit_speed == 0.0;
      if (stuck != prev && run > 0) ph.shortest = std::min(ph.shortest, run), run = 0;
      if (prev && !stuck) ++ph.breaks;
      prev = stuck;
      ++run;
    });
    ph.ss = sim.run(sim.inputs(), false).severity;
    return ph;
  };
  const Phases em = phases(Scheme::exact_modal, 2e-4), ref = phases(Scheme::bdf2, 5e-6);
  EXPECT_GT(ref.breaks, 20) << "a stick-slip limit cycle";
  EXPECT_GT(em.vmin, -1e-9) << "no backward motion";
  EXPECT_GT(em.shortest, 100) << "no stick or slip phase of a few steps";
  EXPECT_EQ(em.breaks, ref.breaks);
  EXPECT_NEAR(em.ss / ref.ss, 1.0, 5e-3);
}

TEST(ExactModal, RefusesDenseDampingAndIsRefusedWhereOnlyModifiedEulerRuns) {
  const Config c = em_field(10, 1.0);
  EXPECT_NO_THROW(Simulation{c});
  ModalROM rom = build_modal_rom(c.string, 4, c.damping);
  const double d01 = 0.3 * std::sqrt(rom.model.D(0, 0) * rom.model.D(1, 1));
  rom.model.D(0, 1) = rom.model.D(1, 0) = d01;  // a damping that couples the modes
  SimOptions o;
  o.scheme = Scheme::exact_modal;
  o.duration = 1.0;
  try {
    Integrator integ(rom.model, c.law, o);
    FAIL() << "a dense damping was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("exact_modal"), std::string::npos) << e.what();
  }
  o.scheme = Scheme::bdf2;  // which runs it
  EXPECT_NO_THROW(Integrator(rom.model, c.law, o));
  json bad = preset_json("thesis-field");
  bad["simulation"]["scheme"] = "exact";
  try {
    parse_config(bad);
    FAIL() << "an unknown scheme was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("exact_modal"), std::string::npos) << e.what();
  }
  json ok = preset_json("thesis-field");
  ok["simulation"]["scheme"] = "exact_modal";
  EXPECT_EQ(parse_config(ok).sim.scheme, Scheme::exact_modal);
  EXPECT_EQ(to_json(parse_config(ok))["simulation"]["scheme"], "exact_modal");
}

TEST(ExactModal, ABatchedRunHasTheSameBitsInEveryLaneAndTheScalarPathsToRounding) {
  // The batched path (ExactSteps: the bit's equation solved by Newton masked across the lanes,
  // Highway's exp/log, FMA, another summation order) against the scalar Integrator: a run has the
  // same bits alone and in every lane position of a full and a partial batch; against the scalar
  // path it differs by rounding, which the Newton tolerance (1e-12 relative) keeps at the level of
  // the solve over these 3 s (measured: bit speed within 3.7e-12 rad/s and torque on bit within
  // 9.3e-6 N.m on the field string, 7.9e-12 rad/s and 3.7e-11 N.m on the rig with its stick
  // phases): bounded here at 1e-9 rad/s and 1e-3 N.m.
  for (const Config& c : {em_field(10, 3.0), [] {
         Config r = rig_with_stick(BitRockLaw::Kind::polynomial_hysteretic);
         r.sim.scheme = Scheme::exact_modal;
         return r;
       }()}) {
    const Simulation sim(c);
    const BatchedIntegrator b(sim.integrator());
    ASSERT_TRUE(b.supports(sim.inputs()));
    const std::size_t w = BatchedIntegrator::width();
    const std::vector<Inputs> in = varied_inputs(sim, w + 3);
    std::vector<StepTrace> alone(in.size());
    for (std::size_t k = 0; k < in.size(); ++k) alone[k] = em_batched(b, {in[k]}).front();
    for (std::size_t pos = 0; pos < in.size(); pos += 3) {
      std::vector<Inputs> batch = in;
      std::swap(batch[0], batch[pos]);
      const std::vector<StepTrace> tr = em_batched(b, batch);
      for (std::size_t k = 0; k < in.size(); ++k) {
        const std::size_t orig = k == 0 ? pos : k == pos ? 0 : k;
        EXPECT_TRUE(tr[k] == alone[orig]) << "run " << orig << " in position " << k;
      }
    }
    for (std::size_t k = 0; k < in.size(); ++k) {
      StepTrace scalar;
      sim.integrator().run(in[k], scalar);
      ASSERT_EQ(scalar.v.size(), alone[k].v.size());
      double dv = 0.0, dT = 0.0;
      for (std::size_t i = 0; i < scalar.v.size(); ++i) {
        dv = std::max(dv, std::fabs(scalar.v[i] - alone[k].v[i]));
        dT = std::max(dT, std::fabs(scalar.T[i] - alone[k].T[i]));
      }
      EXPECT_LT(dv, 1e-9) << "run " << k;
      EXPECT_LT(dT, 1e-3) << "run " << k;
    }
  }
}

TEST(ExactModal, SweepsAndMonteCarloAreBitIdenticalForAnyThreadCountAndChunking) {
  // and agree with the scalar path to the batched path's stated tolerance (SS within 1e-4
  // relative, as for the modified Euler scheme: BatchedIntegrator.AgreesWithTheScalarReference...)
  const Config c = em_field(10, 30.0);
  const Simulation sim(c);
  const std::vector<double> sp = {6, 10, 14, 18, 22, 26};
  const std::vector<double> one = sim.sweep_severity(sp, {}, nullptr, 1, std::nullopt, true);
  EXPECT_EQ(one, sim.sweep_severity(sp, {}, nullptr, 2, std::nullopt, true));
  const std::vector<double> scalar_sweep = sim.sweep_severity(sp, {}, nullptr, 2, std::nullopt, false);
  for (std::size_t k = 0; k < sp.size(); ++k) EXPECT_NEAR(one[k] / scalar_sweep[k], 1.0, 1e-4) << sp[k];
  const MonteCarlo mc(c, GaussianProcess::from_psd(PsdModel(), 0.05, 30.0), 2024, 10.0);
  const std::vector<double> msp = {8.0, 24.0};
  const Eigen::MatrixXd all = mc.severity(msp, 0, 7, nullptr, 1, nullptr, true);
  const Eigen::MatrixXd two = mc.severity(msp, 0, 7, nullptr, 2, nullptr, true);
  const Eigen::MatrixXd scalar = mc.severity(msp, 0, 7, nullptr, 2, nullptr, false);
  const Eigen::MatrixXd a = mc.severity(msp, 0, 2, nullptr, 1), b = mc.severity(msp, 2, 5, nullptr, 2);
  for (int i = 0; i < 7; ++i)
    for (int k = 0; k < 2; ++k) {
      EXPECT_EQ(all(i, k), two(i, k)) << i << "," << k;
      EXPECT_EQ(all(i, k), i < 2 ? a(i, k) : b(i - 2, k)) << i << "," << k;
      EXPECT_NEAR(all(i, k) / scalar(i, k), 1.0, 1e-4) << i << "," << k;
    }
  EXPECT_NE(all(0, 0), all(1, 0));  // distinct realizations
}

TEST(ExactModal, ADampingScanWithADampingPerLaneHasEachRunsOwnBits) {
  // a batch of models that differ in their damping (the kernel's per-lane coefficients) gives each
  // run the bits of a batch of its own (the shared coefficients), and the scalar path's severity to
  // 1e-4 relative (the lightly damped run's stick phases amplify the rounding into single steps:
  // up to 3e-3 rad/s at a damping ratio of 0.02, SS 1.3e-5 relative; the others within 2e-12 rad/s)
  // up to critical damping
  DampingScan scan = em_damping_scan(BitRockLaw::Kind::polynomial_hysteretic, {0.02, 0.1, 0.3, 0.7, 0.95, 1.0});
  const std::vector<const Simulation*>& sims = scan.sims;
  std::vector<Inputs>& in = scan.in;
  const ManyRuns batched = run_many(sims, in, true, 2, true), scalar = run_many(sims, in, true, 1, false);
  for (std::size_t k = 0; k < sims.size(); ++k) {
    ASSERT_TRUE(batched.errors[k].empty()) << batched.errors[k];
    const ManyRuns alone = run_many({sims[k]}, {in[k]}, true, 1, true);
    EXPECT_EQ(batched.reports[k].series.bit_speed, alone.reports[0].series.bit_speed) << k;
    EXPECT_EQ(batched.reports[k].severity, alone.reports[0].severity) << k;
    EXPECT_NEAR(batched.reports[k].severity, scalar.reports[k].severity, 1e-4 * scalar.reports[k].severity) << k;
  }
  EXPECT_NE(batched.reports.front().severity, batched.reports.back().severity);
}

TEST(ExactModal, ADivergingRunInABatchIsReportedAndLeavesTheOthersAlone) {
  // the batched kernel drops a lane whose bit speed or torque is no longer finite; the runs beside
  // it keep the bits they have in a batch of their own
  DampingScan scan = em_damping_scan(BitRockLaw::Kind::polynomial, {0.02, 0.1, 0.3, 0.7, 1.0});
  const std::vector<const Simulation*>& sims = scan.sims;
  std::vector<Inputs>& in = scan.in;
  in[2].eta = Signal::constant(-5.0);  // the law reversed, four times over: the bit runs away
  for (bool batched : {true, false}) {
    const ManyRuns r = run_many(sims, in, true, 0, batched);
    EXPECT_NE(r.errors[2].find("simulation diverged at t = "), std::string::npos) << r.errors[2];
    for (std::size_t k : {0u, 1u, 3u, 4u}) {
      ASSERT_TRUE(r.errors[k].empty()) << r.errors[k];
      const ManyRuns alone = run_many({sims[k]}, {in[k]}, true, 0, batched);
      EXPECT_EQ(r.reports[k].series.bit_speed, alone.reports[0].series.bit_speed) << k;
    }
  }
}

TEST(ExactModal, AMotorTopDriveAndTheRigJackStepAsInModifiedEulerAtATenTimesLargerStep) {
  // The drives with inertia and the jack are stepped as run_euler steps them, explicit in the
  // string's top torque (the jack: in the bit speed at the step's start), the modes exactly
  // (integrator.hpp, run_exact). On the rig (one mode) against the modified Euler at 1e-5 s, 20 s
  // runs from rest: a stiff motor (c_m 20 N m s/rad) commanded at 9 rad/s stick-slips (SS 1.029,
  // stick fraction 0.128 at 1e-5 s; exact_modal at 1e-3 s: 1.028, 0.126); a soft one (c_m 0.25) at
  // 16 rad/s droops to a steady 6.545 rad/s; the jack (180 N/rad, 0.1 s) under the ideal drive
  // (SS 1.482 and 1.480).
  auto rig = [](double dt, Scheme scheme) {
    Config c = preset("thesis-rig");
    c.sim.duration = 20.0;
    c.transient = 10.0;
    c.sim.dt = dt;
    c.sim.scheme = scheme;
    return c;
  };
  auto motor = [](Config c, double command, double slope) {
    c.top_speed = command;
    c.top_drive.kind = TopDrive::Kind::motor;
    c.top_drive.slope = slope;
    c.top_drive.inertia = 0.0186;
    c.top_drive.max_torque = 8.0;
    return c;
  };
  auto jack = [](Config c) {
    c.axial.kind = Axial::Kind::jack;
    c.axial.gain = 180.0;
    c.axial.relaxation = 0.1;
    return c;
  };
  auto report = [](const Config& c) {
    const Simulation sim(c);
    return sim.run(sim.inputs());
  };
  for (int k = 0; k < 3; ++k) {
    auto make = [&](double dt, Scheme s) {
      const Config c = rig(dt, s);
      return k == 0 ? motor(c, 9.0, 20.0) : k == 1 ? motor(c, 16.0, 0.25) : jack(c);
    };
    const RunReport ref = report(make(1e-5, Scheme::modified_euler));
    const RunReport em = report(make(1e-3, Scheme::exact_modal));
    if (k != 1) {
      EXPECT_GT(ref.severity, 1.0) << "case " << k;  // a stick-slip cycle
      EXPECT_GT(ref.stick_fraction, 0.1) << "case " << k;
    }
    EXPECT_NEAR(em.severity, ref.severity, 0.01 * std::max(ref.severity, 0.1)) << "case " << k;
    EXPECT_NEAR(em.stick_fraction, ref.stick_fraction, 0.005) << "case " << k;
    EXPECT_NEAR(em.mean_top_speed, ref.mean_top_speed, 1e-3 * ref.mean_top_speed) << "case " << k;
    if (k < 2) EXPECT_LT(ref.mean_top_speed, make(1e-5, Scheme::modified_euler).top_speed - 0.05) << "droops";
    if (k == 2) EXPECT_TRUE(em.final_state.wob > 0.0 && std::isfinite(em.final_state.wob));  // the jack's state
  }
  // the BDF2 scheme still refuses both, naming the field
  EXPECT_NE(error_of([&] { Simulation s(motor(rig(1e-4, Scheme::bdf2), 9.0, 20.0)); }).find("top_drive.type"),
            std::string::npos);
  EXPECT_NE(error_of([&] { Simulation s(jack(rig(1e-4, Scheme::bdf2))); }).find("axial.type"), std::string::npos);
}
