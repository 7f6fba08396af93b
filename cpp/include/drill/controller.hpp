// Speed controllers of a top drive with inertia (issue 15, item 1; docs/control.md).
//
// The top of the string is a free rotary inertia J [kg m^2] (the drive's rotor and gearing, referred to
// the main shaft) turned by the motor torque u [N m] that a controller computes, against the elastic
// torque T_top [N m] the string applies to it:
//
//   J Omega' = u - T_top,
//   u = sat_L( kp e + T_I ),   T_I' = ki e,   e = Omega_ref - Omega                                (PI)
//
// kp [N m s/rad] and ki [N m/rad] are the proportional and integral gains, T_I [N m] the integral
// torque (the PI's state, kept next to the motor speed), sat_L the motor's torque limit
// (`torque_limit_nm`, |u| <= L). Anti-windup by conditional integration (clamping): while u is
// saturated the integral is frozen whenever the error would drive it further into saturation, and
// |T_I| <= L always. Omega_ref [rad/s] is the commanded speed Omega_c (operation.top_speed_rad_s) for
// stiff, pi and soft_speed; z_torque corrects it by the measured top torque (below).
//
// Seen from the string, the drive (without saturation) is the mechanical impedance
//   Z_d(i w) = T_top / (-Omega) = kp + i (J w - ki / w)                          [N m s/rad]
// (the torque needed to move the top at a speed fluctuation Omega of frequency w). A rigid
// (ideal) drive is |Z_d| -> infinity: torsional waves are reflected from the top with coefficient
// -1; a drive whose impedance equals the drill pipe's characteristic impedance
//   Z = J_p sqrt(G rho)                                                          [N m s/rad]
// (J_p the polar moment of area [m^4], G the shear modulus [Pa], rho the density [kg/m^3] of the
// top section) absorbs the waves coming up the string (reflection coefficient (Z_d - Z) / (Z_d + Z) = 0).
//
// Controllers (their tuning, done by Controller::tune with the string's properties), one header
// each, listed in controllers/registry.hpp:
//  * stiff       high-gain PI with a double pole at -w_b, w_b = bandwidth_ratio x w_1 (w_1 the string's
//                first natural frequency, top clamped): the thesis's ideal drive as the ratio grows
//  * pi          the user's kp_nms_rad and ki_nm_rad
//  * soft_speed  SoftTorque / SoftSpeed (Kyllingstad and Nessjoen 2009): kp = Z, ki = J w_s^2
//  * z_torque    ZTorque (Dwars 2015): the set point corrected by the measured top torque,
//                Omega_ref = Omega_c - (T_top - T_mean) / Z, fed to a stiff PI loop
// Every gain can be overridden (kp_nms_rad, ki_nm_rad); Z by impedance_nms_rad.
//
// Sampling: with `sample_time_s` = T_s the motor torque is computed at the sample instants k T_s
// (at the first time step at or after each instant) from the speed (and torque) measured then, and
// held (zero-order hold) until the next sample; the integral advances by T_s ki e per sample.
// Without it the controller is continuous (integrated in the time step, implicitly in kp and ki:
// backward Euler on (Omega, T_I), stable for any gains).
//
// Discrete stability (validate_sampled): the sampled loop of the PI with the inertia J alone (the
// string's torque a disturbance), x_{k+1} = A x_k with a = kp T_s / J, b = ki T_s^2 / J, has the
// characteristic polynomial z^2 - (2 - a - b) z + (1 - a); by Jury's criterion its roots are inside the
// unit circle iff 0 < a < 2, b > 0 and 2 a + b < 4 (b = 0: a pure P loop, stable for 0 < a < 2). This
// is necessary for the drive's own loop; the string's load is treated by the simulation.
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "drill/controllers/registry.hpp"
#include "drill/errors.hpp"
#include "drill/names.hpp"

namespace drill {

/// A controller of a `controlled` top drive: the configuration (the fields of
/// top_drive.controller) and the gains it resolves to (tune()).
struct Controller {
#define DRILL_CONTROLLER_KIND(name, Ctl) name,
  enum class Kind { DRILL_CONTROLLERS(DRILL_CONTROLLER_KIND) };
#undef DRILL_CONTROLLER_KIND
  Kind kind = Kind::stiff;
  // configured (NaN: absent, tuned from the string)
  double kp_given = NAN;              ///< kp_nms_rad [N m s/rad]
  double ki_given = NAN;              ///< ki_nm_rad [N m/rad]
  double torque_limit = INFINITY;     ///< torque_limit_nm [N m]: |u| <= L
  double sample_time = 0.0;           ///< sample_time_s [s]; 0: continuous
  double bandwidth_ratio = 20.0;      ///< stiff, z_torque: w_b / w_1
  double impedance_given = NAN;       ///< impedance_nms_rad [N m s/rad] (soft_speed, z_torque)
  double stick_slip_frequency = NAN;  ///< stick_slip_frequency_rad_s [rad/s] (soft_speed)
  double torque_filter_given = NAN;   ///< torque_filter_s [s] (z_torque)
  // resolved by tune()
  double kp = NAN, ki = NAN;  ///< [N m s/rad], [N m/rad]
  double impedance = NAN;     ///< Z used by z_torque [N m s/rad]
  double torque_filter = NAN; ///< tau of z_torque [s]

  /// The controllers by name (top_drive.controller.type); their keys are the variants of the
  /// "top_drive.controller" table (config.hpp).
#define DRILL_CONTROLLER_NAME(name, Ctl) {Kind::name, #name},
  static constexpr Named<Kind> kinds[] = {DRILL_CONTROLLERS(DRILL_CONTROLLER_NAME)};
#undef DRILL_CONTROLLER_NAME
  static Kind parse_kind(const std::string& s) {
    return parse_name(kinds, s, "top_drive.controller.type", "controller");
  }
  static std::string kind_name(Kind k) { return name_of(kinds, k); }

  /// f(Ctl{}) for the struct Ctl of kind k (controllers/registry.hpp).
  template <class F>
  static decltype(auto) visit(Kind k, F&& f) {
    switch (k) {
#define DRILL_CONTROLLER_CASE(name, Ctl) \
  case Kind::name:                       \
    return f(controllers::Ctl{});
      DRILL_CONTROLLERS(DRILL_CONTROLLER_CASE)
#undef DRILL_CONTROLLER_CASE
    }
    throw std::logic_error("a controller kind outside controllers/registry.hpp");
  }

  bool sampled() const { return sample_time > 0.0; }
  bool tuned() const { return std::isfinite(kp) && std::isfinite(ki); }
  bool torque_feedback() const {
    return visit(kind, [](auto ctl) { return decltype(ctl)::torque_feedback; });
  }

  /// Resolve the gains from the drive's inertia J [kg m^2], the top section's characteristic
  /// impedance Z [N m s/rad] and the string's first natural frequency w1 [rad/s] (top clamped).
  void tune(double J, double Z, double w1) {
    double p = NAN, i = NAN;
    impedance = std::isfinite(impedance_given) ? impedance_given : Z;
    visit(kind, [&](auto ctl) { decltype(ctl)::gains(*this, J, w1, p, i); });
    kp = std::isfinite(kp_given) ? kp_given : p;
    ki = std::isfinite(ki_given) ? ki_given : i;
    torque_filter = std::isfinite(torque_filter_given) ? torque_filter_given : 5.0 / w1;
    visit(kind, [&](auto ctl) { decltype(ctl)::check_tuned(*this); });
  }

  /// The user's gains when both are given (pi, or overrides): checked before tuning.
  Controller with_given_gains() const {
    Controller c = *this;
    if (std::isfinite(kp_given) && std::isfinite(ki_given)) {
      c.kp = kp_given;
      c.ki = ki_given;
    }
    return c;
  }

  /// The configured fields (before tuning).
  void validate() const {
    const std::string w = "top_drive.controller.";
    visit(kind, [&](auto ctl) { decltype(ctl)::validate(*this); });
    if (!std::isnan(kp_given)) require_positive(kp_given, w + "kp_nms_rad");
    if (!std::isnan(ki_given)) require_non_negative(ki_given, w + "ki_nm_rad");
    require(!std::isnan(torque_limit) && torque_limit > 0.0, w + "torque_limit_nm", torque_limit, "must be positive");
    require(std::isfinite(sample_time) && sample_time >= 0.0, w + "sample_time_s", sample_time,
            "must be positive (omit it for a continuous controller)");
    require(std::isfinite(bandwidth_ratio) && bandwidth_ratio > 0.0, w + "bandwidth_ratio", bandwidth_ratio,
            "must be positive");
    if (!std::isnan(impedance_given)) require_positive(impedance_given, w + "impedance_nms_rad");
    if (!std::isnan(stick_slip_frequency)) require_positive(stick_slip_frequency, w + "stick_slip_frequency_rad_s");
    if (!std::isnan(torque_filter_given)) require_positive(torque_filter_given, w + "torque_filter_s");
  }

  /// The resolved gains, and the sampled loop's stability for the inertia J (Jury, header comment).
  void validate_tuned(double J) const {
    const std::string w = "top_drive.controller.";
    const std::string src = std::isfinite(kp_given) ? "" : " (tuned for " + kind_name(kind) + ")";
    require(std::isfinite(kp) && kp > 0.0, w + "kp_nms_rad", kp, "must be positive" + src);
    require(std::isfinite(ki) && ki >= 0.0, w + "ki_nm_rad", ki, "must not be negative" + src);
    if (!sampled()) return;
    const double a = kp * sample_time / J, b = ki * sample_time * sample_time / J;
    const std::string why = " with sample_time_s = " + show(sample_time) + " s and inertia_kg_m2 = " + show(J) +
                            ": the sampled loop is unstable (Jury: needs a = kp T_s / J < 2 and 2 a + ki T_s^2 / J < 4; a = " +
                            show(a) + ", b = " + show(b) + ")";
    require(a < 2.0, w + "kp_nms_rad", kp, "is too large" + src + why);
    require(2.0 * a + b < 4.0, w + "ki_nm_rad", ki, "is too large" + src + why);
  }
};

/// The characteristic torsional impedance of a uniform shaft, Z = J_p sqrt(G rho) [N m s/rad]:
/// polar moment J_p [m^4], shear modulus G [Pa], density rho [kg/m^3].
inline double characteristic_impedance(double polar_moment, double shear_modulus, double density) {
  return polar_moment * std::sqrt(shear_modulus * density);
}

/// The running state of a controlled drive in the time integration (integrator.hpp), with time steps dt.
/// What does not change during a run is computed once, when the loop is made (the same expressions
/// as in the step, so the same numbers): the torque filter's factor 1 - exp(-dt / tau) (z_torque;
/// 1 - exp(-T_s / tau) sampled), h = dt / J, dt ki, and the reciprocals of Z and of the
/// backward-Euler denominator 1 + h kp + h dt ki (multiplying by them rounds differently from
/// dividing, by an ulp). The step then costs no exponential and no division: it lies on the chain
/// of dependent operations from the string's top torque to the bit's Newton solve, and evaluating
/// these every step was a quarter of z_torque's extra cost, the divisions another tenth
/// (benchmarks/bench_controller.py).
struct ControlLoop {
  double integral;      ///< T_I [N m]
  double mean;          ///< T_mean of z_torque [N m]
  double hold = 0.0;    ///< motor torque held between samples [N m]
  double torque = 0.0;  ///< motor torque of the last step [N m]
  long next_sample = 0;

  /// A loop of controller c (tuned) on the inertia J [kg m^2], with time step dt [s], starting
  /// from the integral and filtered torques [N m].
  ControlLoop(const Controller& c, double J, double dt, double integral0, double mean0)
      : integral(integral0),
        mean(mean0),
        kp_(c.kp),
        ki_(c.ki),
        L_(c.torque_limit),
        inv_Z_(1.0 / c.impedance),
        Ts_(c.sample_time),
        dt_(dt),
        h_(dt / J),
        dt_ki_(dt * c.ki),
        ki_Ts_(c.ki * c.sample_time),
        inv_den_(1.0 / (1.0 + h_ * c.kp + h_ * dt * c.ki)),
        sampled_(c.sampled()),
        feedback_(c.torque_feedback()) {
    if (feedback_) filter_ = 1.0 - std::exp(-(sampled_ ? Ts_ : dt) / c.torque_filter);
  }

  /// The motor speed at the next step from `om`, the command and the string's top torque of the
  /// step at time t.
  double step(double t, double om, double command, double top_torque) {
    const double L = L_;
    if (sampled_) {
      // a sample at the first step at or after each instant k T_s
      if (t + 1e-9 * dt_ >= next_sample * Ts_) {
        while (next_sample * Ts_ <= t + 1e-9 * dt_) ++next_sample;
        double ref = command;
        if (feedback_) {
          mean += filter_ * (top_torque - mean);
          ref -= (top_torque - mean) * inv_Z_;
        }
        const double e = ref - om;
        const double I1 = ki_Ts_ * e + integral;
        double u = kp_ * e + I1;
        if (std::fabs(u) > L) {
          u = std::copysign(L, u);
          if (e * u <= 0.0) integral = I1;  // integrate only out of saturation
        } else {
          integral = I1;
        }
        integral = std::min(std::max(integral, -L), L);
        hold = u;
      }
      torque = hold;
      return om + h_ * (hold - top_torque);
    }
    double ref = command;
    if (feedback_) {
      mean += filter_ * (top_torque - mean);
      ref -= (top_torque - mean) * inv_Z_;
    }
    // backward Euler on J Omega' = kp (ref - Omega) + T_I - T_top, T_I' = ki (ref - Omega)
    double om1 = (om + h_ * (kp_ * ref + integral + dt_ki_ * ref - top_torque)) * inv_den_;
    double I1 = integral + dt_ki_ * (ref - om1);
    double u = kp_ * (ref - om1) + I1;
    if (std::fabs(u) > L) {
      u = std::copysign(L, u);
      om1 = om + h_ * (u - top_torque);
      const double e = ref - om1;
      I1 = e * u <= 0.0 ? integral + dt_ki_ * e : integral;
    }
    integral = std::min(std::max(I1, -L), L);
    torque = u;
    return om1;
  }

 private:
  double kp_, ki_, L_, inv_Z_, Ts_, dt_, h_, dt_ki_, ki_Ts_, inv_den_;
  double filter_ = 0.0;
  bool sampled_, feedback_;
};

}  // namespace drill
