// SS under structural uncertainty in the time domain (the thesis's future work, item 1): random
// SM_CB2 realizations in the integrator, the eta hook, thread invariance.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "drill/presets.hpp"
#include "drill/structural_severity.hpp"

using namespace drill;

namespace {

Config short_ch6() {
  Config c = preset("thesis-ch6");
  c.cb_modes = {6, 3};
  c.sim.dt = 1e-3;
  c.sim.duration = 30.0;
  c.transient = 15.0;
  return c;
}

}  // namespace

TEST(StructuralSeverity, ThreadInvariantAndMeanStructureMatchesADirectRun) {
  const Config c = short_ch6();
  const StochasticModel sm(c, StochasticKind::cb2, std::vector<Dispersions>(2, Dispersions::Constant(0.1)));
  SeverityStudyOptions o;
  o.speeds = {8.0, 20.0};
  o.samples = 4;
  o.seed = 3;
  o.threads = 1;
  const Eigen::MatrixXd a = severity_samples(sm, o);
  o.threads = 2;
  const Eigen::MatrixXd b = severity_samples(sm, o);
  ASSERT_EQ(a.rows(), 4);
  EXPECT_EQ(a, b);
  EXPECT_GT((a.col(0).array() - a(0, 0)).abs().maxCoeff(), 1e-6) << "samples differ";

  // Sample 2 is the integrator run on realization 2 of the random matrices.
  const Integrator integ(sm.sample(3, 2), c.law, c.sim);
  Inputs in;
  in.top_speed = Signal::constant(20.0);
  in.wob = Signal::constant(c.wob);
  SeverityObserver sev(c.transient);
  integ.run(in, sev);
  EXPECT_EQ(a(2, 1), sev.severity());

  o.structural = false;
  const Eigen::MatrixXd m = severity_samples(sm, o);
  const Integrator mean_integ(sm.mean(), c.law, c.sim);
  SeverityObserver sev_mean(c.transient);
  mean_integ.run(in, sev_mean);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(m(i, 1), sev_mean.severity());
  // Low speed: stick-slip (SS > 0.5, Eq. 3.4) for the mean string.
  EXPECT_GT(m(0, 0), 0.5);
}

TEST(StructuralSeverity, EtaHookFeedsEachSampleItsOwnSeries) {
  const Config c = short_ch6();
  const StochasticModel sm(c, StochasticKind::cb2, std::vector<Dispersions>(2, Dispersions::Zero()));
  SeverityStudyOptions o;
  o.speeds = {20.0};
  o.samples = 3;
  o.structural = false;
  const EtaProvider eta = [](std::size_t i) {
    std::vector<double> s(400);
    for (std::size_t k = 0; k < s.size(); ++k) s[k] = 0.3 * std::sin(0.37 * k + i);  // every 0.1 s
    return Signal::sampled(s, 0.0, 0.1);
  };
  o.threads = 1;
  const Eigen::MatrixXd with_eta = severity_samples(sm, o, eta);
  const Eigen::MatrixXd without = severity_samples(sm, o);
  EXPECT_EQ(without(0, 0), without(2, 0));
  EXPECT_GT(std::fabs(with_eta(0, 0) - without(0, 0)), 1e-4);
  EXPECT_NE(with_eta(0, 0), with_eta(1, 0));
  const Integrator integ(sm.mean(), c.law, c.sim);
  Inputs in;
  in.top_speed = Signal::constant(20.0);
  in.wob = Signal::constant(c.wob);
  in.eta = eta(1);
  SeverityObserver sev(c.transient);
  integ.run(in, sev);
  EXPECT_EQ(with_eta(1, 0), sev.severity());
}

TEST(StructuralSeverity, PsdEtaIsChapterFourEtaAndIndependentOfTheMatrices) {
  const Config c = short_ch6();
  const StochasticModel sm(c, StochasticKind::cb2, std::vector<Dispersions>(2, Dispersions::Constant(0.1)));
  const GaussianProcess thesis = GaussianProcess::from_psd(PsdModel{}, 0.05, c.sim.duration);
  // Sample i gets the eta of sample i of the chapter-4 Monte Carlo with the same seed.
  const MonteCarlo mc(c, thesis, 5);
  EXPECT_EQ(psd_eta(thesis, 5)(3).samples, mc.eta(3).samples);
  SeverityStudyOptions o;
  o.speeds = {20.0};
  o.samples = 3;
  o.seed = 5;
  const Eigen::MatrixXd structure = severity_samples(sm, o);
  // A zero PSD leaves every sample's structural realization and SS unchanged ...
  const GaussianProcess zero(std::vector<double>(thesis.psd().size(), 0.0), 0.05, c.sim.duration);
  EXPECT_EQ(severity_samples(sm, o, psd_eta(zero, 5)), structure);
  // ... and the thesis PSD changes them.
  const Eigen::MatrixXd both = severity_samples(sm, o, psd_eta(thesis, 5));
  EXPECT_GT((both - structure).cwiseAbs().maxCoeff(), 1e-4);
}

TEST(StructuralSeverity, RefusesBadInput) {
  const Config c = short_ch6();
  const StochasticModel sm(c, StochasticKind::cb2, std::vector<Dispersions>(2, Dispersions::Zero()));
  SeverityStudyOptions o;
  o.samples = 1;
  EXPECT_THROW(severity_samples(sm, o), std::invalid_argument);  // no speeds
  o.speeds = {10.0, -1.0};
  EXPECT_THROW(severity_samples(sm, o), std::invalid_argument);
  o.speeds = {10.0};
  o.samples = 0;
  EXPECT_THROW(severity_samples(sm, o), std::invalid_argument);
}

TEST(StructuralSeverity, ChunksOfSamplesStackToTheWholeRun) {
  const Config c = short_ch6();
  const StochasticModel sm(c, StochasticKind::cb2, std::vector<Dispersions>(2, Dispersions::Constant(0.1)));
  const EtaProvider psd = psd_eta(GaussianProcess::from_psd(PsdModel{}, 0.05, c.sim.duration), 6);
  for (const EtaProvider& eta : {EtaProvider(), psd}) {
    SeverityStudyOptions o;
    o.speeds = {8.0, 20.0};
    o.seed = 6;
    o.samples = 7;
    const Eigen::MatrixXd whole = severity_samples(sm, o, eta);
    o.samples = 3;
    const Eigen::MatrixXd head = severity_samples(sm, o, eta);
    o.first_sample = 3;
    o.samples = 4;
    const Eigen::MatrixXd tail = severity_samples(sm, o, eta);
    Eigen::MatrixXd stacked(7, 2);
    stacked << head, tail;
    EXPECT_EQ(stacked, whole) << (eta ? "structure + PSD eta" : "structure");
  }
}

namespace {

TopDrive structural_controlled(Controller::Kind kind, double ratio) {
  TopDrive t;
  t.kind = TopDrive::Kind::controlled;
  t.inertia = 2000.0;  // [kg m^2] an assumed field top drive, as in test_controller.cpp
  t.controller.kind = kind;
  t.controller.bandwidth_ratio = ratio;
  return t;
}

}  // namespace

TEST(StructuralSeverity, ControlledDriveRunsOnEveryRandomStringTunedOnTheNominalOne) {
  // The configuration's controlled top drive on SM_CB2 samples (issue 15): the stiff limit gives the
  // ideal drive's SS sample by sample, and the gains are those of the mean model (tuned once). On these
  // 30 s runs bandwidth_ratio 100 still differs by up to 1.4 % (sample 2 at 8 rad/s): 1000 is the limit.
  const Config ideal = short_ch6();
  Config stiff = ideal;
  stiff.top_drive = structural_controlled(Controller::Kind::stiff, 1000.0);
  const std::vector<Dispersions> delta(2, Dispersions::Constant(0.1));
  SeverityStudyOptions o;
  o.speeds = {8.0, 20.0};
  o.samples = 3;
  o.seed = 3;
  o.threads = 1;
  const Eigen::MatrixXd ref = severity_samples(StochasticModel(ideal, StochasticKind::cb2, delta), o);
  const StochasticModel sm(stiff, StochasticKind::cb2, delta);
  const Eigen::MatrixXd s = severity_samples(sm, o);
  ASSERT_EQ(s.rows(), 3);
  EXPECT_GT(ref.col(0).minCoeff(), 0.5) << "8 rad/s is in stick-slip for every sample";
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 2; ++k) {
      std::printf("sample %d speed %g: ideal SS %.5f, stiff SS %.5f\n", i, o.speeds[k], ref(i, k), s(i, k));
      EXPECT_LE(std::fabs(s(i, k) - ref(i, k)), 0.01 * std::max(ref(i, k), 1.0)) << i << " " << k;
    }
  o.threads = 2;
  EXPECT_EQ(severity_samples(sm, o), s) << "thread count";

  // Sample 1 is the integrator run on realization 1 with the drive tuned on the mean model's w_1 ...
  TopDrive td = stiff.top_drive;
  td.tune_controller(top_impedance(stiff.string), first_natural_frequency(sm.mean()));
  EXPECT_EQ(study_top_drive(sm).controller.kp, td.controller.kp);
  const ReducedModel r1 = sm.sample(3, 1);
  Inputs in;
  in.top_speed = Signal::constant(8.0);
  in.wob = Signal::constant(stiff.wob);
  in.top_drive = td;
  SeverityObserver sev(stiff.transient);
  Integrator(r1, stiff.law, stiff.sim).run(in, sev);
  EXPECT_EQ(s(1, 0), sev.severity());
  // ... not on the realization's own (which differs: the gains are not retuned per sample).
  EXPECT_GT(std::fabs(first_natural_frequency(r1) / first_natural_frequency(sm.mean()) - 1.0), 1e-4);
  // w_1 of the mean Craig-Bampton model is the one Simulation tunes on (the modal model's) to the CB truncation.
  EXPECT_NEAR(first_natural_frequency(sm.mean()), build_modal_rom(stiff.string, 1, stiff.damping).omega(0),
              1e-3 * first_natural_frequency(sm.mean()));

  // The drive is really in the loop: z_torque takes the random strings out of stick-slip at 8 rad/s.
  Config z = ideal;
  z.top_drive = structural_controlled(Controller::Kind::z_torque, 20.0);
  o.speeds = {8.0};
  o.threads = 1;
  const Eigen::MatrixXd zs = severity_samples(StochasticModel(z, StochasticKind::cb2, delta), o);
  for (int i = 0; i < 3; ++i) {
    std::printf("sample %d speed 8: ideal SS %.5f, z_torque SS %.5f\n", i, ref(i, 0), zs(i, 0));
    EXPECT_LT(zs(i, 0), 0.5 * ref(i, 0)) << i;
  }
}
