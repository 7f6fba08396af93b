// The modified Euler step of appendix A (Eqs. A.5-A.6) on modal coordinates, for several
// independent runs at once: the state is [modes][lanes] (row-major: mode j of lane l at j N + l),
// and every lane does the same arithmetic in the same order whatever the number of lanes N (its sums
// mode by mode from mode 0, as exact_modal_dot; no floating-point contraction: CMakeLists.txt). So a
// run has the same bits alone (N = 1) and in any lane of any batch. The pass over the modes goes
// through the lanes in vectors of the host's widest double vector (euler_lanes-inl.hpp, compiled per
// target with batched_kernel-inl.hpp and dispatched by Google Highway in batched_integrator.hpp, which
// defines EulerModes::pass; AVX-512: 8 lanes), a vector's sums held in
// registers over the pass (a sum kept in memory would wait on its own store at every mode), the lanes
// left over one by one with the same operations.
// Used by the axial-torsional model (axial_torsional.hpp) on its torsional and its axial modes.
#pragma once

#include <cstddef>

namespace drill {

/// One pass over the modes of N lanes (EulerModes::pass).
struct EulerModes {
  int m = 0;                  ///< modes
  std::size_t N = 1;          ///< lanes
  double dt = 0.0;
  const double* bit = nullptr;   ///< the bit's row of the modes [m]
  const double* top = nullptr;   ///< a second row summed over z (the top's torque), or nullptr [m]
  const double* negd = nullptr;  ///< -diag(D) [m] (nullptr: no forces, the sums alone; dense damping: dense_forces)
  const double* w2 = nullptr;    ///< omega^2 [m]
  const double* load = nullptr;  ///< the load row of a constant force `force` on every lane [m]
  double force = 0.0;            ///< that force (0: none)
  double *z = nullptr, *p = nullptr, *f = nullptr;  ///< state and forces [m][N]

  /// With `update`, Eqs. (A.5)-(A.6) with the bit's force F_l on the bit row, p = p + dt (f - bit F)
  /// then z = z + dt p (the new velocities); then the forces of the next step without the bit's,
  /// f = negd p - w2 z (+ load force), and per lane the sums bz = bit . z, bp = bit . p, bf = bit . f
  /// and tz = top . z (when `top`), each summed mode by mode from mode 0.
  void pass(bool update, const double* F, double* bz, double* bp, double* bf, double* tz) const;

  /// The forces with a dense damping D (row-major [m][m]): f_j = -(sum_k D_jk p_k) - w2_j z_j
  /// (+ load_j force), and bf = bit . f.
  void dense_forces(const double* D, double* bf) const {
    for (std::size_t l = 0; l < N; ++l) {
      double s = 0.0;
      for (int j = 0; j < m; ++j) {
        double d = 0.0;
        for (int k = 0; k < m; ++k) d = d + D[static_cast<std::size_t>(j) * m + k] * p[k * N + l];
        double fj = -d - w2[j] * z[j * N + l];
        if (force != 0.0) fj = fj + load[j] * force;
        f[j * N + l] = fj;
        s = s + bit[j] * fj;
      }
      bf[l] = s;
    }
  }

  /// The load x_l on the lanes where it is not zero (the top's acceleration on the torsional modes,
  /// row -top_load): f = f + row x, and bf = bit . f anew on those lanes.
  void add_load(const double* row, const double* x, double* bf) const {
    for (std::size_t l = 0; l < N; ++l) {
      if (x[l] == 0.0) continue;
      double s = 0.0;
      for (int j = 0; j < m; ++j) {
        double& fj = f[j * N + l];
        fj = fj + row[j] * x[l];
        s = s + bit[j] * fj;
      }
      bf[l] = s;
    }
  }

};

/// The inputs and outputs of one EulerModes::pass (the kernel's second argument).
struct EulerPassIO {
  bool update;
  const double* F;
  double *bz, *bp, *bf, *tz;
};

}  // namespace drill

