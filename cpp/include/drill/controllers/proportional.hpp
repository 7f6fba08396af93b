// SCRATCH (counting the places a controller takes; reverted): a P-only loop, kp = 2 J w_b, ki = 0.
#pragma once

#include <vector>

#include "drill/config_keys.hpp"
#include "drill/controllers/gain_keys.hpp"

namespace drill::controllers {

struct Proportional {
  static constexpr bool torque_feedback = false;
  template <class C>
  static std::vector<Key<C>> keys() {
    return {kp_key<C>(), bandwidth_key<C>()};
  }
  template <class C>
  static void validate(const C&) {}
  template <class C>
  static void gains(const C& c, double J, double w1, double& p, double& i) {
    p = 2.0 * J * c.bandwidth_ratio * w1;
    i = 0.0;
  }
  template <class C>
  static void check_tuned(const C&) {}
};

}  // namespace drill::controllers
