// The axial side of the test rig: the weight on bit as a state of the model, not an input.
//
// The rig's electrical jack lifts the rock holder's platform at a constant input voltage (thesis
// section 5.1); the WOB is read by three load cells under the platform and oscillates with the
// stick-slip cycle, rising while the bit is stuck and falling while it slips (section 5.3.2, Figs.
// 5.6-5.7). The mechanism: the jack feeds the platform at a steady rate while the bit removes rock
// in proportion to its rotation (a depth of cut per revolution, as in the Richard-Germay-Detournay
// account of axial-torsional coupling), so the axial compliance between them is compressed while the
// bit lags its steady rotation and relieved while it runs ahead. The jack's own regulation (constant
// voltage) pulls the force back to its set value on a time scale tau:
//
//   W' = g (Omega_f - v) - (W - W_s(t)) / tau,      W >= 0 (the bit lifts off the rock at W = 0)
//
// g = k_ax d / (2 pi) [N/rad] (axial stiffness k_ax [N/m] times the depth of cut per revolution d
// [m]), Omega_f [rad/s] the bit speed whose cut matches the jack's feed (the drive's steady drilling
// speed at the operating point: Simulation sets it), W_s(t) the jack's set force (operation.wob_n,
// or a slow series: the jack's trend), v the bit speed. In steady drilling (v = Omega_f) W = W_s.
// The bit-rock law then takes this W (every law scales with W / W_ref), so a long stick raises the
// static torque, which is how a stall develops.
//
// The relaxation is integrated exactly over a step (the exponential of -dt / tau) with the rest of
// the right-hand side held at the step's start (first order, like the scheme's explicit parts).
#pragma once

#include <cmath>
#include <string>

#include "drill/axial_string.hpp"
#include "drill/errors.hpp"
#include "drill/names.hpp"
#include "drill/rgd_bit.hpp"

namespace drill {

/// The torque on the bit of the coupled string (axial.torque):
///  * rgd  RGD's own torque law, T_c + T_f (rgd_bit.hpp);
///  * law  the configuration's thesis law (the "law" block: Eqs. 3.1, 3.2-3.3, 5.1, 5.3) at the bit's
///         speed and acceleration with the WOB the model's axial state W (RGD's axial law kept):
///         T = T_law(v, a) W / W_ref (axial_torsional.hpp).
enum class AxialTorque { rgd, law };
inline constexpr Named<AxialTorque> axial_torque_names[] = {{AxialTorque::rgd, "rgd"}, {AxialTorque::law, "law"}};
inline AxialTorque parse_axial_torque(const std::string& s, const std::string& field = "axial.torque") {
  return parse_name(axial_torque_names, s, field, "torque on bit");
}
inline std::string to_string(AxialTorque t) { return name_of(axial_torque_names, t); }

/// The axial model of the coupled string: RGD bit, axial modes, top boundary and its load.
struct AxialTorsionalSpec {
  RgdBit bit;
  AxialTorque torque = AxialTorque::rgd;  ///< the torque on the bit: RGD's or the thesis law's on the axial W
  AxialTop top = AxialTop::hook_load;
  int modes = 10;             ///< retained axial modes
  AxialDamping damping = AxialDamping::modal;  ///< modal: damping_ratio on every mode; distributed: D = 2 k M
  double damping_ratio = 0.05;  ///< modal damping ratio of the axial modes (damping = modal)
  double damping_rate = NAN;    ///< k [1/s] of damping = distributed: ratio k / omega_j on mode j
  double bit_mass = 0.0;      ///< lumped axial mass at the bit [kg]
  double feed_rate = NAN;     ///< V0 with top = feed, the jack's free feed with top = jack [m/s]
  double top_force = NAN;     ///< net force down at the top with top = hook_load (the steady WOB), the jack's set force W_s [N]
  double jack_admittance = NAN;  ///< kappa [m/s per N] with top = jack: X' = V0 + kappa (W_s - F_top)
  double disturbance = 0.01;  ///< start: the bit's axial speed is (1 - disturbance) V0 (0: steady; > 1: upwards)

  /// The depth of cut per revolution of steady drilling at bit speed omega [rad/s]: 2 pi V0 / omega with
  /// top = feed, RGD's balance W0 = a zeta eps d0 + a l sigma with the hook load's W0 (rgd_bit.hpp).
  /// With top = jack the jack's feed carries the WOB of the cut: omega d0 / (2 pi) = V0 + kappa (W_s - W0(d0)),
  /// W0(d) = a zeta eps d + a l sigma, so d0 = (V0 + kappa (W_s - a l sigma)) / (omega / (2 pi) + kappa a zeta eps)
  /// (0 if the jack cannot feed: the bit then rests on the rock).
  double steady_depth(double omega) const {
    if (top == AxialTop::feed) return 2.0 * M_PI * feed_rate / omega;
    if (top == AxialTop::jack)
      return std::max(0.0, (feed_rate + jack_admittance * (top_force - bit.contact_wob())) /
                               (omega / (2.0 * M_PI) + jack_admittance * bit.cutting_wob_per_depth()));
    return bit.steady_depth(top_force);
  }

  /// The axial modes' damping (axial_string.hpp).
  AxialModalDamping modal_damping() const { return {damping, damping_ratio, damping_rate}; }

  void validate(const std::string& where = "axial") const {
    bit.validate(where + ".bit");
    require(modes >= 1, where + ".modes", modes, "must be at least 1");
    if (damping == AxialDamping::modal) {
      require(damping_ratio >= 0.0 && damping_ratio <= 1.0, where + ".damping_ratio", damping_ratio,
              "must be in [0, 1]");
      require(std::isnan(damping_rate), where + ".damping_rate_per_s", damping_rate,
              "is used with " + where + ".damping = distributed only (modal takes " + where + ".damping_ratio)");
    } else {
      require(std::isfinite(damping_rate) && damping_rate >= 0.0, where + ".damping_rate_per_s", damping_rate,
              "must be a finite number >= 0 (required with " + where + ".damping = distributed: D = 2 k M)");
    }
    require_non_negative(bit_mass, where + ".bit_mass_kg");
    require(std::isfinite(disturbance) && std::fabs(disturbance) <= 1000.0, where + ".disturbance", disturbance,
            "must be in [-1000, 1000]");
    require(top == AxialTop::jack || std::isnan(jack_admittance), where + ".jack_admittance_m_s_n", jack_admittance,
            "is used with " + where + ".top = jack only");
    if (top == AxialTop::feed) {
      require_positive(feed_rate, where + ".rop_m_s");
    } else if (top == AxialTop::jack) {
      require_positive(feed_rate, where + ".rop_m_s");
      require_positive(top_force, "operation.wob_n");
      require(std::isfinite(jack_admittance) && jack_admittance > 0.0, where + ".jack_admittance_m_s_n",
              jack_admittance, "must be a positive number with " + where + ".top = jack (the jack's speed lost per N "
              "of force above operation.wob_n)");
      require(feed_rate + jack_admittance * (top_force - bit.contact_wob()) > 0.0, "operation.wob_n", top_force,
              "is too low for the jack to advance the bit: rop_m_s + kappa (wob_n - a l sigma) <= 0 with a l sigma = " +
                  show(bit.contact_wob()) + " N (the wear flats' contact force): the bit would not cut");
    } else {
      require_positive(top_force, "operation.wob_n");
      require(top_force > bit.contact_wob(), "operation.wob_n", top_force,
              "is not above the wear flats' contact force a l sigma = " + show(bit.contact_wob()) +
                  " N of axial.bit: the bit would not cut (RGD's steady drilling needs W > a l sigma)");
    }
  }
};

struct Axial {
  enum class Kind { none, jack, rgd };
  Kind kind = Kind::none;
  double gain = 0.0;          ///< g = k_ax d / (2 pi): WOB per radian of lag of the bit [N/rad]
  double relaxation = 1.0;    ///< tau: the jack's time constant [s]
  double feed_speed = NAN;    ///< Omega_f [rad/s]: set per run (Simulation::inputs); NaN: not set
  AxialTorsionalSpec rgd;     ///< Kind::rgd: the axial string and the RGD bit (axial_torsional.hpp)

  /// The axial models by name (axial.type); their keys are the variants of the "axial" table (config.hpp).
  static constexpr Named<Kind> kinds[] = {{Kind::none, "none"}, {Kind::jack, "jack"}, {Kind::rgd, "rgd"}};
  static Kind parse_kind(const std::string& s) { return parse_name(kinds, s, "axial.type", "axial model"); }
  static std::string kind_name(Kind k) { return name_of(kinds, k); }
  /// The jack is active: the WOB a single state driven by the bit speed (the integrators' path).
  bool active() const { return kind == Kind::jack; }
  /// The axial-torsional model (axial_torsional.hpp): Simulation::run's coupled path.
  bool coupled() const { return kind == Kind::rgd; }

  void validate() const {
    if (coupled()) rgd.validate();
    if (!active()) return;
    require_non_negative(gain, "axial.gain_n_rad");
    require_positive(relaxation, "axial.relaxation_s");
  }

  /// The WOB after one step dt from W at bit speed v and set force W_s [N].
  double step(double W, double v, double set_force, double dt) const {
    const double e = std::exp(-dt / relaxation);
    const double next = set_force + (W - set_force) * e + gain * (feed_speed - v) * relaxation * (1.0 - e);
    return next > 0.0 ? next : 0.0;
  }
};

}  // namespace drill
