// The Tucker-Wang law, Eq. (3.1): T = c0 [tanh(alpha0 v) + alpha1 v / (1 + alpha2 v^2)], reversible
// (no hysteresis) and regularized (it vanishes at rest: no stick condition). A law of
// laws/registry.hpp: its parameters, config keys, validation and formula, scalar and on lanes.
#ifndef DRILL_LAWS_TUCKER_WANG_HPP_
#define DRILL_LAWS_TUCKER_WANG_HPP_

#include <vector>

#include "drill/config_keys.hpp"
#include "drill/errors.hpp"
#include "drill/laws/at_speed.hpp"

namespace drill::laws {

struct TuckerWang {
  /// c0 = mu W r (the thesis's 4700 N.m).
  struct Params {
    double c0 = 0.0, alpha0 = 0.0, alpha1 = 0.0, alpha2 = 0.0;

    bool operator==(const Params& o) const {
      return c0 == o.c0 && alpha0 == o.alpha0 && alpha1 == o.alpha1 && alpha2 == o.alpha2;
    }
  };

  template <class L>
  static std::vector<Key<L>> keys() {
    using schema::number;
    return {{number("c0", "Eq. (3.1): T = c0 [tanh(alpha0 v) + alpha1 v / (1 + alpha2 v^2)] [N m]").req(), &L::c0},
            {number("alpha0", "Eq. (3.1) [1 / speed_unit]").non_negative().req(), &L::alpha0},
            {number("alpha1", "Eq. (3.1) [1 / speed_unit]").req(), &L::alpha1},
            {number("alpha2", "Eq. (3.1) [1 / speed_unit^2]").non_negative().req(), &L::alpha2}};
  }

  template <class L>
  static void validate(const L& l) {
    require_finite(l.c0, "law.c0");
    require_non_negative(l.alpha0, "law.alpha0");
    require_finite(l.alpha1, "law.alpha1");
    require_non_negative(l.alpha2, "law.alpha2");
  }

  /// Eq. (3.1) at the bit speed v [speed_unit]: base and its derivative.
  template <class L>
  static void at_speed(const L& l, double v, double /*sign_v*/, AtSpeed& r) {
    const double t = tanh_sat(l.alpha0 * v), den = 1.0 + l.alpha2 * v * v;
    r.base = l.c0 * (t + l.alpha1 * v / den);
    r.dbase_dv = l.c0 * (l.alpha0 * (1.0 - t * t) + l.alpha1 * (1.0 - l.alpha2 * v * v) / (den * den));
  }

  template <class L>
  static double static_torque(const L&, double /*wob*/) {
    return 0.0;
  }
};

}  // namespace drill::laws

#endif  // DRILL_LAWS_TUCKER_WANG_HPP_

#ifdef DRILL_LAW_LANES  // the per-target part (laws/registry.hpp)
HWY_BEFORE_NAMESPACE();
namespace drill {
namespace HWY_NAMESPACE {
namespace batched_detail {

/// Eq. (3.1) on lanes for the modified Euler kernel (the scalar expression order, no FMA).
template <class L>
HWY_INLINE void LawAtSpeed(laws::TuckerWang, D d, const L& law, V v, V /*sg*/, V& base, V& /*frac*/, V& /*c*/) {
  const V one = hn::Set(d, 1.0);
  const V t = TanhSat(d, hn::Set(d, law.alpha0) * v), den = one + hn::Set(d, law.alpha2) * v * v;
  base = hn::Set(d, law.c0) * (t + hn::Set(d, law.alpha1) * v / den);
}

/// Eq. (3.1) and its speed derivative on lanes for the exact modal kernel (FMA).
template <class L>
HWY_INLINE void LawAtSpeedDv(laws::TuckerWang, D d, const L& law, V v, V /*sg*/, V& base, V& /*frac*/, V& /*c*/,
                             V& dbase, V& /*dfrac*/) {
  const V one = hn::Set(d, 1.0);
  const V t = TanhSatSkip(d, hn::Set(d, law.alpha0) * v), v2 = v * v, den = hn::MulAdd(hn::Set(d, law.alpha2), v2, one);
  const V inv = one / den;
  base = hn::Set(d, law.c0) * hn::MulAdd(hn::Set(d, law.alpha1) * v, inv, t);
  dbase = hn::Set(d, law.c0) * hn::MulAdd(hn::Set(d, law.alpha0), hn::NegMulAdd(t, t, one),
                                          hn::Set(d, law.alpha1) * hn::NegMulAdd(hn::Set(d, law.alpha2), v2, one) * inv * inv);
}

}  // namespace batched_detail
}  // namespace HWY_NAMESPACE
}  // namespace drill
HWY_AFTER_NAMESPACE();
#endif  // DRILL_LAW_LANES
