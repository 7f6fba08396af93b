// Bit-rock interaction laws: torque on bit as a function of bit speed, bit acceleration and WOB.
//
//  * tucker_wang            Eq. (3.1)  T = c0 [tanh(alpha0 v) + alpha1 v / (1 + alpha2 v^2)]
//  * hysteretic             Eq. (3.2)  T = b0 [tanh(b1 v) + b2 |v|^b4 sign(v) / (1 + b3 |v|^b5) (1 + H)]
//                           Eq. (3.3)  H = beta1 tanh(beta2 a) sign(v)
//  * polynomial             Eq. (5.1)  non-regularized piecewise polynomial (coefficients a0..a7,
//                                      breakpoints at 1 % and 5 % of a reference speed, gain 1.36),
//                                      odd in the bit speed when a0 > 0; at rest it is set-valued: the bit stays
//                                      stuck while |string torque| <= the static torque 1.36 a0 W / W_ref
//                                      (static_torque(); the integrators apply this stick condition)
//  * polynomial_hysteretic  Eq. (5.3)  T = T_poly(v) (1 + H(v, a))
//
// All laws scale linearly with the weight on bit: T(W) = T (W / W_ref) (section 3.3, b0 x WOB / 245 kN).
// Every parameter set carries the speed unit it was fitted in (`speed_unit`): the bit speed v and
// the bit acceleration a enter the formulas in that unit (rad/s and rad/s^2, or RPM and RPM/s);
// the engine's own state is always SI. See docs/units.md for which unit the thesis's sets use.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "drill/errors.hpp"
#include "drill/names.hpp"

namespace drill {

enum class SpeedUnit { rad_s, rpm };

inline SpeedUnit parse_speed_unit(const std::string& s, const std::string& field) {
  if (s == "rad_s" || s == "rad/s") return SpeedUnit::rad_s;
  if (s == "rpm" || s == "RPM") return SpeedUnit::rpm;
  throw std::invalid_argument(field + " = \"" + s + "\": unknown speed unit (use \"rad_s\" or \"rpm\")");
}
inline std::string to_string(SpeedUnit u) { return u == SpeedUnit::rpm ? "rpm" : "rad_s"; }
/// Factor converting rad/s to the unit: v_unit = v_si * speed_factor(unit).
inline double speed_factor(SpeedUnit u) { return u == SpeedUnit::rpm ? 30.0 / M_PI : 1.0; }

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

struct BitRockLaw {
  enum class Kind { tucker_wang, hysteretic, polynomial, polynomial_hysteretic };
  Kind kind = Kind::hysteretic;
  SpeedUnit speed_unit = SpeedUnit::rad_s;
  double wob_ref = 245e3;  ///< [N] weight on bit at which the parameters hold

  // Eq. (3.1); c0 = mu W r (the thesis's 4700 N.m)
  double c0 = 0.0, alpha0 = 0.0, alpha1 = 0.0, alpha2 = 0.0;
  // Eq. (3.2)
  std::array<double, 6> b{};
  // Eq. (3.3) and (5.3)
  double beta1 = 0.0, beta2 = 0.0;
  // Eq. (5.1)
  std::array<double, 8> a{};
  double ref_speed = 1.0;  ///< mean bit speed of Eq. (5.1), in speed_unit
  double gain = 1.36;      ///< the constant factor of Eq. (5.1) (ft.lbf -> N.m)

  /// The laws by name (law.type); their keys are the variants of the "law" table (config.hpp).
  static constexpr Named<Kind> kinds[] = {{Kind::tucker_wang, "tucker_wang"},
                                          {Kind::hysteretic, "hysteretic"},
                                          {Kind::polynomial, "polynomial"},
                                          {Kind::polynomial_hysteretic, "polynomial_hysteretic"}};
  static Kind parse_kind(const std::string& s) { return parse_name(kinds, s, "law.type", "law"); }
  static std::string kind_name(Kind k) { return name_of(kinds, k); }
  void validate() const {
    require_positive(wob_ref, "law.wob_ref_n");
    switch (kind) {
      case Kind::tucker_wang:
        require_finite(c0, "law.c0");
        require_non_negative(alpha0, "law.alpha0");
        require_finite(alpha1, "law.alpha1");
        require_non_negative(alpha2, "law.alpha2");
        break;
      case Kind::hysteretic:
        for (int i = 0; i < 6; ++i) require_finite(b[i], "law.b" + std::to_string(i));
        require_non_negative(b[3], "law.b3");
        require_positive(b[4], "law.b4");
        require_positive(b[5], "law.b5");
        break;
      case Kind::polynomial:
      case Kind::polynomial_hysteretic:
        for (int i = 0; i < 8; ++i) require_finite(a[i], "law.a" + std::to_string(i));
        require_positive(ref_speed, "law.ref_speed");
        require_finite(gain, "law.gain");
        break;
    }
    require_finite(beta1, "law.beta1");
    require(beta1 >= 0.0 && beta1 < 1.0, "law.beta1", beta1, "must lie in [0, 1) so that 1 + H > 0");
    require_non_negative(beta2, "law.beta2");
  }

  /// The law at a fixed bit speed as a function of the bit acceleration (all SI, WOB applied):
  ///   T(a) = base + frac (1 + c tanh(k a)),  c = beta1 sign(v), k = beta2 s    (Eqs. 3.2-3.3, 5.3)
  /// with base/frac and their speed derivatives. Every law has this form (frac = 0 without
  /// hysteresis); the integrators use it to solve for the acceleration cheaply.
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

  AtSpeed at_speed(double v_si, double wob) const {
    const double s = speed_factor(speed_unit);
    const double v = v_si * s, w = wob / wob_ref;
    const double sg = (v > 0.0) - (v < 0.0);
    AtSpeed r;
    switch (kind) {
      case Kind::tucker_wang: {  // Eq. (3.1)
        const double t = tanh_sat(alpha0 * v), den = 1.0 + alpha2 * v * v;
        r.base = c0 * (t + alpha1 * v / den);
        r.dbase_dv = c0 * (alpha0 * (1.0 - t * t) + alpha1 * (1.0 - alpha2 * v * v) / (den * den));
        break;
      }
      case Kind::hysteretic: {  // Eq. (3.2): b0 tanh(b1 v) + b0 b2 |v|^b4 sign(v) / (1 + b3 |v|^b5) (1 + H)
        const double t = tanh_sat(b[1] * v);
        r.base = b[0] * t;
        r.dbase_dv = b[0] * b[1] * (1.0 - t * t);
        const double av = std::max(std::fabs(v), 1e-300), lv = std::log(av);
        const double p4 = std::exp(b[4] * lv), p5 = std::exp(b[5] * lv), den = 1.0 + b[3] * p5;
        r.frac = b[0] * sg * b[2] * p4 / den;
        r.dfrac_dv = b[0] * b[2] * (b[4] * den - b[3] * b[5] * p5) * p4 / (av * den * den);
        r.c = beta1 * sg;  // Eq. (3.3)
        break;
      }
      case Kind::polynomial:
      case Kind::polynomial_hysteretic: {  // Eq. (5.1) and its hysteretic form Eq. (5.3)
        // With a static torque (a0 > 0, the non-regularized law) Eq. (5.1) is extended to v < 0 as an
        // odd function (the friction resists the motion in either direction) and v = 0 returns the
        // right limit a0 (the stick condition itself lives in the integrators). With a0 = 0 (the
        // regularized reading) the first piece a1 v holds for every v <= 0.01 ref, as written.
        const bool odd = a[0] > 0.0;
        const double u = odd ? std::fabs(v) : v, su = (odd && v < 0.0) ? -1.0 : 1.0;
        double p, dp;
        if (u <= 0.01 * ref_speed) {
          p = a[0] + a[1] * u;
          dp = a[1];
        } else if (u <= 0.05 * ref_speed) {
          p = a[2] + a[3] * u;
          dp = a[3];
        } else {
          p = a[4] + u * (a[5] + u * (a[6] + u * a[7]));
          dp = a[5] + u * (2.0 * a[6] + 3.0 * u * a[7]);
        }
        p *= su;  // d(su p(|v|))/dv = p'(|v|): dp unchanged
        if (kind == Kind::polynomial) {
          r.base = gain * p;
          r.dbase_dv = gain * dp;
        } else {
          r.frac = gain * p;
          r.dfrac_dv = gain * dp;
          r.c = beta1 * sg;
        }
        break;
      }
    }
    r.k = beta2 * s;  // tanh(beta2 a_unit) = tanh(beta2 s a_si)
    r.base *= w;
    r.frac *= w;
    r.dbase_dv *= w * s;
    r.dfrac_dv *= w * s;
    return r;
  }

  /// Static (break-away) torque at rest [N m] at WOB `wob`: gain a0 W / W_ref for the
  /// non-regularized laws of Eqs. (5.1) and (5.3) (H = 0 at rest since sign(0) = 0), 0 for the
  /// regularized laws (3.1)-(3.2), which vanish at rest and need no stick condition. While the bit is
  /// at rest it stays stuck as long as the torque the string applies to it is within
  /// [-static_torque, static_torque] (the set-valued law at v = 0).
  double static_torque(double wob) const {
    if (kind != Kind::polynomial && kind != Kind::polynomial_hysteretic) return 0.0;
    return std::max(0.0, gain * a[0]) * wob / wob_ref;
  }

  /// Torque on bit [N.m] at SI bit speed v [rad/s], acceleration acc [rad/s^2] and WOB [N].
  double torque(double v, double acc, double wob) const { return at_speed(v, wob).torque(acc); }

  /// Torque with partial derivatives (used by the implicit integrator and the identification).
  TorqueEval eval(double v_si, double a_si, double wob) const { return at_speed(v_si, wob).eval(a_si); }
};

/// The thesis's Tucker-Wang fit of section 3.1: mu W r = 4700, alpha0 = 1.67e4, alpha1 = 5.30,
/// alpha2 = 3.45 (bit speed in rad/s: see docs/units.md).
inline BitRockLaw thesis_tucker_wang() {
  BitRockLaw l;
  l.kind = BitRockLaw::Kind::tucker_wang;
  l.speed_unit = SpeedUnit::rad_s;
  l.c0 = 4700.0;
  l.alpha0 = 1.67e4;
  l.alpha1 = 5.30;
  l.alpha2 = 3.45;
  return l;
}

/// The thesis's hysteretic fit of section 3.2: b0 = 3478, b1 = 938, b2 = 2.56, b3 = 0.38,
/// b4 = 0.78, b5 = 1.1, beta2 = 10.6; beta1 = 0 (model 1), 0.14 (model 2) or 0.56 (model 3).
inline BitRockLaw thesis_hysteretic(double beta1, SpeedUnit unit) {
  BitRockLaw l;
  l.kind = BitRockLaw::Kind::hysteretic;
  l.speed_unit = unit;
  l.b = {3478.0, 938.0, 2.56, 0.38, 0.78, 1.1};
  l.beta1 = beta1;
  l.beta2 = 10.6;
  return l;
}

}  // namespace drill
