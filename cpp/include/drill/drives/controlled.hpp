// The controlled top drive (issue 15): the same free top inertia J as the motor's, driven by the
// torque of a speed controller instead of the motor's characteristic (controller.hpp: stiff, pi,
// soft_speed, z_torque, listed in controllers/registry.hpp, with a torque limit and a sample time):
//
//   J Omega' = u - T_top,   u = sat_L(kp (Omega_ref - Omega) + T_I),   T_I' = ki (Omega_ref - Omega)
//
// Its gains are tuned from the string (Simulation's constructor calls TopDrive::tune_controller with
// the top section's characteristic impedance and the first natural frequency of the reduced model).
// With integral action the drive turns at the command in steady drilling (steady_speed). A top drive
// of drives/registry.hpp.
#pragma once

#include <cmath>
#include <vector>

#include "drill/config_keys.hpp"
#include "drill/controller.hpp"
#include "drill/errors.hpp"
#include "drill/signal.hpp"

namespace drill::drives {

struct Controlled {
  struct Params {
    Controller controller;  ///< top_drive.controller (the gains resolved by TopDrive::tune_controller)
  };

  static constexpr bool has_inertia = true;  // J: TopDrive::inertia
  static constexpr bool has_controller = true;
  static constexpr bool accel_from_torque = false;

  template <class D>
  static std::vector<Key<D>> keys() {
    using schema::number;
    return {{number("inertia_kg_m2", "J: rotor and drive-train inertia [kg m^2]").positive().req(), &D::inertia},
            schema::object("controller", "top_drive.controller", "the speed controller driving the inertia").req()};
  }

  template <class D>
  static void validate(const D& d) {
    require_positive(d.inertia, "top_drive.inertia_kg_m2");
    d.controller.validate();
    const Controller c = d.controller.tuned() ? d.controller : d.controller.with_given_gains();
    if (c.tuned()) c.validate_tuned(d.inertia);
  }

  /// Steady speed under a torque T [N m] at command Omega_c [rad/s]: the command (the integral
  /// carries the torque; ki > 0); a P-only controller droops by T / kp.
  template <class D>
  static double steady_speed(const D& d, double command, double torque) {
    if (!(d.controller.ki > 0.0)) return command - torque / d.controller.kp;  // P only: droop
    return command;
  }
  template <class D>
  static bool droops(const D& d) {
    return !(d.controller.ki > 0.0);
  }

  /// The drive in Integrator::run_euler: its controller's ControlLoop (controller.hpp), starting
  /// from the state's integral and filtered torques, or in equilibrium with the string's top torque
  /// top_torque0() when the state has none. The acceleration is the difference quotient by a product
  /// (off a division's latency).
  template <class D>
  struct Run {
    template <class S, class F>
    Run(const D& d, const Signal& command, double dt, const S& s0, F&& top_torque0)
        : command_(command), inv_dt_(1.0 / dt), loop_(start(d, dt, s0, top_torque0())) {}
    double speed(double /*t*/, double om_state) const { return om_state; }
    double next(double t, double om, double top_torque) { return loop_.step(t, om, command_.at(t), top_torque); }
    double accel(double /*t*/, double om, double om_next) const { return (om_next - om) * inv_dt_; }
    double torque() const { return loop_.torque; }
    template <class S>
    void finish(S& out) const {
      out.drive_integral = loop_.integral;
      out.drive_mean = loop_.mean;
    }

   private:
    template <class S>
    static ControlLoop start(const D& d, double dt, const S& s0, double T0) {
      return ControlLoop(d.controller, d.inertia, dt, std::isfinite(s0.drive_integral) ? s0.drive_integral : T0,
                         std::isfinite(s0.drive_mean) ? s0.drive_mean : T0);
    }
    const Signal& command_;
    double inv_dt_;
    ControlLoop loop_;
  };
};

}  // namespace drill::drives
