// The axial finite-element model of the string and its modal reduction: the axial counterpart of
// fem.hpp and modal.hpp, on the same sections and the same mesh.
//
// Each section is a bar of linear two-node elements with the consistent mass matrix,
//   k_e = E A / h [ 1 -1; -1 1 ],   m_e = rho A h / 6 [ 2 1; 1 2 ],   A = pi (r_o^2 - r_i^2),
// the axial analogue of Eqs. (2.1)-(2.6) (G J -> E A, rho J -> rho A), plus a lumped mass at the bit
// (axial.bit_mass_kg: a BHA or the rig's rock holder). Node 0 is the top, the last node the bit; the
// axial displacement is positive downwards (into the rock). Two top boundaries:
//  * feed       the top is driven at a constant rate of penetration V0: the displacement relative to
//               V0 t is clamped at the top (nodes 1..n free), a fixed-free bar whose natural
//               frequencies tend to (2k - 1) c / (4 L), c = sqrt(E / rho), for a uniform string
//               (tests/cpp/test_axial_string.cpp);
//  * jack       the top is driven by a force-regulated feed, the rig's electrical jack (thesis section
//               5.1): the top moves at X' = V0 + kappa (W_s - F_top), F_top the string's axial force at
//               the top and W_s the set force; the coordinates are relative to the moving top, clamped
//               there as with feed, and the top's acceleration X'' loads them through top_load (the
//               axial counterpart of the torsional top's, modal.hpp). kappa -> 0 is feed; a large kappa
//               holds F_top at W_s as a hook load would;
//  * hook_load  the top is free and pushed down by a constant force (the string's submerged weight
//               less the hook load, the WOB of steady drilling): a free-free bar with its rigid mode.
//               (The weight of a uniform vertical string is a distributed constant load; on a linear
//               bar it shifts only the static state, so applying the net force at the top leaves the
//               motion relative to that state, and the bit's force, unchanged.)
// The reduction keeps the lowest `modes` mass-normalised modes (Phi^T M Phi = I, Phi^T K Phi =
// diag(omega^2)) with a damping diagonal in them (0 for the rigid mode), one of (axial.damping):
//  * modal        one ratio zeta on every mode: Phi^T D Phi = diag(2 zeta omega_j);
//  * distributed  viscous damping proportional to the mass, D = 2 k M: the distributed damping of
//                 Aarsnes and van de Wouw (J. Sound Vib. 2019), whose wave equations carry -2 k v
//                 (v_t = c^2 u_xx - 2 k v: their public MATLAB code, ulfjakob/AxialTorsionalDrillString,
//                 Coupled/waveStep_transportBRI.m, takes k (alpha + beta) = 2 k v from the rate of each Riemann invariant;
//                 the paper could not be read here, so its equation numbers are not given). With
//                 Phi^T M Phi = I it is Phi^T D Phi = 2 k I: the same decay rate k on every mode, the
//                 ratio k / omega_j on mode j, and no truncation error. The rigid mode of hook_load is
//                 left undamped: its motion is the string's steady advance, which a damping of the
//                 absolute velocity would brake (with feed the coordinates are relative to V0 t, so the
//                 steady advance is not damped either; on the motion about steady drilling both are
//                 theirs).
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <string>

#include "drill/errors.hpp"
#include "drill/fem.hpp"
#include "drill/names.hpp"

namespace drill {

enum class AxialTop { feed, hook_load, jack };
/// The top is clamped in a frame moving with it (feed, jack): the coordinates are relative to it.
inline bool moving_frame(AxialTop t) { return t != AxialTop::hook_load; }

/// The damping of the axial modes (axial.damping; the header's comment).
enum class AxialDamping { modal, distributed };
inline constexpr Named<AxialDamping> axial_damping_names[] = {{AxialDamping::modal, "modal"},
                                                              {AxialDamping::distributed, "distributed"}};
inline AxialDamping parse_axial_damping(const std::string& s, const std::string& field = "axial.damping") {
  return parse_name(axial_damping_names, s, field, "axial damping");
}
inline std::string to_string(AxialDamping d) { return name_of(axial_damping_names, d); }

/// The axial modes' damping: a ratio on every mode (modal) or D = 2 k M (distributed).
struct AxialModalDamping {
  AxialDamping kind = AxialDamping::modal;
  double ratio = 0.05;  ///< zeta of kind = modal
  double rate = NAN;    ///< k of kind = distributed [1/s]

  /// The modal damping coefficients Phi^T D Phi (diagonal) at the natural frequencies omega [rad/s]:
  /// 2 zeta omega_j (modal), 2 k (distributed), 0 on a rigid mode (omega_j = 0).
  Eigen::VectorXd coefficients(const Eigen::VectorXd& omega) const {
    if (kind == AxialDamping::modal) return 2.0 * ratio * omega;
    Eigen::VectorXd c(omega.size());
    for (Eigen::Index j = 0; j < omega.size(); ++j) c(j) = omega(j) > 0.0 ? 2.0 * rate : 0.0;
    return c;
  }
};

inline constexpr Named<AxialTop> axial_top_names[] = {
    {AxialTop::hook_load, "hook_load"}, {AxialTop::feed, "feed"}, {AxialTop::jack, "jack"}};
inline AxialTop parse_axial_top(const std::string& s) {
  return parse_name(axial_top_names, s, "axial.top", "top boundary");
}
inline std::string to_string(AxialTop t) { return name_of(axial_top_names, t); }

/// Axial FE matrices of the whole string over all nodes (top node included).
inline FEMatrices assemble_axial(const StringModel& s, double bit_mass) {
  s.validate();
  const int nn = s.n_nodes();
  FEMatrices fe{Eigen::MatrixXd::Zero(nn, nn), Eigen::MatrixXd::Zero(nn, nn), Eigen::VectorXd::Zero(nn)};
  int e = 0;
  for (const Section& sec : s.sections) {
    const double h = sec.length / sec.elements;
    const double area = M_PI * (sec.outer_radius * sec.outer_radius - sec.inner_radius * sec.inner_radius);
    const double ke = sec.youngs_modulus * area / h, me = sec.density * area * h / 6.0;
    for (int i = 0; i < sec.elements; ++i, ++e) {
      add_bar_element(fe, e, ke, me, h);
    }
  }
  fe.M(nn - 1, nn - 1) += bit_mass;
  return fe;
}

/// The reduced axial model: modal coordinates eta with M = I, K = diag(omega^2), D = diag(2 zeta omega).
struct AxialROM {
  AxialTop top = AxialTop::feed;
  Eigen::VectorXd omega;    ///< natural circular frequencies [rad/s] (hook_load: the first is 0)
  Eigen::VectorXd damping;  ///< modal damping 2 zeta omega [1/s]
  Eigen::VectorXd bit;      ///< the bit node's row of the basis: U_bit = bit . eta (+ V0 t with feed)
  Eigen::VectorXd top_row;  ///< the top node's row (hook_load; zero with feed and jack)
  Eigen::VectorXd uniform;  ///< Phi^T M 1: the modal velocity of a rigid axial motion at unit speed
  /// feed and jack (the top clamped in a frame moving with it): the string's axial force on the top,
  /// F_top = top_force . eta (K(free, top)^T Phi: the WOB in a static string), and the load of the
  /// frame's acceleration, -top_load X'' (Phi^T (M 1 + M(free, top))); zero with hook_load
  Eigen::VectorXd top_force, top_load;
  double mass = 0.0;        ///< total mass of the string and the bit [kg]
  int size() const { return static_cast<int>(omega.size()); }
};

/// Modal reduction of the axial string with the top boundary `top`, `modes` modes and the damping `damping`.
inline AxialROM build_axial_rom(const StringModel& s, AxialTop top, int modes, const AxialModalDamping& damping,
                                double bit_mass = 0.0) {
  const FEMatrices fe = assemble_axial(s, bit_mass);
  const Eigen::Index nn = fe.M.rows();
  const Eigen::Index first = moving_frame(top) ? 1 : 0;  // feed, jack: the top node is clamped (moving frame)
  const Eigen::Index n = nn - first;
  require(modes >= 1 && modes <= n, "axial.modes", modes,
          "must be between 1 and the number of free axial DOFs (" + show(n) + ")");
  const Eigen::MatrixXd M = fe.M.bottomRightCorner(n, n), K = fe.K.bottomRightCorner(n, n);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, M);
  if (es.info() != Eigen::Success) throw std::runtime_error("axial eigenproblem failed");
  AxialROM r;
  r.top = top;
  const Eigen::MatrixXd phi = es.eigenvectors().leftCols(modes);
  r.omega = es.eigenvalues().head(modes).cwiseMax(0.0).cwiseSqrt();
  if (top == AxialTop::hook_load) r.omega(0) = 0.0;  // the rigid mode (its eigenvalue is 0 up to rounding)
  r.damping = damping.coefficients(r.omega);
  r.bit = phi.row(n - 1).transpose();
  r.top_row = top == AxialTop::hook_load ? Eigen::VectorXd(phi.row(0).transpose()) : Eigen::VectorXd::Zero(modes);
  r.uniform = phi.transpose() * M * Eigen::VectorXd::Ones(n);
  r.top_force = r.top_load = Eigen::VectorXd::Zero(modes);
  if (moving_frame(top)) {
    r.top_force = phi.transpose() * fe.K.col(0).tail(n);
    r.top_load = phi.transpose() * (M * Eigen::VectorXd::Ones(n) + fe.M.col(0).tail(n));
  }
  r.mass = fe.M.sum();
  return r;
}

/// Modal reduction with one damping ratio zeta on every mode (axial.damping = modal).
inline AxialROM build_axial_rom(const StringModel& s, AxialTop top, int modes, double zeta, double bit_mass = 0.0) {
  return build_axial_rom(s, top, modes, AxialModalDamping{AxialDamping::modal, zeta, NAN}, bit_mass);
}

/// The first n axial natural frequencies [Hz] of the string with this top boundary (all FE modes).
inline Eigen::VectorXd axial_frequencies_hz(const StringModel& s, AxialTop top, int n, double bit_mass = 0.0) {
  return build_axial_rom(s, top, n, 0.0, bit_mass).omega / (2.0 * M_PI);
}

}  // namespace drill
