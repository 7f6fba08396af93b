// The soft_speed controller: the SoftTorque / SoftSpeed principle (Kyllingstad and Nessjoen 2009,
// SPE 119660; Kyllingstad and Nessjoen 2010): a PI speed controller whose I term cancels the
// drive's inertia at the stick-slip frequency w_s, ki = J w_s^2, so that Z_d(i w_s) = kp is real
// (a pure damper at that frequency), and whose P term is the damping that absorbs the waves,
// kp = Z. w_s is the string's first natural frequency from the engine unless
// `stick_slip_frequency_rad_s` is given. A controller of controllers/registry.hpp.
#pragma once

#include <cmath>
#include <vector>

#include "drill/config_keys.hpp"
#include "drill/controllers/gain_keys.hpp"

namespace drill::controllers {

struct SoftSpeed {
  static constexpr bool torque_feedback = false;

  template <class C>
  static std::vector<Key<C>> keys() {
    return {kp_key<C>(),
            ki_key<C>(),
            impedance_key<C>(),
            {schema::number("stick_slip_frequency_rad_s", "w_s [rad/s] (default: the string's first natural frequency)")
                 .positive(),
             &C::stick_slip_frequency}};
  }

  template <class C>
  static void validate(const C&) {}

  template <class C>
  static void gains(const C& c, double J, double w1, double& p, double& i) {
    const double ws = std::isfinite(c.stick_slip_frequency) ? c.stick_slip_frequency : w1;
    p = c.impedance;
    i = J * ws * ws;
  }

  template <class C>
  static void check_tuned(const C&) {}
};

}  // namespace drill::controllers
