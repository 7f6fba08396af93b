// The coupled model's batched path (AxialTorsional::run_lanes, axial_torsional.hpp): a run has the
// same bits alone (run(), the scalar path) and in any lane of a batch of other runs, on both schemes,
// both top boundaries and both torques (RGD's and a thesis law on the axial WOB); the Monte Carlo and
// the sweeps that step coupled runs in lanes give the same numbers as one by one, on 1 and 2 threads
// and for any chunking of the samples. Every comparison is of the bits of two runs of this code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "drill/montecarlo.hpp"
#include "drill/presets.hpp"
#include "drill/simulation.hpp"

using namespace drill;

namespace axial_batched_test {

/// rgd-field over `duration` with `scheme` (dt 0.5 ms, within both schemes' bounds), the top
/// boundary `top` (feed at the preset's steady ROP) and the torque `torque` (law: the thesis's
/// hysteretic law, Eqs. 3.2-3.3, at the preset's WOB reference).
Config coupled(Scheme scheme, AxialTop top, AxialTorque torque, double duration = 1.5) {
  Config c = preset("rgd-field");
  c.sim.scheme = scheme;
  c.sim.duration = duration;
  c.transient = 0.5 * duration;
  c.axial.rgd.top = top;
  c.axial.rgd.feed_rate = 0.0129;  // [m/s] the hook-load run's mean ROP order (docs/axial.md: 46 m/h)
  if (torque == AxialTorque::law) {
    c.axial.rgd.torque = AxialTorque::law;
    c.law = thesis_hysteretic(0.14, SpeedUnit::rpm);
    c.law.wob_ref = 166.8e3;
  }
  return c;
}

/// The bits of every double a run reports at every step (StepState and AxialStep, NaN included).
struct Bits {
  std::vector<std::uint64_t> v;
  void add(double x) {
    std::uint64_t u;
    std::memcpy(&u, &x, sizeof u);
    v.push_back(u);
  }
  void operator()(const StepState& s, const AxialStep& a) {
    v.push_back(static_cast<std::uint64_t>(s.step));
    for (double x : {s.t, s.bit_speed, s.bit_accel, s.bit_angle, s.torque_on_bit, s.top_torque, s.top_speed,
                     s.drive_torque, s.wob, a.t, a.wob, a.rop, a.position, a.depth, a.delay})
      add(x);
    v.push_back(a.contact);
  }
};

/// Eight different runs of one model: the top speeds and the eta of Eq. (4.1) (a sampled series,
/// a different one per run, the first constant 0) differ.
std::vector<Inputs> eight_runs(const Simulation& sim) {
  std::vector<Inputs> in;
  for (int k = 0; k < 8; ++k) {
    Inputs x = sim.inputs(3.0 + 0.5 * k, sim.config().wob);
    if (k > 0) {
      std::vector<double> e(64);
      for (std::size_t i = 0; i < e.size(); ++i) e[i] = 0.05 * k * std::sin(0.7 * i + k);
      x.eta = Signal::sampled(e, 0.0, 0.05);
    }
    in.push_back(x);
  }
  return in;
}

/// The final state's bits (torsional and axial coordinates).
std::vector<double> final_values(const CoupledState& s) {
  std::vector<double> out;
  for (const Eigen::VectorXd* v : {&s.torsion.q, &s.torsion.qdot, &s.eta, &s.eta_dot})
    out.insert(out.end(), v->data(), v->data() + v->size());
  return out;
}

GaussianProcess eta_process(double duration) {
  const PsdModel m;
  return GaussianProcess::from_psd([&](double f) { return m(f); }, 0.05, duration);
}

}  // namespace axial_batched_test

using namespace axial_batched_test;

TEST(AxialBatched, ARunHasTheSameBitsAloneAndInAnyLaneOfABatch) {
  for (Scheme scheme : {Scheme::modified_euler, Scheme::exact_modal})
    for (AxialTop top : {AxialTop::hook_load, AxialTop::feed})
      for (AxialTorque torque : {AxialTorque::rgd, AxialTorque::law}) {
        const std::string what = to_string(scheme) + " " + to_string(top) + " " + to_string(torque);
        const Simulation sim(coupled(scheme, top, torque));
        const AxialTorsional& m = *sim.coupled();
        const std::vector<Inputs> in = eight_runs(sim);
        std::vector<Bits> alone(8);
        std::vector<std::vector<double>> alone_end(8);
        for (int k = 0; k < 8; ++k) alone_end[k] = final_values(m.run(in[k], alone[k]));
        // the eight runs in one batch, run k in lane 7 - k, and in batches of 3, 3 and 2 (run k in lane k % 3)
        for (bool reversed : {true, false}) {
          const std::size_t size = reversed ? 8 : 3;
          for (std::size_t first = 0; first < 8; first += size) {
            const std::size_t n = std::min<std::size_t>(size, 8 - first);
            std::vector<Inputs> lanes;
            std::vector<int> run;
            for (std::size_t l = 0; l < n; ++l) {
              run.push_back(reversed ? 7 - static_cast<int>(l) : static_cast<int>(first + l));
              lanes.push_back(in[run.back()]);
            }
            const std::vector<const ModelState*> s0(n, nullptr);
            std::vector<Bits> obs(n);
            std::vector<CoupledState> end(n);
            m.run_lanes(lanes.data(), s0.data(), n, obs.data(), end.data());
            for (std::size_t l = 0; l < n; ++l) {
              ASSERT_EQ(obs[l].v.size(), alone[run[l]].v.size()) << what;
              EXPECT_TRUE(obs[l].v == alone[run[l]].v) << what << ": run " << run[l] << " in lane " << l << " of " << n;
              EXPECT_TRUE(final_values(end[l]) == alone_end[run[l]]) << what << ": run " << run[l];
            }
          }
        }
        // the runs differ (the batch is not eight copies of one run)
        EXPECT_FALSE(alone[0].v == alone[1].v) << what;
      }
}

TEST(AxialBatched, TheScalarRunReportIsTheSameAsInABatch) {
  // Simulation::run (the scalar path's report) and the lanes' SS through the sweep, both schemes
  for (Scheme scheme : {Scheme::modified_euler, Scheme::exact_modal}) {
    Config c = coupled(scheme, AxialTop::hook_load, AxialTorque::rgd, 4.0);
    const Simulation sim(c);
    const std::vector<double> speeds{2.5, 3.0, 4.0, 5.0, 6.0};
    const std::vector<double> ss = sim.sweep_severity(speeds, {}, nullptr, 2);
    for (std::size_t k = 0; k < speeds.size(); ++k) {
      Config one = c;
      one.top_speed = speeds[k];
      const Simulation single(one);
      const double alone = single.run(single.inputs(), false).severity;
      EXPECT_EQ(ss[k], alone) << to_string(scheme) << " speed " << speeds[k];
    }
    EXPECT_NE(ss.front(), ss.back());
  }
}

TEST(AxialBatched, SweepIsTheSameBatchedOrOneByOneOnOneAndTwoThreads) {
  for (AxialTop top : {AxialTop::hook_load, AxialTop::feed}) {
    const Simulation sim(coupled(Scheme::modified_euler, top, AxialTorque::rgd, 3.0));
    const std::vector<double> speeds{2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0};
    const std::vector<double> wobs = top == AxialTop::hook_load ? std::vector<double>{130e3, 170e3} : std::vector<double>{};
    const std::vector<double> ref = sim.sweep_severity(speeds, wobs, nullptr, 1, std::nullopt, false);
    EXPECT_EQ(ref, sim.sweep_severity(speeds, wobs, nullptr, 1, std::nullopt, true)) << to_string(top);
    EXPECT_EQ(ref, sim.sweep_severity(speeds, wobs, nullptr, 2, std::nullopt, true)) << to_string(top);
  }
}

TEST(AxialBatched, MonteCarloIsTheSameForAnyThreadsChunksAndLanes) {
  // rgd-field with eta of Eq. (4.1) (the thesis's PSD): samples in lanes (one task per batch and
  // speed), on 1 and 2 threads, in two chunks, and one by one through the scalar path
  for (Scheme scheme : {Scheme::modified_euler, Scheme::exact_modal}) {
    const Config c = coupled(scheme, AxialTop::hook_load, AxialTorque::rgd, 3.0);
    const MonteCarlo mc(c, eta_process(3.0), 2026, 0.0);
    ASSERT_TRUE(mc.lockstep());
    const std::vector<double> speeds{3.0, 5.0};
    const std::size_t n = 11;  // batches of width() with a partial one
    const Eigen::MatrixXd one = mc.severity(speeds, 0, n, nullptr, 1);
    const Eigen::MatrixXd two = mc.severity(speeds, 0, n, nullptr, 2);
    const Eigen::MatrixXd scalar = mc.severity(speeds, 0, n, nullptr, 2, nullptr, false);
    const Eigen::MatrixXd a = mc.severity(speeds, 0, 5, nullptr, 2), b = mc.severity(speeds, 5, n - 5, nullptr, 1);
    ASSERT_EQ(one.rows(), static_cast<Eigen::Index>(n));
    EXPECT_TRUE(one == two) << to_string(scheme);
    EXPECT_TRUE(one == scalar) << to_string(scheme);
    EXPECT_TRUE(one.topRows(5) == a) << to_string(scheme);
    EXPECT_TRUE(one.bottomRows(n - 5) == b) << to_string(scheme);
    EXPECT_NE(one(0, 0), one(1, 0)) << to_string(scheme);  // the samples differ
  }
}
