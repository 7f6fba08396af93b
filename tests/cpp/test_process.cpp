// The eta process (section 4.1): PSD model (4.4) with the natural log, tables, and the spectral
// generator: periodogram of many realizations = target PSD, sample variance = PSD integral,
// reproducibility by (seed, sample), and refusal of bad PSDs and grids.
#include <gtest/gtest.h>

#include <unsupported/Eigen/FFT>

#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "drill/process.hpp"
#include "error_text.hpp"

using namespace drill;

namespace {

/// One-sided raw periodogram density of a full record (test oracle): 2 dt / n |DFT_k|^2.
std::vector<double> raw_periodogram(const std::vector<double>& x, double dt) {
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> X;
  fft.fwd(X, x);
  const std::size_t n = x.size();
  std::vector<double> P(n / 2 + 1);
  for (std::size_t k = 0; k <= n / 2; ++k)
    P[k] = (k == 0 || k == n / 2 ? 1.0 : 2.0) * dt / n * std::norm(X[k]);
  return P;
}

}  // namespace

TEST(PsdModel, ThesisParametersAreContinuousAtF0OnlyWithTheNaturalLog) {
  const PsdModel m;  // f0 = 0.27, A0 = -7.6, a = -3.13, b = -11.67
  const double below = std::log(m(m.f0 * (1 - 1e-12))), above = std::log(m(m.f0));
  EXPECT_DOUBLE_EQ(below, -7.6);
  EXPECT_NEAR(above, -3.13 * std::log(0.27) - 11.67, 1e-12);  // -7.5718
  EXPECT_LT(std::fabs(above - below), 0.03);
  // the log10 reading would jump by more than two decades at f0
  EXPECT_GT(std::fabs((-3.13 * std::log10(0.27) - 11.67) - (-7.6)), 2.0);
  EXPECT_NEAR(std::log(m(2.0)), -3.13 * std::log(2.0) - 11.67, 1e-12);
}

TEST(PsdModel, ClosedFormIntegralMatchesQuadrature) {
  const PsdModel m;
  for (double fmax : {0.1, 0.27, 1.0, 10.0}) {
    // midpoint rule on a fine grid, split at f0 where S jumps
    double q = 0.0;
    const int n = 200000;
    const double a = 0.0, c = std::min(fmax, m.f0);
    for (int i = 0; i < n; ++i) q += m(a + (i + 0.5) * (c - a) / n) * (c - a) / n;
    if (fmax > m.f0)
      for (int i = 0; i < n; ++i) q += m(m.f0 + (i + 0.5) * (fmax - m.f0) / n) * (fmax - m.f0) / n;
    EXPECT_NEAR(m.integral(fmax) / q, 1.0, 1e-6) << fmax;
  }
  // variance of the thesis model: 2.0037e-4 (std 0.01416)
  EXPECT_NEAR(m.integral(), std::exp(-7.6) * 0.27 + std::exp(-11.67) * std::pow(0.27, -2.13) / 2.13, 1e-15);
  EXPECT_NEAR(std::sqrt(m.integral()), 0.01416, 1e-5);
}

TEST(PsdTable, InterpolatesLinearlyHoldsBelowAndVanishesAbove) {
  PsdTable t{{0.5, 1.0, 2.0}, {4.0, 2.0, 1.0}};
  t.validate();
  EXPECT_EQ(t(0.0), 4.0);
  EXPECT_EQ(t(0.5), 4.0);
  EXPECT_DOUBLE_EQ(t(0.75), 3.0);
  EXPECT_DOUBLE_EQ(t(1.5), 1.5);
  EXPECT_EQ(t(2.0), 1.0);
  EXPECT_EQ(t(2.0001), 0.0);
}

TEST(GaussianProcess, GridIsAPowerOfTwoCoveringTheDuration) {
  EXPECT_EQ(GaussianProcess::grid_size(0.05, 100.0), 2048u);  // 102.4 s
  EXPECT_EQ(GaussianProcess::grid_size(0.05, 102.4), 2048u);
  EXPECT_EQ(GaussianProcess::grid_size(0.05, 102.5), 4096u);
  const auto f = GaussianProcess::grid_frequencies(0.05, 100.0);
  ASSERT_EQ(f.size(), 1025u);
  EXPECT_DOUBLE_EQ(f.back(), 10.0);  // Nyquist of dt = 0.05 s
  EXPECT_DOUBLE_EQ(f[1], 1.0 / 102.4);
}

TEST(GaussianProcess, PeriodogramOfManyRealizationsMatchesTheTargetPsd) {
  // Convention: one-sided PSD per Hz. The mean raw periodogram over M realizations is
  // S chi^2_{2M} / 2M per bin: relative sd 1/sqrt(M) = 5.8 % for M = 300.
  // Stated tolerances: every bin within 25 % (4.3 sd), 16-bin bands within 7 % (4.8 sd),
  // the mean ratio over all bins within 1 %.
  const PsdModel m;
  const double dt = 0.05, duration = 100.0;
  const GaussianProcess proc = GaussianProcess::from_psd(m, dt, duration);
  const std::size_t n = proc.size(), h = n / 2;
  const int M = 300;
  std::vector<double> avg(h + 1, 0.0);
  for (int i = 0; i < M; ++i) {
    RandomStream rng(11, i, 1);
    const std::vector<double> P = raw_periodogram(proc.sample(rng), dt);
    for (std::size_t k = 0; k <= h; ++k) avg[k] += P[k] / M;
  }
  double worst = 0.0, sum = 0.0, worst_band = 0.0;
  for (std::size_t k = 1; k < h; ++k) {
    const double r = avg[k] / proc.psd()[k];
    worst = std::max(worst, std::fabs(r - 1.0));
    sum += r;
  }
  for (std::size_t k0 = 1; k0 + 16 < h; k0 += 16) {
    double band = 0.0;
    for (std::size_t k = k0; k < k0 + 16; ++k) band += avg[k] / proc.psd()[k] / 16.0;
    worst_band = std::max(worst_band, std::fabs(band - 1.0));
  }
  EXPECT_LT(worst, 0.25);
  EXPECT_LT(worst_band, 0.07);
  EXPECT_NEAR(sum / (h - 1), 1.0, 0.01);
  // the target values on the grid are the model's
  EXPECT_DOUBLE_EQ(proc.psd()[100], m(100 * proc.df()));
}

TEST(GaussianProcess, SampleVarianceMatchesThePsdIntegral) {
  // E[(1/n) sum eta_j^2] over one period = variance() (trapezoidal sum of S on [0, 10 Hz]),
  // which is within 0.5 % of integral_0^inf S df = 2.0037e-4 for df = 1/102.4 Hz. The
  // average over M = 400 realizations has a relative sd of about 0.9 %: tolerance 3 %.
  const PsdModel m;
  const GaussianProcess proc = GaussianProcess::from_psd(m, 0.05, 100.0);
  EXPECT_NEAR(proc.variance() / m.integral(), 1.0, 0.005);
  const int M = 400;
  double var = 0.0, mean = 0.0;
  for (int i = 0; i < M; ++i) {
    RandomStream rng(5, i, 1);
    const std::vector<double> x = proc.sample(rng);
    double s2 = 0.0, s1 = 0.0;
    for (double v : x) {
      s2 += v * v;
      s1 += v;
    }
    var += s2 / x.size() / M;
    mean += s1 / x.size() / M;
  }
  EXPECT_NEAR(var / m.integral(), 1.0, 0.03);
  EXPECT_LT(std::fabs(mean), 3.0 * std::sqrt(proc.psd()[0] * proc.df() / 2.0 / M));  // centred
}

TEST(GaussianProcess, WhiteBandLimitedPsdHasTheExactTrapezoidalVariance) {
  // S = 2 on [0, 1] Hz, 0 above (a table): variance = 2 Hz^-1 x 1 Hz = 2.
  const PsdTable t{{0.0, 1.0}, {2.0, 2.0}};
  const GaussianProcess proc = GaussianProcess::from_psd(t, 0.1, 50.0);  // df = 1/51.2 Hz
  const double df = proc.df();
  const std::size_t kmax = static_cast<std::size_t>(std::floor(1.0 / df));  // last bin with S = 2
  EXPECT_NEAR(proc.variance(), 2.0 * df * (kmax + 0.5), 1e-12);  // half DC bin + kmax bins
  EXPECT_NEAR(proc.variance(), 2.0, 2.0 * df);
}

TEST(GaussianProcess, RealizationDependsOnlyOnSeedAndSample) {
  const GaussianProcess proc = GaussianProcess::from_psd(PsdModel{}, 0.05, 60.0);
  RandomStream a(3, 17, 1), b(3, 17, 1), c(3, 18, 1), d(4, 17, 1);
  const auto xa = proc.sample(a), xb = proc.sample(b), xc = proc.sample(c), xd = proc.sample(d);
  ASSERT_EQ(xa.size(), proc.size());
  EXPECT_EQ(xa, xb);
  EXPECT_NE(xa, xc);
  EXPECT_NE(xa, xd);
  const Signal s = proc.signal(a = RandomStream(3, 17, 1));
  EXPECT_EQ(s.samples, xa);
  EXPECT_DOUBLE_EQ(s.at(0.025), 0.5 * (xa[0] + xa[1]));
}

TEST(GaussianProcess, RefusesNegativeOrNonFinitePsdAndBadGrids) {
  const auto f = GaussianProcess::grid_frequencies(0.05, 10.0);
  std::vector<double> S(f.size(), 1e-3);
  S[3] = -1e-4;
  std::string e = error_of([&] { GaussianProcess(S, 0.05, 10.0); });
  EXPECT_NE(e.find("psd(f = " + show(f[3]) + " Hz) = -0.0001"), std::string::npos) << e;
  EXPECT_NE(e.find("must not be negative"), std::string::npos) << e;
  S[3] = NAN;
  e = error_of([&] { GaussianProcess(S, 0.05, 10.0); });
  EXPECT_NE(e.find("must be a finite number"), std::string::npos) << e;
  S[3] = INFINITY;
  EXPECT_NE(error_of([&] { GaussianProcess(S, 0.05, 10.0); }), "no error");
  S.pop_back();
  e = error_of([&] { GaussianProcess(S, 0.05, 10.0); });
  EXPECT_NE(e.find("one value per grid frequency"), std::string::npos) << e;
  e = error_of([] { GaussianProcess::grid_size(0.0, 10.0); });
  EXPECT_NE(e.find("process.dt_s = 0"), std::string::npos) << e;
  e = error_of([] { GaussianProcess::grid_size(-0.05, 10.0); });
  EXPECT_NE(e.find("process.dt_s = -0.05"), std::string::npos) << e;
  e = error_of([] { GaussianProcess::grid_size(NAN, 10.0); });
  EXPECT_NE(e.find("process.dt_s = nan"), std::string::npos) << e;
  e = error_of([] { GaussianProcess::grid_size(1e-9, 1000.0); });
  EXPECT_NE(e.find("more than 2^26 points"), std::string::npos) << e;
  e = error_of([] { GaussianProcess::grid_size(0.05, -1.0); });
  EXPECT_NE(e.find("process.duration_s = -1"), std::string::npos) << e;
}

TEST(PsdModel, RefusesBadParametersAndTables) {
  PsdModel m;
  m.f0 = 0.0;
  EXPECT_NE(error_of([&] { m.validate(); }).find("psd.f0_hz = 0"), std::string::npos);
  m = PsdModel{};
  m.A0 = NAN;
  EXPECT_NE(error_of([&] { m.validate(); }).find("psd.A0 = nan"), std::string::npos);
  m = PsdModel{};
  m.a = -0.5;  // not integrable to infinity
  EXPECT_NE(error_of([&] { m.integral(); }).find("psd.a = -0.5"), std::string::npos);
  EXPECT_NE(error_of([&] { PsdModel{}(-1.0); }).find("must be finite and non-negative"), std::string::npos);
  PsdTable t{{0.0, 1.0, 2.0}, {1.0, -2.0, 1.0}};
  EXPECT_NE(error_of([&] { t.validate(); }).find("psd.table.S[1] = -2"), std::string::npos);
  t = PsdTable{{0.0, 1.0, 2.0}, {1.0, NAN, 1.0}};
  EXPECT_NE(error_of([&] { t.validate(); }).find("psd.table.S[1] = nan"), std::string::npos);
  t = PsdTable{{0.0, 2.0, 1.0}, {1.0, 1.0, 1.0}};
  EXPECT_NE(error_of([&] { t.validate(); }).find("increase strictly"), std::string::npos);
  t = PsdTable{{0.0}, {1.0}};
  EXPECT_NE(error_of([&] { t.validate(); }).find("at least 2 points"), std::string::npos);
}
