// The z_torque controller: the ZTorque principle (Dwars 2015, SPE/IADC 173037): the speed set point
// is corrected by the measured top torque so that the drive behaves as the impedance Z over a broad
// band, not at one frequency:
//   Omega_ref = Omega_c - (T_top - T_mean) / Z,   tau T_mean' = T_top - T_mean,
// T_mean the low-passed top torque (time constant tau = `torque_filter_s`, default 5 / w_1, so
// that the correction passes the stick-slip frequency almost unchanged and has no steady effect),
// fed to a stiff PI loop (gains as `stiff`). A controller of controllers/registry.hpp.
#pragma once

#include <vector>

#include "drill/config_keys.hpp"
#include "drill/controllers/gain_keys.hpp"
#include "drill/controllers/stiff.hpp"
#include "drill/errors.hpp"

namespace drill::controllers {

struct ZTorque {
  static constexpr bool torque_feedback = true;

  template <class C>
  static std::vector<Key<C>> keys() {
    return {kp_key<C>(),
            ki_key<C>(),
            bandwidth_key<C>(),
            impedance_key<C>(),
            {schema::number("torque_filter_s", "time constant of the top torque's low-pass T_mean [s] (default: 5 / w_1)")
                 .positive(),
             &C::torque_filter_given}};
  }

  template <class C>
  static void validate(const C&) {}

  template <class C>
  static void gains(const C& c, double J, double w1, double& p, double& i) {
    Stiff::gains(c, J, w1, p, i);
  }

  template <class C>
  static void check_tuned(const C& c) {
    require_positive(c.impedance, "top_drive.controller.impedance_nms_rad");
    require_positive(c.torque_filter, "top_drive.controller.torque_filter_s");
  }
};

}  // namespace drill::controllers
