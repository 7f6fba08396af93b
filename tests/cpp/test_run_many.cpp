// Runs of several simulations (run_many.hpp, issue 16): a damping scan steps in SIMD lockstep with
// one damping per lane; a run's bits do not depend on the runs beside it; the batched scan agrees
// with the scalar reference (bit for bit where no exp/log is evaluated on one mode); a diverging
// run is reported and leaves the others alone; models that differ in more than their damping run
// one by one.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "drill/presets.hpp"
#include "drill/run_many.hpp"
#include "rig_with_stick.hpp"

using namespace drill;

namespace {

const std::vector<double> kRatios = {0.02, 0.05, 0.1, 0.2, 0.3, 0.45, 0.7, 1.0};

/// The rig with stick (rig_with_stick.hpp) at one modal damping ratio.
Config rig(BitRockLaw::Kind kind, double ratio) {
  Config c = rig_with_stick(kind);
  c.damping.kind = DampingSpec::Kind::modal;
  c.damping.ratios = {ratio};
  return c;
}

struct Scan {
  std::vector<std::unique_ptr<Simulation>> owned;
  std::vector<const Simulation*> sims;
  std::vector<Inputs> in;
};

Scan scan(BitRockLaw::Kind kind, const std::vector<double>& ratios) {
  Scan s;
  for (double z : ratios) {
    s.owned.push_back(std::make_unique<Simulation>(rig(kind, z)));
    s.sims.push_back(s.owned.back().get());
    Inputs x = s.sims.back()->inputs();
    const double om = x.top_speed.value;  // a top speed that varies, as a measured drive's
    x.top_speed = Signal::sampled({om, 1.3 * om, 0.8 * om, om, 1.1 * om}, 0.0, 1.0);
    s.in.push_back(x);
  }
  return s;
}

bool same_bits(const RunReport& a, const RunReport& b) {
  return a.series.t == b.series.t && a.series.bit_speed == b.series.bit_speed &&
         a.series.torque_on_bit == b.series.torque_on_bit && a.series.top_speed == b.series.top_speed &&
         a.severity == b.severity && a.stick_fraction == b.stick_fraction;
}

}  // namespace

TEST(RunMany, ADampingScanInLockstepHasTheScalarBitsWithoutExpLogOnOneMode) {
  const Scan s = scan(BitRockLaw::Kind::polynomial, kRatios);
  ASSERT_TRUE(BatchedIntegrator(s.sims[0]->integrator()).shares_model(s.sims[3]->integrator()));
  const ManyRuns batched = run_many(s.sims, s.in, true, 0, true);
  const ManyRuns scalar = run_many(s.sims, s.in, true, 0, false);
  for (std::size_t k = 0; k < kRatios.size(); ++k) {
    ASSERT_TRUE(batched.errors[k].empty()) << batched.errors[k];
    EXPECT_TRUE(same_bits(batched.reports[k], scalar.reports[k])) << "damping ratio " << kRatios[k];
    EXPECT_TRUE(batched.reports[k].series.bit_angle.empty());  // not formed in lockstep
    EXPECT_EQ(scalar.reports[k].series.bit_angle.size(), scalar.reports[k].series.t.size());
  }
  // the damping acts per lane: the scan's severities are not all the same
  EXPECT_GT(std::fabs(batched.reports.front().severity - batched.reports.back().severity), 0.05);
}

TEST(RunMany, ARunHasTheSameBitsAloneAndInEveryLanePosition) {
  // Eq. (5.3): its tanh goes through Highway's exp, so this is the lockstep's own determinism
  const Scan s = scan(BitRockLaw::Kind::polynomial_hysteretic, kRatios);
  for (std::size_t k = 0; k < kRatios.size(); ++k) {
    const ManyRuns alone = run_many({s.sims[k]}, {s.in[k]});
    const std::size_t pos = kRatios.size() - 1 - k;  // run k in lane pos % width of batch pos / width
    std::vector<const Simulation*> sims = s.sims;
    std::vector<Inputs> in = s.in;
    std::swap(sims[k], sims[pos]);
    std::swap(in[k], in[pos]);
    const ManyRuns all = run_many(sims, in, true, 1);
    EXPECT_TRUE(same_bits(alone.reports[0], all.reports[pos])) << "damping ratio " << kRatios[k];
  }
}

TEST(RunMany, TheLockstepScanAgreesWithTheScalarReferenceToTheStatedTolerance) {
  // exp within 1 ulp of libm's (batched_integrator.hpp): SS within 1e-4 relative, stick fraction 1e-3
  const Scan s = scan(BitRockLaw::Kind::polynomial_hysteretic, kRatios);
  const ManyRuns batched = run_many(s.sims, s.in, false, 2, true);
  const ManyRuns scalar = run_many(s.sims, s.in, false, 1, false);
  for (std::size_t k = 0; k < kRatios.size(); ++k) {
    EXPECT_NEAR(batched.reports[k].severity, scalar.reports[k].severity, 1e-4 * scalar.reports[k].severity)
        << kRatios[k];
    EXPECT_NEAR(batched.reports[k].stick_fraction, scalar.reports[k].stick_fraction, 1e-3) << kRatios[k];
  }
}

TEST(RunMany, ADivergingRunIsReportedAndLeavesTheOthersAlone) {
  Scan s = scan(BitRockLaw::Kind::polynomial, kRatios);
  s.in[2].eta = Signal::constant(-5.0);  // the law reversed, four times over: the bit runs away
  for (bool batched : {true, false}) {
    const ManyRuns r = run_many(s.sims, s.in, true, 0, batched);
    EXPECT_NE(r.errors[2].find("simulation diverged at t = "), std::string::npos) << r.errors[2];
    for (std::size_t k : {0u, 1u, 3u, 7u}) {
      ASSERT_TRUE(r.errors[k].empty()) << r.errors[k];
      EXPECT_TRUE(same_bits(r.reports[k], run_many({s.sims[k]}, {s.in[k]}, true, 0, batched).reports[0])) << k;
    }
  }
}

TEST(RunMany, ModelsThatDifferInMoreThanDampingRunOneByOne) {
  Scan s = scan(BitRockLaw::Kind::polynomial, {0.1, 0.2});
  Config other = rig(BitRockLaw::Kind::polynomial, 0.2);
  other.law.a[5] *= 1.1;  // another law
  const Simulation third(other);
  EXPECT_FALSE(BatchedIntegrator(s.sims[0]->integrator()).shares_model(third.integrator()));
  s.sims.push_back(&third);
  s.in.push_back(s.in[1]);
  const ManyRuns r = run_many(s.sims, s.in, true, 0, true);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_TRUE(same_bits(r.reports[k], s.sims[k]->run(s.in[k])));
    EXPECT_FALSE(r.reports[k].series.bit_angle.empty());  // the scalar path forms it
  }
  const BatchedIntegrator b(s.sims[0]->integrator());
  std::vector<Recorder> obs(2);
  const std::vector<const ModelState*> start(2, nullptr);
  const std::vector<const Integrator*> model = {nullptr, &third.integrator()};
  EXPECT_THROW(b.run(s.in.data(), start.data(), 2, obs.data(), model.data()), std::invalid_argument);
}
