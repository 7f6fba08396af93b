// The polynomial laws, which share their formula and parameters:
//  * polynomial             Eq. (5.1)  non-regularized piecewise polynomial (coefficients a0..a7,
//                                      breakpoints at 1 % and 5 % of a reference speed, gain 1.36),
//                                      odd in the bit speed when a0 > 0; at rest it is set-valued: the bit
//                                      stays stuck while |string torque| <= the static torque
//                                      1.36 a0 W / W_ref (static_torque(); the integrators apply this
//                                      stick condition)
//  * polynomial_hysteretic  Eq. (5.3)  T = T_poly(v) (1 + H(v, a)), H of Eq. (3.3)
// Laws of laws/registry.hpp: their parameters, config keys, validation and formula, scalar and on lanes.
#ifndef DRILL_LAWS_POLYNOMIAL_HPP_
#define DRILL_LAWS_POLYNOMIAL_HPP_

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "drill/config_keys.hpp"
#include "drill/errors.hpp"
#include "drill/laws/at_speed.hpp"
#include "drill/laws/hysteresis.hpp"

namespace drill::laws {

/// The parameters of Eq. (5.1), shared by both laws.
struct PolynomialParams {
  std::array<double, 8> a{};
  double ref_speed = 1.0;  ///< mean bit speed of Eq. (5.1), in speed_unit
  double gain = 1.36;      ///< the constant factor of Eq. (5.1) (ft.lbf -> N.m)

  bool operator==(const PolynomialParams& o) const { return a == o.a && ref_speed == o.ref_speed && gain == o.gain; }
};

/// Eq. (5.1) (Hysteretic = false: polynomial) or Eq. (5.3) (true: polynomial_hysteretic).
template <bool Hysteretic>
struct PolynomialLaw {
  using Params = PolynomialParams;

  template <class L>
  static std::vector<Key<L>> keys() {
    using schema::number;
    std::vector<Key<L>> k;
    for (int i = 0; i < 8; ++i)
      k.push_back({number("a" + std::to_string(i), "Eq. (5.1) coefficient a" + std::to_string(i)).req(),
                   [i](auto& l) -> auto& { return l.a[i]; }});
    k.push_back({number("ref_speed", "mean bit speed of Eq. (5.1) [speed_unit]").positive().req(), &L::ref_speed});
    k.push_back({number("gain", "constant factor of Eq. (5.1) (1.36: ft.lbf to N m)").req(), &L::gain});
    if constexpr (Hysteretic) {
      const std::vector<Key<L>> h = Hysteresis::keys<L>();
      k.insert(k.end(), h.begin(), h.end());
    }
    return k;
  }

  template <class L>
  static void validate(const L& l) {
    for (int i = 0; i < 8; ++i) require_finite(l.a[i], "law.a" + std::to_string(i));
    require_positive(l.ref_speed, "law.ref_speed");
    require_finite(l.gain, "law.gain");
  }

  /// Eq. (5.1), or its hysteretic form Eq. (5.3), at the bit speed v [speed_unit], sg = sign(v).
  template <class L>
  static void at_speed(const L& l, double v, [[maybe_unused]] double sg, AtSpeed& r) {
    // With a static torque (a0 > 0, the non-regularized law) Eq. (5.1) is extended to v < 0 as an
    // odd function (the friction resists the motion in either direction) and v = 0 returns the
    // right limit a0 (the stick condition itself lives in the integrators). With a0 = 0 (the
    // regularized reading) the first piece a1 v holds for every v <= 0.01 ref, as written.
    const auto& a = l.a;
    const bool odd = a[0] > 0.0;
    const double u = odd ? std::fabs(v) : v, su = (odd && v < 0.0) ? -1.0 : 1.0;
    double p, dp;
    if (u <= 0.01 * l.ref_speed) {
      p = a[0] + a[1] * u;
      dp = a[1];
    } else if (u <= 0.05 * l.ref_speed) {
      p = a[2] + a[3] * u;
      dp = a[3];
    } else {
      p = a[4] + u * (a[5] + u * (a[6] + u * a[7]));
      dp = a[5] + u * (2.0 * a[6] + 3.0 * u * a[7]);
    }
    p *= su;  // d(su p(|v|))/dv = p'(|v|): dp unchanged
    if constexpr (!Hysteretic) {
      r.base = l.gain * p;
      r.dbase_dv = l.gain * dp;
    } else {
      r.frac = l.gain * p;
      r.dfrac_dv = l.gain * dp;
      r.c = l.beta1 * sg;
    }
  }

  /// The static (break-away) torque gain a0 W / W_ref (H = 0 at rest since sign(0) = 0).
  template <class L>
  static double static_torque(const L& l, double wob) {
    return std::max(0.0, l.gain * l.a[0]) * wob / l.wob_ref;
  }
};

using Polynomial = PolynomialLaw<false>;
using PolynomialHysteretic = PolynomialLaw<true>;

}  // namespace drill::laws

#endif  // DRILL_LAWS_POLYNOMIAL_HPP_

#ifdef DRILL_LAW_LANES  // the per-target part (laws/registry.hpp)
HWY_BEFORE_NAMESPACE();
namespace drill {
namespace HWY_NAMESPACE {
namespace batched_detail {

/// Eqs. (5.1), (5.3) on lanes for the modified Euler kernel (the scalar expression order, no FMA).
template <bool Hysteretic, class L>
HWY_INLINE void LawAtSpeed(laws::PolynomialLaw<Hysteretic>, D d, const L& law, V v, [[maybe_unused]] V sg,
                           [[maybe_unused]] V& base, [[maybe_unused]] V& frac, [[maybe_unused]] V& c) {
  const auto& a = law.a;
  const V one = hn::Set(d, 1.0);
  const bool odd = a[0] > 0.0;
  const V u = odd ? hn::Abs(v) : v;
  const V p1 = hn::Set(d, a[0]) + hn::Set(d, a[1]) * u, p2 = hn::Set(d, a[2]) + hn::Set(d, a[3]) * u;
  const V p3 = hn::Set(d, a[4]) + u * (hn::Set(d, a[5]) + u * (hn::Set(d, a[6]) + u * hn::Set(d, a[7])));
  V p = hn::IfThenElse(u <= hn::Set(d, 0.01 * law.ref_speed), p1,
                       hn::IfThenElse(u <= hn::Set(d, 0.05 * law.ref_speed), p2, p3));
  if (odd) p = hn::IfThenElse(v < hn::Zero(d), hn::Set(d, -1.0), one) * p;
  if constexpr (!Hysteretic) {
    base = hn::Set(d, law.gain) * p;
  } else {
    frac = hn::Set(d, law.gain) * p;
    c = hn::Set(d, law.beta1) * sg;
  }
}

/// Eqs. (5.1), (5.3) and their speed derivatives on lanes for the exact modal kernel (FMA).
template <bool Hysteretic, class L>
HWY_INLINE void LawAtSpeedDv(laws::PolynomialLaw<Hysteretic>, D d, const L& law, V v, [[maybe_unused]] V sg,
                             [[maybe_unused]] V& base, [[maybe_unused]] V& frac, [[maybe_unused]] V& c,
                             [[maybe_unused]] V& dbase, [[maybe_unused]] V& dfrac) {
  const auto& a = law.a;
  const bool odd = a[0] > 0.0;
  const V u = odd ? hn::Abs(v) : v;
  const V p1 = hn::MulAdd(hn::Set(d, a[1]), u, hn::Set(d, a[0])), p2 = hn::MulAdd(hn::Set(d, a[3]), u, hn::Set(d, a[2]));
  const V p3 = hn::MulAdd(u, hn::MulAdd(u, hn::MulAdd(u, hn::Set(d, a[7]), hn::Set(d, a[6])), hn::Set(d, a[5])), hn::Set(d, a[4]));
  const V dp3 = hn::MulAdd(u, hn::MulAdd(hn::Set(d, 3.0 * a[7]), u, hn::Set(d, 2.0 * a[6])), hn::Set(d, a[5]));
  const M m1 = u <= hn::Set(d, 0.01 * law.ref_speed), m2 = u <= hn::Set(d, 0.05 * law.ref_speed);
  V p = hn::IfThenElse(m1, p1, hn::IfThenElse(m2, p2, p3));
  const V dp = hn::IfThenElse(m1, hn::Set(d, a[1]), hn::IfThenElse(m2, hn::Set(d, a[3]), dp3));
  if (odd) p = hn::IfThenElse(v < hn::Zero(d), hn::Neg(p), p);  // d(su p(|v|))/dv = p'(|v|)
  if constexpr (!Hysteretic) {
    base = hn::Set(d, law.gain) * p;
    dbase = hn::Set(d, law.gain) * dp;
  } else {
    frac = hn::Set(d, law.gain) * p;
    dfrac = hn::Set(d, law.gain) * dp;
    c = hn::Set(d, law.beta1) * sg;
  }
}

}  // namespace batched_detail
}  // namespace HWY_NAMESPACE
}  // namespace drill
HWY_AFTER_NAMESPACE();
#endif  // DRILL_LAW_LANES
