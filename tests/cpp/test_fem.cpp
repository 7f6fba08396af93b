// FE model of the torsional string (Eqs. 2.1-2.7): thesis frequencies, convergence to the exact
// two-section bar solution with the expected order, and the test-rig frequency.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "drill/exact.hpp"
#include "drill/fem.hpp"
#include "drill/modal.hpp"
#include "drill/presets.hpp"

using namespace drill;

namespace {

StringModel table31(int n_dp, int n_bha) {
  StringModel s;
  s.sections = {{"DP", 4733.60, 0.070, 0.0595, 220e9, 0.29, 7800, n_dp},
                {"BHA", 466.45, 0.0803, 0.0363, 220e9, 0.29, 7800, n_bha}};
  return s;
}

}  // namespace

TEST(Fem, Table31With100ElementsGivesTheThesisFrequencies) {
  const Eigen::VectorXd f = natural_frequencies_hz(table31(91, 9), 5);
  const double thesis[5] = {0.13, 0.42, 0.74, 1.07, 1.41};  // section 3.3, two decimals
  for (int k = 0; k < 5; ++k) EXPECT_NEAR(f(k), thesis[k], 0.005) << "mode " << k + 1;
  EXPECT_NEAR(f(0), 0.1317, 5e-5);  // THESIS-NOTES value
}

TEST(Fem, MassAndStiffnessAreConsistent) {
  const StringModel s = table31(91, 9);
  const FEMatrices fe = assemble(s);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(fe.M.rows());
  EXPECT_LT((fe.K * ones).cwiseAbs().maxCoeff(), 1e-6 * fe.K.cwiseAbs().maxCoeff());  // rigid rotation is free
  double inertia = 0;
  for (const auto& sec : s.sections) inertia += sec.density * sec.polar_moment() * sec.length;
  EXPECT_NEAR(ones.dot(fe.M * ones), inertia, 1e-9 * inertia);  // consistent mass keeps rho J L
  EXPECT_NEAR(fe.x(fe.x.size() - 1), s.total_length(), 1e-9);
}

TEST(Fem, FrequenciesConvergeToExactSolutionAtSecondOrder) {
  const std::vector<double> exact = exact_frequencies_hz(table31(1, 1), 5);
  EXPECT_NEAR(exact[0], 0.1317, 2e-4);
  std::vector<double> err;
  for (int n : {50, 100, 200, 400}) {
    Config c;
    c.string = table31(1, 1);
    c.set_total_elements(n);
    const Eigen::VectorXd f = natural_frequencies_hz(c.string, 5);
    double e = 0;
    for (int k = 0; k < 5; ++k) e = std::max(e, std::fabs(f(k) - exact[k]) / exact[k]);
    err.push_back(e);
  }
  for (std::size_t i = 1; i < err.size(); ++i) {
    const double order = std::log2(err[i - 1] / err[i]);
    EXPECT_GT(order, 1.8) << "refinement " << i;
    EXPECT_LT(order, 2.3) << "refinement " << i;
    EXPECT_LT(err[i], err[i - 1]);
  }
  EXPECT_GT(err.front(), 0.0);
  EXPECT_LT(err.back(), 1e-4);
}

TEST(Fem, TransferMatrixMatchesTheTwoSectionFrequencyEquation) {
  // Continuity of angle and torque at the interface of a clamped-free two-section bar:
  // Z1 cos(k1 L1) cos(k2 L2) - Z2 sin(k1 L1) sin(k2 L2) = 0.
  const StringModel s = table31(1, 1);
  const Section &a = s.sections[0], &b = s.sections[1];
  for (double f : exact_frequencies_hz(s, 5)) {
    const double w = 2 * M_PI * f, k1 = w / a.wave_speed(), k2 = w / b.wave_speed();
    const double z1 = a.shear_modulus() * a.polar_moment() * k1, z2 = b.shear_modulus() * b.polar_moment() * k2;
    const double r = z1 * std::cos(k1 * a.length) * std::cos(k2 * b.length) - z2 * std::sin(k1 * a.length) * std::sin(k2 * b.length);
    EXPECT_LT(std::fabs(r), 1e-9 * z1) << f;
  }
  // a single uniform clamped-free bar: f_n = (2n - 1) c / (4 L)
  StringModel u;
  u.sections = {a};
  const auto fu = exact_frequencies_hz(u, 3);
  for (int n = 1; n <= 3; ++n) EXPECT_NEAR(fu[n - 1], (2 * n - 1) * a.wave_speed() / (4 * a.length), 1e-9);
}

TEST(Fem, TestRigFirstFrequencyNearTheMeasured3Hz) {
  const Config c = preset("thesis-rig");
  const Eigen::VectorXd f = natural_frequencies_hz(c.string, 2);
  // sqrt(k / I) / (2 pi) with k = G J / L = 3.08 N m/rad and I = 9.33e-3 kg m^2: 2.89 Hz
  EXPECT_NEAR(f(0), 2.89, 0.01);
  EXPECT_NEAR(f(0), exact_frequencies_hz(c.string, 1, 0.05)[0], 1e-4);  // bar + disk, exact
  EXPECT_NEAR(f(0), 3.0, 0.15);  // the thesis measured 3 Hz
  EXPECT_GT(f(1), 100.0);        // the bar's own modes are far above
}

TEST(Fem, BadSectionsAreRefusedNamingTheField) {
  auto expect_msg = [](std::function<void(Section&)> edit, const std::string& field) {
    StringModel s = table31(91, 9);
    edit(s.sections[1]);
    try {
      s.validate();
      FAIL() << "no error for " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("string.sections[1]." + field), std::string::npos) << e.what();
    }
  };
  expect_msg([](Section& s) { s.length = -1; }, "length_m");
  expect_msg([](Section& s) { s.outer_radius = 0; }, "outer_radius_m");
  expect_msg([](Section& s) { s.inner_radius = 0.09; }, "inner_radius_m");
  expect_msg([](Section& s) { s.elements = 0; }, "elements");
  expect_msg([](Section& s) { s.density = std::nan(""); }, "density_kg_m3");
  expect_msg([](Section& s) { s.youngs_modulus = INFINITY; }, "youngs_modulus_pa");
}
