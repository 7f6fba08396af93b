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

}  // namespace drill::test
