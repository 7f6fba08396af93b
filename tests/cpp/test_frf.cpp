// Acceleration FRF by partial fractions and its Monte Carlo envelopes (Eqs. 6.5, 6.15, C.2).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <complex>
#include <vector>

#include "drill/frf.hpp"
#include "drill/presets.hpp"

using namespace drill;
using cd = std::complex<double>;

namespace {

Config ch6(int m1 = 10, int m2 = 6) {
  Config c = preset("thesis-ch6");
  c.cb_modes = {m1, m2};
  return c;
}

/// The oracle: a dense complex solve per frequency (what the decomposition avoids).
Eigen::MatrixXcd direct_accel(const Eigen::MatrixXd& M, const Eigen::MatrixXd& D, const Eigen::MatrixXd& K,
                              const Eigen::MatrixXd& C, const Eigen::VectorXd& b, const Eigen::ArrayXd& omega) {
  Eigen::MatrixXcd out(omega.size(), C.rows());
  for (Eigen::Index f = 0; f < omega.size(); ++f) {
    const double w = omega(f);
    const Eigen::MatrixXcd Z = (K - w * w * M).cast<cd>() + cd(0, w) * D.cast<cd>();
    const Eigen::VectorXcd q = Z.partialPivLu().solve(b.cast<cd>());
    out.row(f) = (-w * w * (C.cast<cd>() * q)).transpose();
  }
  return out;
}

}  // namespace

TEST(FrequencyResponse, OneDofMatchesTheClosedForm) {
  Eigen::MatrixXd M(1, 1), D(1, 1), K(1, 1), C(1, 1);
  M << 2.0;
  D << 0.3;
  K << 50.0;
  C << 1.0;
  const FrequencyResponse fr(M, D, K, C, Eigen::VectorXd::Ones(1));
  Eigen::ArrayXd w(4);
  w << 0.5, 4.0, 5.0, 20.0;
  Eigen::ArrayXXd re, im;
  fr.acceleration(w, re, im);
  for (int f = 0; f < 4; ++f) {
    const cd a = -w(f) * w(f) / cd(50.0 - 2.0 * w(f) * w(f), 0.3 * w(f));
    EXPECT_NEAR(re(f, 0), a.real(), 1e-12 * std::abs(a));
    EXPECT_NEAR(im(f, 0), a.imag(), 1e-12 * std::abs(a));
  }
}

TEST(FrequencyResponse, PartialFractionsMatchDenseSolveOnRandomRealizations) {
  const Config c = ch6(25, 25);
  const StochasticModel sm(c, StochasticKind::cb2, std::vector<Dispersions>(2, Dispersions::Constant(0.2)));
  const std::vector<int> nodes = thesis_observation_nodes(c.string);
  Eigen::ArrayXd w = 2 * M_PI * Eigen::ArrayXd::LinSpaced(40, 0.01, 12.0);
  Eigen::MatrixXd C(3, sm.size());
  for (int o = 0; o < 3; ++o) C.row(o) = sm.mean().basis.row(nodes[o] - 1);
  for (int i = 0; i < 3; ++i) {
    Eigen::MatrixXd M, D, K;
    sm.sample_matrices(1, i, M, D, K);
    Eigen::ArrayXXd re, im;
    bit_torque_response(sm.mean(), M, D, K, nodes).acceleration(w, re, im);
    const Eigen::MatrixXcd ref = direct_accel(M, D, K, C, sm.mean().bit.transpose(), w);
    const Eigen::MatrixXcd got = re.matrix().cast<cd>() + cd(0, 1) * im.matrix().cast<cd>();
    EXPECT_LT(((got - ref).array().abs() / ref.array().abs()).maxCoeff(), 1e-8) << "sample " << i;
  }
}

TEST(FrfEnvelope, HoldsTheProbabilityAndIsThreadInvariant) {
  const Config c = ch6();
  const StochasticModel sm(c, StochasticKind::cb2, thesis_case_dispersions(3));
  const std::vector<int> nodes = thesis_observation_nodes(c.string);
  const Eigen::VectorXd fhz = Eigen::VectorXd::LinSpaced(60, 0.05, 10.0);
  EnvelopeOptions o;
  o.samples = 400;
  o.seed = 4;
  o.probability = 0.9;
  o.threads = 1;
  const FrfEnvelope e1 = frf_envelope(sm, nodes, fhz, o);
  o.threads = 2;
  const FrfEnvelope e2 = frf_envelope(sm, nodes, fhz, o);
  ASSERT_EQ(e1.samples, 400u);
  EXPECT_EQ(e1.lower_db, e2.lower_db);
  EXPECT_EQ(e1.upper_db, e2.upper_db);
  EXPECT_EQ(e1.mean_db, e2.mean_db);
  EXPECT_EQ(e1.energy, e2.energy);
  EXPECT_TRUE((e1.lower_db.array() <= e1.mean_db.array()).all());
  EXPECT_TRUE((e1.mean_db.array() <= e1.upper_db.array()).all());
  // Each sample's curve, recomputed independently, lies inside the envelope 90 % of the time; its
  // energy is the trapezoid integral of |a|^2 over omega.
  const Eigen::ArrayXd w = 2 * M_PI * fhz.array();
  long inside = 0, total = 0;
  for (std::size_t i = 0; i < o.samples; ++i) {
    Eigen::MatrixXd M, D, K;
    sm.sample_matrices(o.seed, i, M, D, K);
    Eigen::ArrayXXd re, im;
    bit_torque_response(sm.mean(), M, D, K, nodes).acceleration(w, re, im);
    const Eigen::ArrayXXd a2 = re.square() + im.square();
    const Eigen::ArrayXXd db = 10.0 * a2.log10();
    inside += ((db >= e1.lower_db.array() - 1e-4) && (db <= e1.upper_db.array() + 1e-4)).count();
    total += db.size();
    if (i < 3) {
      const double energy = (0.5 * (a2.col(2).head(59) + a2.col(2).tail(59)) * (w.tail(59) - w.head(59))).sum();
      EXPECT_NEAR(e1.energy(static_cast<Eigen::Index>(i), 2), energy, 1e-9 * energy);
    }
  }
  EXPECT_NEAR(static_cast<double>(inside) / total, 0.9, 0.01);
}

TEST(FrfEnvelope, ZeroDispersionCollapsesOnTheNominalResponse) {
  const Config c = ch6();
  const StochasticModel sm(c, StochasticKind::cb1, std::vector<Dispersions>(2, Dispersions::Zero()));
  EnvelopeOptions o;
  o.samples = 5;
  const FrfEnvelope e =
      frf_envelope(sm, thesis_observation_nodes(c.string), Eigen::VectorXd::LinSpaced(30, 0.1, 10.0), o);
  EXPECT_LT((e.upper_db - e.nominal_db).cwiseAbs().maxCoeff(), 1e-4);  // float storage of the samples
  EXPECT_LT((e.lower_db - e.nominal_db).cwiseAbs().maxCoeff(), 1e-4);
}

TEST(FrfEnvelope, RefusesBadInput) {
  const Config c = ch6();
  const StochasticModel sm(c, StochasticKind::cb2, thesis_case_dispersions(1));
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(10, 0.1, 10.0);
  EnvelopeOptions o;
  o.samples = 2;
  EXPECT_THROW(frf_envelope(sm, {0}, f, o), std::invalid_argument);    // the clamped top
  EXPECT_THROW(frf_envelope(sm, {201}, f, o), std::invalid_argument);  // beyond the bit
  EXPECT_THROW(frf_envelope(sm, {}, f, o), std::invalid_argument);
  Eigen::VectorXd bad = f;
  bad(3) = bad(2);
  EXPECT_THROW(frf_envelope(sm, {1}, bad, o), std::invalid_argument);  // not increasing
  bad = f;
  bad(0) = 0.0;
  EXPECT_THROW(frf_envelope(sm, {1}, bad, o), std::invalid_argument);  // a = 0 at 0 Hz
  o.probability = 1.0;
  EXPECT_THROW(frf_envelope(sm, {1}, f, o), std::invalid_argument);
  o.probability = 0.95;
  o.samples = 0;
  EXPECT_THROW(frf_envelope(sm, {1}, f, o), std::invalid_argument);
}

TEST(FrfEnvelope, ProgressCanCancel) {
  const Config c = ch6();
  const StochasticModel sm(c, StochasticKind::cb2, thesis_case_dispersions(2));
  EnvelopeOptions o;
  o.samples = 64;
  o.threads = 2;
  std::size_t calls = 0;
  const FrfEnvelope e = frf_envelope(sm, {1}, Eigen::VectorXd::LinSpaced(10, 0.1, 10.0), o,
                                     [&](std::size_t, std::size_t total) {
                                       EXPECT_EQ(total, 74u);
                                       return ++calls < 2;
                                     });
  EXPECT_EQ(e.samples, 0u);
  EXPECT_EQ(calls, 2u);
}

TEST(FrfEnvelope, ChunksOfSamplesGiveTheSameRowsAndStatistics) {
  const Config c = ch6();
  const StochasticModel sm(c, StochasticKind::cb2, thesis_case_dispersions(4));
  const std::vector<int> nodes = thesis_observation_nodes(c.string);
  const Eigen::VectorXd fhz = Eigen::VectorXd::LinSpaced(40, 0.05, 10.0);
  EnvelopeOptions o;
  o.samples = 11;
  o.seed = 2;
  o.probability = 0.8;
  const FrfEnvelope whole = frf_envelope(sm, nodes, fhz, o);
  const FrfSamples all = frf_sample_db(sm, nodes, fhz, o.seed, 0, 11);
  const FrfSamples head = frf_sample_db(sm, nodes, fhz, o.seed, 0, 5, 1);
  const FrfSamples tail = frf_sample_db(sm, nodes, fhz, o.seed, 5, 6, 2);
  ASSERT_EQ(tail.db.rows(), 6);
  ASSERT_EQ(tail.db.cols(), 3 * 40);
  EXPECT_EQ(tail.db, all.db.bottomRows(6));
  EXPECT_EQ(tail.energy, all.energy.bottomRows(6));
  FrfDbRows db(11, 3 * 40);
  db << head.db, tail.db;
  Eigen::MatrixXd energy(11, 3);
  energy << head.energy, tail.energy;
  const FrfEnvelope e = frf_statistics(sm, nodes, fhz, db, energy, o.probability);
  ASSERT_EQ(e.samples, 11u);
  EXPECT_EQ(e.nominal_db, whole.nominal_db);
  EXPECT_EQ(e.mean_db, whole.mean_db);
  EXPECT_EQ(e.lower_db, whole.lower_db);
  EXPECT_EQ(e.upper_db, whole.upper_db);
  EXPECT_EQ(e.energy, whole.energy);
  // Row r of a chunk is sample first + r: node o, frequency f at column o n_freq + f.
  Eigen::MatrixXd M, D, K;
  sm.sample_matrices(o.seed, 7, M, D, K);
  const Eigen::MatrixXd db7 = bit_torque_response(sm.mean(), M, D, K, nodes).acceleration_db(2 * M_PI * fhz.array());
  EXPECT_NEAR(tail.db(2, 2 * 40 + 17), db7(17, 2), 1e-4);
  EXPECT_THROW(frf_statistics(sm, nodes, fhz, db.leftCols(3 * 39), energy, 0.9), std::invalid_argument);
  EXPECT_THROW(frf_statistics(sm, nodes, fhz, db, energy.topRows(10), 0.9), std::invalid_argument);
}
