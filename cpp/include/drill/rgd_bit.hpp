// The Richard-Germay-Detournay (RGD) bit-rock law of a drag bit: the weight and torque on bit as
// functions of the depth of cut, with cutting and frictional-contact components and their switches.
//
// Source: T. Richard, C. Germay, E. Detournay, "A simplified model to explore the root cause of
// stick-slip vibrations in drilling systems with drag bits", J. Sound Vib. 305 (2007) 432-456, the
// bit-rock interface laws of its section 2 (this session could not open the paper: the formulas below
// are the ones issue 34 quotes from it, and their equation numbers in the paper are not checked):
//
//   cutting           W_c = a zeta eps d,        T_c = a^2 eps d / 2
//   frictional        W_f = a l sigma,           T_f = gamma mu a W_f / 2
//   depth of cut      d(t) = N [U(t) - U(t - t_N)],   Phi(t) - Phi(t - t_N) = 2 pi / N
//
// a the bit radius [m], eps the intrinsic specific energy [Pa], zeta the ratio of the normal to the
// tangential cutting force [-], sigma the contact strength [Pa], l the total wear-flat length [m], mu the
// friction coefficient and gamma the bit's geometry factor [-], N the blades, d the depth of cut per
// revolution [m] (bit_profile.hpp computes it from the bit's history), U the bit's axial position
// (down, into the rock, positive) and Phi its angle.
//
// The switches (set-valued where the bit is at rest, as in the paper's account of the contact):
//  * cutting acts while the bit turns forward with its blades in the rock (d > 0); a bit at
//    torsional rest does not cut, its blades bearing on the rock with up to the cutting force;
//  * the wear flats carry W_f = a l sigma while the bit advances (V > 0), any force in [0, a l sigma]
//    while it does not move axially, and nothing while it moves up (V < 0);
//  * a bit above the rock surface (d <= 0: bit bounce, lift-off) carries nothing: W = T = 0.
// AxialTorsional (axial_torsional.hpp) solves these inclusions implicitly over each time step.
#pragma once

#include <cmath>
#include <string>

#include "drill/errors.hpp"

namespace drill {

struct RgdBit {
  double radius = 0.108;            ///< a [m]
  double specific_energy = 60e6;    ///< eps: intrinsic specific energy [Pa]
  double contact_strength = 60e6;   ///< sigma [Pa]
  double force_ratio = 0.6;         ///< zeta [-]
  double wear_flat = 0.011;         ///< l: total wear-flat length [m]
  double geometry = 1.0;            ///< gamma [-]
  double friction = 0.6;            ///< mu [-]
  int blades = 4;                   ///< N

  void validate(const std::string& where) const {
    require_positive(radius, where + ".radius_m");
    require_positive(specific_energy, where + ".specific_energy_pa");
    require_non_negative(contact_strength, where + ".contact_strength_pa");
    require_positive(force_ratio, where + ".zeta");
    require_non_negative(wear_flat, where + ".wear_flat_m");
    require_non_negative(geometry, where + ".gamma");
    require_non_negative(friction, where + ".mu");
    require(blades >= 1 && blades <= 64, where + ".blades", blades, "must be between 1 and 64");
  }

  /// The angle between two blades, 2 pi / N [rad].
  double sector() const { return 2.0 * M_PI / blades; }
  /// W_c / d = a zeta eps [N/m] and T_c / d = a^2 eps / 2 [N].
  double cutting_wob_per_depth() const { return radius * force_ratio * specific_energy; }
  double cutting_torque_per_depth() const { return 0.5 * radius * radius * specific_energy; }
  /// W_f = a l sigma [N]: the wear flats' full contact force.
  double contact_wob() const { return radius * wear_flat * contact_strength; }
  /// T_f / W_f = gamma mu a / 2 [m].
  double contact_torque_per_wob() const { return 0.5 * geometry * friction * radius; }

  /// Steady drilling: W = a zeta eps d + a l sigma and T = a^2 eps d / 2 + gamma mu a^2 l sigma / 2.
  double steady_wob(double d) const { return cutting_wob_per_depth() * d + contact_wob(); }
  double steady_torque(double d) const {
    return cutting_torque_per_depth() * d + contact_torque_per_wob() * contact_wob();
  }
  /// The depth of cut per revolution of steady drilling at a WOB [m] (0 below the contact force).
  double steady_depth(double wob) const { return std::max(0.0, (wob - contact_wob()) / cutting_wob_per_depth()); }
};

}  // namespace drill
