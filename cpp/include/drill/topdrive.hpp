// Top-drive models: how the top of the string is turned.
//
// The thesis clamps the top node in a frame rotating at a prescribed speed Omega(t) (Eqs. 2.1-2.6):
// an ideal drive that holds its speed whatever the torque. The test rig's drive is an open-loop DC
// motor (section 5.3.2: "top drive speed decreases between 40 % and 60 % during drilling ... because
// the top drive control is based on open-loop system"; the bit sometimes sticks at a torque "that
// the electrical motor is not able to overcome"). The motor model gives it a linear torque-speed
// characteristic (speed droop) and an inertia:
//
//   J_m Omega' = c_m (Omega_c(t) - Omega) - T_top,      T_top = elastic torque of the string at the top
//
// Omega_c is the commanded (no-load) speed, c_m [N m s/rad] the slope of the characteristic: under a
// steady torque T the motor turns at Omega_c - T / c_m (droop 1 / c_m per N m) and it stalls above
// c_m Omega_c. The motor speed is a state of the simulation; its own damping term is integrated
// implicitly (backward Euler: stable for any c_m dt / J_m), the string torque explicitly.
#pragma once

#include <cmath>
#include <string>

#include "drill/errors.hpp"

namespace drill {

struct TopDrive {
  enum class Kind { ideal, motor };
  Kind kind = Kind::ideal;
  double slope = 0.0;    ///< c_m: torque lost per unit speed [N m s/rad] (motor only)
  double inertia = 0.0;  ///< J_m: rotor and drive train inertia [kg m^2] (motor only)

  static Kind parse_kind(const std::string& s) {
    if (s == "ideal") return Kind::ideal;
    if (s == "motor") return Kind::motor;
    throw std::invalid_argument("top_drive.type = \"" + s + "\": unknown top drive (use ideal or motor)");
  }
  static std::string kind_name(Kind k) { return k == Kind::motor ? "motor" : "ideal"; }
  bool is_motor() const { return kind == Kind::motor; }

  void validate() const {
    if (kind != Kind::motor) return;
    require_positive(slope, "top_drive.slope_nms_rad");
    require_positive(inertia, "top_drive.inertia_kg_m2");
  }

  /// Steady speed under a torque T [N m] at command Omega_c [rad/s]: Omega_c - T / c_m.
  double steady_speed(double command, double torque) const {
    return is_motor() ? command - torque / slope : command;
  }

  /// Motor speed after one step dt from `omega` with the command and the string's top torque of
  /// the current step: (Omega + dt (c_m Omega_c - T_top) / J_m) / (1 + dt c_m / J_m).
  double step(double omega, double command, double top_torque, double dt) const {
    return (omega + dt / inertia * (slope * command - top_torque)) / (1.0 + dt * slope / inertia);
  }
};

}  // namespace drill
