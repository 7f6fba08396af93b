// Stochastic models SM_full, SM_CB1, SM_CB2 (Eqs. 6.4, 6.19-6.25) on the thesis-ch6 string.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "drill/presets.hpp"
#include "drill/stochastic_model.hpp"
#include "min_eig.hpp"

using namespace drill;

namespace {

Config ch6_16_modes(int m1 = 10, int m2 = 6) {
  Config c = preset("thesis-ch6");
  c.cb_modes = {m1, m2};
  c.modes = 16;
  return c;
}

std::vector<Dispersions> all(int ns, double d) { return std::vector<Dispersions>(ns, Dispersions::Constant(d)); }

}  // namespace

TEST(StochasticModel, ZeroDispersionGivesTheMeanModel) {
  for (StochasticKind k : {StochasticKind::full, StochasticKind::cb1, StochasticKind::cb2}) {
    const StochasticModel sm(ch6_16_modes(), k, all(k == StochasticKind::full ? 1 : 2, 0.0));
    Eigen::MatrixXd M, D, K;
    sm.sample_matrices(3, 17, M, D, K);
    EXPECT_LT((M - sm.mean().M).norm(), 1e-12 * M.norm()) << to_string(k);
    EXPECT_LT((D - sm.mean().D).norm(), 1e-12 * D.norm()) << to_string(k);
    EXPECT_LT((K - sm.mean().K).norm(), 1e-12 * K.norm()) << to_string(k);
  }
}

TEST(StochasticModel, SamplesArePositiveDefiniteAndReproducible) {
  for (StochasticKind k : {StochasticKind::full, StochasticKind::cb1, StochasticKind::cb2}) {
    const StochasticModel sm(ch6_16_modes(), k, all(k == StochasticKind::full ? 1 : 2, 0.3));
    for (int i = 0; i < 20; ++i) {
      Eigen::MatrixXd M, D, K, M2, D2, K2;
      sm.sample_matrices(5, i, M, D, K);
      EXPECT_GT(min_eig(M), 0.0);
      EXPECT_GT(min_eig(D), 0.0);
      EXPECT_GT(min_eig(K), 0.0) << "the clamped assembly stays positive definite";
      sm.sample_matrices(5, i, M2, D2, K2);
      EXPECT_EQ(K, K2);
      sm.sample_matrices(5, i + 1, M2, D2, K2);
      EXPECT_GT((K - K2).norm(), 1e-6 * K.norm());
    }
  }
}

TEST(StochasticModel, FloatingBhaStiffnessUsesSePlusZero) {
  const StochasticModel sm(ch6_16_modes(10, 6), StochasticKind::cb2, all(2, 0.1));
  EXPECT_FALSE(sm.ensemble(0, 2).semidefinite());  // DP, clamped top
  EXPECT_TRUE(sm.ensemble(1, 2).semidefinite());   // BHA floats
  EXPECT_EQ(sm.ensemble(1, 2).rank(), 6);
  const Eigen::MatrixXd null = sm.ensemble(1, 2).null_space();
  ASSERT_EQ(null.cols(), 1);
  EXPECT_NEAR(std::fabs(null(6, 0)), 1.0, 1e-9);  // the interface rotation
  EXPECT_FALSE(sm.ensemble(1, 0).semidefinite());
  EXPECT_FALSE(sm.ensemble(1, 1).semidefinite());
}

TEST(StochasticModel, Cb2SeparatesInnerAndInterfaceBlocks) {
  // Eq. (6.22): with only interface dispersions, every inner-inner block keeps its mean value;
  // with only inner dispersions, the interface-interface block keeps its mean value.
  const Config c = ch6_16_modes(10, 6);
  const StochasticModel iface(c, StochasticKind::cb2, thesis_case_dispersions(7));
  const StochasticModel inner(c, StochasticKind::cb2, thesis_case_dispersions(6));
  const CraigBampton& cb = *iface.craig_bampton();
  const int g = cb.interface_offset();
  Eigen::MatrixXd M, D, K;
  for (int i = 0; i < 5; ++i) {
    iface.sample_matrices(1, i, M, D, K);
    EXPECT_LT((K.topLeftCorner(g, g) - cb.K().topLeftCorner(g, g)).norm(), 1e-12 * cb.K().norm());
    EXPECT_LT((M.topLeftCorner(g, g) - cb.M().topLeftCorner(g, g)).norm(), 1e-12 * cb.M().norm());
    EXPECT_GT(std::fabs(M(g, g) / cb.M()(g, g) - 1.0), 1e-6);
    inner.sample_matrices(1, i, M, D, K);
    EXPECT_NEAR(M(g, g), cb.M()(g, g), 1e-12 * cb.M()(g, g));
    EXPECT_NEAR(K(g, g), cb.K()(g, g), 1e-12 * cb.K()(g, g));
    EXPECT_GT((K.topLeftCorner(g, g) - cb.K().topLeftCorner(g, g)).norm(), 1e-6 * cb.K().norm());
  }
}

TEST(StochasticModel, DpOnlyCaseLeavesTheBhaInnerBlockUnchanged) {
  const StochasticModel sm(ch6_16_modes(10, 6), StochasticKind::cb2, thesis_case_dispersions(4));
  const CraigBampton& cb = *sm.craig_bampton();
  const int o = cb.inner_offset(1), m = cb.substructures()[1].modes;
  Eigen::MatrixXd M, D, K;
  sm.sample_matrices(2, 0, M, D, K);
  EXPECT_EQ(M.block(o, o, m, m), cb.M().block(o, o, m, m));
  EXPECT_EQ(K.block(o, o, m, m), cb.K().block(o, o, m, m));
  EXPECT_GT((M.block(0, 0, 10, 10) - cb.M().block(0, 0, 10, 10)).norm(), 1e-6);
}

TEST(StochasticModel, SampleMeanOfCb1AndFullTendsToTheMean) {
  for (StochasticKind k : {StochasticKind::full, StochasticKind::cb1}) {
    const StochasticModel sm(ch6_16_modes(6, 4), k, all(k == StochasticKind::full ? 1 : 2, 0.3));
    Eigen::MatrixXd sM = Eigen::MatrixXd::Zero(sm.size(), sm.size()), sK = sM, M, D, K;
    const int N = 4000;
    for (int i = 0; i < N; ++i) {
      sm.sample_matrices(8, i, M, D, K);
      sM += M;
      sK += K;
    }
    EXPECT_LT((sM / N - sm.mean().M).norm() / sm.mean().M.norm(), 0.01) << to_string(k);
    EXPECT_LT((sK / N - sm.mean().K).norm() / sm.mean().K.norm(), 0.01) << to_string(k);
  }
}

TEST(StochasticModel, RefusesBadDispersionsAndCases) {
  const Config c = ch6_16_modes(10, 6);
  std::vector<Dispersions> d = all(2, 0.1);
  d[1](2, 1) = 0.9;  // delta_K,interface,BHA above sqrt(7/11) = 0.80 (rank 6 of the floating BHA)
  try {
    StochasticModel sm(c, StochasticKind::cb2, d);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("delta_K,interface,BHA = 0.9"), std::string::npos) << e.what();
  }
  d[1](2, 1) = -0.1;
  EXPECT_THROW(StochasticModel(c, StochasticKind::cb2, d), std::invalid_argument);
  EXPECT_THROW(StochasticModel(c, StochasticKind::cb1, all(3, 0.1)), std::invalid_argument);
  EXPECT_THROW(StochasticModel(c, StochasticKind::full, all(2, 0.1)), std::invalid_argument);
  EXPECT_THROW(thesis_case_dispersions(0), std::invalid_argument);
  EXPECT_THROW(thesis_case_dispersions(8), std::invalid_argument);
  EXPECT_THROW(parse_stochastic_kind("SM_CB3"), std::invalid_argument);
  const std::vector<Dispersions> t4 = thesis_case_dispersions(4);
  EXPECT_EQ(t4[0], Dispersions::Constant(0.1));
  EXPECT_EQ(t4[1], Dispersions::Zero());
}

TEST(StochasticModel, SampleTopCouplingsFollowTheRandomMatrices) {
  // A top drive with inertia (issue 15) needs the rotating frame's load and the top torque of each
  // realization (StochasticModel::top_coupling): the random mass on the rigid rotation c, and a top
  // torque that carries the torque on bit in steady drilling, T_top = -top_torque K~^-1 bit^T T_bit = T_bit.
  const StochasticModel sm(ch6_16_modes(), StochasticKind::cb2, all(2, 0.1));
  const ReducedModel& m = sm.mean();
  const Eigen::VectorXd& c = m.init_velocity;
  auto carried = [](const ReducedModel& r, const Eigen::RowVectorXd& top_torque) {
    return -(top_torque * r.K.ldlt().solve(r.bit.transpose()))(0);  // T_top per unit T_bit at equilibrium
  };
  EXPECT_NEAR(carried(m, m.top_torque), 1.0, 0.005);
  double worst_mean_vectors = 0.0;
  for (std::uint64_t i = 0; i < 5; ++i) {
    const ReducedModel r = sm.sample(1, i);
    EXPECT_LT((r.top_load - r.M * c - (m.top_load - m.M * c)).norm(), 1e-12 * m.top_load.norm()) << i;
    EXPECT_NEAR(carried(r, r.top_torque), 1.0, 0.01) << i;
    worst_mean_vectors = std::max(worst_mean_vectors, std::fabs(carried(r, m.top_torque) - 1.0));
    EXPECT_EQ(r.bit, m.bit);
    EXPECT_EQ(r.init_velocity, m.init_velocity);
  }
  EXPECT_GT(worst_mean_vectors, 0.05) << "the mean model's top torque does not carry a random string's torque";
}
