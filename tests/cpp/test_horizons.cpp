// Short-horizon predictions: the state recovered from a bit's speed, acceleration and torque is the
// model's own state (one mode: exact), horizons restarted from a long run's states reproduce that
// run, the sensors' filter is applied, results do not depend on the thread count, and bad requests
// name the field.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "drill/horizons.hpp"
#include "drill/presets.hpp"
#include "error_text.hpp"

using namespace drill;

namespace {

struct LongRun {
  std::vector<double> v, a, T, top, t, wob;
  std::vector<ModelState> states;  ///< state at every recorded step
};

/// A stick-slip run of the rig (motor top drive when asked), every step recorded.
LongRun long_run(const Simulation& sim, double duration) {
  SimOptions o = sim.config().sim;
  o.duration = duration;
  const Integrator integ(sim.rom().model, sim.config().law, o);
  LongRun r;
  integ.run(sim.inputs(), [&](const StepState& s) {
    r.v.push_back(s.bit_speed);
    r.a.push_back(s.bit_accel);
    r.T.push_back(s.torque_on_bit);
    r.top.push_back(s.top_speed);
    r.t.push_back(s.t);
    r.wob.push_back(s.wob);
  });
  return r;
}

Config rig(bool motor) {
  Config c = preset("thesis-rig");
  c.damping.ratios = {0.05};  // light damping: stick-slip with either drive
  if (motor) {
    c.top_drive.kind = TopDrive::Kind::motor;
    c.top_drive.slope = 0.3;
    c.top_drive.inertia = 0.02;
    c.top_speed = 80.9 * M_PI / 30.0 + 2.0 / 0.3;  // command above the mean speed by the droop
  }
  return c;
}

}  // namespace

TEST(Horizons, StateFromBitIsTheModelsStateWithOneMode) {
  for (bool motor : {false, true}) {
    const Simulation sim(rig(motor));
    const Integrator& integ = sim.integrator();
    SimOptions o = sim.config().sim;
    o.duration = 3.0;
    const Integrator run(sim.rom().model, sim.config().law, o);
    // the integrator's own state at a step in slip: rebuild it from what the bit shows
    const Inputs in = sim.inputs();
    std::vector<StepState> steps;
    run.run(in, [&](const StepState& s) { steps.push_back(s); });
    const long i = 25000;
    // the state at step i is the final state of a run of i steps
    SimOptions oi = o;
    oi.duration = i * o.dt;
    const ModelState si = Integrator(sim.rom().model, sim.config().law, oi).run(in, [](const StepState&) {});
    const StepState& s = steps[i];
    const double domega = motor ? (steps[i + 1].top_speed - s.top_speed) / o.dt : 0.0;
    const ModelState r = integ.state_from_bit(s.bit_speed, s.bit_accel, s.torque_on_bit, s.top_speed, domega);
    EXPECT_NEAR(r.q(0), si.q(0), 1e-9 * (1.0 + std::fabs(si.q(0)))) << "motor " << motor;
    EXPECT_NEAR(r.qdot(0), si.qdot(0), 1e-9 * (1.0 + std::fabs(si.qdot(0)))) << "motor " << motor;
    EXPECT_DOUBLE_EQ(r.top_speed, s.top_speed);
  }
}

TEST(Horizons, MotorStateTakesTheTopAccelerationFromTheMotorEquation) {
  // the acceleration the motor equation gives for a state of a run is the run's own
  const Simulation sim(rig(true));
  const LongRun lr = long_run(sim, 3.0);
  const TopDrive& td = sim.config().top_drive;
  const double dt = sim.config().sim.dt;
  for (long i : {12000L, 17000L, 23000L}) {
    const ModelState a = sim.integrator().state_from_bit(lr.v[i], lr.a[i], lr.T[i], lr.top[i], td, sim.config().top_speed);
    const ModelState b = sim.integrator().state_from_bit(lr.v[i], lr.a[i], lr.T[i], lr.top[i], (lr.top[i + 1] - lr.top[i]) / dt);
    EXPECT_NEAR(a.q(0), b.q(0), 1e-12 * (1.0 + std::fabs(b.q(0)))) << i;
    EXPECT_NEAR(a.qdot(0), b.qdot(0), 1e-12) << i;
  }
}

TEST(Horizons, RestartedHorizonsReproduceTheLongRun) {
  for (bool motor : {false, true}) {
    const Simulation sim(rig(motor));
    const double dt = sim.config().sim.dt;
    const LongRun lr = long_run(sim, 6.0);
    const int stride = 10, samples = 200;  // 1 ms output, 0.2 s horizons
    std::vector<HorizonStart> starts;
    for (long k = 20; k < 28; ++k) {  // 4 to 5.6 s: stick-slip
      const long i = k * samples * stride;  // engine step of the start
      HorizonStart h;
      h.index = i / stride;
      h.bit_speed = lr.v[i];
      h.bit_accel = lr.a[i];
      h.torque = lr.T[i];
      h.top_speed = lr.top[i];
      h.top_accel = motor ? (lr.top[i + 1] - lr.top[i]) / dt : 0.0;
      starts.push_back(h);
    }
    HorizonInputs hin;
    hin.dt = stride * dt;
    hin.samples = samples;
    const HorizonResult r = predict_horizons(sim, starts, hin);
    double err = 0.0, vmin = HUGE_VAL, vmax = -HUGE_VAL;
    for (std::size_t h = 0; h < starts.size(); ++h)
      for (int j = 0; j < samples; ++j) {
        const long i = (starts[h].index + j + 1) * stride;
        err = std::max(err, std::fabs(r.bit_speed(h, j) - lr.v[i]));
        err = std::max(err, std::fabs(r.torque(h, j) - lr.T[i]));
        vmin = std::min(vmin, lr.v[i]);
        vmax = std::max(vmax, lr.v[i]);
      }
    EXPECT_GT(vmax - vmin, 5.0) << "motor " << motor;  // an oscillating bit
    EXPECT_LT(err, 1e-6) << "motor " << motor;  // the same steps from the same states
  }
}

TEST(Horizons, TheJacksWobStateRestartsTheHorizons) {
  // drill/axial.hpp: the WOB is a state; a horizon started from the long run's WOB follows it, one
  // started at the set force (the state unknown, NaN) does not; the horizons report that state
  Config c = rig(false);
  c.axial.kind = Axial::Kind::jack;
  c.axial.gain = 130.0;
  c.axial.relaxation = 0.1;
  const Simulation sim(c);
  const double dt = sim.config().sim.dt;
  const LongRun lr = long_run(sim, 6.0);
  const int stride = 10, samples = 200;
  double err[2] = {0.0, 0.0}, werr[2] = {0.0, 0.0}, wmin = HUGE_VAL, wmax = -HUGE_VAL;
  for (int known = 0; known < 2; ++known) {
    std::vector<HorizonStart> starts;
    for (long k = 20; k < 28; ++k) {
      const long i = k * samples * stride;
      HorizonStart h;
      h.index = i / stride;
      h.bit_speed = lr.v[i];
      h.bit_accel = lr.a[i];
      h.torque = lr.T[i];
      h.top_speed = lr.top[i];
      if (known) h.wob = lr.wob[i];
      starts.push_back(h);
    }
    HorizonInputs hin;
    hin.dt = stride * dt;
    hin.samples = samples;
    const HorizonResult r = predict_horizons(sim, starts, hin);
    for (std::size_t h = 0; h < starts.size(); ++h)
      for (int j = 0; j < samples; ++j) {
        const long i = (starts[h].index + j + 1) * stride;
        err[known] = std::max(err[known], std::fabs(r.bit_speed(h, j) - lr.v[i]));
        werr[known] = std::max(werr[known], std::fabs(r.wob(h, j) - lr.wob[i]));
        wmin = std::min(wmin, lr.wob[i]);
        wmax = std::max(wmax, lr.wob[i]);
      }
  }
  EXPECT_GT(wmax - wmin, 20.0);  // the WOB swings with the cycle [N]
  EXPECT_LT(err[1], 1e-6);       // the same steps from the same states
  EXPECT_GT(err[0], 1e-2);       // the WOB state matters [rad/s]
  EXPECT_LT(werr[1], 1e-6);      // the reported WOB is the long run's [N]
  EXPECT_GT(werr[0], 1.0);       // and not the set force's
}

TEST(Horizons, StringFrictionIsPartOfTheRestartStateButNotOfTheReportedTorque) {
  // operation.string_friction_nm (an extension, not in the thesis): a horizon restarted from a
  // slipping bit's measured contact torque T carries the total torque T + c_v v + T_sf sign(v) in its
  // state, and reports the contact torque: it reproduces the long run it was taken from.
  Config c = rig(false);
  c.string_friction = 0.4;
  c.bit_viscous = 0.01;
  const Simulation sim(c);
  const double dt = c.sim.dt, cv = c.bit_viscous;
  const LongRun lr = long_run(sim, 6.0);
  const int stride = 10, samples = 200;
  std::vector<HorizonStart> starts;
  long stuck = 0;
  for (long i = 40000; i < 56000 && starts.size() < 8; i += 1990) {
    if (lr.v[i] < 0.5) continue;  // slipping: the string friction at the start is T_sf sign(v)
    HorizonStart h;
    h.index = i / stride;
    h.bit_speed = lr.v[i];
    h.bit_accel = lr.a[i];
    h.torque = lr.T[i] - cv * lr.v[i];  // what the load cell sees
    h.top_speed = lr.top[i];
    starts.push_back(h);
  }
  ASSERT_GE(starts.size(), 4u);
  for (std::size_t i = 0; i < lr.v.size(); ++i) stuck += std::fabs(lr.v[i]) <= 1e-9;
  EXPECT_GT(stuck, 1000);  // stick-slip
  HorizonInputs hin;
  hin.dt = stride * dt;
  hin.samples = samples;
  const HorizonResult r = predict_horizons(sim, starts, hin);
  double err = 0.0;
  for (std::size_t h = 0; h < starts.size(); ++h)
    for (int j = 0; j < samples; ++j) {
      const long i = (starts[h].index + j + 1) * stride;
      err = std::max(err, std::fabs(r.bit_speed(h, j) - lr.v[i]));
      err = std::max(err, std::fabs(r.torque(h, j) - (lr.T[i] - cv * lr.v[i])));
    }
  EXPECT_LT(err, 1e-6);
}

TEST(Horizons, SensorsFilterTheOutputsAndThreadsDoNotMatter) {
  Config c = preset("thesis-rig");
  const Simulation raw(c);
  c.sensor_lowpass_hz = 10.0;
  const Simulation filtered(c);
  const LongRun lr = long_run(raw, 3.0);
  std::vector<HorizonStart> starts;
  for (long k = 2; k < 12; ++k) {
    const long i = k * 2000;
    HorizonStart h;
    h.index = i / 10;
    h.bit_speed = h.y_bit_speed = lr.v[i];
    h.bit_accel = h.dy_bit_speed = lr.a[i];
    h.torque = h.y_torque = lr.T[i];
    h.top_speed = h.y_top_speed = lr.top[i];
    starts.push_back(h);
  }
  HorizonInputs hin;
  hin.dt = 1e-3;
  hin.samples = 150;
  const HorizonResult a = predict_horizons(raw, starts, hin);
  const HorizonResult b = predict_horizons(filtered, starts, hin, nullptr, 1);
  const HorizonResult b2 = predict_horizons(filtered, starts, hin, nullptr, 2);
  EXPECT_EQ((b.bit_speed - b2.bit_speed).cwiseAbs().maxCoeff(), 0.0);
  // the filtered prediction lags: its correlation with the raw one is highest about
  // sqrt(2) / (2 pi 10 Hz) = 22.5 ms later
  double best = HUGE_VAL;
  int lag_best = -1;
  for (int lag = 0; lag <= 40; ++lag) {
    double sse = 0.0;
    for (Eigen::Index h = 0; h < a.bit_speed.rows(); ++h)
      for (int j = 40; j + 40 < hin.samples; ++j) sse += std::pow(b.bit_speed(h, j + lag) - a.bit_speed(h, j), 2);
    if (sse < best) {
      best = sse;
      lag_best = lag;
    }
  }
  EXPECT_GE(lag_best, 19);
  EXPECT_LE(lag_best, 26);
}

TEST(Horizons, BadRequestsNameTheField) {
  const Simulation sim(preset("thesis-rig"));
  std::vector<HorizonStart> starts(2);
  starts[1].index = 5;
  starts[0].bit_speed = starts[1].bit_speed = 5.0;
  HorizonInputs hin;
  hin.dt = 1e-3;
  hin.samples = 10;
  hin.wob = std::vector<double>(12, 557.0);
  EXPECT_NE(error_of([&] { predict_horizons(sim, starts, hin); }).find("horizons.start_index[1] = 5"),
            std::string::npos);
  hin.wob.clear();
  hin.eta = Eigen::MatrixXd::Zero(2, 5);
  EXPECT_NE(error_of([&] { predict_horizons(sim, starts, hin); }).find("must be horizons x (samples + 1) = 2 x 11"),
            std::string::npos);
  hin.eta.resize(0, 0);
  hin.dt = 1.05e-4;
  EXPECT_NE(error_of([&] { predict_horizons(sim, starts, hin); }).find("simulation.dt_s"), std::string::npos);
  hin.dt = 1e-3;
  starts[0].torque = NAN;
  EXPECT_NE(error_of([&] { predict_horizons(sim, starts, hin); }).find("measured state"), std::string::npos);
}
