// The modified Euler step of appendix A (Eqs. A.5-A.6) on modal coordinates, for several
// independent runs at once: the state is [modes][lanes] (row-major: mode j of lane l at j N + l),
// and every lane does the scalar step's arithmetic in the same order whatever the number of lanes N
// (the mode sums mode by mode, exact_modal_dot; no floating-point contraction: CMakeLists.txt). So a
// run has the same bits alone (N = 1) and in any lane of any batch. The loops over the lanes are
// the inner ones, which the compiler vectorizes without reordering a lane's operations.
// Used by the axial-torsional model (axial_torsional.hpp) on its torsional and its axial modes.
#pragma once

#include <cstddef>

namespace drill {

/// The modal forces of Eq. (A.5) without the bit's: f = -D p - w2 z + load x, mode j of lane l
/// f_jl = negd_j p_jl - w2_j z_jl (the damping diagonal in the modes, negd = -diag(D)), or with a
/// dense damping (`dense`, D row-major [modes][modes]) f_jl = -(sum_k D_jk p_kl) - w2_j z_jl, plus
/// load_j x_l where x_l != 0 (the top's acceleration on the torsional modes, load = -top_load;
/// the top force on the axial ones, load = top_row).
inline void euler_forces(int m, std::size_t N, const double* negd, const double* dense, const double* w2,
                         const double* load, const double* x, const double* z, const double* p, double* f) {
  for (int j = 0; j < m; ++j) {
    const std::size_t o = static_cast<std::size_t>(j) * N;
    if (dense) {
      for (std::size_t l = 0; l < N; ++l) {
        double s = 0.0;
        for (int k = 0; k < m; ++k) s = s + dense[static_cast<std::size_t>(j) * m + k] * p[static_cast<std::size_t>(k) * N + l];
        f[o + l] = -s - w2[j] * z[o + l];
      }
    } else {
      for (std::size_t l = 0; l < N; ++l) f[o + l] = negd[j] * p[o + l] - w2[j] * z[o + l];
    }
    for (std::size_t l = 0; l < N; ++l)
      if (x[l] != 0.0) f[o + l] = f[o + l] + load[j] * x[l];
  }
}

/// Eqs. (A.5)-(A.6) with the bit's force F_l on the modes' bit row: p = p + dt (f - bit F), then
/// z = z + dt p with the new velocities.
inline void euler_update(int m, std::size_t N, double dt, const double* bit, const double* F, const double* f,
                         double* z, double* p) {
  for (int j = 0; j < m; ++j) {
    const std::size_t o = static_cast<std::size_t>(j) * N;
    for (std::size_t l = 0; l < N; ++l) {
      p[o + l] = p[o + l] + dt * (f[o + l] - bit[j] * F[l]);
      z[o + l] = z[o + l] + dt * p[o + l];
    }
  }
}

}  // namespace drill
