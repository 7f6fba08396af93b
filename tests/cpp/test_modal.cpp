// Generalized eigenproblem (2.7), damping models and the reduced-order model (2.8-2.10).
#include <gtest/gtest.h>

#include "drill/modal.hpp"
#include "drill/presets.hpp"

using namespace drill;

TEST(Modal, ModesAreMassNormalizedAndDiagonalizeStiffness) {
  const Config c = preset("thesis-field");
  const ClampedMatrices cm = clamp_top(assemble(c.string));
  const ModalBasis mb = solve_modes(cm.K, cm.M, 10);
  const Eigen::MatrixXd I = mb.phi.transpose() * cm.M * mb.phi;
  const Eigen::MatrixXd W = mb.phi.transpose() * cm.K * mb.phi;
  EXPECT_LT((I - Eigen::MatrixXd::Identity(10, 10)).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((W - Eigen::MatrixXd(mb.omega.cwiseAbs2().asDiagonal())).cwiseAbs().maxCoeff(), 1e-7 * W.maxCoeff());
  for (int k = 1; k < 10; ++k) EXPECT_GT(mb.omega(k), mb.omega(k - 1));
}

TEST(Modal, ModalDampingGivesTheRequestedRatios) {
  const Config c = preset("thesis-field");
  const ModalROM rom = build_modal_rom(c.string, 5, c.damping);
  for (int j = 0; j < 5; ++j) {
    const double zeta = rom.model.D(j, j) / (2.0 * rom.omega(j));
    EXPECT_NEAR(zeta, j == 0 ? 0.095 : 0.02, 1e-12);
  }
}

TEST(Modal, RayleighFitHitsBothPairs) {
  const Rayleigh r = Rayleigh::from_pairs(1.0, 0.05, 10.0, 0.01);
  EXPECT_NEAR(r.ratio(2 * M_PI * 1.0), 0.05, 1e-12);
  EXPECT_NEAR(r.ratio(2 * M_PI * 10.0), 0.01, 1e-12);
  EXPECT_THROW(Rayleigh::from_pairs(1.0, 0.05, 1.0, 0.01), std::invalid_argument);
  EXPECT_THROW(Rayleigh::from_pairs(-1.0, 0.05, 2.0, 0.01), std::invalid_argument);
}

TEST(Modal, InitialVelocityProjectsTheRigidRotation) {
  // With every mode kept, Eq. (2.10) recovers u'(0) = -Omega 1 exactly (Eq. 2.6).
  Config c = preset("thesis-field");
  c.set_total_elements(30);
  const ModalROM rom = build_modal_rom(c.string, 30, c.damping);
  const Eigen::VectorXd u = rom.model.basis * (-7.0 * rom.model.init_velocity);
  EXPECT_LT((u + 7.0 * Eigen::VectorXd::Ones(30)).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(Modal, TooManyModesIsRefused) {
  const Config c = preset("thesis-field");
  try {
    build_modal_rom(c.string, 101, c.damping);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("rom.modes = 101"), std::string::npos) << e.what();
  }
  EXPECT_THROW(build_modal_rom(c.string, 0, c.damping), std::invalid_argument);
}
