// Soize's random matrix ensembles of the nonparametric probabilistic approach (thesis section 6.1,
// Eqs. 6.1-6.3, and section 6.5, Eqs. 6.24-6.25).
//
//  * SG+ : normalized symmetric positive-definite random matrices G with E[G] = I and dispersion
//          delta = (E||G - I||_F^2 / ||I||_F^2)^(1/2) (Eq. 6.3). Soize's generator: G = L^T L with L
//          upper triangular, off-diagonal L_jk = sigma U_jk (U standard normal), diagonal
//          L_jj = sigma sqrt(2 V_j) with V_j ~ Gamma((n+1)/(2 delta^2) + (1-j)/2) for j = 1..n COUNTED
//          FROM 1, sigma = delta / sqrt(n+1). (A 0-based j there biases E[G] to (1 + delta^2/(n+1)) I.)
//          Admissible dispersions: 0 <= delta < sqrt((n+1)/(n+5)).
//  * SE+ : a random matrix around a symmetric positive-definite mean A = L_A L_A^T (Eq. 6.2):
//          A_rand = L_A G L_A^T (Eq. 6.1).
//  * SE+0: around a positive semi-definite mean A = P_flex C P_flex^T (Eq. 6.24, P_flex the
//          orthonormal eigenvectors of the nonzero eigenvalues C): A_rand = P_flex C_rand P_flex^T with
//          C_rand in SE+ around C (Eq. 6.25). The null space of A is kept exactly; only the range is
//          randomized (floating substructures such as the BHA).
//
// Every realization is returned as a factor F with A_rand = F F^T (F = L_A L_G, or P_flex C^(1/2) L_G
// with G = L_G L_G^T), because SM_CB2 (Eq. 6.22) combines factors of independent realizations.
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <string>

#include "drill/errors.hpp"
#include "drill/rng.hpp"

namespace drill {

/// Largest admissible dispersion of SG+ in dimension n: sqrt((n+1)/(n+5)) (excluded).
inline double max_dispersion(Eigen::Index n) { return std::sqrt((n + 1.0) / (n + 5.0)); }

/// Refuse a dispersion outside [0, sqrt((n+1)/(n+5))) with a message naming the field.
inline void check_dispersion(double delta, Eigen::Index n, const std::string& field) {
  require(std::isfinite(delta), field, delta, "must be a finite number");
  require(delta >= 0.0, field, delta, "must not be negative");
  require(n >= 1, field + " (matrix dimension)", n, "must be at least 1");
  require(delta < max_dispersion(n), field, delta,
          "must be below sqrt((n+1)/(n+5)) = " + show(max_dispersion(n)) + " for a random matrix of dimension n = " +
              show(n) + " (Eq. 6.3 admissible range)");
}

/// Lower-triangular factor L_G of a realization G = L_G L_G^T of SG+ (n x n, dispersion delta).
/// delta = 0 gives the identity exactly. Draws: the n Gamma variables in row order, then the
/// off-diagonal normals row by row.
inline Eigen::MatrixXd sg_plus_factor(Eigen::Index n, double delta, RandomStream& rs,
                                      const std::string& field = "delta") {
  check_dispersion(delta, n, field);
  Eigen::MatrixXd L = Eigen::MatrixXd::Identity(n, n);
  if (delta == 0.0) return L;
  const double sigma = delta / std::sqrt(n + 1.0);
  const double base = (n + 1.0) / (2.0 * delta * delta);
  for (Eigen::Index j = 0; j < n; ++j) {
    // Row j is the (j+1)-th, 1-based: shape (n+1)/(2 delta^2) + (1 - (j+1))/2.
    const double shape = base - 0.5 * static_cast<double>(j);
    L(j, j) = sigma * std::sqrt(2.0 * rs.gamma(shape));
  }
  for (Eigen::Index j = 1; j < n; ++j)
    for (Eigen::Index k = 0; k < j; ++k) L(j, k) = sigma * rs.normal();
  return L;
}

/// A realization of SG+: G = L_G L_G^T, E[G] = I, dispersion delta (Eq. 6.3).
inline Eigen::MatrixXd sg_plus(Eigen::Index n, double delta, RandomStream& rs) {
  const Eigen::MatrixXd L = sg_plus_factor(n, delta, rs);
  return L * L.transpose();
}

/// A mean matrix prepared for SE+ (positive definite, Eq. 6.2) or SE+0 (positive semi-definite,
/// Eq. 6.24): mean = F0 F0^T with F0 the Cholesky factor (n x n) or P_flex C^(1/2) (n x rank).
class RandomMatrixEnsemble {
 public:
  RandomMatrixEnsemble() = default;

  /// `field` names the matrix in error messages; eigenvalues below rank_tol x the largest one
  /// are taken as zero (null space of a floating substructure).
  explicit RandomMatrixEnsemble(const Eigen::MatrixXd& mean, const std::string& field = "matrix",
                                double rank_tol = 1e-9)
      : field_(field), mean_(mean) {
    require(mean.rows() == mean.cols() && mean.rows() >= 1, field + " (rows)", mean.rows(),
            "must be a non-empty square matrix (" + show(mean.cols()) + " columns)");
    require(mean.allFinite(), field, "matrix", "has non-finite entries");
    const double scale = mean.cwiseAbs().maxCoeff();
    require(scale > 0.0, field, "zero matrix", "cannot be randomized (no range)");
    require((mean - mean.transpose()).cwiseAbs().maxCoeff() <= 1e-10 * scale, field, "matrix",
            "must be symmetric");
    const Eigen::MatrixXd sym = 0.5 * (mean + mean.transpose());
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(sym);
    if (es.info() != Eigen::Success) throw std::runtime_error(field + ": symmetric eigenproblem failed");
    const Eigen::VectorXd& ev = es.eigenvalues();  // ascending
    const double tol = rank_tol * ev(ev.size() - 1);
    require(ev(0) >= -tol, field + " (smallest eigenvalue)", ev(0),
            "the mean matrix must be positive semi-definite");
    Eigen::Index zero = 0;
    while (zero < ev.size() && ev(zero) <= tol) ++zero;
    if (zero == 0) {
      Eigen::LLT<Eigen::MatrixXd> llt(sym);  // Eq. (6.2)
      if (llt.info() != Eigen::Success) throw std::runtime_error(field + ": Cholesky factorization failed");
      F0_ = llt.matrixL();
      null_ = Eigen::MatrixXd(mean.rows(), 0);
    } else {
      // Eq. (6.24): [A] = [P] diag(0, C) [P]^T; keep P_flex C^(1/2), the null space separately.
      const Eigen::Index r = ev.size() - zero;
      F0_ = es.eigenvectors().rightCols(r) * ev.tail(r).cwiseSqrt().asDiagonal();
      null_ = es.eigenvectors().leftCols(zero);
    }
  }

  Eigen::Index size() const { return F0_.rows(); }
  const Eigen::MatrixXd& mean() const { return mean_; }
  /// Dimension of the randomized part (n for SE+, rank for SE+0): the n of delta's bound.
  Eigen::Index rank() const { return F0_.cols(); }
  bool semidefinite() const { return null_.cols() > 0; }
  const Eigen::MatrixXd& mean_factor() const { return F0_; }
  /// Orthonormal basis of the mean's null space (n x 0 for SE+).
  const Eigen::MatrixXd& null_space() const { return null_; }
  const std::string& field() const { return field_; }

  /// Factor F of one realization, A_rand = F F^T (Eqs. 6.1, 6.25).
  Eigen::MatrixXd sample_factor(double delta, RandomStream& rs, const std::string& field = "") const {
    const Eigen::MatrixXd LG = sg_plus_factor(rank(), delta, rs, field.empty() ? "delta of " + field_ : field);
    return F0_ * LG;
  }

  /// One realization A_rand = F F^T.
  Eigen::MatrixXd sample(double delta, RandomStream& rs) const {
    const Eigen::MatrixXd F = sample_factor(delta, rs);
    return F * F.transpose();
  }

 private:
  std::string field_;
  Eigen::MatrixXd mean_, F0_, null_;
};

}  // namespace drill
