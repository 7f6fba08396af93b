// Type-7 sample quantiles (numpy's default) used by the SS bands and the FRF envelopes.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "drill/quantile.hpp"

using namespace drill;

TEST(Quantile, Type7Interpolation) {
  std::vector<double> v{5, 1, 4, 2, 3};
  EXPECT_DOUBLE_EQ(quantile(v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(quantile(v, 0.5), 3.0);
  EXPECT_DOUBLE_EQ(quantile(v, 0.1), 1.4);  // h = 0.4: 1 + 0.4 (2 - 1)
  EXPECT_DOUBLE_EQ(quantile(v, 1.0), 5.0);
  // numpy.quantile([0, 0.1, ..., 1.9], 0.05) = 0.095 and 0.95 -> 1.805
  std::vector<double> w;
  for (int i = 19; i >= 0; --i) w.push_back(0.1 * i);
  EXPECT_NEAR(quantile(w, 0.05), 0.095, 1e-12);
  EXPECT_NEAR(quantile(w, 0.95), 1.805, 1e-12);
}

TEST(Quantile, RefusesAnEmptySampleAndLevelsOutsideZeroOne) {
  std::vector<double> empty, one{2.0};
  EXPECT_THROW(quantile(empty, 0.5), std::invalid_argument);
  EXPECT_THROW(quantile(one, 1.5), std::invalid_argument);
  EXPECT_DOUBLE_EQ(quantile(one, 0.3), 2.0);
}
