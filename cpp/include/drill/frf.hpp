// Frequency response of a (random) reduced model and its Monte Carlo statistical envelopes
// (thesis Eqs. 6.5, 6.15 and section 6.6; convergence integrand of Eq. C.2).
//
// A unit torque at the bit, T(omega) = 1, drives (-omega^2 M + j omega D + K) q = b (b = basis row of
// the bit); the acceleration at an observed node is a(omega) = -omega^2 c q(omega) (c = basis row of
// the node), shown as 20 log10 |a| [dB re 1 rad/s^2 per N m].
//
// Evaluation: one eigen-decomposition per realization, then O(n) work per frequency. The undamped
// problem K phi = w^2 M phi brings M to I and K to diag(w^2); the first-order form of
// x'' + D^ x' + W^2 x = b^ with state z = (W x, x') is A = [0 W; -W -D^] (balanced scales). Its
// eigenpairs (lambda_i, z_i) with x_i = z_i,bottom / lambda_i are those of the symmetric quadratic
// problem (lambda^2 I + lambda D^ + W^2) x = 0, whose resolvent has the partial fractions
//   (s^2 I + s D^ + W^2)^-1 = sum_i x_i x_i^T / ((s - lambda_i) x_i^T (2 lambda_i I + D^) x_i)
// (left eigenvectors equal right ones for symmetric M, D, K; the transpose, not the adjoint).
// So c q(omega) = sum_i r_i / (j omega - lambda_i) with r_i = (c^ x_i)(x_i^T b^) / x_i^T(2 lambda_i + D^) x_i.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <string>
#include <vector>

#include "drill/errors.hpp"
#include "drill/modal.hpp"
#include "drill/parallel.hpp"
#include "drill/quantile.hpp"
#include "drill/stochastic_model.hpp"

namespace drill {

/// Poles and residues of the displacement response c q(omega) of M q'' + D q' + K q = b T.
class FrequencyResponse {
 public:
  FrequencyResponse() = default;

  /// `outputs`: n_obs x n rows c (u_obs = c q); `input`: generalized force b of a unit torque.
  FrequencyResponse(const Eigen::MatrixXd& M, const Eigen::MatrixXd& D, const Eigen::MatrixXd& K,
                    const Eigen::MatrixXd& outputs, const Eigen::VectorXd& input) {
    const Eigen::Index n = M.rows();
    require(M.cols() == n && D.rows() == n && D.cols() == n && K.rows() == n && K.cols() == n, "matrices", n,
            "M, D and K must be square of the same size");
    require(outputs.cols() == n && input.size() == n, "outputs", outputs.cols(),
            "observation rows and input must have the model size " + show(n));
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, M);
    if (es.info() != Eigen::Success) throw std::runtime_error("frequency response: eigenproblem (K, M) failed");
    const Eigen::VectorXd w2 = es.eigenvalues();
    require(w2(0) > 0.0, "stiffness (smallest eigenvalue)", w2(0),
            "must be positive definite (the clamped string has no rigid-body mode)");
    const Eigen::MatrixXd& phi = es.eigenvectors();
    const Eigen::VectorXd w = w2.cwiseSqrt();
    const Eigen::MatrixXd Dh = phi.transpose() * D * phi;
    const Eigen::MatrixXd Ch = outputs * phi;
    const Eigen::VectorXd bh = phi.transpose() * input;
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
    A.topRightCorner(n, n).diagonal() = w;
    A.bottomLeftCorner(n, n).diagonal() = -w;
    A.bottomRightCorner(n, n) = -Dh;
    Eigen::EigenSolver<Eigen::MatrixXd> eig(A);
    if (eig.info() != Eigen::Success) throw std::runtime_error("frequency response: state eigenproblem failed");
    using cd = std::complex<double>;
    poles_ = eig.eigenvalues();
    const Eigen::MatrixXcd X = eig.eigenvectors().bottomRows(n) * poles_.cwiseInverse().asDiagonal();  // x_i
    const Eigen::MatrixXcd DX = Dh.cast<cd>() * X;
    const Eigen::ArrayXcd norm = 2.0 * poles_.array() * X.array().square().colwise().sum().transpose() +
                                 (X.array() * DX.array()).colwise().sum().transpose();  // x^T (2 lambda + D^) x
    const Eigen::ArrayXcd inp = (bh.cast<cd>().transpose() * X).transpose().array();   // x^T b^
    residues_ = (Ch.cast<cd>() * X) * (inp / norm).matrix().asDiagonal();
  }

  const Eigen::VectorXcd& poles() const { return poles_; }
  const Eigen::MatrixXcd& residues() const { return residues_; }
  Eigen::Index n_outputs() const { return residues_.rows(); }

  /// Accelerations -omega^2 c q(omega): re, im are n_freq x n_obs.
  void acceleration(const Eigen::ArrayXd& omega, Eigen::ArrayXXd& re, Eigen::ArrayXXd& im) const {
    const Eigen::Index nf = omega.size(), no = n_outputs();
    re.setZero(nf, no);
    im.setZero(nf, no);
    Eigen::ArrayXd dr(nf), di(nf), inv(nf);
    for (Eigen::Index i = 0; i < poles_.size(); ++i) {
      // 1 / (j omega - lambda) = (dr - j di) / (dr^2 + di^2) with dr = -Re lambda, di = omega - Im lambda
      di = omega - poles_(i).imag();
      dr.setConstant(-poles_(i).real());
      inv = (dr.square() + di.square()).inverse();
      dr *= inv;
      di *= -inv;
      for (Eigen::Index o = 0; o < no; ++o) {
        const double rr = residues_(o, i).real(), ri = residues_(o, i).imag();
        re.col(o) += rr * dr - ri * di;
        im.col(o) += rr * di + ri * dr;
      }
    }
    const Eigen::ArrayXd w2 = -omega.square();
    re.colwise() *= w2;
    im.colwise() *= w2;
  }

  /// 20 log10 |a(omega)| [dB], n_freq x n_obs.
  Eigen::MatrixXd acceleration_db(const Eigen::ArrayXd& omega) const {
    Eigen::ArrayXXd re, im;
    acceleration(omega, re, im);
    return (10.0 * (re.square() + im.square()).log10()).matrix();
  }

 private:
  Eigen::VectorXcd poles_;
  Eigen::MatrixXcd residues_;
};

/// A reduced model's response to a unit torque at the bit observed at some free nodes.
inline FrequencyResponse bit_torque_response(const ReducedModel& r, const Eigen::MatrixXd& M,
                                             const Eigen::MatrixXd& D, const Eigen::MatrixXd& K,
                                             const std::vector<int>& nodes) {
  Eigen::MatrixXd C(nodes.size(), r.basis.cols());
  for (std::size_t o = 0; o < nodes.size(); ++o) C.row(o) = r.basis.row(nodes[o] - 1);
  return FrequencyResponse(M, D, K, C, r.bit.transpose());
}

/// The thesis's observation points (section 6.6): P_obs,1 the first free node below the clamped
/// top, P_obs,2 the DP/BHA interface (bottom of the first section), P_obs,3 the bit.
inline std::vector<int> thesis_observation_nodes(const StringModel& s) {
  return {1, s.section_end(0), s.n_nodes() - 1};
}

struct EnvelopeOptions {
  std::size_t samples = 2500;
  std::uint64_t seed = 1;
  double probability = 0.95;  ///< the envelope holds this probability: quantiles (1 -+ P)/2
  int threads = 0;
};

/// Monte Carlo statistics of the acceleration FRF in dB (n_freq x n_obs matrices).
struct FrfEnvelope {
  Eigen::VectorXd freq_hz;
  std::vector<int> nodes;
  Eigen::MatrixXd nominal_db;  ///< the mean (deterministic) model
  Eigen::MatrixXd mean_db;     ///< sample mean of the dB response
  Eigen::MatrixXd lower_db, upper_db;  ///< quantiles (1 - P)/2 and (1 + P)/2
  Eigen::MatrixXd energy;      ///< n_samples x n_obs: int_B |a_i(omega)|^2 d omega (Eq. C.2)
  std::size_t samples = 0;     ///< 0 when cancelled
};

/// The dB responses of consecutive samples as float rows: row r is one sample's contiguous block,
/// column o n_freq + f its value at node o and frequency f.
using FrfDbRows = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Per-sample results of samples first .. first + count - 1 (row r: sample first + r).
struct FrfSamples {
  FrfDbRows db;            ///< count x (n_obs n_freq): 20 log10 |a(omega)| [dB]; empty when cancelled
  Eigen::MatrixXd energy;  ///< count x n_obs: int_B |a_i(omega)|^2 d omega (Eq. C.2)
};

/// Observation nodes free (1 .. n_free) and a positive, increasing grid of at least two frequencies.
inline void check_frf_grid(const StochasticModel& sm, const std::vector<int>& nodes, const Eigen::VectorXd& freq_hz) {
  const int n_free = static_cast<int>(sm.mean().basis.rows());
  require(!nodes.empty(), "nodes", nodes.size(), "needs at least one observation node");
  for (std::size_t o = 0; o < nodes.size(); ++o)
    require(nodes[o] >= 1 && nodes[o] <= n_free, "nodes[" + std::to_string(o) + "]", nodes[o],
            "must be a free node between 1 and " + show(n_free) + " (node 0 is the clamped top)");
  require(freq_hz.size() >= 2, "freq_hz", freq_hz.size(), "needs at least two frequencies");
  for (Eigen::Index f = 0; f < freq_hz.size(); ++f) {
    require_positive(freq_hz(f), "freq_hz[" + std::to_string(f) + "]");
    if (f) require(freq_hz(f) > freq_hz(f - 1), "freq_hz[" + std::to_string(f) + "]", freq_hz(f),
                   "the frequency grid must be increasing");
  }
}

/// The probability P held by the envelope lies in (0, 1).
inline void check_envelope_probability(double probability) {
  require(std::isfinite(probability) && probability > 0.0 && probability < 1.0, "probability", probability,
          "must lie in (0, 1)");
}

/// Acceleration FRF in dB (Eqs. 6.5, 6.15) and band energy (integrand of Eq. C.2) of samples
/// first .. first + count - 1: realization i of the stochastic model comes from (seed, i) only and
/// each sample writes its own rows, so they do not depend on the thread count or the chunking.
/// Progress counts samples.
inline FrfSamples frf_sample_db(const StochasticModel& sm, const std::vector<int>& nodes,
                                const Eigen::VectorXd& freq_hz, std::uint64_t seed, std::uint64_t first,
                                std::size_t count, int threads = 0, const ProgressFn& progress = nullptr) {
  check_frf_grid(sm, nodes, freq_hz);
  require(count >= 1, "samples", count, "must be at least 1");
  require(first <= (std::uint64_t(1) << 62), "first_sample", first, "must be below 2^62");
  const Eigen::Index nf = freq_hz.size(), no = static_cast<Eigen::Index>(nodes.size());
  const double values = static_cast<double>(count) * static_cast<double>(nf) * static_cast<double>(no);
  require(values <= 2.5e8, "samples", count,
          "x frequencies x nodes = " + show(values) + " values exceeds the 2.5e8 (1 GB) kept for the quantiles");
  const Eigen::ArrayXd omega = 2.0 * M_PI * freq_hz.array();
  Eigen::ArrayXd weight = Eigen::ArrayXd::Zero(nf);  // trapezoid weights in omega
  for (Eigen::Index f = 0; f + 1 < nf; ++f) {
    const double h = 0.5 * (omega(f + 1) - omega(f));
    weight(f) += h;
    weight(f + 1) += h;
  }
  // Each sample writes its own contiguous row (no false sharing between threads).
  FrfSamples out;
  out.db.resize(static_cast<Eigen::Index>(count), no * nf);
  out.energy.resize(static_cast<Eigen::Index>(count), no);
  const bool done = parallel_for(
      count,
      [&](std::size_t r) {
        const std::uint64_t i = first + r;
        Eigen::MatrixXd M, D, K;
        sm.sample_matrices(seed, i, M, D, K);
        Eigen::ArrayXXd re, im;
        bit_torque_response(sm.mean(), M, D, K, nodes).acceleration(omega, re, im);
        const Eigen::ArrayXXd a2 = re.square() + im.square();
        if (!a2.allFinite() || (a2 <= 0.0).any())
          throw std::runtime_error("FRF of sample " + std::to_string(i) + " is not finite and positive");
        const Eigen::ArrayXXd a2db = 10.0 * a2.log10();
        const Eigen::Index row = static_cast<Eigen::Index>(r);
        for (Eigen::Index o = 0; o < no; ++o) {
          out.energy(row, o) = (a2.col(o) * weight).sum();
          out.db.row(row).segment(o * nf, nf) = a2db.col(o).cast<float>().transpose();
        }
      },
      progress, threads);
  if (!done) return FrfSamples{};
  return out;
}

/// Statistics of the dB responses `db` and energies of n_s samples (frf_sample_db's rows,
/// stacked in sample order) with the nominal response of the mean model: mean and quantiles
/// (1 -+ P)/2 per frequency and node, reduced in sample order. Progress counts frequencies;
/// the envelope has samples = 0 when cancelled.
inline FrfEnvelope frf_statistics(const StochasticModel& sm, const std::vector<int>& nodes,
                                  const Eigen::VectorXd& freq_hz, const Eigen::Ref<const FrfDbRows>& db,
                                  const Eigen::MatrixXd& energy, double probability, int threads = 0,
                                  const ProgressFn& progress = nullptr) {
  check_frf_grid(sm, nodes, freq_hz);
  check_envelope_probability(probability);
  const Eigen::Index nf = freq_hz.size(), no = static_cast<Eigen::Index>(nodes.size());
  require(db.rows() >= 1, "samples", db.rows(), "must be at least 1");
  require(db.cols() == no * nf, "db (columns)", db.cols(),
          "must be nodes x frequencies = " + show(no * nf) + " per sample");
  require(energy.rows() == db.rows() && energy.cols() == no, "energy (shape)", energy.rows(),
          "must be one row of " + show(no) + " nodes per sample (" + show(db.rows()) + ")");

  FrfEnvelope env;
  env.freq_hz = freq_hz;
  env.nodes = nodes;
  const ReducedModel& mean = sm.mean();
  const Eigen::ArrayXd omega = 2.0 * M_PI * freq_hz.array();
  env.nominal_db = bit_torque_response(mean, mean.M, mean.D, mean.K, nodes).acceleration_db(omega);
  env.energy = energy;
  env.mean_db.resize(nf, no);
  env.lower_db.resize(nf, no);
  env.upper_db.resize(nf, no);
  const std::size_t ns = static_cast<std::size_t>(db.rows()), nfs = static_cast<std::size_t>(nf);
  const double plo = 0.5 * (1.0 - probability), phi = 0.5 * (1.0 + probability);
  // Blocks of `fb` consecutive frequencies (whole cache lines of each sample's row).
  const std::size_t fb = 16, n_blocks = (nfs + fb - 1) / fb;
  const bool done = parallel_for(
      n_blocks,
      [&](std::size_t b) {
        const std::size_t f0 = b * fb, nb = std::min(fb, nfs - f0);
        std::vector<double> v(nb * ns);  // v[k ns + i]: frequency f0 + k, sample i
        for (Eigen::Index o = 0; o < no; ++o) {
          for (std::size_t i = 0; i < ns; ++i) {
            const float* row = db.row(static_cast<Eigen::Index>(i)).data() + o * nf + static_cast<Eigen::Index>(f0);
            for (std::size_t k = 0; k < nb; ++k) v[k * ns + i] = row[k];
          }
          for (std::size_t k = 0; k < nb; ++k) {
            std::vector<double> col(v.begin() + static_cast<std::ptrdiff_t>(k * ns),
                                    v.begin() + static_cast<std::ptrdiff_t>((k + 1) * ns));
            double sum = 0.0;
            for (double x : col) sum += x;  // index order
            const Eigen::Index fi = static_cast<Eigen::Index>(f0 + k);
            env.mean_db(fi, o) = sum / static_cast<double>(ns);
            env.lower_db(fi, o) = quantile(col, plo);
            env.upper_db(fi, o) = quantile(col, phi);
          }
        }
      },
      progress ? ProgressFn([&](std::size_t d, std::size_t) { return progress(std::min(d * fb, nfs), nfs); })
               : ProgressFn(),
      threads);
  if (!done) return FrfEnvelope{};
  env.samples = ns;
  return env;
}

/// Statistical envelope of the acceleration FRF (section 6.6): frf_sample_db of samples
/// 0 .. samples - 1, then frf_statistics, so results do not depend on the thread count.
/// Progress counts samples, then frequencies.
inline FrfEnvelope frf_envelope(const StochasticModel& sm, const std::vector<int>& nodes,
                                const Eigen::VectorXd& freq_hz, const EnvelopeOptions& opt,
                                const ProgressFn& progress = nullptr) {
  check_envelope_probability(opt.probability);
  const std::size_t ns = opt.samples, total = ns + static_cast<std::size_t>(freq_hz.size());
  const FrfSamples s = frf_sample_db(
      sm, nodes, freq_hz, opt.seed, 0, ns, opt.threads,
      progress ? ProgressFn([&](std::size_t d, std::size_t) { return progress(d, total); }) : ProgressFn());
  if (s.db.rows() == 0) return FrfEnvelope{};
  return frf_statistics(
      sm, nodes, freq_hz, s.db, s.energy, opt.probability, opt.threads,
      progress ? ProgressFn([&](std::size_t d, std::size_t) { return progress(ns + d, total); }) : ProgressFn());
}

}  // namespace drill
