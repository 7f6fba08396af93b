// Monte Carlo of the stochastic model (section 4.2, appendix C): bit-identical results for any
// thread count and any chunking of the sample range, eta = 0 reproduces the deterministic model,
// statistics and the 5 % speed, Conv1 (C.1) and its convergence, refusal of bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "drill/montecarlo.hpp"
#include "drill/presets.hpp"
#include "error_text.hpp"

using namespace drill;

namespace {

/// thesis-field with 10 modes and short runs: cheap enough for unit tests.
Config small_field(double duration = 30.0, double transient = 10.0) {
  Config c = preset("thesis-field");
  c.modes = 10;
  c.sim.duration = duration;
  c.transient = transient;
  return c;
}

GaussianProcess scaled_thesis_psd(double scale, double duration) {
  const PsdModel m;
  return GaussianProcess::from_psd([&](double f) { return scale * m(f); }, 0.05, duration);
}

}  // namespace

TEST(MonteCarlo, BitIdenticalForOneAndTwoThreadsAndAnyChunking) {
  const MonteCarlo mc(small_field(), scaled_thesis_psd(1.0, 30.0), 2024, 20.0);
  const std::vector<double> sp = {8.0, 18.0, 26.0};
  const Eigen::MatrixXd one = mc.severity(sp, 0, 6, nullptr, 1);
  const Eigen::MatrixXd two = mc.severity(sp, 0, 6, nullptr, 2);
  ASSERT_EQ(one.rows(), 6);
  ASSERT_EQ(one.cols(), 3);
  for (int i = 0; i < 6; ++i)
    for (int s = 0; s < 3; ++s) EXPECT_EQ(one(i, s), two(i, s)) << i << "," << s;
  // chunks [0, 2) + [2, 5) + [5, 6), the middle one on two threads
  const Eigen::MatrixXd a = mc.severity(sp, 0, 2, nullptr, 1), b = mc.severity(sp, 2, 3, nullptr, 2),
                        c = mc.severity(sp, 5, 1, nullptr, 1);
  for (int s = 0; s < 3; ++s) {
    for (int i = 0; i < 2; ++i) EXPECT_EQ(a(i, s), one(i, s));
    for (int i = 0; i < 3; ++i) EXPECT_EQ(b(i, s), one(2 + i, s));
    EXPECT_EQ(c(0, s), one(5, s));
  }
  // samples are different realizations
  EXPECT_NE(one(0, 2), one(1, 2));
  // and the statistics of the concatenated chunks are those of the whole range
  Eigen::MatrixXd joined(6, 3);
  joined << a, b, c;
  const auto s1 = severity_statistics(one, sp), s2 = severity_statistics(joined, sp);
  EXPECT_EQ(s1.mean, s2.mean);
  EXPECT_EQ(s1.q_high, s2.q_high);
}

TEST(MonteCarlo, ZeroPsdReproducesTheDeterministicModelExactly) {
  // eta = 0: T_sto = T_hys (1 + 0) bit for bit (Eq. 4.1), so every sample is the deterministic
  // run of Simulation (Algorithm 2) when there is no warm-up.
  const Config c = small_field();
  const MonteCarlo mc(c, scaled_thesis_psd(0.0, 30.0), 1, 0.0);
  const std::vector<double> sp = {7.0, 17.0, 25.0};
  const Eigen::MatrixXd ss = mc.severity(sp, 3, 2, nullptr, 2);
  const std::vector<double> det = Simulation(c).sweep_severity(sp, {});
  for (int s = 0; s < 3; ++s) {
    EXPECT_EQ(ss(0, s), det[s]);
    EXPECT_EQ(ss(1, s), det[s]);
  }
  // phases too
  const auto ph = mc.phases(7.0, 0, 1);
  const RunReport r = Simulation(c).run(Simulation(c).inputs(7.0, c.wob), false);
  EXPECT_EQ(ph[0].stick, r.stick);
  EXPECT_EQ(ph[0].slip, r.slip);
  EXPECT_EQ(ph[0].severity, r.severity);
  EXPECT_GT(ph[0].stick.size(), 1u);  // stick-slip at 7 rad/s
}

TEST(MonteCarlo, WarmupContinuesTheDeterministicRun) {
  // Starting from the state at t = W equals one run of W + duration with transient W + transient,
  // except for the first step's acceleration estimate (taken as 0 at a restart): SS agrees to 1e-3.
  const Config c = small_field(30.0, 10.0);
  const MonteCarlo mc(c, scaled_thesis_psd(0.0, 30.0), 1, 40.0);
  const std::vector<double> sp = {8.0, 24.0};
  const Eigen::MatrixXd ss = mc.severity(sp, 0, 1, nullptr, 1);
  Config whole = c;
  whole.sim.duration = 70.0;
  whole.transient = 50.0;
  const std::vector<double> det = Simulation(whole).sweep_severity(sp, {});
  for (int s = 0; s < 2; ++s) EXPECT_NEAR(ss(0, s), det[s], 1e-3) << sp[s];
}

TEST(MonteCarlo, StrongerFluctuationsWidenTheSeverityBand) {
  // At a stable speed (26 rad/s) SS of the deterministic model is small; eta spreads it, the
  // more so the larger its PSD (variance x 25 -> standard deviation x 5).
  const Config c = small_field(40.0, 15.0);
  const std::vector<double> sp = {26.0};
  const auto weak = severity_statistics(MonteCarlo(c, scaled_thesis_psd(1.0, 40.0), 9, 60.0).severity(sp, 0, 12), sp);
  const auto strong =
      severity_statistics(MonteCarlo(c, scaled_thesis_psd(25.0, 40.0), 9, 60.0).severity(sp, 0, 12), sp);
  EXPECT_GT(weak.q_high[0] - weak.q_low[0], 0.0);
  EXPECT_GT(strong.q_high[0] - strong.q_low[0], 2.0 * (weak.q_high[0] - weak.q_low[0]));
  EXPECT_GT(strong.mean[0], weak.mean[0]);
}

TEST(SeverityStatistics, MeanQuantilesProbabilityAndFivePercentSpeed) {
  // 20 samples at 4 speeds; column s holds i / 10 * (4 - s) for i = 0..19.
  const std::vector<double> sp = {10.0, 12.0, 14.0, 16.0};
  Eigen::MatrixXd ss(20, 4);
  for (int i = 0; i < 20; ++i)
    for (int s = 0; s < 4; ++s) ss(i, s) = i / 10.0 * (4 - s) / 4.0;
  const SeverityStatistics st = severity_statistics(ss, sp, 0.5, 0.05);
  // column 0: values 0, 0.1, ..., 1.9; mean 0.95; type-7 quantile 0.05 -> h = 0.95 -> 0.095
  EXPECT_NEAR(st.mean[0], 0.95, 1e-12);
  EXPECT_NEAR(st.q_low[0], 0.095, 1e-12);
  EXPECT_NEAR(st.q_high[0], 1.805, 1e-12);
  // P(SS > 0.5): column s has values i (4-s)/40 > 0.5 <=> i > 20/(4-s)
  EXPECT_DOUBLE_EQ(st.p_exceed[0], 14.0 / 20);  // i = 6..19
  EXPECT_DOUBLE_EQ(st.p_exceed[1], 13.0 / 20);  // i = 7..19
  EXPECT_DOUBLE_EQ(st.p_exceed[2], 9.0 / 20);   // i = 11..19
  EXPECT_DOUBLE_EQ(st.p_exceed[3], 0.0);        // max 19/40
  // P crosses 0.05 between 14 (0.45) and 16 (0): 14 + 2 (0.45 - 0.05) / 0.45
  EXPECT_NEAR(st.p_speed, 14.0 + 2.0 * 0.40 / 0.45, 1e-12);
  EXPECT_TRUE(std::isnan(severity_statistics(ss.leftCols(3), {10, 12, 14}).p_speed));  // no crossing
}

TEST(Conv1, FormulaOfEquationC1) {
  const std::vector<double> sp = {6.0, 16.0, 27.0};
  Eigen::MatrixXd ss(2, 3);
  ss << 1.0, 1.0, 1.0,  // integral of 1 over B = 21
      2.0, 0.0, 0.0;    // trapezoid: 0.5 * 4 * 10 = 20
  const std::vector<double> c = conv1(ss, sp);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c[0], std::sqrt(21.0), 1e-12);
  EXPECT_NEAR(c[1], std::sqrt((21.0 + 20.0) / 2.0), 1e-12);
  // speeds in any order
  Eigen::MatrixXd rev = ss.rowwise().reverse();
  EXPECT_NEAR(conv1(rev, {27.0, 16.0, 6.0})[1], c[1], 1e-12);
}

TEST(Conv1, ConvergesAsTheNumberOfSamplesGrows) {
  // Appendix C: Conv1(n_s) settles as n_s grows. Its fluctuation over [n, 2n] shrinks like
  // 1/sqrt(n): over [64, 128] it is less than half of that over [8, 16].
  const Config c = small_field(30.0, 10.0);
  const MonteCarlo mc(c, scaled_thesis_psd(25.0, 30.0), 77, 40.0);
  const std::vector<double> sp = {14.0, 18.0, 20.0, 22.0};
  const Eigen::MatrixXd ss = mc.severity(sp, 0, 128);
  const std::vector<double> cv = conv1(ss, sp);
  auto spread = [&](std::size_t lo, std::size_t hi) {
    const auto [mn, mx] = std::minmax_element(cv.begin() + lo - 1, cv.begin() + hi);
    return *mx - *mn;
  };
  const double early = spread(8, 16), late = spread(64, 128);
  EXPECT_GT(early, 0.0);
  EXPECT_LT(late, 0.5 * early) << "early " << early << " late " << late;
  EXPECT_LT(std::fabs(cv[127] - cv[63]) / cv[127], 0.05);
}

TEST(MonteCarlo, RefusesBadInput) {
  const MonteCarlo mc(small_field(), scaled_thesis_psd(1.0, 30.0), 1, 0.0);
  std::string e = error_of([&] { mc.severity({}, 0, 4); });
  EXPECT_NE(e.find("montecarlo.top_speeds_rad_s = 0: is empty"), std::string::npos) << e;
  e = error_of([&] { mc.severity({10.0, -3.0}, 0, 4); });
  EXPECT_NE(e.find("montecarlo.top_speeds_rad_s[1] = -3"), std::string::npos) << e;
  e = error_of([&] { mc.severity({NAN}, 0, 4); });
  EXPECT_NE(e.find("montecarlo.top_speeds_rad_s[0] = nan"), std::string::npos) << e;
  e = error_of([&] { mc.severity({10.0}, 0, 0); });
  EXPECT_NE(e.find("montecarlo.samples = 0"), std::string::npos) << e;
  e = error_of([&] { mc.severity({10.0}, 0, MonteCarlo::max_samples + 1); });
  EXPECT_NE(e.find("montecarlo.samples = 10000001"), std::string::npos) << e;
  e = error_of([&] { mc.phases(10.0, 0, 0); });
  EXPECT_NE(e.find("montecarlo.samples = 0"), std::string::npos) << e;
  e = error_of([&] { MonteCarlo(small_field(100.0, 10.0), scaled_thesis_psd(1.0, 30.0), 1); });
  EXPECT_NE(e.find("shorter than simulation.duration_s = 100"), std::string::npos) << e;
  e = error_of([&] { MonteCarlo(small_field(), scaled_thesis_psd(1.0, 30.0), 1, -5.0); });
  EXPECT_NE(e.find("montecarlo.warmup_s = -5"), std::string::npos) << e;
  Eigen::MatrixXd bad(1, 2);
  bad << 0.3, NAN;
  e = error_of([&] { severity_statistics(bad, {1.0, 2.0}); });
  EXPECT_NE(e.find("severity[0][1] = nan"), std::string::npos) << e;
  e = error_of([&] { severity_statistics(bad, {1.0}); });
  EXPECT_NE(e.find("must equal the number of speeds"), std::string::npos) << e;
}
