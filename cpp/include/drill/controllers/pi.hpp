// The pi controller: the user's kp_nms_rad and ki_nm_rad, both required. A controller of
// controllers/registry.hpp.
#pragma once

#include <cmath>
#include <vector>

#include "drill/config_keys.hpp"
#include "drill/controllers/gain_keys.hpp"
#include "drill/errors.hpp"

namespace drill::controllers {

struct Pi {
  static constexpr bool torque_feedback = false;

  /// kp and ki, required: validate() refuses an absent one.
  template <class C>
  static std::vector<Key<C>> keys() {
    Key<C> kp = kp_key<C>(), ki = ki_key<C>();
    kp.field.req_in_validate();
    ki.field.req_in_validate();
    return {kp, ki};
  }

  template <class C>
  static void validate(const C& c) {
    const std::string w = "top_drive.controller.";
    require(!std::isnan(c.kp_given), w + "kp_nms_rad", c.kp_given, "is required for the pi controller");
    require(!std::isnan(c.ki_given), w + "ki_nm_rad", c.ki_given, "is required for the pi controller");
  }

  /// No gains of its own: the user's.
  template <class C>
  static void gains(const C&, double /*J*/, double /*w1*/, double& /*p*/, double& /*i*/) {}

  template <class C>
  static void check_tuned(const C&) {}
};

}  // namespace drill::controllers
