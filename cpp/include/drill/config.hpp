// The JSON configuration shared by `drillsim` and `drillpy` (one schema, parsed only here).
//
// {
//   "name": "...",
//   "string": {"sections": [{"name", "length_m", "outer_radius_m", "inner_radius_m",
//                            "youngs_modulus_pa", "poisson_ratio", "density_kg_m3", "elements"}],
//              "lumped_inertias": [{"node": -1, "inertia_kg_m2": ...}]},
//   "rom": {"modes": 20},
//   "damping": {"type": "modal", "ratios": [0.095, 0.02]}
//            | {"type": "rayleigh", "pairs": [[f1_hz, zeta1], [f2_hz, zeta2]]},
//   "law": {"type": "hysteretic", "speed_unit": "rpm", "wob_ref_n": 245000,
//           "b0".."b5", "beta1", "beta2"}          (tucker_wang: "c0", "alpha0".."alpha2";
//           polynomial[_hysteretic]: "a0".."a7", "ref_speed", "gain", "beta1", "beta2"),
//   "operation": {"top_speed_rad_s": 16, "wob_n": 245000, "bit_viscous_nms": 0, "string_friction_nm": 0},
//                                                  (bit_viscous_nms: extra viscous torque c_v v on the bit;
//                                                   string_friction_nm: Coulomb torque T_sf sign(v) of the
//                                                   string on its guides, lumped at the bit, set-valued at
//                                                   rest (adds to the stick capacity); both act outside the
//                                                   bit's torque sensor and are not in the thesis),
//   "top_drive": {"type": "ideal"}                 (the thesis: the top turns at top_speed_rad_s)
//              | {"type": "motor", "slope_nms_rad": c_m, "inertia_kg_m2": J_m}
//                                                  (open-loop motor commanded at top_speed_rad_s:
//                                                   J_m Omega' = c_m (Omega_c - Omega) - T_top)
//              | {"type": "controlled", "inertia_kg_m2": J,
//                 "controller": {"type": "stiff" | "pi" | "soft_speed" | "z_torque",
//                                "torque_limit_nm", "sample_time_s", "kp_nms_rad", "ki_nm_rad",
//                                "bandwidth_ratio" (stiff, z_torque), "impedance_nms_rad",
//                                "stick_slip_frequency_rad_s" (soft_speed), "torque_filter_s" (z_torque)}}
//                                                  (J Omega' = u - T_top, u from a speed controller
//                                                   commanded at top_speed_rad_s: controller.hpp),
//   "axial": {"type": "none"}                      (the WOB is the input operation.wob_n)
//          | {"type": "jack", "gain_n_rad": g, "relaxation_s": tau}
//                                                  (the WOB as a state, axial.hpp:
//                                                   W' = g (Omega_f - v) - (W - W_s) / tau),
//          | {"type": "rgd", "top": "hook_load" | "feed", "rop_m_s" (feed), "modes", "damping_ratio",
//             "bit_mass_kg", "disturbance",
//             "bit": {"radius_m", "specific_energy_pa", "contact_strength_pa", "zeta", "wear_flat_m",
//                     "gamma", "mu", "blades"}}
//                                                  (axial-torsional string with the Richard-Germay-
//                                                   Detournay bit, axial_torsional.hpp; no "law" block:
//                                                   the bit law is axial.bit; hook_load pushes the top
//                                                   with operation.wob_n),
//   "sensors": {"lowpass_hz": 10}                  (measurement chain of recorded channels: second-
//                                                   order Butterworth low-pass; 0 = ideal sensors;
//                                                   used when a model is compared with a record),
//   "simulation": {"scheme": "modified_euler" | "bdf2" | "exact_modal" (integrator.hpp), "acceleration": "implicit" | "lagged" (Eq. 3.3's bit
//                  acceleration, integrator.hpp), "dt_s": 5.12e-4, "duration_s": 200,
//                  "transient_s": 100, "output_stride": 20,
//                  "start": "rest" | "rigid" | "steady" (initial state, Simulation::start_state)},
//   "metrics": {"stick_threshold_fraction": 0.05, "stick_debounce_s": 0.02, "slip_level_fraction": 0.25},
//   "sweep": {"top_speeds_rad_s": [...], "wobs_n": [...]},
//   "craig_bampton": {"modes": [25, 25]}
// }
// plus "description" (free text) and "$schema" (the JSON Schema an editor checks the file with), both
// ignored. Unknown and duplicate keys are refused (they are usually typos); missing optional blocks
// take the defaults written above. Integers are range-checked (never wrapped). Errors name the JSON
// path and the offending value. The keys of every block, with their types, units, bounds and
// defaults, are one table (schema::blocks() below); config_schema.hpp writes it as a JSON Schema.
#pragma once

#include <nlohmann/json.hpp>
#include <algorithm>
#include <climits>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "drill/axial.hpp"
#include "drill/bitrock.hpp"
#include "drill/errors.hpp"
#include "drill/fem.hpp"
#include "drill/integrator.hpp"
#include "drill/modal.hpp"
#include "drill/topdrive.hpp"

namespace drill {

using json = nlohmann::json;

/// How a run starts (the thesis is ambiguous, docs/validation.md):
///  * rest   Eq. (2.10) and Algorithm 1: string untwisted, at rest in the ground frame while the
///           top turns at Omega (q = 0, q' = -Omega M~^-1 Phi^T M 1);
///  * rigid  Eq. (2.3) read at t = 0: the whole string already turning rigidly with the top
///           (q = 0, q' = 0), untwisted, so the bit meets the rock at full speed;
///  * steady steady drilling, slightly disturbed (Simulation::steady_state).
enum class StartMode { rest, rigid, steady };

inline StartMode parse_start(const std::string& s, const std::string& field = "start") {
  if (s == "rest") return StartMode::rest;
  if (s == "rigid") return StartMode::rigid;
  if (s == "steady") return StartMode::steady;
  throw std::invalid_argument(field + " = \"" + s + "\": unknown initial state (use rest, rigid or steady)");
}

inline std::string to_string(StartMode m) {
  return m == StartMode::rest ? "rest" : m == StartMode::rigid ? "rigid" : "steady";
}

struct MetricsSpec {
  double stick_threshold_fraction = 0.05;  ///< stick when bit speed <= fraction x top speed
  double stick_debounce_s = 0.02;          ///< minimum duration of a phase change [s]
  double slip_level_fraction = 0.25;       ///< a slip must exceed fraction x top speed, else it is chatter
};

struct Config {
  std::string name = "custom";
  StringModel string;
  int modes = 20;
  DampingSpec damping;
  BitRockLaw law;
  double top_speed = 10.0;    ///< [rad/s]
  double wob = 245e3;         ///< [N]
  double bit_viscous = 0.0;   ///< [N m s/rad]
  double string_friction = 0.0;  ///< Coulomb string friction at the bit [N m] (an extension, not in the thesis)
  TopDrive top_drive;         ///< ideal (default) or open-loop motor
  Axial axial;                ///< none (default: the WOB is an input) or the rig's jack (axial.hpp)
  double sensor_lowpass_hz = 0.0;  ///< cutoff of the recorded channels' low-pass [Hz]; 0: ideal sensors
  SimOptions sim;
  double transient = 100.0;   ///< [s] discarded before metrics
  long output_stride = 20;
  StartMode start = StartMode::rest;  ///< initial state of Simulation runs and sweeps (simulation.start)
  MetricsSpec metrics;
  std::vector<double> sweep_speeds, sweep_wobs;
  std::vector<int> cb_modes;  ///< fixed-interface modes per substructure (Craig-Bampton)

  void validate() const {
    string.validate();
    require(modes >= 1 && modes <= string.n_elements(), "rom.modes", modes,
            "must be between 1 and the number of free DOFs (" + show(string.n_elements()) + ")");
    damping.validate();
    if (!axial.coupled()) law.validate();  // with axial.type = rgd the bit law is axial.bit
    // The law, the stick threshold and SS (Eq. 3.4) are written for a top turning forward: SS divides
    // by the top speed (0 gave NaN) and a negative speed is a negative torque on bit.
    require_positive(top_speed, "operation.top_speed_rad_s");
    require_non_negative(wob, "operation.wob_n");
    require_non_negative(bit_viscous, "operation.bit_viscous_nms");
    require_non_negative(string_friction, "operation.string_friction_nm");
    top_drive.validate();
    require(!top_drive.has_inertia() || sim.scheme == Scheme::modified_euler, "top_drive.type",
            TopDrive::kind_name(top_drive.kind), "is implemented for simulation.scheme = modified_euler only");
    if (top_drive.is_controlled()) {
      const Controller& ctl = top_drive.controller;
      require(!ctl.sampled() || sim.dt <= ctl.sample_time * (1.0 + 1e-12), "simulation.dt_s", sim.dt,
              "is larger than top_drive.controller.sample_time_s = " + show(ctl.sample_time) + " s");
      // the drive must carry the steady torque of the operating point (law, c_v Omega, T_sf)
      const double steady = law.torque(top_speed, 0.0, wob) + bit_viscous * top_speed + string_friction;
      require(ctl.torque_limit > steady, "top_drive.controller.torque_limit_nm", ctl.torque_limit,
              "is below the steady torque " + show(steady) + " N m the drive carries at operation.top_speed_rad_s = " +
                  show(top_speed) + " rad/s, wob_n = " + show(wob) + " N");
    }
    axial.validate();
    require(!(axial.active() || axial.coupled()) || sim.scheme == Scheme::modified_euler, "axial.type",
            Axial::kind_name(axial.kind), "is implemented for simulation.scheme = modified_euler only");
    if (axial.coupled()) {
      require(top_drive.kind == TopDrive::Kind::ideal, "top_drive.type", TopDrive::kind_name(top_drive.kind),
              "is not implemented with axial.type = rgd (use ideal)");
      const int free_axial = string.n_elements() + (axial.rgd.top == AxialTop::hook_load ? 1 : 0);
      require(axial.rgd.modes <= free_axial, "axial.modes", axial.rgd.modes,
              "must be at most the number of free axial DOFs (" + show(free_axial) + ")");
      require(bit_viscous == 0.0, "operation.bit_viscous_nms", bit_viscous, "is not implemented with axial.type = rgd");
      require(string_friction == 0.0, "operation.string_friction_nm", string_friction,
              "is not implemented with axial.type = rgd");
    }
    require_non_negative(sensor_lowpass_hz, "sensors.lowpass_hz");
    sim.validate();
    require_non_negative(transient, "simulation.transient_s");
    require(transient < sim.duration, "simulation.transient_s", transient,
            "must be shorter than simulation.duration_s = " + show(sim.duration));
    require(output_stride >= 1, "simulation.output_stride", output_stride, "must be at least 1");
    require_fraction(metrics.stick_threshold_fraction, "metrics.stick_threshold_fraction");
    require_non_negative(metrics.stick_debounce_s, "metrics.stick_debounce_s");
    require_fraction(metrics.slip_level_fraction, "metrics.slip_level_fraction");
    for (std::size_t k = 0; k < sweep_speeds.size(); ++k)
      require_positive(sweep_speeds[k], "sweep.top_speeds_rad_s[" + std::to_string(k) + "]");
    for (std::size_t k = 0; k < sweep_wobs.size(); ++k)
      require_non_negative(sweep_wobs[k], "sweep.wobs_n[" + std::to_string(k) + "]");
    for (std::size_t k = 0; k < cb_modes.size(); ++k)
      require(cb_modes[k] >= 1, "craig_bampton.modes[" + std::to_string(k) + "]", cb_modes[k],
              "must be at least 1");
  }

  /// A fraction of the top speed: strictly between 0 and 1.
  static void require_fraction(double value, const std::string& field) {
    require(std::isfinite(value), field, value, "must be a finite number");
    require(value > 0.0 && value < 1.0, field, value, "must be between 0 and 1 (exclusive)");
  }

  /// Distribute n elements over the sections in proportion to their lengths (largest
  /// remainder, at least one per section): 100 on Table 3.1 gives 91 DP + 9 BHA.
  void set_total_elements(int n) {
    const int ns = static_cast<int>(string.sections.size());
    require(n >= ns, "elements", n, "must be at least the number of sections (" + show(ns) + ")");
    const double L = string.total_length();
    std::vector<double> rem(ns);
    int used = 0;
    for (int k = 0; k < ns; ++k) {
      const double share = n * string.sections[k].length / L;
      string.sections[k].elements = std::max(1, static_cast<int>(std::floor(share)));
      rem[k] = share - std::floor(share);
      used += string.sections[k].elements;
    }
    while (used < n) {
      int best = 0;
      for (int k = 1; k < ns; ++k)
        if (rem[k] > rem[best]) best = k;
      ++string.sections[best].elements;
      rem[best] = -1.0;
      ++used;
    }
    while (used > n) {  // only when the at-least-one rule overshoots
      int big = 0;
      for (int k = 1; k < ns; ++k)
        if (string.sections[k].elements > string.sections[big].elements) big = k;
      --string.sections[big].elements;
      --used;
    }
    modes = std::min(modes, string.n_elements());
  }
};

/// The characteristic torsional impedance of the string's top section, Z = J_p sqrt(G rho)
/// [N m s/rad] (controller.hpp): the impedance a controlled top drive is tuned to.
inline double top_impedance(const StringModel& s) {
  const Section& top = s.sections.front();
  return characteristic_impedance(top.polar_moment(), top.shear_modulus(), top.density);
}

/// The keys of every block of the configuration: one table from which parse_config takes the keys
/// it accepts and config_schema() (config_schema.hpp) writes the JSON Schema for editors, with each
/// key's JSON type, meaning and unit, the bounds the validators enforce and the default.
namespace schema {

/// A bound of a number (the validator's): its value and whether the value itself is refused.
struct Bound {
  double value;
  bool exclusive;
};

/// One key of a block. `dflt` is the value taken when the key is absent (null: the key is required,
/// or its default depends on other keys as `doc` says).
struct Field {
  enum class Type { number, integer, string, numbers, integers, rows, object, objects };
  std::string key;
  Type type;
  std::string doc;
  json dflt = nullptr;
  bool required = false;             ///< must be present (an array: and not empty)
  std::optional<Bound> min, max;     ///< number, integer (arrays of them: each item)
  std::vector<std::string> choices;  ///< string: the accepted values (any string when empty)
  std::string block;                 ///< object, objects: the name of the block describing it
  std::vector<Field> columns;        ///< rows: each row is an array of these values
  std::size_t count = 0;             ///< rows: the number of rows

  Field& req() {
    required = true;
    return *this;
  }
  Field& def(json value) {
    dflt = std::move(value);
    return *this;
  }
  Field& above(double v) {
    min = Bound{v, true};
    return *this;
  }
  Field& at_least(double v) {
    min = Bound{v, false};
    return *this;
  }
  Field& below(double v) {
    max = Bound{v, true};
    return *this;
  }
  Field& at_most(double v) {
    max = Bound{v, false};
    return *this;
  }
  Field& positive() { return above(0.0); }
  Field& non_negative() { return at_least(0.0); }
};

inline Field number(std::string key, std::string doc) { return {std::move(key), Field::Type::number, std::move(doc)}; }
inline Field integer(std::string key, std::string doc) { return {std::move(key), Field::Type::integer, std::move(doc)}; }
inline Field numbers(std::string key, std::string doc) { return {std::move(key), Field::Type::numbers, std::move(doc)}; }
inline Field integers(std::string key, std::string doc) {
  return {std::move(key), Field::Type::integers, std::move(doc)};
}
inline Field text(std::string key, std::string doc, std::vector<std::string> choices = {}) {
  Field f{std::move(key), Field::Type::string, std::move(doc)};
  f.choices = std::move(choices);
  return f;
}
inline Field object(std::string key, std::string block, std::string doc) {
  Field f{std::move(key), Field::Type::object, std::move(doc)};
  f.block = std::move(block);
  return f;
}
inline Field objects(std::string key, std::string block, std::string doc) {
  Field f{std::move(key), Field::Type::objects, std::move(doc)};
  f.block = std::move(block);
  return f;
}
inline Field rows(std::string key, std::string doc, std::size_t count, std::vector<Field> columns) {
  Field f{std::move(key), Field::Type::rows, std::move(doc)};
  f.count = count;
  f.columns = std::move(columns);
  return f;
}

/// A variant of a block, picked by the block's "type", with the keys it adds.
struct Variant {
  std::string type;
  std::vector<Field> fields;
};

/// A JSON object of the configuration, named as in error messages ("operation"; "string.sections"
/// for each item of that array; "config" for the top level), with its keys and variants.
struct Block {
  std::string name, doc;
  std::vector<Field> fields;      ///< the keys of every variant
  std::vector<Variant> variants;  ///< empty, or one per value of the key "type"
};

inline std::vector<Block> make_blocks() {
  const Config d;  // the defaults of absent keys
  const std::vector<Field> poly_coefficients = [] {
    std::vector<Field> a;
    for (int i = 0; i < 8; ++i)
      a.push_back(number("a" + std::to_string(i), "Eq. (5.1) coefficient a" + std::to_string(i)).req());
    a.push_back(number("ref_speed", "mean bit speed of Eq. (5.1) [speed_unit]").positive().req());
    a.push_back(number("gain", "constant factor of Eq. (5.1) (1.36: ft.lbf to N m)").req());
    return a;
  }();
  const std::vector<Field> hysteresis = {
      number("beta1", "Eq. (3.3): H = beta1 tanh(beta2 a) sign(v), in [0, 1)").at_least(0.0).below(1.0).req(),
      number("beta2", "Eq. (3.3) [1 / (speed_unit/s)]").non_negative().req()};
  std::vector<Field> hysteretic = {
      number("b0", "Eq. (3.2): T = b0 [tanh(b1 v) + b2 |v|^b4 sign(v) / (1 + b3 |v|^b5) (1 + H)] [N m]").req(),
      number("b1", "Eq. (3.2) [1 / speed_unit]").req(),
      number("b2", "Eq. (3.2)").req(),
      number("b3", "Eq. (3.2)").non_negative().req(),
      number("b4", "Eq. (3.2) exponent").positive().req(),
      number("b5", "Eq. (3.2) exponent").positive().req()};
  hysteretic.insert(hysteretic.end(), hysteresis.begin(), hysteresis.end());
  std::vector<Field> poly_hysteretic = poly_coefficients;
  poly_hysteretic.insert(poly_hysteretic.end(), hysteresis.begin(), hysteresis.end());
  using Law = BitRockLaw::Kind;
  const std::vector<std::string> law_types = {BitRockLaw::kind_name(Law::tucker_wang), BitRockLaw::kind_name(Law::hysteretic),
                                              BitRockLaw::kind_name(Law::polynomial),
                                              BitRockLaw::kind_name(Law::polynomial_hysteretic)};
  const std::vector<std::string> drives = {TopDrive::kind_name(TopDrive::Kind::ideal),
                                           TopDrive::kind_name(TopDrive::Kind::motor),
                                           TopDrive::kind_name(TopDrive::Kind::controlled)};
  using Ctl = Controller::Kind;
  const std::vector<std::string> controllers = {Controller::kind_name(Ctl::stiff), Controller::kind_name(Ctl::pi),
                                                Controller::kind_name(Ctl::soft_speed),
                                                Controller::kind_name(Ctl::z_torque)};
  const Controller dc;  // the defaults of the controller's keys
  const AxialTorsionalSpec ad;  // the defaults of the rgd axial keys
  auto kp = [] { return number("kp_nms_rad", "kp: proportional gain [N m s/rad]").positive(); };
  auto ki = [] { return number("ki_nm_rad", "ki: integral gain [N m/rad]").non_negative(); };
  auto bandwidth = [&] {
    return number("bandwidth_ratio", "closed-loop bandwidth of the speed loop over the string's first natural "
                                     "frequency: kp = 2 J w_b, ki = J w_b^2, w_b = ratio w_1")
        .positive()
        .def(dc.bandwidth_ratio);
  };
  auto impedance = [] {
    return number("impedance_nms_rad", "Z [N m s/rad] (default: the top section's J_p sqrt(G rho))").positive();
  };

  return {
      {"config",
       "drillpy / drillsim configuration (cpp/include/drill/config.hpp); unknown and repeated keys are refused",
       {text("$schema", "the JSON Schema of this file, for editors (ignored by the engine)"),
        text("name", "name of the configuration").def(d.name),
        text("description", "free text (ignored by the engine)"),
        object("string", "string", "the drill string: sections from the top to the bit").req(),
        object("rom", "rom", "reduced-order model (Eqs. 2.7-2.10)"),
        object("damping", "damping", "damping of the reduced model")
            .def({{"type", "modal"}, {"ratios", d.damping.ratios}}),
        object("law", "law", "bit-rock interaction law (required, except with axial.type = rgd, whose bit law is axial.bit)"),
        object("operation", "operation", "operating point"),
        object("top_drive", "top_drive", "how the top is turned").def({{"type", "ideal"}}),
        object("axial", "axial", "the weight on bit: an input, a state driven by the rig's jack, or the axial-torsional "
                                 "string with the RGD bit")
            .def({{"type", "none"}}),
        object("sensors", "sensors", "measurement chain of the recorded channels"),
        object("simulation", "simulation", "time integration (appendices A, B)"),
        object("metrics", "metrics", "stick and slip detection"),
        object("sweep", "sweep", "grid of the sweep job (drillsim --job sweep)"),
        object("craig_bampton", "craig_bampton", "Craig-Bampton substructuring (chapter 6)")}},
      {"string",
       "the drill string (Eqs. 2.1-2.6)",
       {objects("sections", "string.sections", "uniform sections from the top to the bit").req(),
        objects("lumped_inertias", "string.lumped_inertias", "rotary inertias added at nodes").def(json::array())}},
      {"string.sections",
       "a uniform section: a hollow or solid circular shaft of linear torsion elements",
       {text("name", "section name (default: section<index>)"),
        number("length_m", "length [m]").positive().req(),
        number("outer_radius_m", "outer radius [m]").positive().req(),
        number("inner_radius_m", "inner radius [m], below outer_radius_m; 0: a solid bar").non_negative().def(0.0),
        number("youngs_modulus_pa", "Young's modulus [Pa]").positive().req(),
        number("poisson_ratio", "Poisson's ratio [-]").above(-1.0).below(0.5).req(),
        number("density_kg_m3", "density [kg/m^3]").positive().req(),
        integer("elements", "number of linear elements").at_least(1).req()}},
      {"string.lumped_inertias",
       "a rotary inertia added at a node",
       {integer("node", "node index: 0 at the top, negative from the bit (-1: the bit)").def(-1),
        number("inertia_kg_m2", "rotary inertia [kg m^2]").positive().req()}},
      {"rom",
       "reduced-order model",
       {integer("modes", "retained modes, at most the number of elements (default: 20, or that number if smaller)").at_least(1)}},
      {"damping",
       "modal damping ratios, or Rayleigh damping D = a M + b K through two (frequency, ratio) pairs",
       {text("type", "damping model", {"modal", "rayleigh"}).req()},
       {{"modal",
         {numbers("ratios", "damping ratio of modes 1, 2, ... (the last repeats), in [0, 1]")
              .non_negative()
              .at_most(1.0)
              .req()}},
        {"rayleigh",
         {rows("pairs", "[[f1_hz, ratio1], [f2_hz, ratio2]]: the ratios at two distinct frequencies", 2,
               {number("frequency_hz", "frequency [Hz]").positive(),
                number("ratio", "damping ratio in [0, 1]").non_negative().at_most(1.0)})
              .req()}}}},
      {"law",
       "torque on bit as a function of bit speed v, bit acceleration a and WOB; it scales linearly with the WOB",
       {text("type", "law: Eq. (3.1), (3.2)-(3.3), (5.1) or (5.3)", law_types).req(),
        text("speed_unit", "unit of v (and a per second) in the law's formulas", {"rad_s", "rad/s", "rpm", "RPM"})
            .req(),
        number("wob_ref_n", "WOB at which the parameters hold [N]").positive().req()},
       {{law_types[0],
         {number("c0", "Eq. (3.1): T = c0 [tanh(alpha0 v) + alpha1 v / (1 + alpha2 v^2)] [N m]").req(),
          number("alpha0", "Eq. (3.1) [1 / speed_unit]").non_negative().req(),
          number("alpha1", "Eq. (3.1) [1 / speed_unit]").req(),
          number("alpha2", "Eq. (3.1) [1 / speed_unit^2]").non_negative().req()}},
        {law_types[1], hysteretic},
        {law_types[2], poly_coefficients},
        {law_types[3], poly_hysteretic}}},
      {"operation",
       "operating point",
       {number("top_speed_rad_s", "top-drive speed (commanded speed of a motor top drive) [rad/s]")
            .positive()
            .def(d.top_speed),
        number("wob_n", "weight on bit [N] (default: law.wob_ref_n)").non_negative(),
        number("bit_viscous_nms", "viscous torque c_v v on the bit [N m s/rad] (not in the thesis)")
            .non_negative()
            .def(d.bit_viscous),
        number("string_friction_nm", "Coulomb torque T_sf sign(v) of the string, lumped at the bit [N m] "
                                     "(not in the thesis)")
            .non_negative()
            .def(d.string_friction)}},
      {"top_drive",
       "ideal (the thesis: the top turns at top_speed_rad_s) or an open-loop motor commanded at it, "
       "J_m Omega' = c_m (Omega_c - Omega) - T_top",
       {text("type", "top-drive model", drives).req()},
       {{drives[0], {}},
        {drives[1],
         {number("slope_nms_rad", "c_m: torque lost per unit speed [N m s/rad]").positive().req(),
          number("inertia_kg_m2", "J_m: rotor and drive-train inertia [kg m^2]").positive().req(),
          number("max_torque_nm", "T_max: the motor's torque limit [N m]; absent: unlimited").positive()}},
        {drives[2],
         {number("inertia_kg_m2", "J: rotor and drive-train inertia [kg m^2]").positive().req(),
          object("controller", "top_drive.controller", "the speed controller driving the inertia").req()}}}},
      {"top_drive.controller",
       "speed controller of a controlled top drive, J Omega' = u - T_top, u = sat(kp e + ki int e), "
       "e = Omega_ref - Omega (cpp/include/drill/controller.hpp, docs/control.md)",
       {text("type", "stiff (high-gain PI), pi (user gains), soft_speed (SoftSpeed: kp = Z, ki = J w_s^2) or "
                     "z_torque (ZTorque: set point corrected by -(T_top - T_mean) / Z)",
             controllers)
            .req(),
        number("torque_limit_nm", "motor torque limit |u| <= L [N m] (anti-windup); absent: no limit").positive(),
        number("sample_time_s", "sample time of the controller (zero-order hold) [s]; absent: continuous")
            .positive()},
       {{controllers[0], {bandwidth(), kp(), ki()}},
        {controllers[1], {kp().req(), ki().req()}},
        {controllers[2],
         {kp(), ki(), impedance(),
          number("stick_slip_frequency_rad_s", "w_s [rad/s] (default: the string's first natural frequency)")
              .positive()}},
        {controllers[3],
         {bandwidth(), kp(), ki(), impedance(),
          number("torque_filter_s", "time constant of the top torque's low-pass T_mean [s] (default: 5 / w_1)")
              .positive()}}}},
      {"axial",
       "none (the WOB is operation.wob_n), the rig's jack, W' = g (Omega_f - v) - (W - W_s) / tau (axial.hpp), or rgd: "
       "the string's axial modes with the Richard-Germay-Detournay bit (axial_torsional.hpp, docs/axial.md)",
       {text("type", "axial model",
             {Axial::kind_name(Axial::Kind::none), Axial::kind_name(Axial::Kind::jack), Axial::kind_name(Axial::Kind::rgd)})
            .req()},
       {{Axial::kind_name(Axial::Kind::none), {}},
        {Axial::kind_name(Axial::Kind::jack),
         {number("gain_n_rad", "g = k_ax d / (2 pi): WOB per radian the bit lags its steady rotation [N/rad]")
              .non_negative()
              .req(),
          number("relaxation_s", "tau: the jack's time constant [s]").positive().req()}},
        {Axial::kind_name(Axial::Kind::rgd),
         {text("top", "top boundary: hook_load (constant force operation.wob_n down at the top) or feed (constant "
                      "rate of penetration rop_m_s)",
               {"hook_load", "feed"})
              .def("hook_load"),
          number("rop_m_s", "V0: the top's constant feed rate with top = feed [m/s]").positive(),
          integer("modes", "retained axial modes, at most the free axial DOFs").at_least(1).def(ad.modes),
          number("damping_ratio", "modal damping ratio of the axial modes").non_negative().at_most(1.0).def(ad.damping_ratio),
          number("bit_mass_kg", "axial mass lumped at the bit [kg]").non_negative().def(ad.bit_mass),
          number("disturbance", "start: the bit's axial speed is (1 - disturbance) times the steady rate of "
                                "penetration (0: steady drilling; above 1: moving up)")
              .at_least(-1000.0)
              .at_most(1000.0)
              .def(ad.disturbance),
          object("bit", "axial.bit", "the Richard-Germay-Detournay bit law (rgd_bit.hpp)").req()}}}},
      {"axial.bit",
       "the RGD bit: W_c = a zeta eps d, T_c = a^2 eps d / 2, W_f = a l sigma, T_f = gamma mu a W_f / 2, "
       "d = N [U(t) - U(t - t_N)]",
       {number("radius_m", "a: bit radius [m]").positive().req(),
        number("specific_energy_pa", "eps: intrinsic specific energy [Pa]").positive().req(),
        number("contact_strength_pa", "sigma: contact strength of the wear flats [Pa]").non_negative().req(),
        number("zeta", "zeta: normal over tangential cutting force [-]").positive().req(),
        number("wear_flat_m", "l: total wear-flat length [m]").non_negative().req(),
        number("gamma", "gamma: bit geometry factor [-]").non_negative().req(),
        number("mu", "mu: friction coefficient of the wear flats [-]").non_negative().req(),
        integer("blades", "N: blades").at_least(1).at_most(64).req()}},
      {"sensors",
       "measurement chain of the recorded channels",
       {number("lowpass_hz", "cutoff of a second-order Butterworth low-pass [Hz]; 0: ideal sensors")
            .non_negative()
            .def(d.sensor_lowpass_hz)}},
      {"simulation",
       "time integration",
       {text("scheme", "integrator",
             {to_string(Scheme::modified_euler), to_string(Scheme::bdf2), to_string(Scheme::exact_modal)})
            .def(to_string(d.sim.scheme)),
        text("acceleration", "bit acceleration in Eq. (3.3); lagged: modified_euler only",
             {to_string(Acceleration::implicit), to_string(Acceleration::lagged)})
            .def(to_string(d.sim.acceleration)),
        number("dt_s", "time step [s]").positive().def(d.sim.dt),
        number("duration_s", "simulated time [s], at least one step").positive().def(d.sim.duration),
        number("transient_s", "time discarded before the metrics [s], below duration_s "
                              "(default: 100 or half the duration)")
            .non_negative(),
        integer("output_stride", "the series keeps every n-th step").at_least(1).def(d.output_stride),
        text("start", "initial state: rest (Eq. 2.10), rigid (Eq. 2.3) or steady (steady drilling, disturbed)",
             {to_string(StartMode::rest), to_string(StartMode::rigid), to_string(StartMode::steady)})
            .def(to_string(d.start))}},
      {"metrics",
       "stick and slip detection",
       {number("stick_threshold_fraction", "stick when the bit speed is at most this fraction of the top speed")
            .above(0.0)
            .below(1.0)
            .def(d.metrics.stick_threshold_fraction),
        number("stick_debounce_s", "minimum duration of a phase change [s]")
            .non_negative()
            .def(d.metrics.stick_debounce_s),
        number("slip_level_fraction", "a slip exceeds this fraction of the top speed, else it is chatter")
            .above(0.0)
            .below(1.0)
            .def(d.metrics.slip_level_fraction)}},
      {"sweep",
       "grid of the sweep job",
       {numbers("top_speeds_rad_s", "top speeds [rad/s]").positive().def(json::array()),
        numbers("wobs_n", "weights on bit [N]; empty: operation.wob_n").non_negative().def(json::array())}},
      {"craig_bampton",
       "Craig-Bampton substructuring",
       {integers("modes", "fixed-interface modes per substructure").at_least(1).def(json::array())}}};
}

/// Every block of the configuration, the top level ("config") first.
inline const std::vector<Block>& blocks() {
  static const std::vector<Block> all = make_blocks();
  return all;
}

inline const Block& block(const std::string& name) {
  for (const Block& b : blocks())
    if (b.name == name) return b;
  throw std::logic_error("no configuration block " + name);
}

/// The keys a block accepts: its fields and those of the variant `type`.
inline std::set<std::string> keys(const std::string& name, const std::string& type = "") {
  const Block& b = block(name);
  std::set<std::string> out;
  for (const Field& f : b.fields) out.insert(f.key);
  for (const Variant& v : b.variants)
    if (v.type == type)
      for (const Field& f : v.fields) out.insert(f.key);
  return out;
}

}  // namespace schema

namespace detail {

inline void check_keys(const json& j, const std::string& where, const std::set<std::string>& allowed) {
  if (!j.is_object()) throw std::invalid_argument(where + " = " + j.dump() + ": must be a JSON object");
  for (auto it = j.begin(); it != j.end(); ++it)
    if (!allowed.count(it.key())) {
      // a key with a control character (a line break...) is shown JSON-escaped: the error stays one line
      const bool plain = std::all_of(it.key().begin(), it.key().end(), [](unsigned char ch) { return ch >= 0x20; });
      const std::string key = plain ? it.key() : json(it.key()).dump();
      throw std::invalid_argument(where + "." + key + " = " + it.value().dump() + ": unknown key");
    }
}

inline double get_number(const json& j, const std::string& key, const std::string& where) {
  if (!j.contains(key)) throw std::invalid_argument(where + "." + key + ": missing (required number)");
  const json& v = j.at(key);
  if (!v.is_number()) throw std::invalid_argument(where + "." + key + " = " + v.dump() + ": must be a number");
  return v.get<double>();
}

inline double get_number(const json& j, const std::string& key, const std::string& where, double dflt) {
  return j.contains(key) ? get_number(j, key, where) : dflt;
}

/// An int-ranged JSON integer (a float such as 2.5 or 1e12 is refused, never truncated or wrapped).
inline int checked_int(const json& v, const std::string& field) {
  if (!v.is_number_integer()) throw std::invalid_argument(field + " = " + v.dump() + ": must be an integer");
  const bool in_range = v.is_number_unsigned() ? v.get<std::uint64_t>() <= static_cast<std::uint64_t>(INT_MAX)
                                               : v.get<std::int64_t>() >= INT_MIN && v.get<std::int64_t>() <= INT_MAX;
  if (!in_range)
    throw std::invalid_argument(field + " = " + v.dump() + ": out of range (integers are " + std::to_string(INT_MIN) +
                                " to " + std::to_string(INT_MAX) + ")");
  return static_cast<int>(v.get<std::int64_t>());
}

inline int get_int(const json& j, const std::string& key, const std::string& where, int dflt, bool required = false) {
  if (!j.contains(key)) {
    if (required) throw std::invalid_argument(where + "." + key + ": missing (required integer)");
    return dflt;
  }
  return checked_int(j.at(key), where + "." + key);
}

inline std::vector<int> get_ints(const json& j, const std::string& key, const std::string& where) {
  std::vector<int> out;
  if (!j.contains(key)) return out;
  const json& v = j.at(key);
  if (!v.is_array()) throw std::invalid_argument(where + "." + key + " = " + v.dump() + ": must be an array of integers");
  for (std::size_t k = 0; k < v.size(); ++k) out.push_back(checked_int(v[k], where + "." + key + "[" + std::to_string(k) + "]"));
  return out;
}

inline std::string get_string(const json& j, const std::string& key, const std::string& where,
                              const std::string& dflt, bool required = false) {
  if (!j.contains(key)) {
    if (required) throw std::invalid_argument(where + "." + key + ": missing (required string)");
    return dflt;
  }
  const json& v = j.at(key);
  if (!v.is_string()) throw std::invalid_argument(where + "." + key + " = " + v.dump() + ": must be a string");
  return v.get<std::string>();
}

inline std::vector<double> get_numbers(const json& j, const std::string& key, const std::string& where) {
  std::vector<double> out;
  if (!j.contains(key)) return out;
  const json& v = j.at(key);
  if (!v.is_array()) throw std::invalid_argument(where + "." + key + " = " + v.dump() + ": must be an array of numbers");
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (!v[k].is_number())
      throw std::invalid_argument(where + "." + key + "[" + std::to_string(k) + "] = " + v[k].dump() +
                                  ": must be a number");
    out.push_back(v[k].get<double>());
  }
  return out;
}

inline BitRockLaw parse_law(const json& j) {
  const std::string w = "law";
  BitRockLaw l;
  l.kind = BitRockLaw::parse_kind(get_string(j, "type", w, "", true));
  check_keys(j, w, schema::keys(w, BitRockLaw::kind_name(l.kind)));
  l.speed_unit = parse_speed_unit(get_string(j, "speed_unit", w, "", true), w + ".speed_unit");
  l.wob_ref = get_number(j, "wob_ref_n", w);
  auto num = [&](const std::string& k) { return get_number(j, k, w); };
  switch (l.kind) {
    case BitRockLaw::Kind::tucker_wang:
      l.c0 = num("c0");
      l.alpha0 = num("alpha0");
      l.alpha1 = num("alpha1");
      l.alpha2 = num("alpha2");
      break;
    case BitRockLaw::Kind::hysteretic:
      for (int i = 0; i < 6; ++i) l.b[i] = num("b" + std::to_string(i));
      l.beta1 = num("beta1");
      l.beta2 = num("beta2");
      break;
    case BitRockLaw::Kind::polynomial:
    case BitRockLaw::Kind::polynomial_hysteretic:
      for (int i = 0; i < 8; ++i) l.a[i] = num("a" + std::to_string(i));
      l.ref_speed = num("ref_speed");
      l.gain = num("gain");
      if (l.kind == BitRockLaw::Kind::polynomial_hysteretic) {
        l.beta1 = num("beta1");
        l.beta2 = num("beta2");
      }
      break;
  }
  return l;
}

inline json law_to_json(const BitRockLaw& l) {
  json j{{"type", BitRockLaw::kind_name(l.kind)}, {"speed_unit", to_string(l.speed_unit)}, {"wob_ref_n", l.wob_ref}};
  switch (l.kind) {
    case BitRockLaw::Kind::tucker_wang:
      j["c0"] = l.c0;
      j["alpha0"] = l.alpha0;
      j["alpha1"] = l.alpha1;
      j["alpha2"] = l.alpha2;
      break;
    case BitRockLaw::Kind::hysteretic:
      for (int i = 0; i < 6; ++i) j["b" + std::to_string(i)] = l.b[i];
      j["beta1"] = l.beta1;
      j["beta2"] = l.beta2;
      break;
    case BitRockLaw::Kind::polynomial:
    case BitRockLaw::Kind::polynomial_hysteretic:
      for (int i = 0; i < 8; ++i) j["a" + std::to_string(i)] = l.a[i];
      j["ref_speed"] = l.ref_speed;
      j["gain"] = l.gain;
      if (l.kind == BitRockLaw::Kind::polynomial_hysteretic) {
        j["beta1"] = l.beta1;
        j["beta2"] = l.beta2;
      }
      break;
  }
  return j;
}

}  // namespace detail

/// Parse and validate a configuration.
inline Config parse_config(const json& j) {
  using namespace detail;
  check_keys(j, "config", schema::keys("config"));
  Config c;
  c.name = get_string(j, "name", "config", c.name);
  get_string(j, "description", "config", "");  // free text and the editors' "$schema": strings, else ignored
  get_string(j, "$schema", "config", "");
  if (!j.contains("string")) throw std::invalid_argument("config.string: missing (required object)");
  const json& js = j.at("string");
  check_keys(js, "string", schema::keys("string"));
  if (!js.contains("sections") || !js.at("sections").is_array())
    throw std::invalid_argument("string.sections: missing or not an array");
  for (std::size_t k = 0; k < js.at("sections").size(); ++k) {
    const json& s = js.at("sections")[k];
    const std::string w = "string.sections[" + std::to_string(k) + "]";
    check_keys(s, w, schema::keys("string.sections"));
    Section sec;
    sec.name = get_string(s, "name", w, "section" + std::to_string(k));
    sec.length = get_number(s, "length_m", w);
    sec.outer_radius = get_number(s, "outer_radius_m", w);
    sec.inner_radius = get_number(s, "inner_radius_m", w, 0.0);
    sec.youngs_modulus = get_number(s, "youngs_modulus_pa", w);
    sec.poisson_ratio = get_number(s, "poisson_ratio", w);
    sec.density = get_number(s, "density_kg_m3", w);
    sec.elements = get_int(s, "elements", w, 0, true);
    c.string.sections.push_back(sec);
  }
  if (js.contains("lumped_inertias")) {
    const json& li = js.at("lumped_inertias");
    if (!li.is_array()) throw std::invalid_argument("string.lumped_inertias = " + li.dump() + ": must be an array");
    for (std::size_t k = 0; k < li.size(); ++k) {
      const std::string w = "string.lumped_inertias[" + std::to_string(k) + "]";
      check_keys(li[k], w, schema::keys("string.lumped_inertias"));
      c.string.lumped.push_back({get_int(li[k], "node", w, -1), get_number(li[k], "inertia_kg_m2", w)});
    }
  }
  c.modes = std::min(20, c.string.n_elements());
  if (j.contains("rom")) {
    check_keys(j.at("rom"), "rom", schema::keys("rom"));
    c.modes = get_int(j.at("rom"), "modes", "rom", c.modes);
  }
  if (j.contains("damping")) {
    const json& d = j.at("damping");
    const std::string type = get_string(d, "type", "damping", "", true);
    if (type != "modal" && type != "rayleigh")
      throw std::invalid_argument("damping.type = \"" + type + "\": unknown damping (use modal or rayleigh)");
    check_keys(d, "damping", schema::keys("damping", type));
    if (type == "modal") {
      c.damping.kind = DampingSpec::Kind::modal;
      c.damping.ratios = get_numbers(d, "ratios", "damping");
    } else {
      c.damping.kind = DampingSpec::Kind::rayleigh;
      const json& p = d.contains("pairs") ? d.at("pairs") : json();
      if (!p.is_array() || p.size() != 2 || !p[0].is_array() || !p[1].is_array() || p[0].size() != 2 ||
          p[1].size() != 2 || !p[0][0].is_number() || !p[0][1].is_number() || !p[1][0].is_number() ||
          !p[1][1].is_number())
        throw std::invalid_argument("damping.pairs = " + p.dump() +
                                    ": must be [[f1_hz, ratio1], [f2_hz, ratio2]]");
      c.damping.f1 = p[0][0];
      c.damping.z1 = p[0][1];
      c.damping.f2 = p[1][0];
      c.damping.z2 = p[1][1];
    }
  }
  // with the axial-torsional model the bit law is axial.bit (RGD): a "law" block would be ignored
  const bool rgd = j.contains("axial") && j.at("axial").is_object() && j.at("axial").contains("type") &&
                   j.at("axial").at("type") == "rgd";
  const bool feed = rgd && j.at("axial").contains("top") && j.at("axial").at("top") == "feed";
  if (rgd) {
    if (j.contains("law"))
      throw std::invalid_argument("config.law = " + j.at("law").dump() +
                                  ": not used with axial.type = rgd (the bit law is axial.bit): remove it");
  } else {
    if (!j.contains("law")) throw std::invalid_argument("config.law: missing (required object)");
    c.law = parse_law(j.at("law"));
  }
  if (rgd && !feed && !(j.contains("operation") && j.at("operation").contains("wob_n")))
    throw std::invalid_argument("operation.wob_n: missing (required with axial.type = rgd, top = hook_load: the "
                                "net force down at the top, the WOB of steady drilling)");
  if (feed && j.contains("operation") && j.at("operation").contains("wob_n"))
    throw std::invalid_argument("operation.wob_n = " + j.at("operation").at("wob_n").dump() +
                                ": not used with axial.top = feed (the WOB follows from axial.rop_m_s): remove it");
  if (j.contains("operation")) {
    const json& o = j.at("operation");
    check_keys(o, "operation", schema::keys("operation"));
    c.top_speed = get_number(o, "top_speed_rad_s", "operation", c.top_speed);
    c.wob = get_number(o, "wob_n", "operation", feed ? 0.0 : c.law.wob_ref);
    c.bit_viscous = get_number(o, "bit_viscous_nms", "operation", 0.0);
    c.string_friction = get_number(o, "string_friction_nm", "operation", 0.0);
  } else {
    c.wob = feed ? 0.0 : c.law.wob_ref;
  }
  if (j.contains("top_drive")) {
    const json& t = j.at("top_drive");
    c.top_drive.kind = TopDrive::parse_kind(get_string(t, "type", "top_drive", "", true));
    check_keys(t, "top_drive", schema::keys("top_drive", TopDrive::kind_name(c.top_drive.kind)));
    if (c.top_drive.is_motor()) {
      c.top_drive.slope = get_number(t, "slope_nms_rad", "top_drive");
      c.top_drive.inertia = get_number(t, "inertia_kg_m2", "top_drive");
      if (t.contains("max_torque_nm")) c.top_drive.max_torque = get_number(t, "max_torque_nm", "top_drive");
    }
    if (c.top_drive.is_controlled()) {
      c.top_drive.inertia = get_number(t, "inertia_kg_m2", "top_drive");
      if (!t.contains("controller")) throw std::invalid_argument("top_drive.controller: missing (required object)");
      const json& k = t.at("controller");
      const std::string w = "top_drive.controller";
      if (!k.is_object()) throw std::invalid_argument(w + " = " + k.dump() + ": must be a JSON object");
      Controller& ctl = c.top_drive.controller;
      ctl.kind = Controller::parse_kind(get_string(k, "type", w, "", true));
      check_keys(k, w, schema::keys(w, Controller::kind_name(ctl.kind)));
      ctl.torque_limit = get_number(k, "torque_limit_nm", w, ctl.torque_limit);
      if (k.contains("sample_time_s")) {
        ctl.sample_time = get_number(k, "sample_time_s", w);
        require(ctl.sample_time > 0.0, w + ".sample_time_s", ctl.sample_time,
                "must be positive (omit it for a continuous controller)");
      }
      ctl.kp_given = get_number(k, "kp_nms_rad", w, NAN);
      ctl.ki_given = get_number(k, "ki_nm_rad", w, NAN);
      ctl.bandwidth_ratio = get_number(k, "bandwidth_ratio", w, ctl.bandwidth_ratio);
      ctl.impedance_given = get_number(k, "impedance_nms_rad", w, NAN);
      ctl.stick_slip_frequency = get_number(k, "stick_slip_frequency_rad_s", w, NAN);
      ctl.torque_filter_given = get_number(k, "torque_filter_s", w, NAN);
    }
  }
  if (j.contains("axial")) {
    const json& a = j.at("axial");
    c.axial.kind = Axial::parse_kind(get_string(a, "type", "axial", "", true));
    if (c.axial.coupled() && c.wob > 0.0) c.axial.rgd.top_force = c.wob;
    check_keys(a, "axial", schema::keys("axial", Axial::kind_name(c.axial.kind)));
    if (c.axial.active()) {
      c.axial.gain = get_number(a, "gain_n_rad", "axial");
      c.axial.relaxation = get_number(a, "relaxation_s", "axial");
    }
    if (c.axial.coupled()) {
      AxialTorsionalSpec& x = c.axial.rgd;
      x.top = parse_axial_top(get_string(a, "top", "axial", to_string(x.top)));
      if (x.top == AxialTop::feed) x.feed_rate = get_number(a, "rop_m_s", "axial");
      else if (a.contains("rop_m_s"))
        throw std::invalid_argument("axial.rop_m_s = " + a.at("rop_m_s").dump() +
                                    ": only with axial.top = feed (hook_load sets the WOB, operation.wob_n)");
      x.modes = get_int(a, "modes", "axial", x.modes);
      x.damping_ratio = get_number(a, "damping_ratio", "axial", x.damping_ratio);
      x.bit_mass = get_number(a, "bit_mass_kg", "axial", x.bit_mass);
      x.disturbance = get_number(a, "disturbance", "axial", x.disturbance);
      if (!a.contains("bit")) throw std::invalid_argument("axial.bit: missing (required object with axial.type = rgd)");
      const json& b = a.at("bit");
      check_keys(b, "axial.bit", schema::keys("axial.bit"));
      x.bit.radius = get_number(b, "radius_m", "axial.bit");
      x.bit.specific_energy = get_number(b, "specific_energy_pa", "axial.bit");
      x.bit.contact_strength = get_number(b, "contact_strength_pa", "axial.bit");
      x.bit.force_ratio = get_number(b, "zeta", "axial.bit");
      x.bit.wear_flat = get_number(b, "wear_flat_m", "axial.bit");
      x.bit.geometry = get_number(b, "gamma", "axial.bit");
      x.bit.friction = get_number(b, "mu", "axial.bit");
      x.bit.blades = get_int(b, "blades", "axial.bit", 0, true);
    }
  }
  if (j.contains("sensors")) {
    check_keys(j.at("sensors"), "sensors", schema::keys("sensors"));
    c.sensor_lowpass_hz = get_number(j.at("sensors"), "lowpass_hz", "sensors", 0.0);
  }
  {  // an absent block takes the same defaults as an empty one
    const json s = j.contains("simulation") ? j.at("simulation") : json::object();
    check_keys(s, "simulation", schema::keys("simulation"));
    c.sim.scheme = parse_scheme(get_string(s, "scheme", "simulation", to_string(c.sim.scheme)));
    c.sim.acceleration =
        parse_acceleration(get_string(s, "acceleration", "simulation", to_string(c.sim.acceleration)));
    c.sim.dt = get_number(s, "dt_s", "simulation", c.sim.dt);
    c.sim.duration = get_number(s, "duration_s", "simulation", c.sim.duration);
    c.transient = get_number(s, "transient_s", "simulation", std::min(c.transient, 0.5 * c.sim.duration));
    c.output_stride = get_int(s, "output_stride", "simulation", static_cast<int>(c.output_stride));
    c.start = parse_start(get_string(s, "start", "simulation", to_string(c.start)), "simulation.start");
  }
  if (j.contains("metrics")) {
    const json& m = j.at("metrics");
    check_keys(m, "metrics", schema::keys("metrics"));
    c.metrics.stick_threshold_fraction =
        get_number(m, "stick_threshold_fraction", "metrics", c.metrics.stick_threshold_fraction);
    c.metrics.stick_debounce_s = get_number(m, "stick_debounce_s", "metrics", c.metrics.stick_debounce_s);
    c.metrics.slip_level_fraction = get_number(m, "slip_level_fraction", "metrics", c.metrics.slip_level_fraction);
  }
  if (j.contains("sweep")) {
    check_keys(j.at("sweep"), "sweep", schema::keys("sweep"));
    c.sweep_speeds = get_numbers(j.at("sweep"), "top_speeds_rad_s", "sweep");
    c.sweep_wobs = get_numbers(j.at("sweep"), "wobs_n", "sweep");
  }
  if (j.contains("craig_bampton")) {
    check_keys(j.at("craig_bampton"), "craig_bampton", schema::keys("craig_bampton"));
    c.cb_modes = get_ints(j.at("craig_bampton"), "modes", "craig_bampton");
  }
  c.validate();
  return c;
}

/// Deepest nesting of arrays and objects parse_json_text reads: a configuration nests 4 levels
/// (the damping pairs), so deeper text is not one; refusing it at this depth keeps a hostile
/// file (200 000 nested arrays) from costing minutes and a message as long as the file.
inline constexpr int max_json_depth = 64;

/// Parse JSON text, refusing a key repeated in an object (plain parsing keeps the last one
/// silently): std::invalid_argument("<path>.<key>: duplicate key ..."), and nesting deeper than
/// max_json_depth: std::invalid_argument("<what>: JSON nested too deep: ..."), raised by the
/// parser's callback as it opens level max_json_depth + 1 (nothing deeper is read). Syntax errors
/// become std::invalid_argument naming the position. `what` names the text in the messages
/// (e.g. "config", or "--config FILE").
inline json parse_json_text(const std::string& text, const std::string& what = "config") {
  struct Frame {
    std::string path;
    bool array;
    std::set<std::string> keys;
  };
  std::vector<Frame> stack;
  std::string last_key;
  auto child_path = [&]() -> std::string {
    if (stack.empty()) return "";
    const Frame& f = stack.back();
    if (f.array) return f.path + "[]";
    return f.path.empty() ? last_key : f.path + "." + last_key;
  };
  const json::parser_callback_t cb = [&](int, json::parse_event_t ev, json& parsed) {
    switch (ev) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        if (stack.size() >= static_cast<std::size_t>(max_json_depth))
          throw std::invalid_argument(what + ": JSON nested too deep: more than " + std::to_string(max_json_depth) +
                                      " levels of arrays and objects (a configuration has 4)");
        stack.push_back({child_path(), ev == json::parse_event_t::array_start, {}});
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!stack.empty()) stack.pop_back();
        break;
      case json::parse_event_t::key: {
        const std::string key = parsed.get<std::string>();
        Frame& f = stack.back();
        const std::string field = f.path.empty() ? key : f.path + "." + key;
        if (!f.keys.insert(key).second)
          throw std::invalid_argument(field + ": duplicate key \"" + key + "\" in a JSON object of the " + what);
        last_key = key;
        break;
      }
      case json::parse_event_t::value:
        break;
    }
    return true;
  };
  try {
    return json::parse(text, cb);
  } catch (const json::parse_error& e) {
    // nlohmann's text starts with "[json.exception.parse_error.101] parse error at ...": keep the position
    std::string why = e.what();
    const std::size_t tag = why.find("] ");
    if (why.rfind("[json.exception.", 0) == 0 && tag != std::string::npos) why = why.substr(tag + 2);
    throw std::invalid_argument(what + ": malformed JSON: " + why);
  }
}

/// Parse JSON text (parse_json_text) into a validated configuration.
inline Config parse_config_text(const std::string& text) { return parse_config(parse_json_text(text)); }

/// The configuration written back as JSON (all defaults made explicit).
inline json to_json(const Config& c) {
  json secs = json::array();
  for (const auto& s : c.string.sections)
    secs.push_back({{"name", s.name}, {"length_m", s.length}, {"outer_radius_m", s.outer_radius},
                    {"inner_radius_m", s.inner_radius}, {"youngs_modulus_pa", s.youngs_modulus},
                    {"poisson_ratio", s.poisson_ratio}, {"density_kg_m3", s.density}, {"elements", s.elements}});
  json li = json::array();
  for (const auto& l : c.string.lumped) li.push_back({{"node", l.node}, {"inertia_kg_m2", l.inertia}});
  json damping = c.damping.kind == DampingSpec::Kind::modal
                     ? json{{"type", "modal"}, {"ratios", c.damping.ratios}}
                     : json{{"type", "rayleigh"},
                            {"pairs", {{c.damping.f1, c.damping.z1}, {c.damping.f2, c.damping.z2}}}};
  json j{{"name", c.name},
         {"string", {{"sections", secs}, {"lumped_inertias", li}}},
         {"rom", {{"modes", c.modes}}},
         {"damping", damping},
         {"operation",
          {{"top_speed_rad_s", c.top_speed},
           {"wob_n", c.wob},
           {"bit_viscous_nms", c.bit_viscous},
           {"string_friction_nm", c.string_friction}}},
         {"simulation",
          {{"scheme", to_string(c.sim.scheme)}, {"acceleration", to_string(c.sim.acceleration)}, {"dt_s", c.sim.dt}, {"duration_s", c.sim.duration},
           {"transient_s", c.transient}, {"output_stride", c.output_stride}, {"start", to_string(c.start)}}},
         {"metrics",
          {{"stick_threshold_fraction", c.metrics.stick_threshold_fraction},
           {"stick_debounce_s", c.metrics.stick_debounce_s},
           {"slip_level_fraction", c.metrics.slip_level_fraction}}}};
  if (!c.sweep_speeds.empty() || !c.sweep_wobs.empty())
    j["sweep"] = {{"top_speeds_rad_s", c.sweep_speeds}, {"wobs_n", c.sweep_wobs}};
  if (!c.cb_modes.empty()) j["craig_bampton"] = {{"modes", c.cb_modes}};
  if (c.top_drive.is_motor()) {
    j["top_drive"] = {{"type", "motor"}, {"slope_nms_rad", c.top_drive.slope}, {"inertia_kg_m2", c.top_drive.inertia}};
    if (std::isfinite(c.top_drive.max_torque)) j["top_drive"]["max_torque_nm"] = c.top_drive.max_torque;
  }
  if (c.top_drive.is_controlled()) {  // the configured fields (the tuned gains follow from them)
    const Controller& k = c.top_drive.controller;
    json ctl{{"type", Controller::kind_name(k.kind)}};
    auto put = [&](const char* key, double v) {
      if (!std::isnan(v)) ctl[key] = v;
    };
    if (std::isfinite(k.torque_limit)) ctl["torque_limit_nm"] = k.torque_limit;
    if (k.sampled()) ctl["sample_time_s"] = k.sample_time;
    put("kp_nms_rad", k.kp_given);
    put("ki_nm_rad", k.ki_given);
    if (k.kind == Controller::Kind::stiff || k.kind == Controller::Kind::z_torque)
      ctl["bandwidth_ratio"] = k.bandwidth_ratio;
    if (k.kind == Controller::Kind::soft_speed || k.kind == Controller::Kind::z_torque)
      put("impedance_nms_rad", k.impedance_given);
    if (k.kind == Controller::Kind::soft_speed) put("stick_slip_frequency_rad_s", k.stick_slip_frequency);
    if (k.kind == Controller::Kind::z_torque) put("torque_filter_s", k.torque_filter_given);
    j["top_drive"] = {{"type", "controlled"}, {"inertia_kg_m2", c.top_drive.inertia}, {"controller", ctl}};
  }
  if (!c.axial.coupled()) j["law"] = detail::law_to_json(c.law);
  if (c.axial.active())
    j["axial"] = {{"type", "jack"}, {"gain_n_rad", c.axial.gain}, {"relaxation_s", c.axial.relaxation}};
  if (c.axial.coupled()) {
    const AxialTorsionalSpec& x = c.axial.rgd;
    const RgdBit& b = x.bit;
    j["axial"] = {{"type", "rgd"},
                  {"top", to_string(x.top)},
                  {"modes", x.modes},
                  {"damping_ratio", x.damping_ratio},
                  {"bit_mass_kg", x.bit_mass},
                  {"disturbance", x.disturbance},
                  {"bit",
                   {{"radius_m", b.radius},
                    {"specific_energy_pa", b.specific_energy},
                    {"contact_strength_pa", b.contact_strength},
                    {"zeta", b.force_ratio},
                    {"wear_flat_m", b.wear_flat},
                    {"gamma", b.geometry},
                    {"mu", b.friction},
                    {"blades", b.blades}}}};
    if (x.top == AxialTop::feed) {
      j["axial"]["rop_m_s"] = x.feed_rate;
      j["operation"].erase("wob_n");
    }
  }
  if (c.sensor_lowpass_hz > 0.0) j["sensors"] = {{"lowpass_hz", c.sensor_lowpass_hz}};
  return j;
}

}  // namespace drill
