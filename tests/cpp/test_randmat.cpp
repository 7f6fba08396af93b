// SG+, SE+ and SE+0 random matrices (Eqs. 6.1-6.3, 6.24-6.25): positive definiteness, E[G] = I with
// the 1-based Gamma shape, the estimated dispersion, the kept null space, and refused dispersions.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <string>

#include "drill/randmat.hpp"
#include "min_eig.hpp"

using namespace drill;

namespace {

Eigen::MatrixXd spd(int n, unsigned seed) {
  RandomStream rs(seed, 0, 99);
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = rs.normal();
  return B * B.transpose() + n * Eigen::MatrixXd::Identity(n, n);
}

}  // namespace

TEST(SgPlus, SampleMeanIsIdentityWithOneBasedShape) {
  const int n = 10, N = 20000;
  const double delta = 0.5;
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < N; ++i) {
    RandomStream rs(7, i);
    sum += sg_plus(n, delta, rs);
  }
  const Eigen::MatrixXd mean = sum / N;
  // A 0-based j in the Gamma shape would bias every diagonal entry by delta^2/(n+1) = 0.0227.
  const double bias_of_trap = delta * delta / (n + 1);
  const double diag_avg = mean.diagonal().mean();
  EXPECT_NEAR(diag_avg, 1.0, 0.003);
  EXPECT_GT(bias_of_trap, 5 * 0.003);
  for (int j = 0; j < n; ++j) EXPECT_NEAR(mean(j, j), 1.0, 0.012) << "diagonal entry " << j + 1;
  EXPECT_LT((mean - Eigen::MatrixXd(mean.diagonal().asDiagonal())).cwiseAbs().maxCoeff(), 0.01);
}

TEST(SgPlus, EstimatedDispersionMatchesDelta) {
  const int n = 8, N = 20000;
  for (double delta : {0.1, 0.3, 0.6}) {
    double s = 0.0;
    for (int i = 0; i < N; ++i) {
      RandomStream rs(11, i);
      s += (sg_plus(n, delta, rs) - Eigen::MatrixXd::Identity(n, n)).squaredNorm();
    }
    const double estimate = std::sqrt(s / N / n);  // Eq. (6.3), ||I||_F^2 = n
    EXPECT_NEAR(estimate / delta, 1.0, 0.02) << "delta " << delta;
  }
}

TEST(SgPlus, SamplesArePositiveDefiniteNearTheBound) {
  const int n = 26;
  const double delta = 0.95 * max_dispersion(n);
  for (int i = 0; i < 300; ++i) {
    RandomStream rs(3, i);
    const Eigen::MatrixXd L = sg_plus_factor(n, delta, rs);
    EXPECT_EQ(Eigen::MatrixXd(L.triangularView<Eigen::StrictlyUpper>()).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_GT(L.diagonal().minCoeff(), 0.0);
    EXPECT_GT(min_eig(L * L.transpose()), 0.0) << "sample " << i;
  }
}

TEST(SgPlus, ZeroDispersionIsIdentityAndStreamsReproduce) {
  RandomStream a(5, 2), b(5, 2), c(5, 3);
  EXPECT_EQ(sg_plus(6, 0.0, a), Eigen::MatrixXd::Identity(6, 6));
  const Eigen::MatrixXd g1 = sg_plus(6, 0.3, b), g2 = sg_plus(6, 0.3, c);
  RandomStream b2(5, 2);
  EXPECT_EQ(g1, sg_plus(6, 0.3, b2));
  EXPECT_GT((g1 - g2).norm(), 1e-3);
}

TEST(SgPlus, RefusesInadmissibleDispersion) {
  RandomStream rs(1, 0);
  const int n = 10;
  EXPECT_THROW(sg_plus(n, max_dispersion(n), rs), std::invalid_argument);
  EXPECT_THROW(sg_plus(n, 0.9, rs), std::invalid_argument);  // sqrt(11/15) = 0.856
  EXPECT_THROW(sg_plus(n, -0.1, rs), std::invalid_argument);
  EXPECT_THROW(sg_plus(n, std::nan(""), rs), std::invalid_argument);
  EXPECT_NO_THROW(sg_plus(n, 0.85, rs));
  try {
    check_dispersion(0.9, n, "delta_K,inner,DP");
    FAIL();
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("delta_K,inner,DP = 0.9"), std::string::npos) << msg;
    EXPECT_NE(msg.find("sqrt((n+1)/(n+5))"), std::string::npos) << msg;
  }
}

TEST(SePlus, MeanIsReproducedAndSamplesArePositiveDefinite) {
  const int n = 6, N = 20000;
  const Eigen::MatrixXd A = spd(n, 1);
  const RandomMatrixEnsemble e(A, "A");
  EXPECT_FALSE(e.semidefinite());
  EXPECT_EQ(e.rank(), n);
  EXPECT_LT((e.mean_factor() * e.mean_factor().transpose() - A).norm(), 1e-12 * A.norm());  // Eq. (6.2)
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < N; ++i) {
    RandomStream rs(2, i);
    const Eigen::MatrixXd S = e.sample(0.4, rs);
    if (i < 200) EXPECT_GT(min_eig(S), 0.0);
    sum += S;
  }
  EXPECT_LT((sum / N - A).norm() / A.norm(), 0.01);
}

TEST(SePlusZero, NullSpaceIsKeptExactlyAndRangeRandomized) {
  // A positive semi-definite mean of rank 4 in dimension 6 (a floating substructure).
  RandomStream rs0(9, 0, 5);
  Eigen::MatrixXd B(6, 4);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 4; ++j) B(i, j) = rs0.normal();
  const Eigen::MatrixXd A = B * B.transpose();
  const RandomMatrixEnsemble e(A, "K");
  ASSERT_TRUE(e.semidefinite());
  EXPECT_EQ(e.rank(), 4);
  const Eigen::MatrixXd N0 = e.null_space();
  ASSERT_EQ(N0.cols(), 2);
  EXPECT_LT((A * N0).norm(), 1e-12 * A.norm());
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(6, 6);
  const int N = 20000;
  for (int i = 0; i < N; ++i) {
    RandomStream rs(4, i);
    const Eigen::MatrixXd S = e.sample(0.5, rs);
    EXPECT_LT((S * N0).norm(), 1e-12 * S.norm()) << "sample " << i;  // Eq. (6.25): null space kept
    if (i < 100) {
      const Eigen::MatrixXd P = e.mean_factor();  // P_flex C^(1/2): the range is randomized
      EXPECT_GT(min_eig(P.transpose() * S * P), 0.0);
      EXPECT_GT((S - A).norm(), 1e-3 * A.norm());
    }
    sum += S;
  }
  EXPECT_LT((sum / N - A).norm() / A.norm(), 0.01);
  // The admissible dispersion follows the rank (4), not the dimension (6).
  RandomStream rs(1, 1);
  EXPECT_THROW(e.sample(max_dispersion(4), rs), std::invalid_argument);
}

TEST(RandomMatrixEnsemble, RefusesBadMeans) {
  Eigen::MatrixXd A = spd(4, 3);
  A(0, 1) += 1.0;
  EXPECT_THROW(RandomMatrixEnsemble(A, "A"), std::invalid_argument);  // not symmetric
  Eigen::MatrixXd I = -Eigen::MatrixXd::Identity(3, 3);
  I(0, 0) = 1.0;
  EXPECT_THROW(RandomMatrixEnsemble(I, "A"), std::invalid_argument);  // indefinite
  EXPECT_THROW(RandomMatrixEnsemble(Eigen::MatrixXd::Zero(3, 3), "A"), std::invalid_argument);
}
