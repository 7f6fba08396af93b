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
#include <cmath>
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
struct HorizonResult {
  Eigen::MatrixXd bit_speed, torque, top_speed;
};

/// The sensors of one horizon: observes its run and writes its row of the result.
struct HorizonSensors {
  const HorizonStart* st;
  double bit_viscous;
  long stride;
  Eigen::Index row;
  HorizonResult* r;
  LowPass2 fv, ft, fo;

  void operator()(const StepState& s) {
    // (the integrator's torque on bit already leaves the string friction out)
    const double contact = s.torque_on_bit - bit_viscous * s.bit_speed;
    if (s.step == 0) {
      fv.reset(st->y_bit_speed, st->dy_bit_speed, s.bit_speed);
      ft.reset(st->y_torque, st->dy_torque, contact);
      fo.reset(st->y_top_speed, st->dy_top_speed, s.top_speed);
      return;
    }
    const double yv = fv.step(s.bit_speed), yt = ft.step(contact), yo = fo.step(s.top_speed);
    if (s.step % stride == 0) {
      const Eigen::Index j = static_cast<Eigen::Index>(s.step / stride - 1);
      r->bit_speed(row, j) = yv;
      r->torque(row, j) = yt;
      r->top_speed(row, j) = yo;
    }
  }
};

/// `batched`: through BatchedIntegrator where it supports the configuration (false: Integrator,
/// the reference, one horizon at a time).
inline HorizonResult predict_horizons(const Simulation& sim, const std::vector<HorizonStart>& starts,
                                      const HorizonInputs& hin, const ProgressFn& progress = nullptr,
                                      int threads = 0, bool batched = true) {
  const Config& c = sim.config();
  require_positive(hin.dt, "horizons.dt_s");
  require(hin.samples >= 1, "horizons.samples", hin.samples, "must be at least 1");
  const double ratio = hin.dt / c.sim.dt;
  const long stride = std::lround(ratio);
  require(stride >= 1 && std::fabs(ratio - stride) <= 1e-6 * ratio, "simulation.dt_s", c.sim.dt,
          "must divide the record's sampling interval " + show(hin.dt) + " s");
  const std::size_t n = starts.size();
  const long need = static_cast<long>(hin.samples) + 1;
  auto check_series = [&](const std::vector<double>& s, const char* field) {
    if (s.empty()) return;
    for (std::size_t k = 0; k < s.size(); ++k) require_finite(s[k], std::string(field) + "[" + std::to_string(k) + "]");
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
  SimOptions o = c.sim;
  o.duration = hin.samples * hin.dt;
  const Integrator integ(sim.rom().model, c.law, o);
  HorizonResult r;
  r.bit_speed.resize(n, hin.samples);
  r.torque.resize(n, hin.samples);
  r.top_speed.resize(n, hin.samples);
  // the inputs, the restart state and the sensors of horizon h
  auto setup = [&](std::size_t h, Inputs& in, ModelState& s0) {
    const HorizonStart& st = starts[h];
    in = sim.inputs();
    auto slice = [&](const std::vector<double>& s) {
      return Signal::sampled(std::vector<double>(s.begin() + st.index, s.begin() + st.index + need), 0.0, hin.dt);
    };
    if (!hin.top_speed.empty()) in.top_speed = slice(hin.top_speed);
    if (!hin.wob.empty()) in.wob = slice(hin.wob);
    if (hin.eta.size() > 0) {
      const Eigen::RowVectorXd row = hin.eta.row(static_cast<Eigen::Index>(h));
      in.eta = Signal::sampled(std::vector<double>(row.data(), row.data() + row.size()), 0.0, hin.dt);
    }
    // the state carries the total torque on the bit: the measured contact torque plus c_v v
    // and the string friction T_sf sign(v)
    double Tb = st.torque + in.bit_viscous * st.bit_speed;
    if (in.string_friction > 0.0) Tb += in.string_friction * ((st.bit_speed > 0.0) - (st.bit_speed < 0.0));
    s0 = in.top_drive.is_motor() && !std::isfinite(st.top_accel)
             ? integ.state_from_bit(st.bit_speed, st.bit_accel, Tb, st.top_speed, in.top_drive, in.top_speed.at(0.0))
             : integ.state_from_bit(st.bit_speed, st.bit_accel, Tb, st.top_speed, st.top_accel);
    s0.wob = st.wob;
    const double fc = c.sensor_lowpass_hz, dt = c.sim.dt;
    return HorizonSensors{&st, in.bit_viscous, stride, static_cast<Eigen::Index>(h), &r,
                          LowPass2(fc, dt), LowPass2(fc, dt), LowPass2(fc, dt)};
  };
  // one parallel region: a call is short, and barriers cost on busy machines
  const BatchedIntegrator lockstep(integ);
  bool done;
  if (batched && lockstep.supports(sim.inputs())) {
    done = parallel_batches(
        n,
        [&](std::size_t h0, std::size_t count) {
          std::vector<Inputs> in(count);
          std::vector<ModelState> s0(count);
          std::vector<const ModelState*> s0p(count);
          std::vector<HorizonSensors> sensors;
          for (std::size_t k = 0; k < count; ++k) {
            sensors.push_back(setup(h0 + k, in[k], s0[k]));
            s0p[k] = &s0[k];
          }
          lockstep.run(in.data(), s0p.data(), count, sensors.data());
        },
        progress, threads, n);
  } else {
    done = parallel_for(
        n,
        [&](std::size_t h) {
          Inputs in;
          ModelState s0;
          HorizonSensors sensors = setup(h, in, s0);
          integ.run(in, sensors, &s0);
        },
        progress, threads, n);
  }
  if (!done) return HorizonResult{};
  return r;
}

}  // namespace drill
