// Test helper: a batch of distinct runs of one simulation and the per-step trace that compares
// them bit for bit (shared by the batched-integrator and exact-modal tests).
#pragma once

#include <cstddef>
#include <vector>

#include "drill/montecarlo.hpp"
#include "drill/process.hpp"
#include "drill/rng.hpp"
#include "drill/simulation.hpp"

/// Every step's bit speed, acceleration and torque on bit.
struct StepTrace {
  std::vector<double> v, a, T;
  void operator()(const drill::StepState& s) {
    v.push_back(s.bit_speed);
    a.push_back(s.bit_accel);
    T.push_back(s.torque_on_bit);
  }
  bool operator==(const StepTrace& o) const { return v == o.v && a == o.a && T == o.T; }
};

/// n distinct runs: speeds across the stick-slip band, every other one with an eta realization,
/// every third one with a sampled top speed and WOB (ramps between the samples).
inline std::vector<drill::Inputs> varied_inputs(const drill::Simulation& sim, std::size_t n) {
  using namespace drill;
  const Config& c = sim.config();
  const GaussianProcess proc = GaussianProcess::from_psd(PsdModel(), 0.05, c.sim.duration);
  std::vector<Inputs> in;
  for (std::size_t k = 0; k < n; ++k) {
    Inputs x = sim.inputs(c.top_speed * (0.3 + 0.15 * static_cast<double>(k)), c.wob * (1.0 - 0.02 * k));
    if (k % 2 == 1) {
      RandomStream rng(11, k, MonteCarlo::eta_stream);
      x.eta = proc.signal(rng);
    }
    if (k % 3 == 2) {
      const double om = x.top_speed.value, w = x.wob.value, dt = c.sim.duration / 4.0;
      x.top_speed = Signal::sampled({om, 1.4 * om, 0.7 * om, om, 1.2 * om}, 0.0, dt);
      x.wob = Signal::sampled({w, 0.8 * w, 1.1 * w}, 0.2 * dt, dt);
    }
    in.push_back(x);
  }
  return in;
}
