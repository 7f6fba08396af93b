// Top-drive models: how the top of the string is turned.
//
// The thesis clamps the top node in a frame rotating at a prescribed speed Omega(t) (Eqs. 2.1-2.6):
// an ideal drive that holds its speed whatever the torque. The test rig's drive is an open-loop DC
// motor with a torque-speed characteristic, a torque limit and an inertia (thesis sections 5.3.2,
// 5.1), and a `controlled` drive (issue 15) is the same free top inertia driven by a speed
// controller (controller.hpp). The drives, one header each, are listed in drives/registry.hpp:
//
//   ideal       drives/ideal.hpp       Omega = Omega_c(t)
//   motor       drives/motor.hpp       J_m Omega' = min(c_m (Omega_c - Omega), T_max) - T_top
//   controlled  drives/controlled.hpp  J Omega' = u - T_top, u = sat_L(kp (Omega_ref - Omega) + T_I)
//
// TopDrive is the configured drive (the "top_drive" block): its kind, the parameters of every drive
// (each drive's Params, and the top's inertia J that the drives with inertia share) and the hooks
// that dispatch to the drive of its kind. Integrator::run_euler is instantiated once per drive
// (TopDrive::visit), with the drive's per-step update of the top speed inlined.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "drill/controller.hpp"
#include "drill/drives/registry.hpp"
#include "drill/errors.hpp"
#include "drill/names.hpp"
#include "drill/parameter_set.hpp"

namespace drill {

namespace drives {

/// The parameters of the drives, each struct once (parameter_set.hpp).
#define DRILL_DRIVE_PARAMS(name, Drive) , Drive::Params
using AllParameters = UniqueParameters<Parameters<> DRILL_TOP_DRIVES(DRILL_DRIVE_PARAMS)>::type;
#undef DRILL_DRIVE_PARAMS

}  // namespace drives

struct TopDrive : drives::AllParameters {
#define DRILL_DRIVE_KIND(name, Drive) name,
  enum class Kind { DRILL_TOP_DRIVES(DRILL_DRIVE_KIND) };
#undef DRILL_DRIVE_KIND
  Kind kind = Kind{};    ///< the first of the list (ideal)
  double inertia = 0.0;  ///< J_m, J: rotor and drive train inertia [kg m^2] (the drives with inertia)

  /// The top drives by name (top_drive.type); their keys are the variants of the "top_drive" table (config.hpp).
#define DRILL_DRIVE_NAME(name, Drive) {Kind::name, #name},
  static constexpr Named<Kind> kinds[] = {DRILL_TOP_DRIVES(DRILL_DRIVE_NAME)};
#undef DRILL_DRIVE_NAME
  static Kind parse_kind(const std::string& s) { return parse_name(kinds, s, "top_drive.type", "top drive"); }
  static std::string kind_name(Kind k) { return name_of(kinds, k); }

  /// f(Drive{}) for the struct Drive of kind k (drives/registry.hpp).
  template <class F>
  static decltype(auto) visit(Kind k, F&& f) {
    switch (k) {
#define DRILL_DRIVE_CASE(name, Drive) \
  case Kind::name:                    \
    return f(drives::Drive{});
      DRILL_TOP_DRIVES(DRILL_DRIVE_CASE)
#undef DRILL_DRIVE_CASE
    }
    throw std::logic_error("a top drive kind outside drives/registry.hpp");
  }

  /// The top is a free inertia (motor, controlled): its speed is a state of the simulation.
  bool has_inertia() const {
    return visit(kind, [](auto d) { return decltype(d)::has_inertia; });
  }
  /// The drive is run by a speed controller (top_drive.controller, tuned from the string).
  bool has_controller() const {
    return visit(kind, [](auto d) { return decltype(d)::has_controller; });
  }
  /// The drive's equation gives the top's acceleration from the string's top torque (top_accel).
  bool accel_from_torque() const {
    return visit(kind, [](auto d) { return decltype(d)::accel_from_torque; });
  }

  void validate() const {
    visit(kind, [&](auto d) { decltype(d)::validate(*this); });
  }

  /// Tune a controlled drive's gains from the top section's characteristic impedance Z [N m s/rad]
  /// and the string's first natural frequency w1 [rad/s] (Controller::tune), and check them.
  void tune_controller(double Z, double w1) {
    if (!has_controller()) return;
    controller.tune(inertia, Z, w1);
    controller.validate_tuned(inertia);
  }

  /// Steady speed under a torque T [N m] at command Omega_c [rad/s]: Omega_c - T / c_m for the motor;
  /// the command for the ideal drive and a controller (the integral carries the torque; ki > 0).
  double steady_speed(double command, double torque) const {
    return visit(kind, [&](auto d) { return decltype(d)::steady_speed(*this, command, torque); });
  }
  /// Whether the steady speed depends on the torque (motor, P-only controller): Simulation::steady_speed.
  bool droops() const {
    return visit(kind, [&](auto d) { return decltype(d)::droops(*this); });
  }

  /// The top's acceleration at speed omega and the command, from the drive's equation with the
  /// string's top torque t0 + dT domega, time step dt (the motor: drives/motor.hpp); refused for a
  /// drive without such an equation (accel_from_torque).
  double top_accel(double command, double omega, double dt, double t0, double dT) const {
    return visit(kind, [&](auto d) -> double {
      using Drive = decltype(d);
      if constexpr (Drive::accel_from_torque) {
        return Drive::top_accel(*this, command, omega, dt, t0, dT);
      } else {
        require(false, "top_drive.type", kind_name(kind), "has no equation for the top's acceleration here");
        return NAN;
      }
    });
  }
};

}  // namespace drill
