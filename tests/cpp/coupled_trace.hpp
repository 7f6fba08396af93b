// The step-by-step trace of a coupled axial-torsional run (axial_torsional.hpp), shared by the
// coupled model's test files.
#pragma once

#include <vector>

#include "drill/simulation.hpp"

namespace drill::test {

/// Every step's torsional and axial state of one run.
struct CoupledTrace {
  std::vector<StepState> s;
  std::vector<AxialStep> a;
};

/// The run of `sim`'s coupled model from `start` (default: its own start).
inline CoupledTrace coupled_trace(const Simulation& sim, const ModelState* start = nullptr) {
  CoupledTrace out;
  sim.coupled()->run(
      sim.inputs(),
      [&](const StepState& s, const AxialStep& a) {
        out.s.push_back(s);
        out.a.push_back(a);
      },
      start);
  return out;
}

/// `c` set to start in steady drilling with the top boundary `top` at a 5 mm/s feed (no disturbance).
inline void steady_start(Config& c, AxialTop top) {
  c.axial.rgd.top = top;
  c.axial.rgd.feed_rate = 0.005;
  c.axial.rgd.disturbance = 0.0;
}

/// RGD's steady WOB at the depth of cut d: W = a zeta eps d + a l sigma (docs/axial.md).
inline double rgd_steady_wob(const RgdBit& b, double depth) {
  return b.radius * b.force_ratio * b.specific_energy * depth + b.radius * b.wear_flat * b.contact_strength;
}

}  // namespace drill::test
