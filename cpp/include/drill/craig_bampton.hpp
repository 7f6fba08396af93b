// Craig-Bampton substructuring of the clamped drill string (thesis section 6.2.1, Eqs. 6.6-6.18).
//
// Each section of the string is one substructure S_k (DP, BHA, ...), a chain from the top drive to
// the bit. The top of S_1 is clamped (rotating frame, Eq. 2.5); consecutive substructures share one
// interface node; the bit is an inner DOF of the last substructure (which therefore floats: its
// reduced stiffness is only positive semi-definite, see randmat.hpp, SE+0).
//
// Per substructure (local DOFs ordered [inner; interface], Eq. 6.6-6.7):
//   fixed-interface elastic modes  K_II phi = w^2 M_II phi, m_k of them, mass-normalized   (Eq. 6.8)
//   static constraint modes        R = -K_II^-1 K_IG                                       (Eq. 6.9)
//   Psi_k = [Phi R; 0 I]                                                                 (Eqs. 6.10-6.11)
//   reduced blocks                 A~_k = Psi_k^T A_k Psi_k,  A = M, D, K                 (Eqs. 6.12-6.13)
// Assembly (Eqs. 6.16-6.17): q_CB = (q_1^I, ..., q_ns^I, u^G) with one column per interface node;
// A_CB gathers the inner blocks on the diagonal and sums the interface blocks of the substructures
// sharing an interface. Recovery (Eq. 6.18): u = Psi q_CB.
// Damping: Rayleigh per substructure, D~_k = a M~_k + b K~_k (section 6.6).
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "drill/config.hpp"
#include "drill/errors.hpp"
#include "drill/fem.hpp"
#include "drill/modal.hpp"

namespace drill {

/// One substructure after reduction (Eqs. 6.8-6.13).
struct Substructure {
  std::string name;
  std::vector<int> inner_nodes;      ///< global node indices of the inner DOFs (clamped top excluded)
  std::vector<int> interface_nodes;  ///< global node indices of the interface DOFs
  std::vector<int> interface_slots;  ///< index of each interface node in u^G of q_CB
  int modes = 0;                     ///< m_k fixed-interface modes kept
  Eigen::VectorXd omega;             ///< fixed-interface natural frequencies [rad/s]
  Eigen::MatrixXd psi;               ///< Psi_k, rows [inner; interface], columns [q^I; u^G] (Eq. 6.11)
  Eigen::MatrixXd M, D, K;           ///< reduced blocks A~_k, n_k x n_k (Eq. 6.12)

  int n_interface() const { return static_cast<int>(interface_nodes.size()); }
  int size() const { return modes + n_interface(); }
};

/// The assembled Craig-Bampton model of a chain of substructures (Eqs. 6.16-6.18).
class CraigBampton {
 public:
  /// One substructure per section of cfg.string, with cfg.cb_modes[k] fixed-interface modes and
  /// the Rayleigh damping of cfg.damping applied to every substructure.
  explicit CraigBampton(const Config& cfg) : CraigBampton(cfg.string, cfg.cb_modes, cfg.damping) {}

  CraigBampton(const StringModel& s, const std::vector<int>& modes, const DampingSpec& damping) {
    s.validate();
    damping.validate();
    const int ns = static_cast<int>(s.sections.size());
    require(static_cast<int>(modes.size()) == ns, "craig_bampton.modes", modes.size(),
            "needs one number of fixed-interface modes per section (" + show(ns) + " sections)");
    require(damping.kind == DampingSpec::Kind::rayleigh, "damping.type", "modal",
            "Craig-Bampton substructures need Rayleigh damping (damping.type = rayleigh, section 6.6)");
    const Rayleigh ab = Rayleigh::from_pairs(damping.f1, damping.z1, damping.f2, damping.z2);
    n_interface_ = ns - 1;
    int offset = 0;
    for (int k = 0; k < ns; ++k) {
      subs_.push_back(reduce(s, k, modes[k], ab));
      inner_offset_.push_back(offset);
      offset += subs_.back().modes;
    }
    interface_offset_ = offset;
    size_ = offset + n_interface_;
    M_ = assemble_blocks(Blocks::M);
    K_ = assemble_blocks(Blocks::K);
    D_ = assemble_blocks(Blocks::D);
    build_recovery(s);
    const ClampedMatrices c = clamp_top(drill::assemble(s));
    model_ = project(c, psi_, D_);
    model_.M = M_;  // the assembled blocks (Eq. 6.17) equal Psi^T M Psi of the clamped string
    model_.K = K_;
    model_.init_velocity = M_.ldlt().solve(psi_.transpose() * (c.M * Eigen::VectorXd::Ones(c.M.rows())));
  }

  const std::vector<Substructure>& substructures() const { return subs_; }
  int n_substructures() const { return static_cast<int>(subs_.size()); }
  int size() const { return size_; }
  int n_interface() const { return n_interface_; }
  /// Position in q_CB of the first generalized coordinate of substructure k.
  int inner_offset(int k) const { return inner_offset_.at(k); }
  /// Position in q_CB of the first interface displacement.
  int interface_offset() const { return interface_offset_; }
  /// Assembled matrices (Eq. 6.17).
  const Eigen::MatrixXd& M() const { return M_; }
  const Eigen::MatrixXd& D() const { return D_; }
  const Eigen::MatrixXd& K() const { return K_; }
  /// Recovery matrix Psi (Eq. 6.18): u(free nodes 1..N) = Psi q_CB.
  const Eigen::MatrixXd& psi() const { return psi_; }
  /// The Craig-Bampton model as a reduced model for the integrator and the FRF.
  const ReducedModel& model() const { return model_; }

  /// Position in q_CB of local coordinate l of substructure k (inner modes, then interfaces).
  int global_index(int k, int l) const {
    const Substructure& sub = subs_.at(k);
    return l < sub.modes ? inner_offset_[k] + l : interface_offset_ + sub.interface_slots.at(l - sub.modes);
  }

  /// Assemble one n_k x n_k block per substructure into A_CB (Eq. 6.17 for any chain).
  Eigen::MatrixXd assemble(const std::vector<Eigen::MatrixXd>& blocks) const {
    require(blocks.size() == subs_.size(), "blocks", blocks.size(),
            "needs one matrix per substructure (" + show(subs_.size()) + ")");
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(size_, size_);
    for (int k = 0; k < n_substructures(); ++k) {
      const int nk = subs_[k].size();
      require(blocks[k].rows() == nk && blocks[k].cols() == nk, "blocks[" + std::to_string(k) + "] (rows)",
              blocks[k].rows(), "must be " + show(nk) + " x " + show(nk));
      for (int i = 0; i < nk; ++i)
        for (int j = 0; j < nk; ++j) A(global_index(k, i), global_index(k, j)) += blocks[k](i, j);
    }
    return A;
  }

  /// Natural frequencies [Hz] of the assembled model (first n).
  Eigen::VectorXd frequencies_hz(int n) const {
    require(n >= 1 && n <= size_, "n", n, "must be between 1 and the Craig-Bampton size " + show(size_));
    return solve_modes(K_, M_, n).omega / (2.0 * M_PI);
  }

 private:
  enum class Blocks { M, D, K };

  static Substructure reduce(const StringModel& s, int k, int m, const Rayleigh& ab) {
    const int ns = static_cast<int>(s.sections.size());
    const int first = k == 0 ? 0 : s.section_end(k - 1);  // global index of the local node 0
    const int ne = s.sections[k].elements;
    FEMatrices fe = assemble_sections(s, k, k + 1);
    for (const auto& li : s.lumped) {  // an inertia on an interface node goes to the upper substructure
      const int g = s.resolve_node(li.node);
      const bool mine = g >= first && g <= first + ne && !(k > 0 && g == first);
      if (mine) fe.M(g - first, g - first) += li.inertia;
    }
    Substructure sub;
    sub.name = s.sections[k].name;
    std::vector<int> inner, iface;  // local node indices
    if (k > 0) {
      iface.push_back(0);
      sub.interface_slots.push_back(k - 1);
    }
    for (int l = 1; l < ne; ++l) inner.push_back(l);
    if (k < ns - 1) {
      iface.push_back(ne);
      sub.interface_slots.push_back(k);
    } else {
      inner.push_back(ne);  // the bit
    }
    const std::string field = "craig_bampton.modes[" + std::to_string(k) + "]";
    require(m >= 1 && m <= static_cast<int>(inner.size()), field, m,
            "must be between 1 and the " + show(inner.size()) + " inner DOFs of substructure '" + sub.name + "'");
    for (int l : inner) sub.inner_nodes.push_back(first + l);
    for (int l : iface) sub.interface_nodes.push_back(first + l);
    sub.modes = m;

    std::vector<int> order = inner;
    order.insert(order.end(), iface.begin(), iface.end());
    const int ni = static_cast<int>(inner.size()), ng = static_cast<int>(iface.size());
    const Eigen::MatrixXd Ml = fe.M(order, order), Kl = fe.K(order, order);
    const Eigen::MatrixXd KII = Kl.topLeftCorner(ni, ni), MII = Ml.topLeftCorner(ni, ni);
    const ModalBasis fixed = solve_modes(KII, MII, m);  // Eq. (6.8): fixed-interface modes
    sub.omega = fixed.omega;
    sub.psi = Eigen::MatrixXd::Zero(ni + ng, m + ng);
    sub.psi.topLeftCorner(ni, m) = fixed.phi;
    if (ng > 0) {
      sub.psi.topRightCorner(ni, ng) = -KII.llt().solve(Kl.topRightCorner(ni, ng));  // Eq. (6.9)
      sub.psi.bottomRightCorner(ng, ng).setIdentity();
    }
    sub.M = sub.psi.transpose() * Ml * sub.psi;  // Eq. (6.12)
    sub.K = sub.psi.transpose() * Kl * sub.psi;
    sub.M = 0.5 * (sub.M + sub.M.transpose()).eval();
    sub.K = 0.5 * (sub.K + sub.K.transpose()).eval();
    sub.D = ab.a * sub.M + ab.b * sub.K;  // Rayleigh damping per substructure (section 6.6)
    return sub;
  }

  Eigen::MatrixXd assemble_blocks(Blocks which) const {
    std::vector<Eigen::MatrixXd> b;
    for (const auto& s : subs_) b.push_back(which == Blocks::M ? s.M : which == Blocks::D ? s.D : s.K);
    return assemble(b);
  }

  void build_recovery(const StringModel& s) {
    psi_ = Eigen::MatrixXd::Zero(s.n_nodes() - 1, size_);  // free nodes 1..N (Eq. 6.18)
    for (int k = 0; k < n_substructures(); ++k) {
      const Substructure& sub = subs_[k];
      for (std::size_t r = 0; r < sub.inner_nodes.size(); ++r)
        for (int l = 0; l < sub.size(); ++l) psi_(sub.inner_nodes[r] - 1, global_index(k, l)) = sub.psi(r, l);
      for (int g = 0; g < sub.n_interface(); ++g)
        psi_(sub.interface_nodes[g] - 1, interface_offset_ + sub.interface_slots[g]) = 1.0;
    }
  }

  std::vector<Substructure> subs_;
  std::vector<int> inner_offset_;
  int interface_offset_ = 0, n_interface_ = 0, size_ = 0;
  Eigen::MatrixXd M_, D_, K_, psi_;
  ReducedModel model_;
};

}  // namespace drill
