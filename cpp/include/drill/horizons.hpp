// Short-horizon predictions of a configured model restarted from measured states.
//
// The dynamic residual of a model against a record (drillpy loop) compares the measured bit speed
// and torque on bit with the model's prediction over short horizons: at each restart time the
// model is put in the state that reproduces the measured bit speed, bit acceleration, torque on
// bit and top speed (Integrator::state_from_bit, exact for one retained mode), then integrated over
// the horizon driven by the boundary inputs on the record's grid (top speed or the motor's
// command, WOB, torque fluctuation eta of Eq. 4.1). Restarting keeps chaos and phase drift from
// dominating the comparison. The outputs pass through the sensors' low-pass filter of the
// configuration (sensor.hpp), started from the measured filtered values and rates, so that they
// are comparable with the recorded channels.
//
// The torque reported is the contact torque T_law (1 + eta) that a load cell under the rock
// holder measures; the extra viscous torque c_v v of `operation.bit_viscous_nms` and the string
// friction T_sf sign(v) of `operation.string_friction_nm` (extensions, not in the thesis) act on the
// bit but are not part of it. The restart state carries the total torque T + c_v v + T_sf sign(v),
// with sign(0) = 0 (a measured bit at rest: the set-valued string friction is taken as zero).
// Horizons are independent and run in parallel, each writing its own rows; with an ideal top drive
// they run in SIMD lockstep unless `batched` is false (batched_integrator.hpp; a horizon's numbers
// do not depend on which horizons share its batch).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <utility>
#include <vector>

#include "drill/batched_integrator.hpp"
#include "drill/errors.hpp"
#include "drill/integrator.hpp"
#include "drill/parallel.hpp"
#include "drill/sensor.hpp"
#include "drill/simulation.hpp"

namespace drill {

/// Where a horizon starts and the measured state it starts from. With a motor top drive a
/// non-finite top_accel means: the one the motor equation gives for this state.
struct HorizonStart {
  long index = 0;  ///< sample of the input grid at which the horizon starts
  // state of the model (sensor effects already removed), SI
  double bit_speed = 0.0, bit_accel = 0.0, torque = 0.0, top_speed = 0.0, top_accel = 0.0;
  // recorded (filtered) channels and their rates: the initial states of the sensor filters
  double y_bit_speed = 0.0, dy_bit_speed = 0.0, y_torque = 0.0, dy_torque = 0.0, y_top_speed = 0.0,
         dy_top_speed = 0.0;
  /// the WOB state [N] of an axial jack (drill/axial.hpp), the recorded WOB at the restart; NaN:
  /// the set force at the horizon's start (without an axial model it is not read)
  double wob = NAN;
  /// the recorded (filtered) WOB's rate at the restart [N/s]: with `wob`, the WOB sensor filter's state
  double dy_wob = 0.0;
};

/// Inputs shared by all horizons, sampled on the record's grid (empty vectors: the configuration's
/// constant operation point). With an ideal top drive `top_speed` is the top's speed; with a motor
/// it is the motor's command.
struct HorizonInputs {
  double dt = 1e-3;               ///< sampling interval of the inputs and of the outputs [s]
  int samples = 1;                ///< output samples per horizon (horizon = samples dt)
  std::vector<double> top_speed;  ///< [rad/s]
  std::vector<double> wob;        ///< [N]
  Eigen::MatrixXd eta;            ///< horizons x (samples + 1): eta at 0, dt, ..., samples dt (empty: 0)
};

/// Outputs after the sensors: row h, column j is the value at (j + 1) dt after the start of horizon h.
/// `wob` is the WOB the law saw (the axial jack's state, or the input) after the same sensors, its
/// filter started from the recorded WOB at the restart and its rate (the input where it is NaN).
struct HorizonResult {
  Eigen::MatrixXd bit_speed, torque, top_speed, wob;
};

/// The sensors of one horizon: observes its run and writes its row of the result.
struct HorizonSensors {
  const HorizonStart* st;
  double bit_viscous;
  long stride;
  Eigen::Index row;
  HorizonResult* r;
  LowPass2 fv, ft, fo, fw;

  void operator()(const StepState& s) {
    // (the integrator's torque on bit already leaves the string friction out)
    const double contact = s.torque_on_bit - bit_viscous * s.bit_speed;
    if (s.step == 0) {
      fv.reset(st->y_bit_speed, st->dy_bit_speed, s.bit_speed);
      ft.reset(st->y_torque, st->dy_torque, contact);
      fo.reset(st->y_top_speed, st->dy_top_speed, s.top_speed);
      fw.reset(std::isfinite(st->wob) ? st->wob : s.wob, std::isfinite(st->wob) ? st->dy_wob : 0.0, s.wob);
      next = stride;
      out = 0;
      return;
    }
    const double yv = fv.step(s.bit_speed), yt = ft.step(contact), yo = fo.step(s.top_speed), yw = fw.step(s.wob);
    if (s.step == next) {  // every stride-th step (a counter: no division per step)
      r->bit_speed(row, out) = yv;
      r->torque(row, out) = yt;
      r->top_speed(row, out) = yo;
      r->wob(row, out) = yw;
      ++out;
      next += stride;
    }
  }
  long next = 0;         ///< the step of the next output (set at step 0: stride)
  Eigen::Index out = 0;  ///< its column
};

/// One predict_horizons call, validated and set up: its integrator and result rows. Its work
/// splits into units (one SIMD batch of horizons, or one horizon on the scalar reference path),
/// each writing its own rows, which run in any order on any thread: predict_horizons runs the
/// units of one call, predict_horizons_many those of several calls in one parallel region (the
/// Jacobian of the loop's calibration: one call per perturbed model). A unit's numbers depend on
/// its horizons alone (batched_integrator.hpp: a run's bits do not depend on its batch). Neither
/// copyable nor movable: the batched integrator and the sensors point into it.
class HorizonRun {
 public:
  /// `batched`: through BatchedIntegrator where it supports the configuration (false: Integrator,
  /// the reference, one horizon at a time). Throws like predict_horizons on invalid inputs.
  HorizonRun(const Simulation& sim, const std::vector<HorizonStart>& starts, const HorizonInputs& hin, bool batched)
      : sim_(sim), starts_(starts), hin_(hin), c_(sim.config()), stride_(checked_stride(c_, hin)),
        integ_(sim.rom().model, c_.law, options(c_, hin)), lockstep_(integ_) {
    const std::size_t n = starts.size();
    const long need = static_cast<long>(hin.samples) + 1;
    auto check_series = [&](const std::vector<double>& s, const char* field) {
      if (s.empty()) return;
      for (std::size_t k = 0; k < s.size(); ++k)  // (the field's name built for a failure only)
        if (!std::isfinite(s[k])) require_finite(s[k], std::string(field) + "[" + std::to_string(k) + "]");
      for (std::size_t h = 0; h < n; ++h)
        require(starts[h].index >= 0 && starts[h].index + need <= static_cast<long>(s.size()),
                "horizons.start_index[" + std::to_string(h) + "]", starts[h].index,
                std::string("leaves the ") + field + " series (" + show(s.size()) + " samples)");
    };
    check_series(hin.top_speed, "top_speed");
    check_series(hin.wob, "wob");
    if (hin.eta.size() > 0) {
      require(hin.eta.rows() == static_cast<Eigen::Index>(n) && hin.eta.cols() == need, "horizons.eta rows x cols",
              show(hin.eta.rows()) + " x " + show(hin.eta.cols()),
              "must be horizons x (samples + 1) = " + show(n) + " x " + show(need));
      require(hin.eta.allFinite(), "horizons.eta", "non-finite", "must be finite");
    }
    result.bit_speed.resize(n, hin.samples);
    result.torque.resize(n, hin.samples);
    result.top_speed.resize(n, hin.samples);
    result.wob.resize(n, hin.samples);
    lanes_ = batched && lockstep_.supports(sim.inputs()) ? BatchedIntegrator::width() : 0;
  }
  HorizonRun(const HorizonRun&) = delete;
  HorizonRun& operator=(const HorizonRun&) = delete;

  /// Units of work: SIMD batches of BatchedIntegrator::width() horizons, or single horizons.
  std::size_t units() const {
    const std::size_t n = starts_.size();
    return lanes_ ? (n + lanes_ - 1) / lanes_ : n;
  }
  /// Horizons done once units 0 .. k - 1 are (for the progress callback).
  std::size_t horizons_done(std::size_t k) const { return lanes_ ? std::min(starts_.size(), k * lanes_) : k; }

  /// Run unit k (writes its horizons' rows of `result`).
  void run_unit(std::size_t k) {
    if (!lanes_) {
      Inputs in;
      ModelState s0;
      HorizonSensors sensors = setup(k, in, s0);
      integ_.run(in, sensors, &s0);
      return;
    }
    const std::size_t h0 = k * lanes_, count = std::min(lanes_, starts_.size() - h0);
    std::vector<Inputs> in(count);
    std::vector<ModelState> s0(count);
    std::vector<const ModelState*> s0p(count);
    std::vector<HorizonSensors> sensors;
    for (std::size_t j = 0; j < count; ++j) {
      sensors.push_back(setup(h0 + j, in[j], s0[j]));
      s0p[j] = &s0[j];
    }
    lockstep_.run(in.data(), s0p.data(), count, sensors.data());
  }

  HorizonResult result;  ///< the predictions, complete once every unit has run

 private:
  static long checked_stride(const Config& c, const HorizonInputs& hin) {
    require_positive(hin.dt, "horizons.dt_s");
    require(hin.samples >= 1, "horizons.samples", hin.samples, "must be at least 1");
    const double ratio = hin.dt / c.sim.dt;
    const long stride = std::lround(ratio);
    require(stride >= 1 && std::fabs(ratio - stride) <= 1e-6 * ratio, "simulation.dt_s", c.sim.dt,
            "must divide the record's sampling interval " + show(hin.dt) + " s");
    return stride;
  }
  static SimOptions options(const Config& c, const HorizonInputs& hin) {
    SimOptions o = c.sim;
    o.duration = hin.samples * hin.dt;
    return o;
  }

  /// The inputs, the restart state and the sensors of horizon h.
  HorizonSensors setup(std::size_t h, Inputs& in, ModelState& s0) {
    const HorizonStart& st = starts_[h];
    const long need = static_cast<long>(hin_.samples) + 1;
    in = sim_.inputs();
    auto slice = [&](const std::vector<double>& s) {
      return Signal::sampled(std::vector<double>(s.begin() + st.index, s.begin() + st.index + need), 0.0, hin_.dt);
    };
    if (!hin_.top_speed.empty()) in.top_speed = slice(hin_.top_speed);
    if (!hin_.wob.empty()) in.wob = slice(hin_.wob);
    if (hin_.eta.size() > 0) {
      const Eigen::RowVectorXd row = hin_.eta.row(static_cast<Eigen::Index>(h));
      in.eta = Signal::sampled(std::vector<double>(row.data(), row.data() + row.size()), 0.0, hin_.dt);
    }
    // the state carries the total torque on the bit: the measured contact torque plus c_v v
    // and the string friction T_sf sign(v)
    double Tb = st.torque + in.bit_viscous * st.bit_speed;
    if (in.string_friction > 0.0) Tb += in.string_friction * ((st.bit_speed > 0.0) - (st.bit_speed < 0.0));
    s0 = in.top_drive.accel_from_torque() && !std::isfinite(st.top_accel)
             ? integ_.state_from_bit(st.bit_speed, st.bit_accel, Tb, st.top_speed, in.top_drive, in.top_speed.at(0.0))
             : integ_.state_from_bit(st.bit_speed, st.bit_accel, Tb, st.top_speed, st.top_accel);
    s0.wob = st.wob;
    const double fc = c_.sensor_lowpass_hz, dt = c_.sim.dt;
    return HorizonSensors{&st, in.bit_viscous, stride_, static_cast<Eigen::Index>(h), &result,
                          LowPass2(fc, dt), LowPass2(fc, dt), LowPass2(fc, dt), LowPass2(fc, dt)};
  }

  const Simulation& sim_;
  const std::vector<HorizonStart>& starts_;
  const HorizonInputs& hin_;
  const Config& c_;
  long stride_;
  Integrator integ_;
  BatchedIntegrator lockstep_;
  std::size_t lanes_ = 0;  ///< horizons per unit on the batched path; 0: the scalar path
};

/// `batched`: through BatchedIntegrator where it supports the configuration (false: Integrator,
/// the reference, one horizon at a time).
inline HorizonResult predict_horizons(const Simulation& sim, const std::vector<HorizonStart>& starts,
                                      const HorizonInputs& hin, const ProgressFn& progress = nullptr,
                                      int threads = 0, bool batched = true) {
  HorizonRun run(sim, starts, hin, batched);
  const std::size_t n = starts.size(), units = run.units();
  ProgressFn runs;
  if (progress) runs = [&](std::size_t done, std::size_t) { return progress(run.horizons_done(done), n); };
  // one parallel region: a call is short, and barriers cost on busy machines
  if (!parallel_for(units, [&](std::size_t k) { run.run_unit(k); }, runs, threads, std::max<std::size_t>(units, 1)))
    return HorizonResult{};
  return std::move(run.result);
}

/// One call of predict_horizons_many: a model, its horizons and their inputs.
struct HorizonJob {
  const Simulation* sim = nullptr;
  std::vector<HorizonStart> starts;
  HorizonInputs inputs;
};

/// Several predict_horizons calls in one parallel region (the units of every call share the
/// threads): out[i] is what predict_horizons(*jobs[i].sim, jobs[i].starts, jobs[i].inputs, nullptr,
/// threads, batched) returns, bit for bit, or empty with errors[i] the exception it throws (that of
/// its lowest unit, as predict_horizons rethrows); one call's failure leaves the others' results.
inline std::vector<HorizonResult> predict_horizons_many(const std::vector<HorizonJob>& jobs,
                                                        std::vector<std::exception_ptr>& errors, int threads = 0,
                                                        bool batched = true) {
  require(threads >= 0, "threads", threads, "must not be negative (0: the OpenMP default)");
  const std::size_t nj = jobs.size();
  errors.assign(nj, nullptr);
  std::vector<std::unique_ptr<HorizonRun>> runs(nj);
  std::vector<std::pair<std::size_t, std::size_t>> units;  // (job, unit), job-major
  for (std::size_t i = 0; i < nj; ++i) {
    try {
      require(jobs[i].sim != nullptr, "horizons.jobs", i, "has no simulation");
      runs[i] = std::make_unique<HorizonRun>(*jobs[i].sim, jobs[i].starts, jobs[i].inputs, batched);
      for (std::size_t k = 0; k < runs[i]->units(); ++k) units.emplace_back(i, k);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  }
  std::vector<std::exception_ptr> unit_errors(units.size());
  const int nt = threads > 0 ? threads : max_threads();
  const long nu = static_cast<long>(units.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(nt)
  for (long u = 0; u < nu; ++u) {
    const auto [i, k] = units[static_cast<std::size_t>(u)];
    try {
      runs[i]->run_unit(k);
    } catch (...) {
      unit_errors[static_cast<std::size_t>(u)] = std::current_exception();
    }
  }
  for (std::size_t u = 0; u < units.size(); ++u)  // job-major: the first error met is a job's lowest unit's
    if (unit_errors[u] && !errors[units[u].first]) errors[units[u].first] = unit_errors[u];
  std::vector<HorizonResult> out(nj);
  for (std::size_t i = 0; i < nj; ++i)
    if (runs[i] && !errors[i]) out[i] = std::move(runs[i]->result);
  return out;
}

}  // namespace drill
