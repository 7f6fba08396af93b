// The axial finite elements of the string (axial_string.hpp): the natural frequencies of a uniform bar
// converge to the analytic ones, (2k - 1) c / (4 L) fixed-free (top = feed) and (k - 1) c / (2 L)
// free-free (top = hook_load, its rigid mode 0), at second order in the element size.
#include <gtest/gtest.h>

#include <cmath>

#include "drill/axial_string.hpp"

using namespace drill;

namespace {

StringModel bar(double L, int elements) {
  Section s;
  s.name = "bar";
  s.length = L;
  s.outer_radius = 0.07;
  s.inner_radius = 0.0595;
  s.youngs_modulus = 220e9;
  s.poisson_ratio = 0.29;
  s.density = 7800.0;
  s.elements = elements;
  StringModel m;
  m.sections = {s};
  return m;
}

}  // namespace

TEST(AxialString, FixedFreeFrequenciesConvergeToTheWaveSolution) {
  const double L = 2000.0, c = std::sqrt(220e9 / 7800.0);
  double err[2][3];
  const int ne[2] = {50, 100};
  for (int m = 0; m < 2; ++m) {
    const Eigen::VectorXd f = axial_frequencies_hz(bar(L, ne[m]), AxialTop::feed, 3);
    for (int k = 1; k <= 3; ++k) {
      const double exact = (2 * k - 1) * c / (4.0 * L);
      err[m][k - 1] = std::fabs(f(k - 1) - exact) / exact;
    }
  }
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT(err[1][k], 2e-3) << "mode " << k + 1;
    EXPECT_NEAR(err[0][k] / err[1][k], 4.0, 0.3) << "mode " << k + 1;  // O(h^2)
  }
}

TEST(AxialString, HookLoadIsFreeFreeWithARigidMode) {
  const double L = 1000.0, c = std::sqrt(220e9 / 7800.0);
  const AxialROM r = build_axial_rom(bar(L, 200), AxialTop::hook_load, 3, 0.05);
  EXPECT_EQ(r.omega(0), 0.0);
  EXPECT_EQ(r.damping(0), 0.0);
  EXPECT_NEAR(r.omega(1) / (2.0 * M_PI), c / (2.0 * L), 1e-4 * c / (2.0 * L));
  EXPECT_NEAR(r.omega(2) / (2.0 * M_PI), c / L, 1e-4 * c / L);
  // a rigid motion lives in the rigid mode only: Phi^T M 1 has a single non-zero entry, sqrt(mass)
  EXPECT_NEAR(std::fabs(r.uniform(0)), std::sqrt(r.mass), 1e-9 * std::sqrt(r.mass));
  EXPECT_LT(r.uniform.tail(2).cwiseAbs().maxCoeff(), 1e-6 * std::sqrt(r.mass));
}

TEST(AxialString, RefusesMoreModesThanDofs) {
  EXPECT_THROW(build_axial_rom(bar(100.0, 5), AxialTop::feed, 6, 0.0), std::invalid_argument);
  EXPECT_NO_THROW(build_axial_rom(bar(100.0, 5), AxialTop::hook_load, 6, 0.0));
}
