// The stiff controller: a high-gain PI, the loop J s^2 + kp s + ki with a double pole at -w_b,
// w_b = bandwidth_ratio x w_1 (w_1 the string's first natural frequency, top clamped):
// kp = 2 J w_b, ki = J w_b^2. With bandwidth_ratio -> infinity the top turns at the command whatever
// the torque: the thesis's ideal drive (test_controller.cpp). A controller of controllers/registry.hpp.
#pragma once

#include <vector>

#include "drill/config_keys.hpp"
#include "drill/controllers/gain_keys.hpp"

namespace drill::controllers {

struct Stiff {
  static constexpr bool torque_feedback = false;

  template <class C>
  static std::vector<Key<C>> keys() {
    return {kp_key<C>(), ki_key<C>(), bandwidth_key<C>()};
  }

  template <class C>
  static void validate(const C&) {}

  template <class C>
  static void gains(const C& c, double J, double w1, double& p, double& i) {
    const double wb = c.bandwidth_ratio * w1;
    p = 2.0 * J * wb;
    i = J * wb * wb;
  }

  template <class C>
  static void check_tuned(const C&) {}
};

}  // namespace drill::controllers
