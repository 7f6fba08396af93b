// SCRATCH (counting the places a law takes; reverted): a constant torque T = t0 sign(v).
#ifndef DRILL_LAWS_CONSTANT_TORQUE_HPP_
#define DRILL_LAWS_CONSTANT_TORQUE_HPP_

#include <vector>

#include "drill/config_keys.hpp"
#include "drill/errors.hpp"
#include "drill/laws/at_speed.hpp"

namespace drill::laws {

struct ConstantTorque {
  struct Params {
    double t0 = 0.0;
    bool operator==(const Params& o) const { return t0 == o.t0; }
  };
  template <class L>
  static std::vector<Key<L>> keys() {
    return {{schema::number("t0", "T = t0 sign(v) [N m]").req(), &L::t0}};
  }
  template <class L>
  static void validate(const L& l) {
    require_finite(l.t0, "law.t0");
  }
  template <class L>
  static void at_speed(const L& l, double /*v*/, double sg, AtSpeed& r) {
    r.base = l.t0 * sg;
  }
  template <class L>
  static double static_torque(const L&, double /*wob*/) {
    return 0.0;
  }
};

}  // namespace drill::laws

#endif  // DRILL_LAWS_CONSTANT_TORQUE_HPP_

#ifdef DRILL_LAW_LANES
HWY_BEFORE_NAMESPACE();
namespace drill {
namespace HWY_NAMESPACE {
namespace batched_detail {

template <class L>
HWY_INLINE void LawAtSpeed(laws::ConstantTorque, D d, const L& law, V /*v*/, V sg, V& base, V& /*frac*/, V& /*c*/) {
  base = hn::Set(d, law.t0) * sg;
}
template <class L>
HWY_INLINE void LawAtSpeedDv(laws::ConstantTorque, D d, const L& law, V /*v*/, V sg, V& base, V& /*frac*/, V& /*c*/,
                             V& /*dbase*/, V& /*dfrac*/) {
  base = hn::Set(d, law.t0) * sg;
}

}  // namespace batched_detail
}  // namespace HWY_NAMESPACE
}  // namespace drill
HWY_AFTER_NAMESPACE();
#endif  // DRILL_LAW_LANES
