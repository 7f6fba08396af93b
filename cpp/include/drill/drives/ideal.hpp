// The ideal top drive, the thesis's: the top node is clamped in a frame rotating at the prescribed
// speed Omega(t) (Eqs. 2.1-2.6), which it holds whatever the torque. It has no parameters and no
// inertia (the top speed is not a state of the simulation: Integrator::run_euler reads it from the
// command signal, and the batched integrator and the axial-torsional model run it only). A top
// drive of drives/registry.hpp.
#pragma once

#include <cmath>
#include <vector>

#include "drill/config_keys.hpp"
#include "drill/signal.hpp"

namespace drill::drives {

struct Ideal {
  struct Params {};

  static constexpr bool has_inertia = false;
  static constexpr bool has_controller = false;
  static constexpr bool accel_from_torque = false;

  template <class D>
  static std::vector<Key<D>> keys() {
    return {};
  }

  template <class D>
  static void validate(const D&) {}

  /// It turns at the command whatever the torque.
  template <class D>
  static double steady_speed(const D&, double command, double /*torque*/) {
    return command;
  }
  template <class D>
  static bool droops(const D&) {
    return false;
  }

  /// The top's speed in Integrator::run_euler: the command signal, its rate the acceleration.
  template <class D>
  struct Run {
    template <class S, class F>
    Run(const D&, const Signal& command, double dt, const S& /*s0*/, F&& /*top_torque0*/)
        : command_(command), dt_(dt) {}
    /// The top speed at step time t (om_state: the last step's next(), unused here).
    double speed(double t, double /*om_state*/) const { return command_.at(t); }
    /// The top speed at the next step from om at time t and the string's top torque of the step.
    double next(double t, double /*om*/, double /*top_torque*/) { return command_.at(t + dt_); }
    /// The top's acceleration over the step from om to om_next.
    double accel(double t, double /*om*/, double /*om_next*/) const { return command_.rate(t); }
    /// The drive's torque of the last step, reported (NaN: none computed).
    double torque() const { return NAN; }
    template <class S>
    void finish(S&) const {}

   private:
    const Signal& command_;
    double dt_;
  };
};

}  // namespace drill::drives
