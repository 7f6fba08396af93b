// The batched integrator (issue 16): a run gives the same bits alone and in every lane of a batch,
// on AVX2 (4 lanes) and AVX-512 (8 lanes); it agrees with the scalar reference Integrator bit for
// bit where no exp/log is evaluated and one mode is retained, and to the stated tolerance
// otherwise; the studies (sweeps, Monte Carlo, horizon predictions) use it and fall back to
// Integrator outside its scope.
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "drill/batched_integrator.hpp"
#include "drill/horizons.hpp"
#include "drill/montecarlo.hpp"
#include "drill/presets.hpp"
#include "drill/process.hpp"
#include "drill/simulation.hpp"
#include "rig_with_stick.hpp"
#include "varied_runs.hpp"

using namespace drill;

namespace {

/// Every step's bit speed, torque on bit, top speed and WOB (the motor's and the jack's states).
struct DriveTrace {
  std::vector<double> v, T, top, wob;
  void operator()(const StepState& s) {
    v.push_back(s.bit_speed);
    T.push_back(s.torque_on_bit);
    top.push_back(s.top_speed);
    wob.push_back(s.wob);
  }
  bool operator==(const DriveTrace& o) const { return v == o.v && T == o.T && top == o.top && wob == o.wob; }
};

/// The rig with stick (rig_with_stick.hpp) turned by the thesis's open-loop motor (section 5.3.2:
/// a speed droop, a torque limit of 8 N m at which the top stalls) and loaded by the jack.
Config rig_with_motor(BitRockLaw::Kind kind, bool motor, bool jack) {
  Config c = rig_with_stick(kind);
  if (motor) {
    c.top_drive.kind = TopDrive::Kind::motor;
    c.top_drive.inertia = 0.02;
    c.top_drive.slope = 0.3;
    c.top_drive.max_torque = 8.0;
  }
  if (jack) {
    c.axial.kind = Axial::Kind::jack;
    c.axial.gain = 200.0;
    c.axial.relaxation = 0.1;
  }
  return c;
}

/// Eleven horizon restarts from the states of a long run of `sim` (every 17 * stride steps from
/// step 10 * stride), on a grid of stride engine steps; the WOB state too (the jack's).
std::vector<HorizonStart> restarts_of_a_long_run(const Simulation& sim, int stride, std::size_t* grid = nullptr) {
  std::vector<double> v, a, T, top, wob;
  sim.integrator().run(sim.inputs(), [&](const StepState& s) {
    v.push_back(s.bit_speed);
    a.push_back(s.bit_accel);
    T.push_back(s.torque_on_bit);
    top.push_back(s.top_speed);
    wob.push_back(s.wob);
  });
  if (grid) *grid = v.size() / stride;
  std::vector<HorizonStart> starts;
  for (long k = 0; k < 11; ++k) {
    const long i = (10 + 17 * k) * stride;
    HorizonStart h;
    h.index = i / stride;
    h.bit_speed = v[i];
    h.bit_accel = a[i];
    h.torque = T[i];
    h.top_speed = top[i];
    h.wob = wob[i];
    h.y_bit_speed = v[i];
    h.y_torque = T[i];
    h.y_top_speed = top[i];
    starts.push_back(h);
  }
  return starts;
}

Config batch_field(double duration) {
  Config c = preset("thesis-field");
  c.modes = 10;
  c.sim.duration = duration;
  c.transient = duration / 3.0;
  return c;
}

std::vector<StepTrace> run_batched(const BatchedIntegrator& b, const std::vector<Inputs>& in) {
  std::vector<StepTrace> tr(in.size());
  const std::vector<const ModelState*> start(in.size(), nullptr);
  b.run(in.data(), start.data(), in.size(), tr.data());
  return tr;
}

void expect_lane_independent(const Config& c) {
  const Simulation sim(c);
  const BatchedIntegrator b(sim.integrator());
  const std::size_t w = BatchedIntegrator::width();
  std::vector<Inputs> in = varied_inputs(sim, w + 3);  // a full batch and a partial one
  const StepTrace alone = run_batched(b, {in[0]}).front();
  ASSERT_EQ(alone.v.size(), static_cast<std::size_t>(c.sim.steps() + 1));
  for (std::size_t pos = 0; pos < in.size(); ++pos) {
    std::vector<Inputs> batch = in;
    std::swap(batch[0], batch[pos]);  // run 0 in lane pos % w of batch pos / w
    const std::vector<StepTrace> tr = run_batched(b, batch);
    EXPECT_TRUE(tr[pos] == alone) << "lane position " << pos;
  }
}

}  // namespace

TEST(BatchedIntegrator, ARunHasTheSameBitsAloneAndInEveryLane) {
  expect_lane_independent(batch_field(3.0));  // hysteretic law (Eqs. 3.2-3.3), eta of Eq. (4.1)
  expect_lane_independent(rig_with_stick(BitRockLaw::Kind::polynomial_hysteretic));  // Eq. (5.3), stick
  Config tw = batch_field(3.0);
  tw.law = thesis_tucker_wang();  // Eq. (3.1)
  expect_lane_independent(tw);
  Config em = batch_field(3.0);
  em.sim.scheme = Scheme::exact_modal;  // exact_modal.hpp: ExactSteps, the bit solve masked across the lanes
  expect_lane_independent(em);
}

TEST(BatchedIntegrator, AVX2AndAVX512GiveTheSameBits) {
  const std::int64_t have = hwy::SupportedTargets();
  if (!(have & HWY_AVX2) || !(have & HWY_AVX3)) GTEST_SKIP() << "this host lacks AVX2 or AVX-512";
  Config em = batch_field(3.0);
  em.sim.scheme = Scheme::exact_modal;  // ExactSteps: FMA on both targets
  for (const Config& c : {batch_field(3.0), em}) {
    const Simulation sim(c);
    const BatchedIntegrator b(sim.integrator());
    const std::vector<Inputs> in = varied_inputs(sim, 8);
    ASSERT_EQ(BatchedIntegrator::width(), 8u);
    const std::vector<StepTrace> wide = run_batched(b, in);
    hwy::SetSupportedTargetsForTest(HWY_AVX2 | HWY_SSE4 | HWY_SSSE3 | HWY_EMU128);
    hwy::GetChosenTarget().Update(hwy::SupportedTargets());
    const std::size_t narrow_width = BatchedIntegrator::width();
    const std::vector<StepTrace> narrow = run_batched(b, in);
    hwy::SetSupportedTargetsForTest(0);
    hwy::GetChosenTarget().Update(hwy::SupportedTargets());
    EXPECT_EQ(narrow_width, 4u);
    EXPECT_EQ(BatchedIntegrator::width(), 8u);
    for (std::size_t k = 0; k < in.size(); ++k) EXPECT_TRUE(wide[k] == narrow[k]) << to_string(c.sim.scheme) << " run " << k;
  }
}

TEST(BatchedIntegrator, ReproducesTheScalarBitsWithoutExpLogOnOneMode) {
  // Eq. (5.1) has no transcendental function and the rig retains one mode (no dot product to
  // reorder): every operation is the scalar path's, in its order, so the bits are the same,
  // through the stick condition and the string friction.
  const Simulation sim(rig_with_stick(BitRockLaw::Kind::polynomial));
  const BatchedIntegrator b(sim.integrator());
  const std::vector<Inputs> in = varied_inputs(sim, 5);
  const std::vector<StepTrace> tr = run_batched(b, in);
  for (std::size_t k = 0; k < in.size(); ++k) {
    StepTrace ref;
    sim.integrator().run(in[k], ref);
    EXPECT_TRUE(tr[k] == ref) << "run " << k;
  }
}

TEST(BatchedIntegrator, AgreesWithTheScalarReferenceToTheStatedTolerance) {
  // Highway's exp and log are within 1 and 4 ulp of libm's and the modal sums are added in another
  // order: differences of rounding size, which the Newton stopping test (1e-9 relative) and the
  // explicit scheme's chattering stick phases carry into single steps (up to a few 1e-2 rad/s
  // there) but not into the metrics: SS within 1e-4 relative (2.8e-5 measured at 10 modes over
  // 30 s) and the stick fraction within 1e-3.
  const Config c = batch_field(30.0);
  const Simulation sim(c);
  const std::vector<double> sp = {6, 8, 10, 12, 14, 16, 18, 20, 22, 26};
  const std::vector<double> batched = sim.sweep_severity(sp, {}, nullptr, 0, std::nullopt, true);
  const std::vector<double> scalar = sim.sweep_severity(sp, {}, nullptr, 0, std::nullopt, false);
  for (std::size_t k = 0; k < sp.size(); ++k) EXPECT_NEAR(batched[k] / scalar[k], 1.0, 1e-4) << sp[k];
  const BatchedIntegrator b(sim.integrator());
  const std::vector<Inputs> in = varied_inputs(sim, 6);
  std::vector<PhaseObserver> ph;
  for (const Inputs& x : in) ph.emplace_back(c.transient, 0.05 * x.top_speed.value);
  const std::vector<const ModelState*> start(in.size(), nullptr);
  b.run(in.data(), start.data(), in.size(), ph.data());
  for (std::size_t k = 0; k < in.size(); ++k) {
    PhaseObserver ref(c.transient, 0.05 * in[k].top_speed.value);
    sim.integrator().run(in[k], ref);
    EXPECT_NEAR(ph[k].stick_fraction(), ref.stick_fraction(), 1e-3) << "run " << k;
  }
}

TEST(BatchedIntegrator, StudiesFallBackToTheScalarPathOutsideItsScope) {
  Config c = batch_field(10.0);
  c.top_drive.kind = TopDrive::Kind::motor;  // the motor on the exact modal scheme: ExactSteps has no motor
  c.top_drive.inertia = 2000.0;
  c.top_drive.slope = 1e5;
  c.sim.scheme = Scheme::exact_modal;
  const Simulation sim(c);
  EXPECT_FALSE(BatchedIntegrator(sim.integrator()).supports(sim.inputs()));
  const std::vector<double> sp = {8, 20};
  EXPECT_EQ(sim.sweep_severity(sp, {}, nullptr, 0, std::nullopt, true),
            sim.sweep_severity(sp, {}, nullptr, 0, std::nullopt, false));
  Config d = batch_field(10.0);
  d.sim.scheme = Scheme::bdf2;
  EXPECT_FALSE(BatchedIntegrator(Simulation(d).integrator()).supports(Simulation(d).inputs()));
}

TEST(BatchedIntegrator, MonteCarloSamplesAgreeWithTheScalarPath) {
  const Config c = batch_field(20.0);
  const MonteCarlo mc(c, GaussianProcess::from_psd(PsdModel(), 0.05, 20.0), 5, 0.0);
  const std::vector<double> sp = {9.0, 24.0};
  const Eigen::MatrixXd b = mc.severity(sp, 3, 5, nullptr, 2, nullptr, true),
                        s = mc.severity(sp, 3, 5, nullptr, 1, nullptr, false);
  for (int i = 0; i < 5; ++i)
    for (int k = 0; k < 2; ++k) EXPECT_NEAR(b(i, k) / s(i, k), 1.0, 1e-4) << i << "," << k;
  // samples 3 .. 7 are the same bits in a batch of their own as in a batch starting at 0
  const Eigen::MatrixXd all = mc.severity(sp, 0, 8, nullptr, 1, nullptr, true);
  for (int i = 0; i < 5; ++i)
    for (int k = 0; k < 2; ++k) EXPECT_EQ(b(i, k), all(3 + i, k));
}

TEST(BatchedIntegrator, HorizonPredictionsAgreeWithTheScalarPath) {
  // drillpy loop's horizons (horizons.hpp) on the rig: sampled top speed, WOB and eta, restarts
  // from states of a long run; one mode and Eq. (5.3), whose tanh is the only exp: the batched
  // and scalar predictions agree to rounding (1e-9 relative), and for any thread count.
  Config c = preset("thesis-rig");
  c.damping.ratios = {0.05};
  c.sim.duration = 3.0;
  c.transient = 1.0;
  const Simulation sim(c);
  const int stride = 10, samples = 100;
  std::size_t grid = 0;
  const std::vector<HorizonStart> starts = restarts_of_a_long_run(sim, stride, &grid);
  HorizonInputs hin;
  hin.dt = stride * c.sim.dt;
  hin.samples = samples;
  for (std::size_t j = 0; j < grid; ++j) {
    hin.top_speed.push_back(c.top_speed * (1.0 + 0.1 * std::sin(0.01 * j)));
    hin.wob.push_back(c.wob * (1.0 + 0.05 * std::cos(0.02 * j)));
  }
  hin.eta = Eigen::MatrixXd::NullaryExpr(11, samples + 1, [](Eigen::Index r, Eigen::Index j) {
    return 0.2 * std::sin(0.3 * r + 0.05 * j);
  });
  const HorizonResult b = predict_horizons(sim, starts, hin, nullptr, 2, true);
  const HorizonResult b1 = predict_horizons(sim, starts, hin, nullptr, 1, true);
  const HorizonResult s = predict_horizons(sim, starts, hin, nullptr, 1, false);
  EXPECT_EQ(b.bit_speed, b1.bit_speed);
  EXPECT_EQ(b.torque, b1.torque);
  const double vs = s.bit_speed.cwiseAbs().maxCoeff(), ts = s.torque.cwiseAbs().maxCoeff();
  EXPECT_LE((b.bit_speed - s.bit_speed).cwiseAbs().maxCoeff(), 1e-9 * vs);
  EXPECT_LE((b.torque - s.torque).cwiseAbs().maxCoeff(), 1e-9 * ts);
  EXPECT_LE((b.top_speed - s.top_speed).cwiseAbs().maxCoeff(), 1e-12 * vs);
  EXPECT_GT(s.bit_speed.maxCoeff() - s.bit_speed.minCoeff(), 1.0);  // the horizons see stick-slip
}

TEST(BatchedIntegrator, StepsTheMotorAndTheJackAsTheScalarPath) {
  // The open-loop motor (drives/motor.hpp) and the rig's jack (axial.hpp) are states of the lanes:
  // with one mode and Eq. (5.1) (no exp or log) the motor's runs are the scalar path's bits, top
  // speed included; the jack's WOB enters the law as W / W_ref and its static torque as the law's
  // at W_ref times that scale (the scalar path: at W), so they agree to rounding. A run's bits do
  // not depend on its lane or on the drives of the runs beside it.
  for (const bool jack : {false, true}) {
    const Simulation sim(rig_with_motor(BitRockLaw::Kind::polynomial, true, jack));
    const BatchedIntegrator b(sim.integrator());
    ASSERT_TRUE(b.supports(sim.inputs()));
    const std::vector<Inputs> in = varied_inputs(sim, 5);
    std::vector<DriveTrace> tr(in.size());
    const std::vector<const ModelState*> start(in.size(), nullptr);
    b.run(in.data(), start.data(), in.size(), tr.data());
    for (std::size_t k = 0; k < in.size(); ++k) {
      DriveTrace ref;
      sim.integrator().run(in[k], ref);
      if (!jack) {
        EXPECT_TRUE(tr[k] == ref) << "run " << k;
        continue;
      }
      ASSERT_EQ(tr[k].v.size(), ref.v.size());
      const double vs = Eigen::Map<const Eigen::VectorXd>(ref.v.data(), ref.v.size()).cwiseAbs().maxCoeff();
      const double ws = Eigen::Map<const Eigen::VectorXd>(ref.wob.data(), ref.wob.size()).cwiseAbs().maxCoeff();
      for (std::size_t i = 0; i < ref.v.size(); ++i) {
        ASSERT_NEAR(tr[k].v[i], ref.v[i], 1e-6 * vs) << "run " << k << " step " << i;
        ASSERT_NEAR(tr[k].wob[i], ref.wob[i], 1e-9 * ws) << "run " << k << " step " << i;
        ASSERT_NEAR(tr[k].top[i], ref.top[i], 1e-6 * vs) << "run " << k << " step " << i;
      }
    }
    // the states move: the motor droops under the torque and the jack's WOB follows the bit's lag
    double top_swing = 0.0, wob_swing = 0.0;
    for (const DriveTrace& t : tr) {
      top_swing = std::max(top_swing, *std::max_element(t.top.begin(), t.top.end()) - *std::min_element(t.top.begin(), t.top.end()));
      wob_swing = std::max(wob_swing, *std::max_element(t.wob.begin(), t.wob.end()) - *std::min_element(t.wob.begin(), t.wob.end()));
    }
    EXPECT_GT(top_swing, 0.1 * sim.config().top_speed);
    if (jack) EXPECT_GT(wob_swing, 1.0);
  }
  // lanes of every kind side by side: ideal, motor, jack, both (Eq. 5.3: its tanh, Highway's exp)
  std::vector<Inputs> in;
  std::vector<Simulation> sims;
  for (int k = 0; k < 4; ++k) sims.emplace_back(rig_with_motor(BitRockLaw::Kind::polynomial_hysteretic, k & 1, k & 2));
  for (std::size_t r = 0; r < 2 * BatchedIntegrator::width() + 1; ++r) in.push_back(sims[r % 4].inputs());
  const BatchedIntegrator b(sims[0].integrator());
  std::vector<DriveTrace> mixed(in.size());
  const std::vector<const ModelState*> start(in.size(), nullptr);
  b.run(in.data(), start.data(), in.size(), mixed.data());
  for (std::size_t r = 0; r < in.size(); ++r) {
    DriveTrace alone;
    b.run(&in[r], start.data(), 1, &alone);
    EXPECT_TRUE(mixed[r] == alone) << "run " << r;
  }
}

TEST(BatchedIntegrator, HorizonsWithTheMotorRunOnTheBatchedPath) {
  // the loop's motor candidate: horizons restarted with the top speed a state agree with the
  // scalar path's to rounding, for any thread count
  Config c = rig_with_motor(BitRockLaw::Kind::polynomial_hysteretic, true, true);
  c.sim.duration = 3.0;
  const Simulation sim(c);
  const int stride = 10;
  const std::vector<HorizonStart> starts = restarts_of_a_long_run(sim, stride);
  HorizonInputs hin;
  hin.dt = stride * c.sim.dt;
  hin.samples = 100;
  const HorizonResult b = predict_horizons(sim, starts, hin, nullptr, 2, true);
  const HorizonResult b1 = predict_horizons(sim, starts, hin, nullptr, 1, true);
  const HorizonResult s = predict_horizons(sim, starts, hin, nullptr, 1, false);
  EXPECT_EQ(b.bit_speed, b1.bit_speed);
  EXPECT_EQ(b.top_speed, b1.top_speed);
  const double vs = s.bit_speed.cwiseAbs().maxCoeff();
  EXPECT_LE((b.bit_speed - s.bit_speed).cwiseAbs().maxCoeff(), 1e-9 * vs);
  EXPECT_LE((b.top_speed - s.top_speed).cwiseAbs().maxCoeff(), 1e-9 * vs);
  EXPECT_GT(s.top_speed.maxCoeff() - s.top_speed.minCoeff(), 0.1 * c.top_speed);  // the motor droops and recovers
}
