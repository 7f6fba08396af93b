// Counter-based streams: reproducibility by (seed, sample, stream) and the moments of the
// uniform, normal and gamma transforms.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "drill/rng.hpp"

using drill::RandomStream;

TEST(Rng, SameKeySameNumbersDifferentKeyDifferentNumbers) {
  RandomStream a(42, 7, 1), b(42, 7, 1), c(42, 8, 1), d(43, 7, 1), e(42, 7, 2);
  for (int i = 0; i < 100; ++i) {
    const double x = a.uniform();
    EXPECT_EQ(x, b.uniform());
    EXPECT_NE(x, c.uniform());
    EXPECT_NE(x, d.uniform());
    EXPECT_NE(x, e.uniform());
  }
}

TEST(Rng, UniformMomentsAndRange) {
  RandomStream r(1, 0);
  const int n = 200000;
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    const double u = r.uniform();
    ASSERT_GT(u, 0.0);
    ASSERT_LT(u, 1.0);
    s += u;
    s2 += u * u;
  }
  const double mean = s / n, var = s2 / n - mean * mean;
  EXPECT_NEAR(mean, 0.5, 4 * std::sqrt(1.0 / 12 / n));
  EXPECT_NEAR(var, 1.0 / 12, 0.002);
}

TEST(Rng, NormalMomentsAndTail) {
  RandomStream r(2, 0);
  const int n = 400000;
  double s = 0, s2 = 0, s4 = 0;
  int beyond2 = 0;
  for (int i = 0; i < n; ++i) {
    const double z = r.normal();
    s += z;
    s2 += z * z;
    s4 += z * z * z * z;
    beyond2 += std::fabs(z) > 2.0;
  }
  EXPECT_NEAR(s / n, 0.0, 4 / std::sqrt(double(n)));
  EXPECT_NEAR(s2 / n, 1.0, 0.01);
  EXPECT_NEAR(s4 / n, 3.0, 0.05);                          // kurtosis of a Gaussian
  EXPECT_NEAR(double(beyond2) / n, 0.0455, 0.002);         // P(|Z| > 2) = 4.55 %
}

TEST(Rng, GammaMeanAndVarianceEqualShape) {
  for (double shape : {0.4, 1.0, 3.5, 50.0}) {
    RandomStream r(3, static_cast<std::uint64_t>(shape * 10));
    const int n = 200000;
    double s = 0, s2 = 0;
    for (int i = 0; i < n; ++i) {
      const double g = r.gamma(shape);
      ASSERT_GT(g, 0.0);
      s += g;
      s2 += g * g;
    }
    const double mean = s / n, var = s2 / n - mean * mean;
    EXPECT_NEAR(mean, shape, 5 * std::sqrt(shape / n)) << "shape " << shape;
    EXPECT_NEAR(var / shape, 1.0, 0.03) << "shape " << shape;
  }
}

TEST(Rng, GammaRefusesNonPositiveShape) {
  RandomStream r(4, 0);
  EXPECT_THROW(r.gamma(0.0), std::invalid_argument);
  EXPECT_THROW(r.gamma(-1.0), std::invalid_argument);
}
