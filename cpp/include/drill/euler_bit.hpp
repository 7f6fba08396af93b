// The torque on the bit in a modified Euler step (appendix A) with a law of the thesis: the solve of
// Eq. (A.1) for the bit acceleration together with the torque of the hysteretic laws, and the stick
// condition of the non-regularized laws (Eqs. 5.1, 5.3), set-valued at rest. Shared by the torsional
// engine (Integrator::run_euler, integrator.hpp) and the axial-torsional model driven by a thesis law
// (axial.torque = "law", axial_torsional.hpp), whose WOB is then its axial state.
#pragma once

#include <algorithm>
#include <cmath>

#include "drill/laws/at_speed.hpp"

namespace drill {

/// Bit speeds below this are "at rest" (a stuck bit's speed is zero up to rounding).
inline double bit_rest_tolerance(double om) { return 1e-12 * (1.0 + std::fabs(om)); }

/// The share of a stuck bit's friction F (string torque at the bit less c_v v) that the string
/// friction carries: the bit-rock contact takes F up to the static torque Ts, the string friction
/// the rest up to T_sf (the split of two set-valued frictions is otherwise indeterminate; this one
/// reports the whole string torque as contact torque when there is no string friction).
inline double string_share(double F, double Ts, double Tsf) {
  const double s = (F > 0.0) - (F < 0.0);
  return s * std::min(std::max(std::fabs(F) - Ts, 0.0), Tsf);
}

/// Eq. (A.1) with a hysteretic law (ts.frac ts.c != 0, ts.k != 0: Eqs. 3.2-3.3, 5.3): the step's bit
/// acceleration a = (v_{i+1} - v_i) / dt solves a = alpha - g T(a), T(a) = scale (base + frac (1 + c
/// tanh(k a))) + rest, increasing in a (scale = 1 + eta of Eq. 4.1, rest the torques that do not
/// depend on a). Saturated branches first (tanh = +-1 to double precision), safeguarded Newton
/// otherwise, started at `guess` (th_guess = tanh_sat(k guess) when `use_th`, computed by the
/// caller). On return (a, T) are the acceleration and the torque; returns whether Newton ran.
inline bool solve_euler_accel(const laws::AtSpeed& ts, double alpha, double g, double scale, double rest,
                              double guess, double th_guess, bool use_th, double& a, double& T) {
  const double T_up = scale * (ts.base + ts.frac * (1.0 + ts.c)) + rest;
  const double T_dn = scale * (ts.base + ts.frac * (1.0 - ts.c)) + rest;
  const double up = alpha - g * T_up, dn = alpha - g * T_dn;
  if (ts.k * up > 19.1) {
    a = up;
    T = T_up;
    return false;
  }
  if (ts.k * dn < -19.1) {
    a = dn;
    T = T_dn;
    return false;
  }
  // F(x) = x + g T(x) - alpha is increasing with F' >= 1 and changes sign on [lo, hi]: Newton steps
  // kept inside the shrinking bracket (bisection when a step leaves it or does not halve the previous
  // one); converged when the step is below tol, the next Newton error being of the order of its
  // square. Faster than Integrator::solve_root (one evaluation less per step, no bracket search) on
  // the Monte Carlo runs. The caller's start is the parabola through the last three solutions
  // extrapolated to this step: within tol of the root at almost every step of a smooth run, so that
  // one evaluation converges (the last solution alone needed two: benchmarks/bench_controller.py).
  double lo = std::min(up, dn), hi = std::max(up, dn), x = std::min(std::max(guess, lo), hi);
  const double tol = 1e-9 * (1.0 + std::fabs(alpha));
  double dx_old = HUGE_VAL;
  T = NAN;  // stays NaN (and is reported as a divergence) only if 200 steps do not converge
  for (int it = 0; it < 200; ++it) {
    const TorqueEval e = use_th && x == guess ? ts.eval_tanh(th_guess) : ts.eval(x);
    const double F = x + g * (scale * e.T + rest) - alpha;
    (F < 0.0 ? lo : hi) = x;
    double xn = x - F / (1.0 + g * scale * e.dT_da);
    if (!(xn >= lo && xn <= hi) || std::fabs(xn - x) > 0.5 * dx_old) xn = 0.5 * (lo + hi);
    dx_old = std::fabs(xn - x);
    if (std::fabs(xn - x) <= tol || hi - lo <= 1e-15 * (1.0 + std::fabs(alpha))) {
      T = scale * (e.T + e.dT_da * (xn - x)) + rest;  // to second order in the last step
      x = xn;
      break;
    }
    x = xn;
  }
  a = x;
  return true;
}

/// Stick condition of the non-regularized laws (Eqs. 5.1, 5.3) in the modified Euler step: the
/// law is set-valued at rest, T in [-Ts, Ts], and so is the string friction, in [-Tsf, Tsf]. The
/// torque that brings the bit to rest at the end of the step, v + dt (alpha - g T) = 0, is
/// T_req = (alpha + v / dt) / g. A bit at rest stays stuck while the friction T_req - c_v v it
/// would need is within the static capacity Ts + Tsf, and breaks away with the static torque and
/// the string friction otherwise; a moving bit whose slip step would reverse its speed comes to
/// rest when the friction can hold it (or the string pushes it on in its own direction).
/// v the bit speed at the step's start, om the top speed, alpha the bit acceleration without the bit
/// torque, g the bit's modal gain, visc = c_v v. On entry (a, T) are the slipping step's; on return
/// the step's bit acceleration and total torque, and fric the part of T that is string friction
/// (unchanged when the bit slips on). Returns whether the bit is stuck (at rest at the step's end).
inline bool stick_euler(double v, double om, double alpha, double g, double dt, double Ts, double Tsf, double visc,
                        double& a, double& T, double& fric) {
  const double T_req = (alpha + v / dt) / g, F_req = T_req - visc;
  const double sv = (v > 0.0) - (v < 0.0), sf = (F_req > 0.0) - (F_req < 0.0);
  const bool at_rest = std::fabs(v) <= bit_rest_tolerance(om);
  const bool crossing = !at_rest && v * (v + dt * a) <= 0.0;
  if ((at_rest || crossing) && (std::fabs(F_req) <= Ts + Tsf || (crossing && sf == sv))) {
    T = T_req;  // stuck: the bit is at rest at the end of the step
    a = -v / dt;
    fric = Tsf > 0.0 ? string_share(F_req, Ts, Tsf) : 0.0;
    return true;
  }
  if (at_rest) {
    fric = sf * Tsf;
    T = sf * (Ts + Tsf) + visc;  // break-away: sign(0) = 0, so H = 0 in Eq. (5.3)
    a = alpha - g * T;
  }
  return false;
}

}  // namespace drill
