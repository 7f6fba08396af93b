// Bit-rock interaction laws: torque on bit as a function of bit speed, bit acceleration and WOB.
// The laws are listed in laws/registry.hpp, one header each (laws/*.hpp: parameters, config keys,
// validation and formula); BitRockLaw holds the parameters of all of them and evaluates the one of
// its `kind`:
//
//  * tucker_wang            Eq. (3.1)       laws/tucker_wang.hpp
//  * hysteretic             Eqs. (3.2-3.3)  laws/hysteretic.hpp
//  * polynomial             Eq. (5.1)       laws/polynomial.hpp (set-valued at rest: static_torque())
//  * polynomial_hysteretic  Eq. (5.3)       laws/polynomial.hpp
//
// All laws scale linearly with the weight on bit: T(W) = T (W / W_ref) (section 3.3, b0 x WOB / 245 kN).
// Every parameter set carries the speed unit it was fitted in (`speed_unit`): the bit speed v and
// the bit acceleration a enter the formulas in that unit (rad/s and rad/s^2, or RPM and RPM/s);
// the engine's own state is always SI. See docs/units.md for which unit the thesis's sets use.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "drill/errors.hpp"
#include "drill/laws/at_speed.hpp"
#include "drill/laws/hysteresis.hpp"
#include "drill/laws/registry.hpp"
#include "drill/names.hpp"
#include "drill/parameter_set.hpp"

namespace drill {

enum class SpeedUnit { rad_s, rpm };

inline SpeedUnit parse_speed_unit(const std::string& s, const std::string& field) {
  if (s == "rad_s" || s == "rad/s") return SpeedUnit::rad_s;
  if (s == "rpm" || s == "RPM") return SpeedUnit::rpm;
  throw std::invalid_argument(field + " = \"" + s + "\": unknown speed unit (use \"rad_s\" or \"rpm\")");
}
inline std::string to_string(SpeedUnit u) { return u == SpeedUnit::rpm ? "rpm" : "rad_s"; }
/// Factor converting rad/s to the unit: v_unit = v_si * speed_factor(unit).
inline double speed_factor(SpeedUnit u) { return u == SpeedUnit::rpm ? 30.0 / M_PI : 1.0; }

namespace laws {

/// The parameters of every law of laws/registry.hpp.
#define DRILL_LAW_PARAMS(name, Law) , Law::Params
using AllParameters = UniqueParameters<Parameters<> DRILL_BIT_ROCK_LAWS(DRILL_LAW_PARAMS)>::type;
#undef DRILL_LAW_PARAMS

}  // namespace laws

/// The law of `kind` with the parameters of every law (laws/*.hpp) and those they share: the
/// hysteresis of Eq. (3.3) (laws/hysteresis.hpp), the speed unit and the reference WOB.
struct BitRockLaw : laws::Hysteresis, laws::AllParameters {
#define DRILL_LAW_KIND(name, Law) name,
  enum class Kind { DRILL_BIT_ROCK_LAWS(DRILL_LAW_KIND) };
#undef DRILL_LAW_KIND
  Kind kind = Kind::hysteretic;
  SpeedUnit speed_unit = SpeedUnit::rad_s;
  double wob_ref = 245e3;  ///< [N] weight on bit at which the parameters hold
  /// Ageing of the static torque (not in the thesis; the rig's stall, docs/records.md section 4):
  /// after tau [s] stuck the static torque is static_torque(W) (1 + A tau / (tau + tau_a)), A =
  /// static_ageing (absent: none), tau_a = static_ageing_s. A bit that sticks for a cycle's short stick
  /// phase breaks away near the law's static torque; one held longer (a stall) holds more.
  double static_ageing = NAN;
  double static_ageing_s = NAN;  ///< tau_a [s]: the time stuck at which the static torque has grown by A / 2

  /// The laws by name (law.type); their keys are the variants of the "law" table (config.hpp).
#define DRILL_LAW_NAME(name, Law) {Kind::name, #name},
  static constexpr Named<Kind> kinds[] = {DRILL_BIT_ROCK_LAWS(DRILL_LAW_NAME)};
#undef DRILL_LAW_NAME
  static Kind parse_kind(const std::string& s) { return parse_name(kinds, s, "law.type", "law"); }
  static std::string kind_name(Kind k) { return name_of(kinds, k); }

  /// f(Law{}) for the struct Law of kind k (laws/registry.hpp).
  template <class F>
  static decltype(auto) visit(Kind k, F&& f) {
    switch (k) {
#define DRILL_LAW_CASE(name, Law) \
  case Kind::name:                \
    return f(laws::Law{});
      DRILL_BIT_ROCK_LAWS(DRILL_LAW_CASE)
#undef DRILL_LAW_CASE
    }
    throw std::logic_error("a law kind outside laws/registry.hpp");
  }

  void validate() const {
    require_positive(wob_ref, "law.wob_ref_n");
    visit(kind, [&](auto law) { decltype(law)::validate(*this); });
    Hysteresis::validate();
    require(std::isnan(static_ageing_s) || (std::isfinite(static_ageing_s) && static_ageing_s > 0.0),
            "law.static_ageing_s", static_ageing_s, "must be a positive time");
    if (std::isnan(static_ageing)) return;
    require_non_negative(static_ageing, "law.static_ageing");
    require(std::isfinite(static_ageing_s), "law.static_ageing_s", static_ageing_s,
            "must be a positive time with law.static_ageing");
    require(static_ageing == 0.0 || static_torque(wob_ref) > 0.0, "law.static_ageing", static_ageing,
            "needs a static torque to age: Eq. (5.1) or (5.3) with a0 > 0");
  }

  /// Whether the static torque ages (static_ageing present and positive).
  bool ages() const { return std::isfinite(static_ageing) && static_ageing > 0.0; }
  /// The static torque's factor after `stuck_s` [s] at rest: 1 + A tau / (tau + tau_a) (1 without ageing).
  double ageing_factor(double stuck_s) const {
    return ages() ? 1.0 + static_ageing * (stuck_s / (stuck_s + static_ageing_s)) : 1.0;
  }

  bool operator==(const BitRockLaw& o) const {
    const auto same = [](double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); };
    return kind == o.kind && speed_unit == o.speed_unit && wob_ref == o.wob_ref &&
           same(static_ageing, o.static_ageing) && same(static_ageing_s, o.static_ageing_s) &&
           Hysteresis::operator==(o) && laws::AllParameters::operator==(o);
  }

  /// The law at a fixed bit speed as a function of the bit acceleration (all SI, WOB applied):
  ///   T(a) = base + frac (1 + c tanh(k a)),  c = beta1 sign(v), k = beta2 s    (Eqs. 3.2-3.3, 5.3)
  /// with base/frac and their speed derivatives (laws/at_speed.hpp). Every law has this form
  /// (frac = 0 without hysteresis); the integrators use it to solve for the acceleration cheaply.
  using AtSpeed = laws::AtSpeed;

  AtSpeed at_speed(double v_si, double wob) const {
    const double s = speed_factor(speed_unit);
    const double v = v_si * s, w = wob / wob_ref;
    const double sg = (v > 0.0) - (v < 0.0);
    AtSpeed r;
    visit(kind, [&](auto law) { decltype(law)::at_speed(*this, v, sg, r); });
    r.k = beta2 * s;  // tanh(beta2 a_unit) = tanh(beta2 s a_si)
    r.base *= w;
    r.frac *= w;
    r.dbase_dv *= w * s;
    r.dfrac_dv *= w * s;
    return r;
  }

  /// Static (break-away) torque at rest [N m] at WOB `wob`: gain a0 W / W_ref for the
  /// non-regularized laws of Eqs. (5.1) and (5.3), 0 for the regularized laws (3.1)-(3.2), which
  /// vanish at rest and need no stick condition. While the bit is at rest it stays stuck as long as
  /// the torque the string applies to it is within [-static_torque, static_torque] (the set-valued
  /// law at v = 0).
  double static_torque(double wob) const {
    return visit(kind, [&](auto law) { return decltype(law)::static_torque(*this, wob); });
  }
  /// Torque on bit [N.m] at SI bit speed v [rad/s], acceleration acc [rad/s^2] and WOB [N].
  double torque(double v, double acc, double wob) const { return at_speed(v, wob).torque(acc); }

  /// Torque with partial derivatives (used by the implicit integrator and the identification).
  TorqueEval eval(double v_si, double a_si, double wob) const { return at_speed(v_si, wob).eval(a_si); }
};

/// The thesis's Tucker-Wang fit of section 3.1: mu W r = 4700, alpha0 = 1.67e4, alpha1 = 5.30,
/// alpha2 = 3.45 (bit speed in rad/s: see docs/units.md).
inline BitRockLaw thesis_tucker_wang() {
  BitRockLaw l;
  l.kind = BitRockLaw::Kind::tucker_wang;
  l.speed_unit = SpeedUnit::rad_s;
  l.c0 = 4700.0;
  l.alpha0 = 1.67e4;
  l.alpha1 = 5.30;
  l.alpha2 = 3.45;
  return l;
}

/// The thesis's hysteretic fit of section 3.2: b0 = 3478, b1 = 938, b2 = 2.56, b3 = 0.38,
/// b4 = 0.78, b5 = 1.1, beta2 = 10.6; beta1 = 0 (model 1), 0.14 (model 2) or 0.56 (model 3).
inline BitRockLaw thesis_hysteretic(double beta1, SpeedUnit unit) {
  BitRockLaw l;
  l.kind = BitRockLaw::Kind::hysteretic;
  l.speed_unit = unit;
  l.b = {3478.0, 938.0, 2.56, 0.38, 0.78, 1.1};
  l.beta1 = beta1;
  l.beta2 = 10.6;
  return l;
}

}  // namespace drill
