// The hysteretic law, Eqs. (3.2)-(3.3):
//   T = b0 [tanh(b1 v) + b2 |v|^b4 sign(v) / (1 + b3 |v|^b5) (1 + H)],  H = beta1 tanh(beta2 a) sign(v)
// regularized (it vanishes at rest: no stick condition). A law of laws/registry.hpp: its
// parameters, config keys, validation and formula, scalar and on lanes.
#ifndef DRILL_LAWS_HYSTERETIC_HPP_
#define DRILL_LAWS_HYSTERETIC_HPP_

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

struct Hysteretic {
  /// b0..b5 of Eq. (3.2) (beta1, beta2 of Eq. 3.3: Hysteresis).
  struct Params {
    std::array<double, 6> b{};

    bool operator==(const Params& o) const { return b == o.b; }
  };

  template <class L>
  static std::vector<Key<L>> keys() {
    using schema::number;
    auto b = [](int i) { return [i](auto& l) -> auto& { return l.b[i]; }; };
    std::vector<Key<L>> k = {
        {number("b0", "Eq. (3.2): T = b0 [tanh(b1 v) + b2 |v|^b4 sign(v) / (1 + b3 |v|^b5) (1 + H)] [N m]").req(),
         b(0)},
        {number("b1", "Eq. (3.2) [1 / speed_unit]").req(), b(1)},
        {number("b2", "Eq. (3.2)").req(), b(2)},
        {number("b3", "Eq. (3.2)").non_negative().req(), b(3)},
        {number("b4", "Eq. (3.2) exponent").positive().req(), b(4)},
        {number("b5", "Eq. (3.2) exponent").positive().req(), b(5)}};
    const std::vector<Key<L>> h = Hysteresis::keys<L>();
    k.insert(k.end(), h.begin(), h.end());
    return k;
  }

  template <class L>
  static void validate(const L& l) {
    for (int i = 0; i < 6; ++i) require_finite(l.b[i], "law.b" + std::to_string(i));
    require_non_negative(l.b[3], "law.b3");
    require_positive(l.b[4], "law.b4");
    require_positive(l.b[5], "law.b5");
  }

  /// Eq. (3.2) at the bit speed v [speed_unit], sg = sign(v): b0 tanh(b1 v) + b0 b2 |v|^b4 sign(v) /
  /// (1 + b3 |v|^b5) (1 + H), base and frac with their derivatives, c of Eq. (3.3).
  template <class L>
  static void at_speed(const L& l, double v, double sg, AtSpeed& r) {
    const auto& b = l.b;
    const double t = tanh_sat(b[1] * v);
    r.base = b[0] * t;
    r.dbase_dv = b[0] * b[1] * (1.0 - t * t);
    const double av = std::max(std::fabs(v), 1e-300), lv = std::log(av);
    const double p4 = std::exp(b[4] * lv), p5 = std::exp(b[5] * lv), den = 1.0 + b[3] * p5;
    r.frac = b[0] * sg * b[2] * p4 / den;
    r.dfrac_dv = b[0] * b[2] * (b[4] * den - b[3] * b[5] * p5) * p4 / (av * den * den);
    r.c = l.beta1 * sg;  // Eq. (3.3)
  }

  template <class L>
  static double static_torque(const L&, double /*wob*/) {
    return 0.0;
  }
};

}  // namespace drill::laws

#endif  // DRILL_LAWS_HYSTERETIC_HPP_

#ifdef DRILL_LAW_LANES  // the per-target part (laws/registry.hpp)
HWY_BEFORE_NAMESPACE();
namespace drill {
namespace HWY_NAMESPACE {
namespace batched_detail {

/// Eq. (3.2) on lanes for the modified Euler kernel (the scalar expression order, no FMA).
template <class L>
HWY_INLINE void LawAtSpeed(laws::Hysteretic, D d, const L& law, V v, V sg, V& base, V& frac, V& c) {
  const auto& b = law.b;
  const V one = hn::Set(d, 1.0);
  base = hn::Set(d, b[0]) * TanhSat(d, hn::Set(d, b[1]) * v);
  const V av = StdMax(hn::Abs(v), hn::Set(d, 1e-300)), lv = hn::Log(d, av);
  const V p4 = hn::Exp(d, hn::Set(d, b[4]) * lv), p5 = hn::Exp(d, hn::Set(d, b[5]) * lv);
  const V den = one + hn::Set(d, b[3]) * p5;
  frac = hn::Set(d, b[0]) * sg * hn::Set(d, b[2]) * p4 / den;
  c = hn::Set(d, law.beta1) * sg;  // Eq. (3.3)
}

/// Eq. (3.2) and its speed derivatives on lanes for the exact modal kernel (FMA).
template <class L>
HWY_INLINE void LawAtSpeedDv(laws::Hysteretic, D d, const L& law, V v, V sg, V& base, V& frac, V& c, V& dbase,
                             V& dfrac) {
  const auto& b = law.b;
  const V one = hn::Set(d, 1.0);
  const V t = TanhSatSkip(d, hn::Set(d, b[1]) * v);
  base = hn::Set(d, b[0]) * t;
  dbase = hn::Set(d, b[0] * b[1]) * hn::NegMulAdd(t, t, one);
  const V av = StdMax(hn::Abs(v), hn::Set(d, 1e-300)), lv = hn::Log(d, av);
  const V p4 = hn::Exp(d, hn::Set(d, b[4]) * lv), p5 = hn::Exp(d, hn::Set(d, b[5]) * lv);
  // q = |v|^b4 / (1 + b3 |v|^b5) and its derivative (b4 den - b3 b5 |v|^b5) |v|^b4 / (|v| den^2) of
  // q sign(v), with one division (off the Newton iteration's chain of latencies)
  const V den = hn::MulAdd(hn::Set(d, b[3]), p5, one), r = one / (av * den), q = p4 * av * r;
  frac = hn::Set(d, b[0] * b[2]) * sg * q;
  dfrac = hn::Set(d, b[0] * b[2]) * hn::MulSub(hn::Set(d, b[4]), den, hn::Set(d, b[3] * b[5]) * p5) * q * r;
  c = hn::Set(d, law.beta1) * sg;  // Eq. (3.3)
}

}  // namespace batched_detail
}  // namespace HWY_NAMESPACE
}  // namespace drill
HWY_AFTER_NAMESPACE();
#endif  // DRILL_LAW_LANES
