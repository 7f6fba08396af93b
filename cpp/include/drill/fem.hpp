// Finite-element model of a torsional bar made of sections (thesis Eqs. 2.1-2.6).
//
// Each section is a hollow (or solid) circular shaft discretized by linear two-node
// torsion elements with the consistent mass matrix:
//   k_e = G J / h [ 1 -1; -1 1 ],   m_e = rho J h / 6 [ 2 1; 1 2 ]      (FE form of Eq. 2.1)
// Nodes are numbered from the top (node 0, the top drive) to the bit (last node).
// Lumped rotary inertias (the test rig's disk) are added to the diagonal of M.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "drill/errors.hpp"

namespace drill {

/// One uniform section of the string, SI units.
struct Section {
  std::string name = "section";
  double length = 0.0;          ///< [m]
  double outer_radius = 0.0;    ///< [m]
  double inner_radius = 0.0;    ///< [m], 0 for a solid bar
  double youngs_modulus = 0.0;  ///< [Pa]
  double poisson_ratio = 0.0;   ///< [-]
  double density = 0.0;         ///< [kg/m^3]
  int elements = 0;             ///< number of linear elements

  double shear_modulus() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
  /// Polar moment of area J = pi/2 (ro^4 - ri^4) [m^4].
  double polar_moment() const {
    const double ro2 = outer_radius * outer_radius, ri2 = inner_radius * inner_radius;
    return 0.5 * M_PI * (ro2 * ro2 - ri2 * ri2);
  }
  /// Torsional wave speed sqrt(G / rho) [m/s].
  double wave_speed() const { return std::sqrt(shear_modulus() / density); }

  void validate(const std::string& where) const {
    require_positive(length, where + ".length_m");
    require_positive(outer_radius, where + ".outer_radius_m");
    require_non_negative(inner_radius, where + ".inner_radius_m");
    require(inner_radius < outer_radius, where + ".inner_radius_m", inner_radius,
            "must be smaller than outer_radius_m = " + show(outer_radius));
    require_positive(youngs_modulus, where + ".youngs_modulus_pa");
    require_finite(poisson_ratio, where + ".poisson_ratio");
    require(poisson_ratio > -1.0 && poisson_ratio < 0.5, where + ".poisson_ratio", poisson_ratio,
            "must lie in (-1, 0.5)");
    require_positive(density, where + ".density_kg_m3");
    require(elements >= 1, where + ".elements", elements, "must be at least 1");
  }
};

/// A rotary inertia added at a node. Negative node indices count from the bit (-1 = bit).
struct LumpedInertia {
  int node = -1;
  double inertia = 0.0;  ///< [kg m^2]
};

/// The whole string: sections from top to bit plus lumped inertias.
struct StringModel {
  std::vector<Section> sections;
  std::vector<LumpedInertia> lumped;
  static constexpr int max_elements = 5000;  ///< total elements accepted (validate)

  int n_elements() const {
    int n = 0;
    for (const auto& s : sections) n += s.elements;
    return n;
  }
  int n_nodes() const { return n_elements() + 1; }
  /// Resolve a possibly negative node index to 0..n_nodes-1.
  int resolve_node(int node) const { return node < 0 ? n_nodes() + node : node; }
  /// Node index at the bottom of each section (the DP/BHA interface is section_end(0)).
  int section_end(std::size_t k) const {
    int n = 0;
    for (std::size_t i = 0; i <= k; ++i) n += sections.at(i).elements;
    return n;
  }
  double total_length() const {
    double l = 0.0;
    for (const auto& s : sections) l += s.length;
    return l;
  }

  void validate() const {
    require(!sections.empty(), "string.sections", sections.size(), "needs at least one section");
    for (std::size_t k = 0; k < sections.size(); ++k)
      sections[k].validate("string.sections[" + std::to_string(k) + "]");
    // the modal reduction solves a dense n x n eigenproblem (Eq. 2.7): 3000 elements take 40 s, and the
    // thesis converges with 100 (docs/numerics.md)
    long long total = 0;  // summed wide: sections of up to INT_MAX elements each
    for (const auto& s : sections) total += s.elements;
    require(total <= max_elements, "string.sections[].elements", total,
            "in total exceeds " + show(max_elements) + " (the dense eigenproblem of the reduction would take minutes)");
    for (std::size_t k = 0; k < lumped.size(); ++k) {
      const std::string w = "string.lumped_inertias[" + std::to_string(k) + "]";
      const int node = resolve_node(lumped[k].node);
      require(node >= 0 && node < n_nodes(), w + ".node", lumped[k].node,
              "is outside the mesh of " + show(n_nodes()) + " nodes");
      require_positive(lumped[k].inertia, w + ".inertia_kg_m2");
    }
  }
};

/// Unconstrained global matrices over all nodes (top node included), plus node positions.
struct FEMatrices {
  Eigen::MatrixXd M;  ///< mass [kg m^2]
  Eigen::MatrixXd K;  ///< stiffness [N m / rad]
  Eigen::VectorXd x;  ///< node depth from the top [m]
};

/// Add one two-node linear bar element of length h between nodes e and e + 1: stiffness
/// ke [1 -1; -1 1] and consistent mass me [2 1; 1 2], with ke = G J / h and me = rho J h / 6 in
/// torsion (the FE form of Eq. 2.1, header comment) or ke = E A / h and me = rho A h / 6 axially;
/// the element's lower node sits h below its upper one.
inline void add_bar_element(FEMatrices& fe, int e, double ke, double me, double h) {
  fe.K(e, e) += ke;
  fe.K(e + 1, e + 1) += ke;
  fe.K(e, e + 1) -= ke;
  fe.K(e + 1, e) -= ke;
  fe.M(e, e) += 2.0 * me;
  fe.M(e + 1, e + 1) += 2.0 * me;
  fe.M(e, e + 1) += me;
  fe.M(e + 1, e) += me;
  fe.x(e + 1) = fe.x(e) + h;
}

/// Assemble the element matrices of sections [first, last) into global matrices whose
/// node 0 is the top of section `first`. Lumped inertias are added only for the full string.
inline FEMatrices assemble_sections(const StringModel& s, std::size_t first, std::size_t last) {
  int ne = 0;
  for (std::size_t k = first; k < last; ++k) ne += s.sections[k].elements;
  const int nn = ne + 1;
  FEMatrices fe{Eigen::MatrixXd::Zero(nn, nn), Eigen::MatrixXd::Zero(nn, nn), Eigen::VectorXd::Zero(nn)};
  double x0 = 0.0;
  for (std::size_t k = 0; k < first; ++k) x0 += s.sections[k].length;
  int e = 0;
  for (std::size_t k = first; k < last; ++k) {
    const Section& sec = s.sections[k];
    const double h = sec.length / sec.elements;
    const double gj = sec.shear_modulus() * sec.polar_moment();
    const double rj = sec.density * sec.polar_moment();
    const double ke = gj / h, me = rj * h / 6.0;
    for (int i = 0; i < sec.elements; ++i, ++e) {
      add_bar_element(fe, e, ke, me, h);
    }
  }
  fe.x.array() += x0;
  return fe;
}

/// Global matrices of the whole string including lumped inertias.
inline FEMatrices assemble(const StringModel& s) {
  s.validate();
  FEMatrices fe = assemble_sections(s, 0, s.sections.size());
  for (const auto& li : s.lumped) {
    const int n = s.resolve_node(li.node);
    fe.M(n, n) += li.inertia;
  }
  return fe;
}

/// The string with its top node clamped in the rotating frame (Eqs. 2.4-2.5): the free
/// DOFs are nodes 1..N (u = theta_rel); the couplings to the top node are kept to compute
/// the top torque and the inertial load of a varying top speed.
struct ClampedMatrices {
  Eigen::MatrixXd M, K;    ///< free-free blocks, n x n with n = n_nodes - 1
  Eigen::VectorXd m_top;   ///< M(free, top)
  Eigen::VectorXd k_top;   ///< K(free, top)
};

inline ClampedMatrices clamp_top(const FEMatrices& fe) {
  const Eigen::Index n = fe.M.rows() - 1;
  return {fe.M.bottomRightCorner(n, n), fe.K.bottomRightCorner(n, n), fe.M.col(0).tail(n),
          fe.K.col(0).tail(n)};
}

}  // namespace drill
