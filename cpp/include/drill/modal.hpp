// Generalized eigenproblem (Eq. 2.7), damping models and the reduced-order model (Eqs. 2.8-2.10).
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <vector>

#include "drill/errors.hpp"
#include "drill/fem.hpp"
#include "drill/names.hpp"

namespace drill {

/// Mass-normalized elastic modes in ascending order: Phi^T M Phi = I, Phi^T K Phi = diag(omega^2).
struct ModalBasis {
  Eigen::VectorXd omega;  ///< natural circular frequencies [rad/s]
  Eigen::MatrixXd phi;    ///< n x m mode shapes
};

/// Solve [K] phi = lambda [M] phi (Eq. 2.7) and keep the first m modes.
inline ModalBasis solve_modes(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, int m) {
  require(m >= 1 && m <= K.rows(), "rom.modes", m,
          "must be between 1 and the number of free DOFs (" + show(K.rows()) + ")");
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, M);
  if (es.info() != Eigen::Success) throw std::runtime_error("generalized eigenproblem (2.7) failed");
  ModalBasis b;
  b.omega = es.eigenvalues().head(m).cwiseMax(0.0).cwiseSqrt();
  b.phi = es.eigenvectors().leftCols(m);
  return b;
}

/// A damping ratio zeta in [0, 1]: 1 is critical damping; above it a "mode" no longer vibrates
/// and a ratio such as 5 is almost always a percentage typed as a fraction (0.05).
inline void require_damping_ratio(double zeta, const std::string& field) {
  require_non_negative(zeta, field);
  require(zeta <= 1.0, field, zeta, "must be at most 1 (critical damping; 5 % is written 0.05)");
}

/// Rayleigh coefficients (a, b) with D = a M + b K giving ratio z1 at f1 and z2 at f2 [Hz]:
/// zeta(omega) = a / (2 omega) + b omega / 2.
struct Rayleigh {
  double a = 0.0, b = 0.0;
  static Rayleigh from_pairs(double f1, double z1, double f2, double z2) {
    require_positive(f1, "damping.pairs[0].frequency_hz");
    require_positive(f2, "damping.pairs[1].frequency_hz");
    require_damping_ratio(z1, "damping.pairs[0].ratio");
    require_damping_ratio(z2, "damping.pairs[1].ratio");
    require(f1 != f2, "damping.pairs[1].frequency_hz", f2, "must differ from the first frequency");
    const double w1 = 2.0 * M_PI * f1, w2 = 2.0 * M_PI * f2;
    const double den = w2 * w2 - w1 * w1;
    return {2.0 * w1 * w2 * (z1 * w2 - z2 * w1) / den, 2.0 * (z2 * w2 - z1 * w1) / den};
  }
  double ratio(double omega) const { return a / (2.0 * omega) + b * omega / 2.0; }
};

/// Damping of the reduced model: modal ratios (diagonal generalized damping, the thesis's
/// choice: 0.095 for mode 1 and 0.02 for the others; the last ratio repeats) or Rayleigh.
struct DampingSpec {
  enum class Kind { modal, rayleigh } kind = Kind::modal;
  std::vector<double> ratios{0.095, 0.02};
  double f1 = 1.0, z1 = 0.05, f2 = 10.0, z2 = 0.01;

  /// The damping models by name (damping.type).
  static constexpr Named<Kind> kinds[] = {{Kind::modal, "modal"}, {Kind::rayleigh, "rayleigh"}};
  static Kind parse_kind(const std::string& s) { return parse_name(kinds, s, "damping.type", "damping"); }
  static std::string kind_name(Kind k) { return name_of(kinds, k); }

  void validate() const {
    if (kind == Kind::modal) {
      require(!ratios.empty(), "damping.ratios", ratios.size(), "needs at least one ratio");
      for (std::size_t j = 0; j < ratios.size(); ++j)
        require_damping_ratio(ratios[j], "damping.ratios[" + std::to_string(j) + "]");
    } else {
      Rayleigh::from_pairs(f1, z1, f2, z2);
    }
  }
  double modal_ratio(int j) const {
    return ratios[std::min<std::size_t>(static_cast<std::size_t>(j), ratios.size() - 1)];
  }
};

/// A reduced model u = [basis] q of the clamped string (Eqs. 2.8-2.10), generic enough to hold
/// the modal ROM, a Craig-Bampton model (Eq. 6.18) or random realizations of either.
struct ReducedModel {
  Eigen::MatrixXd M, D, K;         ///< generalized matrices (Eq. 2.9)
  Eigen::MatrixXd basis;           ///< n x m reduction basis
  Eigen::RowVectorXd bit;          ///< basis row of the bit DOF: u_bit = bit q
  Eigen::RowVectorXd top_torque;   ///< elastic torque the top drive applies: T_top = top_torque q
  Eigen::VectorXd top_load;        ///< basis^T (M 1 + M_f0): inertia load per unit top acceleration
  Eigen::VectorXd init_velocity;   ///< M~^-1 basis^T M 1: q'(0) = -Omega init_velocity (Eq. 2.10)

  int size() const { return static_cast<int>(M.rows()); }
};

/// Project the clamped FE model on a basis and fill the top/bit couplings.
inline ReducedModel project(const ClampedMatrices& c, const Eigen::MatrixXd& basis,
                            const Eigen::MatrixXd& D_reduced) {
  ReducedModel r;
  r.basis = basis;
  r.M = basis.transpose() * c.M * basis;
  r.K = basis.transpose() * c.K * basis;
  r.D = D_reduced;
  r.bit = basis.row(basis.rows() - 1);
  r.top_torque = c.k_top.transpose() * basis;
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(c.M.rows());
  const Eigen::VectorXd m1 = c.M * ones;
  r.top_load = basis.transpose() * (m1 + c.m_top);
  r.init_velocity = r.M.ldlt().solve(basis.transpose() * m1);
  return r;
}

/// Modal reduced-order model on the first m elastic modes (Eqs. 2.7-2.10).
struct ModalROM {
  ReducedModel model;
  Eigen::VectorXd omega;  ///< retained natural circular frequencies [rad/s]
};

inline ModalROM build_modal_rom(const StringModel& s, int modes, const DampingSpec& damping) {
  damping.validate();
  const ClampedMatrices c = clamp_top(assemble(s));
  const ModalBasis mb = solve_modes(c.K, c.M, modes);
  Eigen::MatrixXd D;
  if (damping.kind == DampingSpec::Kind::modal) {
    D = Eigen::MatrixXd::Zero(modes, modes);  // Phi^T M Phi = I: D~ = diag(2 zeta_j omega_j)
    for (int j = 0; j < modes; ++j) D(j, j) = 2.0 * damping.modal_ratio(j) * mb.omega(j);
  } else {
    const Rayleigh ab = Rayleigh::from_pairs(damping.f1, damping.z1, damping.f2, damping.z2);
    D = (ab.a * Eigen::VectorXd::Ones(modes) + ab.b * mb.omega.cwiseAbs2()).asDiagonal();
  }
  return {project(c, mb.phi, D), mb.omega};
}

/// First n natural frequencies [Hz] of the clamped string.
inline Eigen::VectorXd natural_frequencies_hz(const StringModel& s, int n) {
  const ClampedMatrices c = clamp_top(assemble(s));
  return solve_modes(c.K, c.M, n).omega / (2.0 * M_PI);
}

}  // namespace drill
