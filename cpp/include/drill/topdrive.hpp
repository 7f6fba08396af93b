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
//
// The motor's torque is limited (`max_torque_nm`, T_max; the rig's motor: 8 N m, thesis section 5.1):
//
//   J_m Omega' = min(c_m (Omega_c - Omega), T_max) - T_top
//
// so that a bit stuck at a torque above min(c_m Omega_c, T_max) stalls the top ("the bit sticks and
// achieves a reactive torque that the electrical motor is not able to overcome", section 5.3.2).
// Without the key the characteristic is unlimited (the previous model).
//
// A `controlled` drive (issue 15) is the same free top inertia J driven by the torque of a speed
// controller instead of the motor's characteristic (controller.hpp: stiff, pi, soft_speed, z_torque,
// with a torque limit and a sample time):
//
//   J Omega' = u - T_top,   u = sat_L(kp (Omega_ref - Omega) + T_I),   T_I' = ki (Omega_ref - Omega)
//
// Its gains are tuned from the string (Simulation's constructor calls tune_controller with the top
// section's characteristic impedance and the first natural frequency of the reduced model). With
// integral action the drive turns at the command in steady drilling (steady_speed).
#pragma once

#include <cmath>
#include <string>

#include "drill/controller.hpp"
#include "drill/errors.hpp"
#include "drill/names.hpp"

namespace drill {

struct TopDrive {
  enum class Kind { ideal, motor, controlled };
  Kind kind = Kind::ideal;
  double slope = 0.0;    ///< c_m: torque lost per unit speed [N m s/rad] (motor only)
  double inertia = 0.0;  ///< J_m, J: rotor and drive train inertia [kg m^2] (motor, controlled)
  double max_torque = HUGE_VAL;  ///< T_max: the motor's torque limit [N m] (motor only; HUGE_VAL: none)
  Controller controller;  ///< controlled only

  /// The top drives by name (top_drive.type); their keys are the variants of the "top_drive" table (config.hpp).
  static constexpr Named<Kind> kinds[] = {{Kind::ideal, "ideal"}, {Kind::motor, "motor"}, {Kind::controlled, "controlled"}};
  static Kind parse_kind(const std::string& s) { return parse_name(kinds, s, "top_drive.type", "top drive"); }
  static std::string kind_name(Kind k) { return name_of(kinds, k); }
  bool is_motor() const { return kind == Kind::motor; }
  bool is_controlled() const { return kind == Kind::controlled; }
  /// The top is a free inertia (motor or controlled): its speed is a state of the simulation.
  bool has_inertia() const { return kind != Kind::ideal; }

  void validate() const {
    if (kind == Kind::ideal) return;
    if (kind == Kind::motor) {
      require_positive(slope, "top_drive.slope_nms_rad");
      require(max_torque > 0.0, "top_drive.max_torque_nm", max_torque, "must be positive (absent: unlimited)");
    }
    require_positive(inertia, "top_drive.inertia_kg_m2");
    if (kind == Kind::controlled) {
      controller.validate();
      const Controller c = controller.tuned() ? controller : controller.with_given_gains();
      if (c.tuned()) c.validate_tuned(inertia);
    }
  }

  /// Tune a controlled drive's gains from the top section's characteristic impedance Z [N m s/rad]
  /// and the string's first natural frequency w1 [rad/s] (Controller::tune), and check them.
  void tune_controller(double Z, double w1) {
    if (kind != Kind::controlled) return;
    controller.tune(inertia, Z, w1);
    controller.validate_tuned(inertia);
  }

  /// Steady speed under a torque T [N m] at command Omega_c [rad/s]: Omega_c - T / c_m for the motor;
  /// the command for the ideal drive and a controller (the integral carries the torque; ki > 0).
  double steady_speed(double command, double torque) const {
    if (is_motor()) return torque >= max_torque ? 0.0 : command - torque / slope;
    if (is_controlled() && !(controller.ki > 0.0)) return command - torque / controller.kp;  // P only: droop
    return command;
  }

  /// Motor speed after one step dt from `omega` with the command and the string's top torque of
  /// the current step: (Omega + dt (c_m Omega_c - T_top) / J_m) / (1 + dt c_m / J_m) on the
  /// characteristic; Omega + dt (T_max - T_top) / J_m where the characteristic's torque at the new
  /// speed would exceed the limit (the step is implicit in the characteristic, explicit in the limit).
  double step(double omega, double command, double top_torque, double dt) const {
    const double next = (omega + dt / inertia * (slope * command - top_torque)) / (1.0 + dt * slope / inertia);
    if (slope * (command - next) <= max_torque) return next;
    return omega + dt / inertia * (max_torque - top_torque);
  }
};

}  // namespace drill
