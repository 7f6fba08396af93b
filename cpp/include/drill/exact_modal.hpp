// The exact modal scheme (`simulation.scheme: "exact_modal"`, issue 33): each mode's linear part
// integrated exactly over the step, the bit torque implicit at the step's end.
//
// In the modal basis of Integrator (M = I, K = diag(omega^2), D diagonal) mode j obeys
//   z_j'' + d_j z_j' + omega_j^2 z_j = F_j(t),   F_j = -top_load_j Omega' - bit_j T_bit(t)
// (Eqs. 2.5, 2.9 with the reduced basis of Eq. 2.9 brought to its modes). Over a step t_i -> t_i+1
// the top's acceleration is taken as its average over the step, (Omega_i+1 - Omega_i) / dt (exact
// when Omega is linear over the step, as an ideal drive's sampled command is between samples that
// fall on steps), and the bit torque as varying linearly from T_i to T_i+1. The mode's state then
// follows exactly from its 2x2 propagator Phi = exp(A dt), A = [0 1; -omega^2 -d], and the exact
// particular solution of the linear forcing,
//   [z; p]_i+1 = Phi [z; p]_i + G0 F_i + G1 F_i+1,
// G0, G1 the responses at t_i+1 to the two hat functions of the step (the 2-vectors of the
// augmented 4x4 exponential below: any damping, under-, critically or over-damped). No stability
// bound (Eq. A.7 does not apply), no error in the linear part at any step.
//
// The bit torque at the step's end is implicit, as the modified Euler's acceleration of Eq. (A.1) is:
// the bit speed at the step's end is v_i+1 = Omega_i+1 + w - c T_i+1 (w the bit's relative speed
// without the unknown end torque, c = sum_j bit_j G1p_j > 0), the bit acceleration of Eq. (3.3) is the
// step's own forward difference (v_i+1 - v_i) / dt (Eq. A.1), and T_i+1 = T_law(v_i+1, a_i+1) (Eqs.
// 3.1-3.3, 5.1, 5.3, times (1 + eta) of Eq. 4.1, plus the viscous torque and the string friction)
// is the scalar equation x + c T(Omega_i+1 + x, (Omega_i+1 + x - v_i) / dt) = w for x = v_i+1 - Omega_i+1,
// solved by Newton (Integrator::exact_newton, with solve_bit's safeguarded iteration as its fallback). The stick condition of Eqs. (5.1), (5.3) is
// the BDF2 step's (Integrator::exact_bit): a bit at rest stays at rest while the torque that keeps
// it there at the step's end is within the static capacity. Over a step that starts and ends at
// rest the torque is held constant (T_i = T_i+1 = the holding torque): interpolated linearly, the
// holding torque of one step would depend on the last one's with a factor near -1, a torque that
// alternates from step to step and lets the bit break away and stick again every other step. So is
// the torque of a step in which a moving bit comes to rest (the one that stops it at the step's end,
// held: the friction jumps within the step from the sliding torque to the holding one, as the
// modified Euler's stick_euler takes it); interpolated from the sliding T_i, the end torque needed
// where the string pulls the landing bit backwards lay beyond the capacity and the bit broke away
// backwards for a step (1-step stick and slip phases at each stop with a static torque: issue 33).
// The torque reported for a step is its mean over the step, (T_i + T_i+1) / 2, or the held torque:
// reported as the end torque of a sliding step and the mean of a held one, the torque at the sample
// where a bit lands jumped by half the last sliding step's rise when the landing crossed the sample
// (1.06 N m under a 0.1 % change of the damping on a validation case of the loop, which stopped its
// least squares short); the modified Euler's torque is likewise one value per step.
//
// The propagation below (exact_modal_free, exact_modal_close) is the scalar path's (Integrator::
// run_exact_lanes, one lane). The batched path (batched_integrator.hpp, ExactSteps in
// batched_kernel-inl.hpp) steps a vector of runs through the same equations: the bit's equation
// solved by a Newton iteration masked across the lanes, the step's end state and the next step's
// w = bit . ps in one pass over the modes (coefficients kl: w summed from the state at the step's
// start), with FMA and Highway's exp/log. Its lanes never mix, so a run has the same bits alone and
// in any lane of a batch; against the scalar path it differs by rounding.
#pragma once

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include <array>
#include <cstddef>
#include <vector>

namespace drill {

/// Per-mode coefficients of one exact step, [mode][kind] (kinds below), and the end-torque
/// compliance c of the bit speed.
struct ExactModal {
  /// zz, zp, pz, pp: Phi; ez, ep: response to the top's acceleration (times Omega'); hz0, hp0: to
  /// the start torque T_i; hz1, hp1: to the end torque T_i+1 (both with the sign of -bit_j T).
  enum Kind { zz, zp, pz, pp, ez, ep, hz0, hp0, hz1, hp1, kinds };
  /// The batched kernel's coefficients per mode (batched_kernel-inl.hpp, ExactSteps): the ten kinds
  /// and bpz = bit_j Phi10_j, bpp = bit_j Phi11_j, with which w = bit . ps is summed from the state at
  /// the step's start: w = sum_j (bpz_j z_j + bpp_j p_j) + ce Omega' - c0 T_i.
  static constexpr int bpz = kinds, bpp = kinds + 1, lane_kinds = kinds + 2;
  int modes = 0;
  std::vector<double> k;  ///< [modes][kinds]
  std::vector<double> kl;  ///< [modes][lane_kinds]: the batched kernel's
  double c = 0.0;         ///< sum_j bit_j hp1_j: dv_i+1 / dT_i+1 = -c
  double c0 = 0.0;        ///< sum_j bit_j hp0_j: dv_i+1 / dT_i = -c0
  double ce = 0.0;        ///< sum_j bit_j ep_j: dv_i+1 / dOmega' (the top's acceleration over the step)

  double at(int j, Kind q) const { return k[static_cast<std::size_t>(j) * kinds + q]; }

  /// The propagator of z'' + d z' + w2 z = F0 + (F1 - F0) s / dt over one step dt:
  /// [z1, p1] = Phi [z0, p0] + g0 F0 + g1 F1. Returned as {Phi00, Phi01, Phi10, Phi11, g0z, g0p, g1z, g1p}.
  /// From exp of the augmented matrix of (z, p, u, r) with z' = p, p' = -w2 z - d p + u, u' = r / dt,
  /// u(0) = F0, r = F1 - F0 (scaled to the step: a 4x4 exponential, Pade with scaling and squaring).
  static std::array<double, 8> propagator(double w2, double d, double dt) {
    Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
    A(0, 1) = dt;
    A(1, 0) = -w2 * dt;
    A(1, 1) = -d * dt;
    A(1, 2) = dt;
    A(2, 3) = 1.0;
    const Eigen::Matrix4d E = A.exp();
    return {E(0, 0), E(0, 1), E(1, 0), E(1, 1), E(0, 2) - E(0, 3), E(1, 2) - E(1, 3), E(0, 3), E(1, 3)};
  }

  static ExactModal build(const Eigen::VectorXd& w2, const Eigen::VectorXd& d, const Eigen::VectorXd& bit,
                          const Eigen::VectorXd& top_load, double dt) {
    ExactModal e;
    e.modes = static_cast<int>(w2.size());
    e.k.assign(static_cast<std::size_t>(e.modes) * kinds, 0.0);
    for (int j = 0; j < e.modes; ++j) {
      const std::array<double, 8> P = propagator(w2(j), d(j), dt);
      double* r = e.k.data() + static_cast<std::size_t>(j) * kinds;
      r[zz] = P[0];
      r[zp] = P[1];
      r[pz] = P[2];
      r[pp] = P[3];
      r[ez] = -(P[4] + P[6]) * top_load(j);  // F_j = -top_load_j Omega' over the whole step
      r[ep] = -(P[5] + P[7]) * top_load(j);
      r[hz0] = P[4] * bit(j);
      r[hp0] = P[5] * bit(j);
      r[hz1] = P[6] * bit(j);
      r[hp1] = P[7] * bit(j);
    }
    e.kl.assign(static_cast<std::size_t>(e.modes) * lane_kinds, 0.0);
    for (int j = 0; j < e.modes; ++j) {
      e.c += bit(j) * e.at(j, hp1);
      e.c0 += bit(j) * e.at(j, hp0);
      e.ce += bit(j) * e.at(j, ep);
      double* r = e.kl.data() + static_cast<std::size_t>(j) * lane_kinds;
      for (int q = 0; q < kinds; ++q) r[q] = e.at(j, static_cast<Kind>(q));
      r[bpz] = bit(j) * e.at(j, pz);
      r[bpp] = bit(j) * e.at(j, pp);
    }
    return e;
  }
};

/// The step's free part: zs, ps = the modal state at t_i+1 without the end torque, from z, p, the
/// top's acceleration dom and the start torque T0 [lanes], and w = bit . ps [lanes] (summed mode by
/// mode). State and results are [modes][lanes].
inline void exact_modal_free(int m, std::size_t N, const double* coef, const double* bit, const double* z,
                             const double* p, const double* dom, const double* T0, double* zs, double* ps,
                             double* w) {
  constexpr int K = ExactModal::kinds;
  for (std::size_t l = 0; l < N; ++l) w[l] = 0.0;
  for (int j = 0; j < m; ++j) {
    const double* c = coef + static_cast<std::size_t>(j) * K * N;
    const double b = bit[j];
    const std::size_t o = static_cast<std::size_t>(j) * N;
    for (std::size_t l = 0; l < N; ++l) {
      const double zj = z[o + l], pj = p[o + l];
      const double zn = c[ExactModal::zz * N + l] * zj + c[ExactModal::zp * N + l] * pj +
                        c[ExactModal::ez * N + l] * dom[l] - c[ExactModal::hz0 * N + l] * T0[l];
      const double pn = c[ExactModal::pz * N + l] * zj + c[ExactModal::pp * N + l] * pj +
                        c[ExactModal::ep * N + l] * dom[l] - c[ExactModal::hp0 * N + l] * T0[l];
      zs[o + l] = zn;
      ps[o + l] = pn;
      w[l] = w[l] + b * pn;
    }
  }
}

/// The step's end: z, p = zs, ps with the response to the end torque T1 [lanes] and to dT0, a change
/// of the start torque (T1 - T0 where the torque is held over the step, 0 elsewhere) [lanes].
inline void exact_modal_close(int m, std::size_t N, const double* coef, const double* zs, const double* ps,
                              const double* T1, const double* dT0, double* z, double* p) {
  constexpr int K = ExactModal::kinds;
  for (int j = 0; j < m; ++j) {
    const double* c = coef + static_cast<std::size_t>(j) * K * N;
    const std::size_t o = static_cast<std::size_t>(j) * N;
    for (std::size_t l = 0; l < N; ++l) {
      z[o + l] = zs[o + l] - c[ExactModal::hz1 * N + l] * T1[l] - c[ExactModal::hz0 * N + l] * dT0[l];
      p[o + l] = ps[o + l] - c[ExactModal::hp1 * N + l] * T1[l] - c[ExactModal::hp0 * N + l] * dT0[l];
    }
  }
}

/// bit . p per lane, summed mode by mode (the order of exact_modal_free).
inline void exact_modal_dot(int m, std::size_t N, const double* bit, const double* p, double* out) {
  for (std::size_t l = 0; l < N; ++l) out[l] = 0.0;
  for (int j = 0; j < m; ++j)
    for (std::size_t l = 0; l < N; ++l) out[l] = out[l] + bit[j] * p[static_cast<std::size_t>(j) * N + l];
}

}  // namespace drill
