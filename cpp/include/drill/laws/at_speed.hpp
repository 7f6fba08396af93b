// The form every bit-rock law takes at a fixed bit speed (laws/registry.hpp): as a function of the
// bit acceleration a,
//   T(a) = base + frac (1 + c tanh(k a)),  c = beta1 sign(v), k = beta2 s    (Eqs. 3.2-3.3, 5.3)
// with base, frac and their speed derivatives (frac = 0 without hysteresis). The integrators use
// it to solve for the acceleration cheaply; BitRockLaw::at_speed fills it through the laws.
#pragma once

#include <cmath>

namespace drill {

/// tanh(x) for the regularizing terms of Eqs. (3.1)-(3.3), to an absolute error of a few 1e-16
/// (all the laws need: the terms enter as 1 + c tanh): +-1 where tanh rounds to +-1 in double
/// precision (|x| > 19.1), otherwise 1 - 2 / (e^2x + 1), one exp instead of libm's expm1-based
/// tanh (a third of a Monte Carlo run's time when the hysteresis term is not saturated).
inline double tanh_sat(double x) {
  if (x > 19.1) return 1.0;
  if (x < -19.1) return -1.0;
  return 1.0 - 2.0 / (std::exp(2.0 * x) + 1.0);
}

/// Torque and its partial derivatives with respect to SI bit speed and SI bit acceleration.
struct TorqueEval {
  double T = 0.0, dT_dv = 0.0, dT_da = 0.0;
};

namespace laws {

/// The law at a fixed bit speed (all SI, WOB applied): T(a) = base + frac (1 + c tanh(k a)).
struct AtSpeed {
  double base = 0.0, frac = 0.0, dbase_dv = 0.0, dfrac_dv = 0.0, c = 0.0, k = 0.0;
  double torque(double a) const { return base + frac * (1.0 + c * tanh_sat(k * a)); }
  TorqueEval eval(double a) const { return eval_tanh(tanh_sat(k * a)); }
  /// eval(a) from th = tanh_sat(k a), computed by the caller.
  TorqueEval eval_tanh(double th) const {
    const double h = 1.0 + c * th;
    return {base + frac * h, dbase_dv + dfrac_dv * h, frac * c * k * (1.0 - th * th)};
  }
};

}  // namespace laws
}  // namespace drill
