// A configured simulation (Algorithm 2 of appendix B): the reduced-order model of a Config, its
// integrator, single runs with their metrics, and parallel SS sweeps over top speed and WOB.
#pragma once

#include <algorithm>
#include <climits>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "drill/axial_torsional.hpp"
#include "drill/batched_integrator.hpp"
#include "drill/config.hpp"
#include "drill/integrator.hpp"
#include "drill/metrics.hpp"
#include "drill/modal.hpp"
#include "drill/parallel.hpp"

namespace drill {

/// The axial channels and metrics of a run of the axial-torsional model (axial.type = rgd): the
/// series every output_stride-th step, the metrics over t >= transient. Empty without it.
struct AxialReport {
  std::vector<double> t, wob, rop, position, depth_of_cut, delay;  ///< [s], [N], [m/s], [m], [m], [s]
  double mean_wob = NAN, wob_std = NAN;  ///< WOB mean and standard deviation [N]
  double mean_rop = NAN, rop_std = NAN;  ///< the bit's axial speed: mean and standard deviation [m/s]
  double bounce_fraction = NAN;          ///< fraction of the window with the bit off the rock (W = 0)
  double mean_depth_of_cut = NAN;        ///< [m] per revolution
  /// Mechanical specific energy (Teale 1965): the work the bit does on the rock (torque x bit speed
  /// plus WOB x axial speed, integrated) per volume removed (bit face pi a^2 x advance) [Pa]; NaN
  /// when the bit does not advance. At steady drilling it is Teale's W / A + T Omega / (A V).
  double mse = NAN;
  double steady_wob = NAN, steady_rop = NAN, steady_depth = NAN, steady_torque = NAN;  ///< RGD steady drilling
  double steady_mse = NAN;  ///< MSE of steady drilling [Pa]
  /// The speed of steady drilling under the top drive [rad/s]: the command, or a drooping drive's
  /// speed (AxialTorsional::steady_speed); NaN where the drive cannot carry steady drilling (it stalls:
  /// the run starts from the command's steady drilling, whose values the steady_* fields then hold).
  double steady_speed = NAN;
  bool present() const { return std::isfinite(steady_wob); }
};

/// Everything a single run reports.
struct RunReport {
  Recorder series;
  double severity = 0.0;        ///< SS over t >= transient (Eq. 3.4)
  double mean_top_speed = 0.0;  ///< [rad/s] over the same window
  double stick_fraction = 0.0;  ///< fraction of the window spent in stick
  std::vector<double> stick, slip;
  bool slip_first = false;
  Periodicity periodic;
  ModelState final_state;
  AxialReport axial;  ///< axial channels (axial.type = rgd only)
};

// StartMode and parse_start: config.hpp (simulation.start).

/// Called by Simulation::run about a thousand times per run with the simulated time and the duration [s].
using RunProgressFn = std::function<void(double t, double duration)>;

class Simulation {
 public:
  explicit Simulation(Config cfg)
      : cfg_(validated(std::move(cfg))),
        rom_(build_modal_rom(cfg_.string, cfg_.modes, cfg_.damping)),
        integ_(rom_.model, torsional_law(cfg_), cfg_.sim) {
    if (cfg_.axial.coupled()) coupled_.emplace(rom_.model, cfg_.string, cfg_.axial.rgd, cfg_.sim, cfg_.law);
    // a controlled top drive is tuned from the top section's characteristic impedance and the
    // first natural frequency of the reduced model (string clamped at the top): controller.hpp
    if (cfg_.top_drive.has_controller()) cfg_.top_drive.tune_controller(top_impedance(), rom_.omega(0));
  }

  /// The characteristic torsional impedance of the top section, Z = J_p sqrt(G rho) [N m s/rad].
  double top_impedance() const { return drill::top_impedance(cfg_.string); }

  const Config& config() const { return cfg_; }
  const ModalROM& rom() const { return rom_; }
  const Integrator& integrator() const { return integ_; }
  /// The axial-torsional model (axial.type = rgd), or nullptr.
  const AxialTorsional* coupled() const { return coupled_ ? &*coupled_ : nullptr; }

  /// Refuse the axial-torsional model in a study that only the torsional engine implements.
  void require_torsional(const std::string& what) const {
    require(!cfg_.axial.coupled(), "axial.type", Axial::kind_name(cfg_.axial.kind),
            "is implemented for single runs (drillpy simulate, drillsim --job run); " + what + " is not");
  }

  /// Inputs at constant top speed and WOB (the configured operation point by default).
  Inputs inputs(double top_speed, double wob) const {
    Inputs in;
    in.top_speed = Signal::constant(top_speed);
    in.wob = Signal::constant(wob);
    in.bit_viscous = cfg_.bit_viscous;
    in.string_friction = cfg_.string_friction;
    in.top_drive = cfg_.top_drive;
    in.axial = cfg_.axial;
    if (in.axial.active()) in.axial.feed_speed = steady_speed(top_speed, wob);
    return in;
  }
  Inputs inputs() const { return inputs(cfg_.top_speed, cfg_.wob); }

  /// Steady drilling at a constant top speed, disturbed: the static twist that carries the torque
  /// on bit, K~ q = -bit^T T(Omega, 0, W) (Eq. 2.9 at equilibrium), and a relative velocity that
  /// is `disturbance` times the one of Eq. (2.10) (the string lagging the top by that fraction of
  /// Omega). An unstable equilibrium needs the disturbance to leave it. Starting here instead of
  /// from Eq. (2.10) probes the other side of the bistable band (docs/validation.md).
  /// With a motor top drive the string turns at the speed where the motor's torque carries the
  /// torque on bit, Omega = Omega_c - T(Omega) / c_m (bisection on [0, Omega_c]; 0 if it stalls).
  /// With a controlled drive (controller.hpp) with integral action the top turns at the command and
  /// the PI's integral carries the torque (T_I = T_mean = the twist's top torque): zero steady speed error.
  /// The twist and the motor carry the total torque at the bit, c_v Omega and the string friction
  /// T_sf sign(Omega) of `operation.string_friction_nm` included.
  ModelState steady_state(double top_speed, double wob, double disturbance = 0.01) const {
    // axial.type = rgd: its steady torque, at the drive's steady speed (a motor's or a P controller's droop)
    if (coupled_) return coupled_->steady_start(cfg_.top_drive, top_speed, disturbance);
    const ReducedModel& r = rom_.model;
    const double om = steady_speed(top_speed, wob);
    ModelState s{r.K.ldlt().solve(-steady_torque(om, wob) * r.bit.transpose()), -disturbance * om * r.init_velocity};
    const TopDrive& td = cfg_.top_drive;
    if (td.has_inertia()) s.top_speed = om;
    // the integral carries the reduced model's top torque of this twist (T(Omega) to the modal
    // truncation of the static twist), so that the drive starts in equilibrium
    if (td.has_controller()) s.drive_integral = s.drive_mean = td.controller.ki > 0.0 ? integ_.top_torque(s) : 0.0;
    return s;
  }

  /// The total torque at the bit in steady drilling at bit speed om [rad/s] and WOB [N]: the law at
  /// zero acceleration, c_v om and the string friction.
  double steady_torque(double om, double wob) const {
    const double sf = cfg_.string_friction;
    const double T = cfg_.law.torque(om, 0.0, wob) + cfg_.bit_viscous * om;
    return sf > 0.0 ? T + sf * ((om > 0.0) - (om < 0.0)) : T;
  }

  /// The speed of steady drilling at a top-speed command [rad/s] and WOB [N]: the command with an
  /// ideal drive or a controller with integral action; with a motor (or a P-only controller) the
  /// speed where the drive's torque carries the torque on bit, Omega = Omega_c - T(Omega) / c_m
  /// (bisection on [0, Omega_c]; 0 if it stalls).
  double steady_speed(double top_speed, double wob) const {
    auto torque = [&](double om) { return steady_torque(om, wob); };
    double om = top_speed;
    const TopDrive& td = cfg_.top_drive;
    // the speed depends on the torque (TopDrive::droops: a motor, a P-only controller), or it is the
    // command (the ideal drive, a controller with integral action)
    if (td.droops() && top_speed > 0.0) {
      double lo = 0.0, hi = top_speed;  // g(om) = om - Omega_c + T(om) / c_m is negative at 0 unless stalled
      auto g = [&](double x) { return x - cfg_.top_drive.steady_speed(top_speed, torque(x)); };
      if (g(lo) >= 0.0) hi = lo;
      for (int it = 0; it < 200 && hi - lo > 1e-12 * top_speed; ++it) (g(0.5 * (lo + hi)) < 0.0 ? lo : hi) = 0.5 * (lo + hi);
      om = 0.5 * (lo + hi);
    }
    return om;
  }

  /// Inputs with the axial jack's feed speed set (axial.hpp): the steady drilling speed at the mean
  /// command and the mean set force of the inputs, unless already set (inputs() sets it for its
  /// constant operating point; a caller that changes the inputs' speed or WOB resets it to NaN).
  /// Unchanged without the jack.
  Inputs axial_feed(Inputs in) const {
    if (!in.axial.active() || std::isfinite(in.axial.feed_speed)) return in;
    auto avg = [](const Signal& s) { return s.is_constant() ? s.value : mean(s.samples); };
    in.axial.feed_speed = steady_speed(avg(in.top_speed), avg(in.wob));
    return in;
  }

  /// The initial state of a run at this top speed and WOB (nothing for `rest`: the integrator's Eq. 2.10).
  std::optional<ModelState> start_state(StartMode mode, double top_speed, double wob) const {
    if (mode == StartMode::steady) return steady_state(top_speed, wob);
    if (mode == StartMode::rigid) {
      const int m = rom_.model.size();
      return ModelState{Eigen::VectorXd::Zero(m), Eigen::VectorXd::Zero(m)};
    }
    return std::nullopt;
  }

  /// The configured start (simulation.start) of a run with these inputs: the state at their
  /// initial top speed and WOB (their first samples when sampled); nothing for `rest`.
  std::optional<ModelState> start_state(const Inputs& in) const {
    auto first = [](const Signal& s) { return s.is_constant() ? s.value : s.samples.front(); };
    return start_state(cfg_.start, first(in.top_speed), first(in.wob));
  }

  /// One run with metrics; `record` keeps every output_stride-th step of the series. Without an
  /// explicit `start` the run starts as simulation.start says. `progress` is told how far the run
  /// is (the steps between its calls cost one integer comparison each).
  RunReport run(const Inputs& inputs_, bool record = true, const ModelState* start = nullptr,
                const RunProgressFn& progress = nullptr) const {
    if (coupled_) return run_coupled(inputs_, record, start, progress);
    const Inputs in = axial_feed(inputs_);
    std::optional<ModelState> s0;
    if (!start) {
      s0 = start_state(in);
      if (s0) start = &*s0;
    }
    RunObserver obs(cfg_, in, record);
    const long every = std::max(1L, cfg_.sim.steps() / 1000);
    long next_report = progress ? 0 : LONG_MAX;
    ModelState last = integ_.run(
        in,
        [&](const StepState& s) {
          obs(s);
          if (s.step >= next_report) {
            progress(s.t, cfg_.sim.duration);
            next_report += every;
          }
        },
        start);
    return obs.report(std::move(last));
  }

  /// The torsional start of a run of the coupled model `m` at top-speed command om0: steady drilling
  /// (disturbed) at the drive's steady speed (AxialTorsional::steady_start: a drive's droop), or
  /// `start`'s state (rest: Eq. 2.10); the axial state is always steady drilling's.
  ModelState coupled_start(const AxialTorsional& m, double om0, StartMode start) const {
    std::optional<ModelState> s0;
    if (start == StartMode::steady) s0 = m.steady_start(cfg_.top_drive, om0);
    else s0 = start_state(start, om0, 0.0);
    if (!s0) s0 = integ_.initial_state(om0);  // rest: Eq. (2.10)
    return *s0;
  }

  /// One run through the model's own integrator, obs(const StepState&) at every step: the torsional
  /// Integrator, or with axial.type = rgd the axial-torsional model (`start` null: simulation.start).
  /// The Monte Carlo runs go through it.
  template <class Observer>
  void run_observed(const Inputs& in, Observer&& obs, const ModelState* start) const {
    if (!coupled_) {
      integ_.run(in, obs, start);
      return;
    }
    const ModelState s0 = start ? *start : coupled_start(*coupled_, in.top_speed.at(0.0), cfg_.start);
    coupled_->run(in, [&](const StepState& s, const AxialStep&) { obs(s); }, &s0);
  }

  /// SS of the axial-torsional model on a grid (sweep_severity with axial.type = rgd): result[w *
  /// speeds.size() + s]. With top = hook_load a WOB of `wobs` is the net force at the top, the WOB of
  /// steady drilling (operation.wob_n), with top = jack the jack's set force, one coupled model per
  /// WOB; with top = feed the WOB is the bit's
  /// response, not an input, and `wobs` must be empty. Each run starts as run_coupled starts it, from
  /// `start` (other than steady: the torsional state only). The speeds of one WOB in batches of
  /// BatchedIntegrator::width() runs stepped together (AxialTorsional::run_lanes; `batched` false:
  /// one run per task), the batches in parallel; a run's SS is the same either way.
  std::vector<double> sweep_coupled(const std::vector<double>& speeds, const std::vector<double>& wobs,
                                    const ProgressFn& progress, int threads, StartMode start, bool batched) const {
    const AxialTorsionalSpec& base = cfg_.axial.rgd;
    require(wobs.empty() || base.top != AxialTop::feed, "sweep.wobs_n", wobs.size(),
            "values given, but with axial.top = feed the WOB is the bit's response, not an input (sweep "
            "axial.rop_m_s in separate runs, or use axial.top = hook_load or jack)");
    std::vector<AxialTorsional> models;
    if (wobs.empty()) {
      models.push_back(*coupled_);
    } else {
      for (double wi : wobs) {
        AxialTorsionalSpec spec = base;
        spec.top_force = wi;
        models.emplace_back(rom_.model, cfg_.string, spec, cfg_.sim, cfg_.law);
      }
    }
    const double w0 = cfg_.wob;
    const std::size_t ns = speeds.size(), width = batched ? BatchedIntegrator::width() : 1,
                      nb = (ns + width - 1) / width;
    std::vector<double> out(ns * models.size());
    ProgressFn tasks;
    if (progress) tasks = [&](std::size_t done, std::size_t) { return progress(std::min(out.size(), done * width), out.size()); };
    const bool done = parallel_for(
        nb * models.size(),
        [&](std::size_t task) {
          const std::size_t iw = task / nb, s0 = task % nb * width, n = std::min(width, ns - s0);
          std::vector<Inputs> in;
          std::vector<ModelState> st;
          for (std::size_t k = 0; k < n; ++k) {
            in.push_back(inputs(speeds[s0 + k], wobs.empty() ? w0 : wobs[iw]));
            st.push_back(coupled_start(models[iw], in.back().top_speed.value, start));
          }
          std::vector<const ModelState*> stp;
          for (const ModelState& x : st) stp.push_back(&x);
          std::vector<TorsionOnly<SeverityObserver>> sev(n, TorsionOnly<SeverityObserver>{SeverityObserver(cfg_.transient)});
          std::vector<CoupledState> last(n);
          models[iw].run_lanes(in.data(), stp.data(), n, sev.data(), last.data());
          for (std::size_t k = 0; k < n; ++k) out[iw * ns + s0 + k] = sev[k].obs.severity();
        },
        tasks, threads);
    if (!done) out.clear();
    return out;
  }

  /// A coupled run's observer that sees the torsional StepState only (the Monte Carlo's and the
  /// sweep's SeverityObserver).
  template <class Obs>
  struct TorsionOnly {
    Obs obs;
    void operator()(const StepState& s, const AxialStep&) { obs(s); }
  };

  /// A run of the axial-torsional model (axial_torsional.hpp): the torsional metrics as run() and the
  /// axial channels. Starts in steady drilling (disturbed) unless `start` or simulation.start say
  /// otherwise (rest, rigid: the torsional state only; the axial state and the rock surface are
  /// always steady drilling's).
  RunReport run_coupled(const Inputs& in, bool record, const ModelState* start, const RunProgressFn& progress) const {
    return run_coupled(*coupled_, in, record, start, progress);
  }
  /// run_coupled on the coupled model `m` (one of sweep_coupled's WOBs).
  RunReport run_coupled(const AxialTorsional& m, const Inputs& in, bool record, const ModelState* start,
                        const RunProgressFn& progress) const {
    const double om0 = in.top_speed.at(0.0);
    require_positive(om0, "operation.top_speed_rad_s");
    std::optional<ModelState> s0;
    if (!start) {
      s0 = coupled_start(m, om0, cfg_.start);
      start = &*s0;
    }
    RunObserver obs(cfg_, in, record);
    AxialReport ax;
    ax.steady_speed = m.steady_speed(in.top_drive, om0);  // the command, a drive's drooped speed, or NaN (stall)
    const double om_s = m.start_speed(in.top_drive, om0);
    const AxialTorsional::Steady st = m.steady(om_s);
    ax.steady_wob = st.wob;
    ax.steady_rop = st.rop;
    ax.steady_depth = st.depth;
    ax.steady_torque = st.torque;
    const double face = M_PI * cfg_.axial.rgd.bit.radius * cfg_.axial.rgd.bit.radius;  // A = pi a^2
    ax.steady_mse = (st.torque * om_s + st.wob * st.rop) / (face * st.rop);
    const long stride = std::max(1L, cfg_.output_stride);
    const long every = std::max(1L, cfg_.sim.steps() / 1000);
    long next_report = progress ? 0 : LONG_MAX, count = 0, off = 0;
    double sw = 0.0, sw2 = 0.0, sv = 0.0, sv2 = 0.0, sd = 0.0, work = 0.0;
    long step = 0;
    const CoupledState last = m.run(
        in,
        [&](const StepState& s, const AxialStep& a) {
          obs(s);
          step = s.step;
          if (record && s.step % stride == 0) {
            ax.t.push_back(a.t);
            ax.wob.push_back(a.wob);
            ax.rop.push_back(a.rop);
            ax.position.push_back(a.position);
            ax.depth_of_cut.push_back(a.depth);
            ax.delay.push_back(a.delay);
          }
          if (a.t >= cfg_.transient) {
            ++count;
            off += a.contact ? 0 : 1;
            sw += a.wob;
            sw2 += a.wob * a.wob;
            sv += a.rop;
            sv2 += a.rop * a.rop;
            sd += a.depth;
            work += s.torque_on_bit * s.bit_speed + a.wob * a.rop;  // power at the bit [W]
          }
          if (s.step >= next_report) {
            progress(s.t, cfg_.sim.duration);
            next_report += every;
          }
        },
        start);
    if (count > 0) {
      const double n = static_cast<double>(count);
      ax.mean_wob = sw / n;
      ax.wob_std = std::sqrt(std::max(0.0, sw2 / n - ax.mean_wob * ax.mean_wob));
      ax.mean_rop = sv / n;
      ax.rop_std = std::sqrt(std::max(0.0, sv2 / n - ax.mean_rop * ax.mean_rop));
      ax.bounce_fraction = off / n;
      ax.mean_depth_of_cut = sd / n;
      if (sv > 0.0) ax.mse = work / (face * sv);  // (sum of power dt) / (A x sum of V dt)
    }
    RunReport r = obs.report(last.torsion);
    r.axial = std::move(ax);
    return r;
  }

  /// The observers of one run with metrics (run, run_many): the series every output_stride-th
  /// step when `record`, SS (Eq. 3.4) and the stick and slip phases after the transient.
  class RunObserver {
   public:
    RunObserver(const Config& cfg, const Inputs& in, bool record)
        : record_(record), sev_(cfg.transient), ph_(phases(cfg, in)) {
      r_.series = Recorder(record ? cfg.output_stride : 0, record ? cfg.sim.steps() : 0);
    }
    void operator()(const StepState& s) {
      sev_(s);
      ph_(s);
      if (record_) r_.series(s);
    }
    /// The report of the observed run, which ended in `final_state`.
    RunReport report(ModelState final_state) {
      r_.severity = sev_.severity();
      r_.mean_top_speed = sev_.mean_top_speed();
      r_.stick_fraction = ph_.stick_fraction();
      r_.stick = ph_.stick;
      r_.slip = ph_.slip;
      r_.slip_first = ph_.slip_first;
      r_.periodic = detect_periodicity(ph_);
      r_.final_state = std::move(final_state);
      return std::move(r_);
    }

   private:
    static PhaseObserver phases(const Config& cfg, const Inputs& in) {
      const double omega_ref = std::fabs(in.top_speed.is_constant() ? in.top_speed.value : mean(in.top_speed.samples));
      return PhaseObserver(cfg.transient, cfg.metrics.stick_threshold_fraction * omega_ref,
                           cfg.metrics.stick_debounce_s, cfg.metrics.slip_level_fraction * omega_ref);
    }
    bool record_;
    RunReport r_;
    SeverityObserver sev_;
    PhaseObserver ph_;
  };

  /// SS on a grid: result[w * speeds.size() + s] for wobs[w], speeds[s]. An empty `wobs` means
  /// the configured WOB. Returns an empty vector if cancelled.
  /// Every run starts as `start` says (default: simulation.start of the configuration).
  /// `batched`: the runs go through BatchedIntegrator in SIMD lockstep when it supports them (an
  /// ideal top drive, modified Euler: batched_integrator.hpp), else one by one through Integrator,
  /// the reference (false: always); with axial.type = rgd, sweep_coupled (the same SS either way).
  std::vector<double> sweep_severity(const std::vector<double>& speeds, const std::vector<double>& wobs,
                                     const ProgressFn& progress = nullptr, int threads = 0,
                                     std::optional<StartMode> start_mode = std::nullopt, bool batched = true) const {
    const StartMode start = start_mode.value_or(cfg_.start);
    require(!speeds.empty(), "sweep.top_speeds_rad_s", speeds.size(), "is empty");
    const std::vector<double> w = wobs.empty() ? std::vector<double>{cfg_.wob} : wobs;
    for (std::size_t k = 0; k < speeds.size(); ++k) {
      require_finite(speeds[k], "sweep.top_speeds_rad_s[" + std::to_string(k) + "]");
      require(speeds[k] > 0.0, "sweep.top_speeds_rad_s[" + std::to_string(k) + "]", speeds[k], "must be positive");
    }
    for (std::size_t k = 0; k < w.size(); ++k) require_non_negative(w[k], "sweep.wobs_n[" + std::to_string(k) + "]");
    if (coupled_) return sweep_coupled(speeds, wobs.empty() ? std::vector<double>{} : w, progress, threads, start, batched);
    std::vector<double> out(speeds.size() * w.size());
    const BatchedIntegrator lockstep(integ_);
    if (batched && lockstep.supports(inputs(speeds[0], w[0]))) {
      const bool done = parallel_batches(
          out.size(),
          [&](std::size_t first, std::size_t count) {
            std::vector<Inputs> in;
            std::vector<std::optional<ModelState>> s0;
            for (std::size_t i = first; i < first + count; ++i) {
              in.push_back(inputs(speeds[i % speeds.size()], w[i / speeds.size()]));
              s0.push_back(start_state(start, in.back().top_speed.value, in.back().wob.value));
            }
            std::vector<const ModelState*> s0p;
            for (const auto& s : s0) s0p.push_back(s ? &*s : nullptr);
            std::vector<SeverityObserver> sev(count, SeverityObserver(cfg_.transient));
            lockstep.run(in.data(), s0p.data(), count, sev.data());
            for (std::size_t k = 0; k < count; ++k) out[first + k] = sev[k].severity();
          },
          progress, threads);
      if (!done) out.clear();
      return out;
    }
    const bool done = parallel_for(
        out.size(),
        [&](std::size_t i) {
          const Inputs in = inputs(speeds[i % speeds.size()], w[i / speeds.size()]);
          SeverityObserver sev(cfg_.transient);
          const std::optional<ModelState> s0 = start_state(start, in.top_speed.value, in.wob.value);
          integ_.run(in, sev, s0 ? &*s0 : nullptr);
          out[i] = sev.severity();
        },
        progress, threads);
    if (!done) out.clear();
    return out;
  }

 private:
  /// The law of the torsional integrator: the configuration's; with axial.type = rgd, whose bit law is
  /// axial.bit (or, with axial.torque = law, the configuration's law driven by the coupled model's WOB,
  /// which the coupled model evaluates itself), a zero law (Tucker-Wang with c0 = 0) that nothing evaluates (Integrator::run refuses
  /// the coupled inputs; run() takes the coupled path).
  static BitRockLaw torsional_law(const Config& c) {
    if (!c.axial.coupled()) return c.law;
    BitRockLaw zero;
    zero.kind = BitRockLaw::Kind::tucker_wang;
    return zero;
  }
    static Config validated(Config c) {
    c.validate();
    return c;
  }
  static double mean(const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / v.size();
  }

  Config cfg_;
  ModalROM rom_;
  Integrator integ_;
  std::optional<AxialTorsional> coupled_;  ///< axial.type = rgd
};

}  // namespace drill
