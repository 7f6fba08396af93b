// The config keys the controllers of controllers/registry.hpp share (top_drive.controller): the
// gains kp, ki, which every controller lets the user override, the stiff loop's bandwidth ratio
// and the impedance Z.
#pragma once

#include "drill/config_keys.hpp"

namespace drill::controllers {

template <class C>
Key<C> kp_key() {
  return {schema::number("kp_nms_rad", "kp: proportional gain [N m s/rad]").positive(), &C::kp_given};
}

template <class C>
Key<C> ki_key() {
  return {schema::number("ki_nm_rad", "ki: integral gain [N m/rad]").non_negative(), &C::ki_given};
}

template <class C>
Key<C> bandwidth_key() {
  return {schema::number("bandwidth_ratio", "closed-loop bandwidth of the speed loop over the string's first "
                                            "natural frequency: kp = 2 J w_b, ki = J w_b^2, w_b = ratio w_1")
              .positive()
              .def(C{}.bandwidth_ratio),
          &C::bandwidth_ratio};
}

template <class C>
Key<C> impedance_key() {
  return {schema::number("impedance_nms_rad", "Z [N m s/rad] (default: the top section's J_p sqrt(G rho))").positive(),
          &C::impedance_given};
}

}  // namespace drill::controllers
