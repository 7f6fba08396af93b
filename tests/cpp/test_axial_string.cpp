// The axial finite elements of the string (axial_string.hpp): the natural frequencies of a uniform bar
// converge to the analytic ones, (2k - 1) c / (4 L) fixed-free (top = feed) and (k - 1) c / (2 L)
// free-free (top = hook_load, its rigid mode 0), at second order in the element size; the distributed
// damping D = 2 k M gives mode j the ratio k / omega_j, the modal one the same ratio on every mode.
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

// axial.damping = distributed: D = 2 k M is 2 k I in the mass-normalised modes, the ratio k / omega_j
// on mode j; checked against Phi^T (2 k M) Phi of the FE matrices themselves, and the modal option's
// coefficients are still 2 zeta omega_j to the last bit.
TEST(AxialString, DistributedDampingGivesModeJTheRatioKOverOmegaJ) {
  const StringModel s = bar(2000.0, 100);
  const double k = 1.0;
  for (AxialTop top : {AxialTop::feed, AxialTop::hook_load}) {
    const AxialROM r = build_axial_rom(s, top, 8, AxialModalDamping{AxialDamping::distributed, 0.05, k});
    // the FE model's own modes and Phi^T D Phi with D = 2 k M
    const FEMatrices fe = assemble_axial(s, 0.0);
    const Eigen::Index first = top == AxialTop::feed ? 1 : 0, n = fe.M.rows() - first;
    const Eigen::MatrixXd M = fe.M.bottomRightCorner(n, n), K = fe.K.bottomRightCorner(n, n);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, M);
    const Eigen::MatrixXd phi = es.eigenvectors().leftCols(8);
    const Eigen::MatrixXd modal_D = phi.transpose() * (2.0 * k * M) * phi;
    EXPECT_LT((modal_D - Eigen::MatrixXd(modal_D.diagonal().asDiagonal())).cwiseAbs().maxCoeff(), 1e-9 * k);
    for (int j = 0; j < 8; ++j) {
      if (r.omega(j) == 0.0) {  // hook_load's rigid mode: the steady advance is not braked
        EXPECT_EQ(r.damping(j), 0.0);
        continue;
      }
      const double ratio = r.damping(j) / (2.0 * r.omega(j));
      EXPECT_NEAR(ratio, k / r.omega(j), 1e-12 * k / r.omega(j)) << to_string(top) << " mode " << j + 1;
      EXPECT_NEAR(r.damping(j), modal_D(j, j), 1e-9 * k) << to_string(top) << " mode " << j + 1;
    }
    // the ratio falls as 1 / omega_j: on a fixed-free bar the third mode's is a fifth of the first's
    if (top == AxialTop::feed) EXPECT_NEAR(r.damping(2) / (2.0 * r.omega(2)) * 5.0, r.damping(0) / (2.0 * r.omega(0)),
                                           5e-3 * r.damping(0) / (2.0 * r.omega(0)));
    // modal, the default, is unchanged: 2 zeta omega_j on every mode
    const AxialROM m = build_axial_rom(s, top, 8, 0.05);
    for (int j = 0; j < 8; ++j) EXPECT_EQ(m.damping(j), 2.0 * 0.05 * m.omega(j));
  }
}
