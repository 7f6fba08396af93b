// Craig-Bampton substructuring (Eqs. 6.6-6.18): convergence of the natural frequencies to the full
// FE model, exactness with all modes, assembly versus projection, static modes and recovery.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "drill/craig_bampton.hpp"
#include "drill/presets.hpp"

using namespace drill;

namespace {

Config small_chain(int n_sections) {
  Config c = preset("thesis-ch6");
  c.string.sections.resize(2);
  c.string.sections[0].elements = 12;
  c.string.sections[1].elements = 8;
  if (n_sections == 3) {
    Section mid = c.string.sections[0];
    mid.name = "HWDP";
    mid.length = 200.0;
    mid.outer_radius = 0.075;
    mid.elements = 6;
    c.string.sections.insert(c.string.sections.begin() + 1, mid);
  }
  c.cb_modes.assign(n_sections, 1);
  return c;
}

double max_rel(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a.array() / b.array() - 1.0).abs().maxCoeff(); }

}  // namespace

TEST(CraigBampton, FrequenciesConvergeToFullModelWithModes) {
  Config c = preset("thesis-ch6");
  const Eigen::VectorXd fe = natural_frequencies_hz(c.string, 8);
  double prev = HUGE_VAL;
  for (int m : {8, 10, 15, 25, 50}) {
    c.cb_modes = {m, m};
    const Eigen::VectorXd cb = CraigBampton(c).frequencies_hz(8);
    const double err = max_rel(cb, fe);
    EXPECT_LT(err, prev) << m << " modes";
    EXPECT_TRUE((cb.array() >= fe.array() * (1 - 1e-12)).all()) << "Rayleigh-Ritz bound, " << m << " modes";
    prev = err;
  }
  c.cb_modes = {7, 7};  // the thesis: converged after about 7 modes (first five frequencies)
  EXPECT_LT(max_rel(CraigBampton(c).frequencies_hz(5), fe.head(5)), 2e-4);
  c.cb_modes = {25, 25};  // the thesis's choice
  EXPECT_LT(max_rel(CraigBampton(c).frequencies_hz(8), fe), 1e-4);
}

TEST(CraigBampton, AllModesReproduceTheFullModelForAnyChain) {
  for (int ns : {2, 3}) {
    Config c = small_chain(ns);
    for (int k = 0; k < ns; ++k) c.cb_modes[k] = c.string.sections[k].elements - (k + 1 < ns ? 1 : 0);
    const CraigBampton cb(c);
    EXPECT_EQ(cb.size(), c.string.n_elements());
    EXPECT_EQ(cb.n_interface(), ns - 1);
    const int n = c.string.n_elements();
    EXPECT_LT(max_rel(cb.frequencies_hz(n), natural_frequencies_hz(c.string, n)), 1e-9) << ns << " substructures";
  }
}

TEST(CraigBampton, AssembledBlocksEqualProjectionOfTheClampedString) {
  Config c = small_chain(3);
  c.cb_modes = {4, 2, 3};
  const CraigBampton cb(c);
  const ClampedMatrices fe = clamp_top(assemble(c.string));
  const Eigen::MatrixXd& P = cb.psi();  // Eq. (6.18)
  EXPECT_LT((P.transpose() * fe.M * P - cb.M()).norm(), 1e-10 * cb.M().norm());  // Eq. (6.17)
  EXPECT_LT((P.transpose() * fe.K * P - cb.K()).norm(), 1e-10 * cb.K().norm());
  const Rayleigh ab = Rayleigh::from_pairs(1.0, 0.05, 10.0, 0.01);
  EXPECT_LT((cb.D() - ab.a * cb.M() - ab.b * cb.K()).norm(), 1e-10 * cb.D().norm());
  EXPECT_EQ(cb.model().M, cb.M());
  EXPECT_EQ(cb.model().bit, P.row(P.rows() - 1));
}

TEST(CraigBampton, SubstructureBlocksHaveTheCraigBamptonStructure) {
  const Config c = preset("thesis-ch6");
  const CraigBampton cb(c);
  ASSERT_EQ(cb.n_substructures(), 2);
  for (const Substructure& s : cb.substructures()) {
    const int m = s.modes;
    EXPECT_EQ(m, 25);
    // Mass-normalized fixed-interface modes: M~^II = I, K~^II = diag(omega^2) (Eq. 6.8).
    EXPECT_LT((s.M.topLeftCorner(m, m) - Eigen::MatrixXd::Identity(m, m)).norm(), 1e-9);
    EXPECT_LT((s.K.topLeftCorner(m, m) - Eigen::MatrixXd(s.omega.cwiseAbs2().asDiagonal())).norm(),
              1e-9 * s.omega.squaredNorm());
    // Static modes (Eq. 6.9): the stiffness coupling blocks vanish.
    EXPECT_LT(s.K.topRightCorner(m, 1).norm(), 1e-8 * s.K.norm());
  }
  // DP (clamped top): K~ positive definite with interface stiffness GJ/L; BHA floats: the rigid
  // rotation of the interface is its null space, K~^GG = 0.
  const Section& dp = c.string.sections[0];
  const double gj_l = dp.shear_modulus() * dp.polar_moment() / dp.length;
  EXPECT_NEAR(cb.substructures()[0].K(25, 25), gj_l, 1e-8 * gj_l);
  EXPECT_LT(std::fabs(cb.substructures()[1].K(25, 25)), 1e-9 * cb.substructures()[1].K.norm());
  // Fixed-interface BHA (clamped-free, 300 m): f1 = c / (4 L).
  const Section& bha = c.string.sections[1];
  EXPECT_NEAR(cb.substructures()[1].omega(0) / (2 * M_PI), bha.wave_speed() / (4 * bha.length), 2e-3);
}

TEST(CraigBampton, StaticInterfaceLoadIsRecoveredExactly) {
  // A torque at the interface: the static modes (Eq. 6.9) carry it exactly, whatever m_k.
  Config c = small_chain(3);
  c.cb_modes = {1, 1, 1};
  const CraigBampton cb(c);
  const ClampedMatrices fe = clamp_top(assemble(c.string));
  for (int node : {c.string.section_end(0), c.string.section_end(1)}) {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(fe.K.rows());
    f(node - 1) = 1.0;
    const Eigen::VectorXd u_fe = fe.K.llt().solve(f);
    const Eigen::VectorXd u_cb = cb.psi() * cb.K().llt().solve(cb.psi().transpose() * f);  // Eq. (6.18)
    EXPECT_LT((u_cb - u_fe).norm(), 1e-10 * u_fe.norm()) << "node " << node;
  }
}

TEST(CraigBampton, RefusesBadModeCountsAndModalDamping) {
  Config c = preset("thesis-ch6");
  c.cb_modes = {25};
  EXPECT_THROW(CraigBampton{c}, std::invalid_argument);
  c.cb_modes = {25, 101};  // the BHA has 100 inner DOFs (99 nodes + bit)
  try {
    CraigBampton cb(c);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("craig_bampton.modes[1] = 101"), std::string::npos) << e.what();
  }
  c.cb_modes = {25, 100};
  EXPECT_NO_THROW(CraigBampton{c});
  c.cb_modes = {0, 25};
  EXPECT_THROW(CraigBampton{c}, std::invalid_argument);
  c.cb_modes = {25, 25};
  c.damping.kind = DampingSpec::Kind::modal;
  EXPECT_THROW(CraigBampton{c}, std::invalid_argument);
}
