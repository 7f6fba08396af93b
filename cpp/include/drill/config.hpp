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
//           "b0".."b5", "beta1", "beta2"}          (the keys of each law: its header, listed in
//                                                   laws/registry.hpp),
//   "operation": {"top_speed_rad_s": 16, "wob_n": 245000, "bit_viscous_nms": 0, "string_friction_nm": 0},
//                                                  (bit_viscous_nms: extra viscous torque c_v v on the bit;
//                                                   string_friction_nm: Coulomb torque T_sf sign(v) of the
//                                                   string on its guides, lumped at the bit, set-valued at
//                                                   rest (adds to the stick capacity); both act outside the
//                                                   bit's torque sensor and are not in the thesis),
//   "top_drive": {"type": "ideal"}                 (the thesis: the top turns at top_speed_rad_s; the keys
//                                                   of each drive: its header, listed in drives/registry.hpp)
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
//          | {"type": "rgd", "top": "hook_load" | "feed" | "jack", "rop_m_s" (feed, jack),
//             "jack_admittance_m_s_n" (jack), "modes",
//             "damping": "modal" | "distributed", "damping_ratio" (modal), "damping_rate_per_s" (distributed),
//             "bit_mass_kg", "disturbance", "torque": "rgd" | "law",
//             "bit": {"radius_m", "specific_energy_pa", "contact_strength_pa", "zeta", "wear_flat_m",
//                     "gamma", "mu", "blades"}}
//                                                  (axial-torsional string with the Richard-Germay-
//                                                   Detournay bit, axial_torsional.hpp; with torque =
//                                                   "rgd" (default) no "law" block: the bit law is
//                                                   axial.bit; with torque = "law" the torque on bit
//                                                   is the "law" block's at the axial WOB, the axial
//                                                   law stays axial.bit's; hook_load pushes the top
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
// path and the offending value. Each key is declared once, in its block's table (schema::make_tables()
// below, config_keys.hpp): its type, unit, bounds, default and the member it binds to; parse_config,
// to_json and the JSON Schema (config_schema.hpp) are all taken from the tables.
#pragma once

#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "drill/axial.hpp"
#include "drill/bitrock.hpp"
#include "drill/config_keys.hpp"
#include "drill/errors.hpp"
#include "drill/fem.hpp"
#include "drill/integrator.hpp"
#include "drill/json_text.hpp"
#include "drill/modal.hpp"
#include "drill/names.hpp"
#include "drill/topdrive.hpp"

namespace drill {


/// How a run starts (the thesis is ambiguous, docs/validation.md):
///  * rest   Eq. (2.10) and Algorithm 1: string untwisted, at rest in the ground frame while the
///           top turns at Omega (q = 0, q' = -Omega M~^-1 Phi^T M 1);
///  * rigid  Eq. (2.3) read at t = 0: the whole string already turning rigidly with the top
///           (q = 0, q' = 0), untwisted, so the bit meets the rock at full speed;
///  * steady steady drilling, slightly disturbed (Simulation::steady_state).
enum class StartMode { rest, rigid, steady };

inline constexpr Named<StartMode> start_names[] = {
    {StartMode::rest, "rest"}, {StartMode::rigid, "rigid"}, {StartMode::steady, "steady"}};
inline StartMode parse_start(const std::string& s, const std::string& field = "start") {
  return parse_name(start_names, s, field, "initial state");
}
inline std::string to_string(StartMode m) { return name_of(start_names, m); }

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
    // with axial.type = rgd the bit law is axial.bit, unless axial.torque = law takes the torque from the law
    if (!axial.coupled() || axial.rgd.torque == AxialTorque::law) law.validate();
    require(!law.ages() || (sim.scheme == Scheme::modified_euler && !axial.coupled()), "law.static_ageing",
            law.static_ageing, "is implemented on the torsional engine's modified_euler scheme only");
    // The law, the stick threshold and SS (Eq. 3.4) are written for a top turning forward: SS divides
    // by the top speed (0 gave NaN) and a negative speed is a negative torque on bit.
    require_positive(top_speed, "operation.top_speed_rad_s");
    require_non_negative(wob, "operation.wob_n");
    require_non_negative(bit_viscous, "operation.bit_viscous_nms");
    require_non_negative(string_friction, "operation.string_friction_nm");
    top_drive.validate();
    require(!top_drive.has_inertia() || sim.scheme != Scheme::bdf2, "top_drive.type",
            TopDrive::kind_name(top_drive.kind), "is implemented for simulation.scheme = modified_euler and exact_modal only");
    if (top_drive.has_controller()) {
      const Controller& ctl = top_drive.controller;
      require(!ctl.sampled() || sim.dt <= ctl.sample_time * (1.0 + 1e-12), "simulation.dt_s", sim.dt,
              "is larger than top_drive.controller.sample_time_s = " + show(ctl.sample_time) + " s");
      // the drive must carry the steady torque of the operating point (law, c_v Omega, T_sf; with
      // axial.type = rgd the coupled model's: RGD's T0 at its steady depth of cut, or the law's at W0)
      double steady = law.torque(top_speed, 0.0, wob) + bit_viscous * top_speed + string_friction;
      if (axial.coupled()) {
        const AxialTorsionalSpec& x = axial.rgd;
        x.validate();  // its feed rate or top force first
        const double d0 = x.steady_depth(top_speed);
        steady = x.torque == AxialTorque::law ? law.torque(top_speed, 0.0, x.bit.steady_wob(d0)) : x.bit.steady_torque(d0);
      }
      require(ctl.torque_limit > steady, "top_drive.controller.torque_limit_nm", ctl.torque_limit,
              "is below the steady torque " + show(steady) + " N m the drive carries at operation.top_speed_rad_s = " +
                  show(top_speed) + " rad/s, wob_n = " + show(wob) + " N");
    }
    axial.validate();
    require((!axial.active() && !axial.coupled()) || sim.scheme != Scheme::bdf2, "axial.type",
            Axial::kind_name(axial.kind), "is implemented for simulation.scheme = modified_euler and exact_modal only");
    if (axial.coupled()) {
      const int free_axial = string.n_elements() + (moving_frame(axial.rgd.top) ? 0 : 1);
      require(axial.rgd.modes <= free_axial, "axial.modes", axial.rgd.modes,
              "must be at most the number of free axial DOFs (" + show(free_axial) + ")");
      require(bit_viscous == 0.0, "operation.bit_viscous_nms", bit_viscous, "is not implemented with axial.type = rgd");
      require(string_friction == 0.0, "operation.string_friction_nm", string_friction,
              "is not implemented with axial.type = rgd");
      require(axial.rgd.torque != AxialTorque::law || sim.acceleration == Acceleration::implicit, "axial.torque",
              to_string(axial.rgd.torque),
              "is implemented with simulation.acceleration = implicit only (the step's own bit acceleration in "
              "Eq. 3.3), not " + to_string(sim.acceleration));
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

/// The configuration's keys, one table per block (config_keys.hpp): each key with its JSON type,
/// meaning and unit, the bounds the validators enforce, its default and the member it binds to.
/// parse_config and to_json read and write the blocks through them; config_schema() (config_schema.hpp)
/// writes them as the JSON Schema. Blocks nest through `object` keys, which the tables describe
/// and parse_config / to_json compose (a block's presence can depend on other blocks).
namespace schema {

struct Tables {
  Table<Config> config, string, rom, operation, sensors, simulation, sweep, craig_bampton;
  Table<Section> sections;
  Table<LumpedInertia> lumped_inertias;
  Table<DampingSpec> damping;
  Table<BitRockLaw> law;
  Table<TopDrive> top_drive;
  Table<Controller> controller;
  Table<Axial> axial;
  Table<RgdBit> bit;
  Table<MetricsSpec> metrics;
};

inline Tables make_tables() {
  const Config d;               // the defaults of absent keys
  const AxialTorsionalSpec ad;  // those of the rgd axial keys
  Tables t;

  t.config = {"config",
              "drillpy / drillsim configuration (cpp/include/drill/config.hpp); unknown and repeated keys are refused",
              {{text("name", "name of the configuration").def(d.name), &Config::name},
               Key<Config>::ignored(text("description", "free text (ignored by the engine)")),
               Key<Config>::ignored(
                   text("$schema", "the JSON Schema of this file, for editors (ignored by the engine)")),
               object("string", "string", "the drill string: sections from the top to the bit").req(),
               object("rom", "rom", "reduced-order model (Eqs. 2.7-2.10)"),
               object("damping", "damping", "damping of the reduced model")
                   .def({{"type", "modal"}, {"ratios", d.damping.ratios}}),
               object("law", "law",
                      "bit-rock interaction law (required, except with axial.type = rgd, whose bit law is axial.bit "
                      "unless axial.torque = law)"),
               object("operation", "operation", "operating point"),
               object("top_drive", "top_drive", "how the top is turned").def({{"type", "ideal"}}),
               object("axial", "axial",
                      "the weight on bit: an input, a state driven by the rig's jack, or the axial-torsional "
                      "string with the RGD bit")
                   .def({{"type", "none"}}),
               object("sensors", "sensors", "measurement chain of the recorded channels"),
               object("simulation", "simulation", "time integration (appendices A, B)"),
               object("metrics", "metrics", "stick and slip detection"),
               object("sweep", "sweep", "grid of the sweep job (drillsim --job sweep)"),
               object("craig_bampton", "craig_bampton", "Craig-Bampton substructuring (chapter 6)")}};

  t.string = {"string",
              "the drill string (Eqs. 2.1-2.6)",
              {objects("sections", "string.sections", "uniform sections from the top to the bit").req(),
               objects("lumped_inertias", "string.lumped_inertias", "rotary inertias added at nodes")
                   .def(json::array())}};

  t.sections = {
      "string.sections",
      "a uniform section: a hollow or solid circular shaft of linear torsion elements",
      {{text("name", "section name (default: section<index>)"), &Section::name},
       {number("length_m", "length [m]").positive().req(), &Section::length},
       {number("outer_radius_m", "outer radius [m]").positive().req(), &Section::outer_radius},
       {number("inner_radius_m", "inner radius [m], below outer_radius_m; 0: a solid bar").non_negative().def(0.0),
        &Section::inner_radius},
       {number("youngs_modulus_pa", "Young's modulus [Pa]").positive().req(), &Section::youngs_modulus},
       {number("poisson_ratio", "Poisson's ratio [-]").above(-1.0).below(0.5).req(), &Section::poisson_ratio},
       {number("density_kg_m3", "density [kg/m^3]").positive().req(), &Section::density},
       {integer("elements", "number of linear elements").at_least(1).req(), &Section::elements}}};

  t.lumped_inertias = {
      "string.lumped_inertias",
      "a rotary inertia added at a node",
      {{integer("node", "node index: 0 at the top, negative from the bit (-1: the bit)").def(-1), &LumpedInertia::node},
       {number("inertia_kg_m2", "rotary inertia [kg m^2]").positive().req(), &LumpedInertia::inertia}}};

  t.rom = {"rom",
           "reduced-order model",
           {{integer("modes", "retained modes, at most the number of elements (default: 20, or that number if smaller)")
                 .at_least(1),
             &Config::modes}}};

  t.damping = {
      "damping",
      "modal damping ratios, or Rayleigh damping D = a M + b K through two (frequency, ratio) pairs",
      {kind_key<DampingSpec>("damping model")},
      {{"modal",
        {{numbers("ratios", "damping ratio of modes 1, 2, ... (the last repeats), in [0, 1]")
              .non_negative()
              .at_most(1.0)
              .req(),
          &DampingSpec::ratios}}},
       {"rayleigh",
        {{rows("pairs", "[[f1_hz, ratio1], [f2_hz, ratio2]]", "the ratios at two distinct frequencies", 2,
               {number("frequency_hz", "frequency [Hz]").positive(),
                number("ratio", "damping ratio in [0, 1]").non_negative().at_most(1.0)})
              .req(),
          [](const DampingSpec& s) { return json{{s.f1, s.z1}, {s.f2, s.z2}}; },
          [](DampingSpec& s, const json& p) {
            s.f1 = p[0][0];
            s.z1 = p[0][1];
            s.f2 = p[1][0];
            s.z2 = p[1][1];
          }}}}}};

  {  // the bit-rock laws: common keys, then each law's parameters (laws/registry.hpp)
    using L = BitRockLaw;
    std::vector<Case<L>> variants;
    for (const Named<L::Kind>& k : L::kinds)
      L::visit(k.value, [&](auto law) { variants.push_back({k.name, decltype(law)::template keys<L>()}); });
    t.law = {
        "law",
        "torque on bit as a function of bit speed v, bit acceleration a and WOB; it scales linearly with the WOB",
        {kind_key<L>("law: Eq. (3.1), (3.2)-(3.3), (5.1) or (5.3)"),
         {text("speed_unit", "unit of v (and a per second) in the law's formulas", {"rad_s", "rad/s", "rpm", "RPM"})
              .req(),
          [](const L& l) { return to_string(l.speed_unit); },
          [](L& l, const std::string& v, const std::string& path) { l.speed_unit = parse_speed_unit(v, path); }},
         {number("wob_ref_n", "WOB at which the parameters hold [N]").positive().req(), &L::wob_ref},
         {number("static_ageing", "A: after tau s stuck the static torque is (1 + A tau / (tau + tau_a)) times the "
                                  "law's (ageing; Eqs. 5.1, 5.3 with a0 > 0, modified_euler; absent: none)")
              .non_negative(),
          &L::static_ageing},
         {number("static_ageing_s", "tau_a: the time stuck at which the static torque has grown by A / 2 [s] "
                                    "(with static_ageing)")
              .positive(),
          &L::static_ageing_s}},
        variants};
  }

  t.operation = {
      "operation",
      "operating point",
      {{number("top_speed_rad_s", "top-drive speed (commanded speed of a motor top drive) [rad/s]")
            .positive()
            .def(d.top_speed),
        &Config::top_speed},
       {number("wob_n", "weight on bit [N] (default: law.wob_ref_n)").non_negative(), &Config::wob},
       {number("bit_viscous_nms", "viscous torque c_v v on the bit [N m s/rad] (not in the thesis)")
            .non_negative()
            .def(d.bit_viscous),
        &Config::bit_viscous},
       {number("string_friction_nm", "Coulomb torque T_sf sign(v) of the string, lumped at the bit [N m] "
                                     "(not in the thesis)")
            .non_negative()
            .def(d.string_friction),
        &Config::string_friction}}};

  {
    using D = TopDrive;
    std::vector<Case<D>> variants;  // each drive's keys (drives/registry.hpp)
    for (const Named<D::Kind>& k : D::kinds)
      D::visit(k.value, [&](auto drive) { variants.push_back({k.name, decltype(drive)::template keys<D>()}); });
    t.top_drive = {"top_drive",
                   "ideal (the thesis: the top turns at top_speed_rad_s) or an open-loop motor commanded at it, "
                   "J_m Omega' = c_m (Omega_c - Omega) - T_top",
                   {kind_key<D>("top-drive model")},
                   variants};
  }

  {
    using C = Controller;
    std::vector<Case<C>> variants;  // each controller's keys (controllers/registry.hpp)
    for (const Named<C::Kind>& k : C::kinds)
      C::visit(k.value, [&](auto ctl) { variants.push_back({k.name, decltype(ctl)::template keys<C>()}); });
    t.controller = {
        "top_drive.controller",
        "speed controller of a controlled top drive, J Omega' = u - T_top, u = sat(kp e + ki int e), "
        "e = Omega_ref - Omega (cpp/include/drill/controller.hpp, docs/control.md)",
        {kind_key<C>("stiff (high-gain PI), pi (user gains), soft_speed (SoftSpeed: kp = Z, ki = J w_s^2) or "
                     "z_torque (ZTorque: set point corrected by -(T_top - T_mean) / Z)"),
         {number("torque_limit_nm", "motor torque limit |u| <= L [N m] (anti-windup); absent: no limit").positive(),
          &C::torque_limit},
         {number("sample_time_s", "sample time of the controller (zero-order hold) [s]; absent: continuous").positive(),
          [](const C& k) { return k.sampled() ? k.sample_time : NAN; },
          [](C& k, const double& v, const std::string& path) {
            require(v > 0.0, path, v, "must be positive (omit it for a continuous controller)");
            k.sample_time = v;
          }}},
        variants};
  }

  {
    using A = Axial;
    t.axial = {
        "axial",
        "none (the WOB is operation.wob_n), the rig's jack, W' = g (Omega_f - v) - (W - W_s) / tau (axial.hpp), or "
        "rgd: the string's axial modes with the Richard-Germay-Detournay bit (axial_torsional.hpp, docs/axial.md)",
        {kind_key<A>("axial model")},
        {{A::kind_name(A::Kind::none), {}},
         {A::kind_name(A::Kind::jack),
          {{number("gain_n_rad", "g = k_ax d / (2 pi): WOB per radian the bit lags its steady rotation [N/rad]")
                .non_negative()
                .req(),
            &A::gain},
           {number("relaxation_s", "tau: the jack's time constant [s]").positive().req(), &A::relaxation}}},
         {A::kind_name(A::Kind::rgd),
          {{text("top", "top boundary: hook_load (constant force operation.wob_n down at the top), feed (constant "
                        "rate of penetration rop_m_s) or jack (the rig's force-regulated feed: the top moves at "
                        "rop_m_s + jack_admittance_m_s_n (operation.wob_n - F_top), F_top the string's force on it)",
                 names_of(axial_top_names))
                .def(to_string(ad.top)),
            [](const A& a) { return to_string(a.rgd.top); },
            [](A& a, const std::string& v) { a.rgd.top = parse_axial_top(v); }},
           {number("rop_m_s", "V0: the top's constant feed rate with top = feed, the jack's free feed with top = "
                              "jack [m/s]")
                .positive(),
            [](auto& a) -> auto& { return a.rgd.feed_rate; }},
           {number("jack_admittance_m_s_n", "kappa: the jack's feed speed lost per N of the string's force on the top "
                                            "above operation.wob_n, with top = jack [m/s per N]")
                .positive(),
            [](auto& a) -> auto& { return a.rgd.jack_admittance; }},
           {integer("modes", "retained axial modes, at most the free axial DOFs").at_least(1).def(ad.modes),
            [](auto& a) -> auto& { return a.rgd.modes; }},
           {text("damping", "damping of the axial modes: modal (damping_ratio on every mode) or distributed "
                            "(D = 2 k M, the ratio damping_rate_per_s / omega_j on mode j, as the distributed "
                            "damping of Aarsnes and van de Wouw 2019; axial_string.hpp)",
                 names_of(axial_damping_names))
                .def(to_string(ad.damping)),
            [](const A& a) { return to_string(a.rgd.damping); },
            [](A& a, const std::string& v, const std::string& path) { a.rgd.damping = parse_axial_damping(v, path); }},
           // written only with damping = modal (a distributed string's JSON has no ratio: it is refused there)
           {number("damping_ratio", "modal damping ratio of every axial mode (damping = modal; refused with "
                                    "distributed)")
                .non_negative()
                .at_most(1.0)
                .def(ad.damping_ratio),
            [](const A& a) { return a.rgd.damping == AxialDamping::modal ? a.rgd.damping_ratio : NAN; },
            [](A& a, const double& v) { a.rgd.damping_ratio = v; }},
           {number("damping_rate_per_s", "k: the decay rate of every axial mode with damping = distributed (required "
                                         "there, refused with modal) [1/s]")
                .non_negative(),
            [](auto& a) -> auto& { return a.rgd.damping_rate; }},
           {number("bit_mass_kg", "axial mass lumped at the bit [kg]").non_negative().def(ad.bit_mass),
            [](auto& a) -> auto& { return a.rgd.bit_mass; }},
           {number("disturbance", "start: the bit's axial speed is (1 - disturbance) times the steady rate of "
                                  "penetration (0: steady drilling; above 1: moving up)")
                .at_least(-1000.0)
                .at_most(1000.0)
                .def(ad.disturbance),
            [](auto& a) -> auto& { return a.rgd.disturbance; }},
           {text("torque", "torque on bit: rgd (RGD's T_c + T_f, axial.bit) or law (the \"law\" block, Eqs. 3.1, "
                           "3.2-3.3, 5.1 or 5.3, at the bit speed and acceleration with the WOB the axial state W, "
                           "T scaling with W / law.wob_ref_n; the axial law stays axial.bit's)",
                 names_of(axial_torque_names))
                .def(to_string(ad.torque)),
            [](const A& a) { return to_string(a.rgd.torque); },
            [](A& a, const std::string& v, const std::string& path) { a.rgd.torque = parse_axial_torque(v, path); }},
           object("bit", "axial.bit", "the Richard-Germay-Detournay bit law (rgd_bit.hpp)").req()}}}};
  }

  t.bit = {"axial.bit",
           "the RGD bit: W_c = a zeta eps d, T_c = a^2 eps d / 2, W_f = a l sigma, T_f = gamma mu a W_f / 2, "
           "d = N [U(t) - U(t - t_N)]",
           {{number("radius_m", "a: bit radius [m]").positive().req(), &RgdBit::radius},
            {number("specific_energy_pa", "eps: intrinsic specific energy [Pa]").positive().req(),
             &RgdBit::specific_energy},
            {number("contact_strength_pa", "sigma: contact strength of the wear flats [Pa]").non_negative().req(),
             &RgdBit::contact_strength},
            {number("zeta", "zeta: normal over tangential cutting force [-]").positive().req(), &RgdBit::force_ratio},
            {number("wear_flat_m", "l: total wear-flat length [m]").non_negative().req(), &RgdBit::wear_flat},
            {number("gamma", "gamma: bit geometry factor [-]").non_negative().req(), &RgdBit::geometry},
            {number("mu", "mu: friction coefficient of the wear flats [-]").non_negative().req(), &RgdBit::friction},
            {integer("blades", "N: blades").at_least(1).at_most(64).req(), &RgdBit::blades}}};

  t.sensors = {"sensors",
               "measurement chain of the recorded channels",
               {{number("lowpass_hz", "cutoff of a second-order Butterworth low-pass [Hz]; 0: ideal sensors")
                     .non_negative()
                     .def(d.sensor_lowpass_hz),
                 &Config::sensor_lowpass_hz}}};

  t.simulation = {
      "simulation",
      "time integration",
      {{text("scheme", "integrator", names_of(scheme_names)).def(to_string(d.sim.scheme)),
        [](const Config& c) { return to_string(c.sim.scheme); },
        [](Config& c, const std::string& v) { c.sim.scheme = parse_scheme(v); }},
       {text("acceleration", "bit acceleration in Eq. (3.3); lagged: modified_euler only", names_of(acceleration_names))
            .def(to_string(d.sim.acceleration)),
        [](const Config& c) { return to_string(c.sim.acceleration); },
        [](Config& c, const std::string& v) { c.sim.acceleration = parse_acceleration(v); }},
       {number("dt_s", "time step [s]").positive().def(d.sim.dt), [](auto& c) -> auto& { return c.sim.dt; }},
       {number("duration_s", "simulated time [s], at least one step").positive().def(d.sim.duration),
        [](auto& c) -> auto& { return c.sim.duration; }},
       {number("transient_s", "time discarded before the metrics [s], below duration_s "
                              "(default: 100 or half the duration)")
            .non_negative(),
        &Config::transient},
       {integer("output_stride", "the series keeps every n-th step").at_least(1).def(d.output_stride),
        &Config::output_stride},
       {text("start", "initial state: rest (Eq. 2.10), rigid (Eq. 2.3) or steady (steady drilling, disturbed)",
             names_of(start_names))
            .def(to_string(d.start)),
        [](const Config& c) { return to_string(c.start); },
        [](Config& c, const std::string& v, const std::string& path) { c.start = parse_start(v, path); }}}};

  t.metrics = {"metrics",
               "stick and slip detection",
               {{number("stick_threshold_fraction",
                        "stick when the bit speed is at most this fraction of the top speed")
                     .above(0.0)
                     .below(1.0)
                     .def(d.metrics.stick_threshold_fraction),
                 &MetricsSpec::stick_threshold_fraction},
                {number("stick_debounce_s", "minimum duration of a phase change [s]")
                     .non_negative()
                     .def(d.metrics.stick_debounce_s),
                 &MetricsSpec::stick_debounce_s},
                {number("slip_level_fraction", "a slip exceeds this fraction of the top speed, else it is chatter")
                     .above(0.0)
                     .below(1.0)
                     .def(d.metrics.slip_level_fraction),
                 &MetricsSpec::slip_level_fraction}}};

  t.sweep = {"sweep",
             "grid of the sweep job",
             {{numbers("top_speeds_rad_s", "top speeds [rad/s]").positive().def(json::array()), &Config::sweep_speeds},
              {numbers("wobs_n", "weights on bit [N]; empty: operation.wob_n").non_negative().def(json::array()),
               &Config::sweep_wobs}}};

  t.craig_bampton = {"craig_bampton",
                     "Craig-Bampton substructuring",
                     {{integers("modes", "fixed-interface modes per substructure").at_least(1).def(json::array()),
                       &Config::cb_modes}}};
  return t;
}

inline const Tables& tables() {
  static const Tables all = make_tables();
  return all;
}

/// Every block of the configuration, the top level ("config") first.
inline const std::vector<Block>& blocks() {
  static const std::vector<Block> all = [] {
    const Tables& t = tables();
    return std::vector<Block>{t.config.block(),     t.string.block(),    t.sections.block(),
                              t.lumped_inertias.block(), t.rom.block(), t.damping.block(),
                              t.law.block(),        t.operation.block(), t.top_drive.block(),
                              t.controller.block(), t.axial.block(),     t.bit.block(),
                              t.sensors.block(),    t.simulation.block(), t.metrics.block(),
                              t.sweep.block(),      t.craig_bampton.block()};
  }();
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

/// A "law" block (also the Python binding's law_torque) into a law, unvalidated.
inline BitRockLaw parse_law(const json& j) {
  BitRockLaw l;
  schema::tables().law.read(j, "law", l);
  return l;
}

}  // namespace detail

/// Parse and validate a configuration: the blocks through their tables (schema::tables()), composed
/// here with the defaults and checks that relate blocks.
inline Config parse_config(const json& j) {
  const schema::Tables& t = schema::tables();
  Config c;
  t.config.read(j, "config", c);
  if (!j.contains("string")) throw std::invalid_argument("config.string: missing (required object)");
  const json& js = j.at("string");
  t.string.read(js, "string", c);
  if (!js.contains("sections") || !js.at("sections").is_array())
    throw std::invalid_argument("string.sections: missing or not an array");
  for (std::size_t k = 0; k < js.at("sections").size(); ++k) {
    Section sec;
    sec.name = "section" + std::to_string(k);
    t.sections.read(js.at("sections")[k], "string.sections[" + std::to_string(k) + "]", sec);
    c.string.sections.push_back(sec);
  }
  if (js.contains("lumped_inertias")) {
    const json& li = js.at("lumped_inertias");
    if (!li.is_array()) throw std::invalid_argument("string.lumped_inertias = " + li.dump() + ": must be an array");
    for (std::size_t k = 0; k < li.size(); ++k) {
      LumpedInertia l;
      t.lumped_inertias.read(li[k], "string.lumped_inertias[" + std::to_string(k) + "]", l);
      c.string.lumped.push_back(l);
    }
  }
  c.modes = std::min(20, c.string.n_elements());
  if (j.contains("rom")) t.rom.read(j.at("rom"), "rom", c);
  if (j.contains("damping")) t.damping.read(j.at("damping"), "damping", c.damping);
  // with the axial-torsional model the bit law is axial.bit (RGD): a "law" block would be ignored,
  // unless axial.torque = law takes the torque on bit from it (the axial law staying axial.bit's)
  const bool rgd = j.contains("axial") && j.at("axial").is_object() && j.at("axial").contains("type") &&
                   j.at("axial").at("type") == "rgd";
  const bool feed = rgd && j.at("axial").contains("top") && j.at("axial").at("top") == "feed";
  bool by_law = false;  // axial.torque = "law" (its value checked first: an unknown one is named as such)
  if (rgd && j.at("axial").contains("torque")) {
    const json& tq = j.at("axial").at("torque");
    if (!tq.is_string()) throw std::invalid_argument("axial.torque = " + tq.dump() + ": must be a string (rgd or law)");
    by_law = parse_axial_torque(tq.get<std::string>()) == AxialTorque::law;
  }
  if (rgd && !by_law) {
    if (j.contains("law"))
      throw std::invalid_argument("config.law = " + j.at("law").dump() +
                                  ": not used with axial.type = rgd (the bit law is axial.bit): remove it, or set "
                                  "axial.torque = \"law\" to drive the torque on bit by it");
  } else {
    if (!j.contains("law"))
      throw std::invalid_argument(by_law ? "axial.torque = \"law\": needs a \"law\" block (config.law missing): the "
                                           "thesis law whose torque the axial WOB drives"
                                         : "config.law: missing (required object)");
    c.law = detail::parse_law(j.at("law"));
  }
  if (rgd && !feed && !(j.contains("operation") && j.at("operation").contains("wob_n")))
    throw std::invalid_argument("operation.wob_n: missing (required with axial.type = rgd and top = hook_load or "
                                "jack: the net force down at the top, the WOB of steady drilling, or the jack's set "
                                "force)");
  if (feed && j.contains("operation") && j.at("operation").contains("wob_n"))
    throw std::invalid_argument("operation.wob_n = " + j.at("operation").at("wob_n").dump() +
                                ": not used with axial.top = feed (the WOB follows from axial.rop_m_s): remove it");
  c.wob = feed ? 0.0 : c.law.wob_ref;  // operation.wob_n's default (required with rgd's hook_load)
  if (j.contains("operation")) t.operation.read(j.at("operation"), "operation", c);
  if (j.contains("top_drive")) {
    const json& td = j.at("top_drive");
    t.top_drive.read(td, "top_drive", c.top_drive);
    if (c.top_drive.has_controller()) {
      if (!td.contains("controller")) throw std::invalid_argument("top_drive.controller: missing (required object)");
      const json& k = td.at("controller");
      const std::string w = "top_drive.controller";
      if (!k.is_object()) throw std::invalid_argument(w + " = " + k.dump() + ": must be a JSON object");
      t.controller.read(k, w, c.top_drive.controller);
    }
  }
  if (j.contains("axial")) {
    const json& a = j.at("axial");
    t.axial.read(a, "axial", c.axial);
    if (c.axial.coupled()) {
      AxialTorsionalSpec& x = c.axial.rgd;
      if (c.wob > 0.0) x.top_force = c.wob;
      if (moving_frame(x.top) && !a.contains("rop_m_s"))
        throw std::invalid_argument("axial.rop_m_s: missing (required number)");
      if (!moving_frame(x.top) && a.contains("rop_m_s"))
        throw std::invalid_argument("axial.rop_m_s = " + a.at("rop_m_s").dump() +
                                    ": only with axial.top = feed or jack (hook_load sets the WOB, operation.wob_n)");
      if (x.top == AxialTop::jack && !a.contains("jack_admittance_m_s_n"))
        throw std::invalid_argument("axial.jack_admittance_m_s_n: missing (required number with axial.top = jack)");
      if (x.damping == AxialDamping::distributed && a.contains("damping_ratio"))
        throw std::invalid_argument("axial.damping_ratio = " + a.at("damping_ratio").dump() +
                                    ": not used with axial.damping = distributed (the ratio on mode j is "
                                    "damping_rate_per_s / omega_j): remove it, or set axial.damping = \"modal\"");
      if (!a.contains("bit")) throw std::invalid_argument("axial.bit: missing (required object with axial.type = rgd)");
      t.bit.read(a.at("bit"), "axial.bit", x.bit);
    }
  }
  if (j.contains("sensors")) t.sensors.read(j.at("sensors"), "sensors", c);
  {  // an absent block takes the same defaults as an empty one
    const json s = j.contains("simulation") ? j.at("simulation") : json::object();
    t.simulation.read(s, "simulation", c);
    if (!s.contains("transient_s")) c.transient = std::min(c.transient, 0.5 * c.sim.duration);  // depends on duration_s
  }
  if (j.contains("metrics")) t.metrics.read(j.at("metrics"), "metrics", c.metrics);
  if (j.contains("sweep")) t.sweep.read(j.at("sweep"), "sweep", c);
  if (j.contains("craig_bampton")) t.craig_bampton.read(j.at("craig_bampton"), "craig_bampton", c);
  c.validate();
  return c;
}

/// Parse JSON text (parse_json_text) into a validated configuration.
inline Config parse_config_text(const std::string& text) { return parse_config(parse_json_text(text)); }

/// The configuration written back as JSON (all defaults made explicit), block by block through the
/// tables; optional blocks are written when they differ from their defaults.
inline json to_json(const Config& c) {
  const schema::Tables& t = schema::tables();
  json j = t.config.write(c);
  json sections = json::array(), lumped = json::array();
  for (const Section& s : c.string.sections) sections.push_back(t.sections.write(s));
  for (const LumpedInertia& l : c.string.lumped) lumped.push_back(t.lumped_inertias.write(l));
  j["string"] = {{"sections", sections}, {"lumped_inertias", lumped}};
  j["rom"] = t.rom.write(c);
  j["damping"] = t.damping.write(c.damping);
  j["operation"] = t.operation.write(c);
  j["simulation"] = t.simulation.write(c);
  j["metrics"] = t.metrics.write(c.metrics);
  if (!c.sweep_speeds.empty() || !c.sweep_wobs.empty()) j["sweep"] = t.sweep.write(c);
  if (!c.cb_modes.empty()) j["craig_bampton"] = t.craig_bampton.write(c);
  if (c.top_drive.kind != TopDrive{}.kind) {  // the default drive (ideal) is not written
    j["top_drive"] = t.top_drive.write(c.top_drive);
    if (c.top_drive.has_controller()) j["top_drive"]["controller"] = t.controller.write(c.top_drive.controller);
  }
  if (!c.axial.coupled() || c.axial.rgd.torque == AxialTorque::law) j["law"] = t.law.write(c.law);
  if (c.axial.kind != Axial::Kind::none) j["axial"] = t.axial.write(c.axial);
  if (c.axial.coupled()) {
    j["axial"]["bit"] = t.bit.write(c.axial.rgd.bit);
    if (c.axial.rgd.top == AxialTop::feed) j["operation"].erase("wob_n");  // the WOB follows from the feed
  }
  if (c.sensor_lowpass_hz > 0.0) j["sensors"] = t.sensors.write(c);
  return j;
}

}  // namespace drill
