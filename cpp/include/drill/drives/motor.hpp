// The open-loop motor top drive of the test rig (thesis section 5.3.2: "top drive speed decreases
// between 40 % and 60 % during drilling ... because the top drive control is based on open-loop
// system"; the bit sometimes sticks at a torque "that the electrical motor is not able to
// overcome"). The motor has a linear torque-speed characteristic (speed droop) and an inertia:
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
// Without the key the characteristic is unlimited (the previous model). A top drive of
// drives/registry.hpp.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "drill/config_keys.hpp"
#include "drill/errors.hpp"
#include "drill/signal.hpp"

namespace drill::drives {

struct Motor {
  struct Params {
    double slope = 0.0;            ///< c_m: torque lost per unit speed [N m s/rad]
    double max_torque = HUGE_VAL;  ///< T_max: the motor's torque limit [N m] (HUGE_VAL: none)
  };

  static constexpr bool has_inertia = true;  // J_m: TopDrive::inertia
  static constexpr bool has_controller = false;
  static constexpr bool accel_from_torque = true;

  template <class D>
  static std::vector<Key<D>> keys() {
    using schema::number;
    return {{number("slope_nms_rad", "c_m: torque lost per unit speed [N m s/rad]").positive().req(), &D::slope},
            {number("inertia_kg_m2", "J_m: rotor and drive-train inertia [kg m^2]").positive().req(), &D::inertia},
            {number("max_torque_nm", "T_max: the motor's torque limit [N m]; absent: unlimited").positive(),
             &D::max_torque}};
  }

  template <class D>
  static void validate(const D& d) {
    require_positive(d.slope, "top_drive.slope_nms_rad");
    require(d.max_torque > 0.0, "top_drive.max_torque_nm", d.max_torque, "must be positive (absent: unlimited)");
    require_positive(d.inertia, "top_drive.inertia_kg_m2");
  }

  /// Steady speed under a torque T [N m] at command Omega_c [rad/s]: Omega_c - T / c_m on the
  /// characteristic, 0 (stalled) at or above the torque limit.
  template <class D>
  static double steady_speed(const D& d, double command, double torque) {
    return torque >= d.max_torque ? 0.0 : command - torque / d.slope;
  }
  template <class D>
  static bool droops(const D&) {
    return true;
  }

  /// Motor speed after one step dt from `omega` with the command and the string's top torque of
  /// the current step: (Omega + dt (c_m Omega_c - T_top) / J_m) / (1 + dt c_m / J_m) on the
  /// characteristic; Omega + dt (T_max - T_top) / J_m where the characteristic's torque at the new
  /// speed would exceed the limit (the step is implicit in the characteristic, explicit in the limit).
  template <class D>
  static double step(const D& d, double omega, double command, double top_torque, double dt) {
    const double next = (omega + dt / d.inertia * (d.slope * command - top_torque)) / (1.0 + dt * d.slope / d.inertia);
    if (d.slope * (command - next) <= d.max_torque) return next;
    return omega + dt / d.inertia * (d.max_torque - top_torque);
  }

  /// The top's acceleration at speed omega and command, as the motor step makes it,
  /// (J_m + c_m dt) domega = c_m (command - omega) - T_top(domega), with the string's top torque
  /// linear in domega, T_top = t0 + dT domega (Integrator::state_from_bit).
  template <class D>
  static double top_accel(const D& d, double command, double omega, double dt, double t0, double dT) {
    const double den = d.inertia + d.slope * dt + dT;
    require(den > 0.0, "top_drive.inertia_kg_m2", d.inertia,
            "is too small for the string's inertia load at the top (J_m + dT_top/dOmega' = " + show(den) + " <= 0)");
    return (d.slope * (command - omega) - t0) / den;
  }

  /// The motor speed in Integrator::run_euler: a state, stepped by step(); the acceleration is the
  /// difference quotient by a division (drillpy loop's results move with its rounding).
  template <class D>
  struct Run {
    template <class S, class F>
    Run(const D& d, const Signal& command, double dt, const S& /*s0*/, F&& /*top_torque0*/)
        : d_(d), command_(command), dt_(dt) {}
    double speed(double /*t*/, double om_state) const { return om_state; }
    double next(double t, double om, double top_torque) { return step(d_, om, command_.at(t), top_torque, dt_); }
    double accel(double /*t*/, double om, double om_next) const { return (om_next - om) / dt_; }
    double torque() const { return NAN; }
    template <class S>
    void finish(S&) const {}

   private:
    const D& d_;
    const Signal& command_;
    double dt_;
  };
};

}  // namespace drill::drives
