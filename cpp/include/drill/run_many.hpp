// Independent runs of several configured simulations, in parallel and, where their models differ
// at most in their modal damping, in SIMD lockstep (batched_integrator.hpp): a damping scan
// (drillpy analyze's rig calibration) is one batched call instead of one run after another.
#pragma once

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "drill/batched_integrator.hpp"
#include "drill/errors.hpp"
#include "drill/parallel.hpp"
#include "drill/simulation.hpp"

namespace drill {

/// What run_many returns: per run its report, and its error (empty: the run completed).
struct ManyRuns {
  std::vector<RunReport> reports;
  std::vector<std::string> errors;
};

/// Run r of sims[r] with inputs in[r], starting as sims[r]'s simulation.start says, with the
/// metrics and (when `record`) the series of Simulation::run. When `batched`, every input is in
/// the batched integrator's scope and every model shares_model() with the first, the runs go in
/// SIMD lockstep, each with its own modal damping; then the series' bit_angle and top_torque are
/// left empty (the lockstep path does not form them). Otherwise they run one by one through
/// Integrator, the reference. A run that fails (diverges) gets its error message and an empty
/// report; the others go on. A run's numbers do not depend on the other runs, the thread count or
/// the chunking.
inline ManyRuns run_many(const std::vector<const Simulation*>& sims, std::vector<Inputs> in,
                         bool record = true, int threads = 0, bool batched = true) {
  require(sims.size() == in.size(), "run_many inputs", in.size(), "must have one entry per simulation");
  const std::size_t n = sims.size();
  ManyRuns out{std::vector<RunReport>(n), std::vector<std::string>(n)};
  if (n == 0) return out;
  for (std::size_t r = 0; r < n; ++r) {
    require(sims[r] != nullptr, "run_many simulation", r, "is null");
    in[r] = sims[r]->axial_feed(in[r]);
    in[r].validate();
  }
  const BatchedIntegrator lockstep(sims[0]->integrator());
  bool together = batched;
  for (std::size_t r = 0; together && r < n; ++r)
    together = lockstep.supports(in[r]) && lockstep.shares_model(sims[r]->integrator());
  if (!together) {
    parallel_for(
        n,
        [&](std::size_t r) {
          try {
            out.reports[r] = sims[r]->run(in[r], record);
          } catch (const std::runtime_error& e) {  // diverged: this run only
            out.errors[r] = e.what();
          }
        },
        nullptr, threads);
    return out;
  }
  parallel_batches(
      n,
      [&](std::size_t first, std::size_t count) {
        std::vector<std::optional<ModelState>> s0;
        std::vector<const ModelState*> s0p;
        std::vector<const Integrator*> model;
        std::vector<Simulation::RunObserver> obs;
        for (std::size_t r = first; r < first + count; ++r) {
          s0.push_back(sims[r]->start_state(in[r]));
          model.push_back(&sims[r]->integrator());
          obs.emplace_back(sims[r]->config(), in[r], record);
        }
        for (const auto& s : s0) s0p.push_back(s ? &*s : nullptr);
        std::vector<double> diverged(count);
        std::vector<ModelState> last =
            lockstep.run(in.data() + first, s0p.data(), count, obs.data(), model.data(), diverged.data());
        for (std::size_t k = 0; k < count; ++k) {
          if (!std::isnan(diverged[k])) {
            out.errors[first + k] = Integrator::divergence(diverged[k]);
            continue;
          }
          out.reports[first + k] = obs[k].report(std::move(last[k]));
          out.reports[first + k].series.bit_angle.clear();  // NaN in lockstep: not formed
          out.reports[first + k].series.top_torque.clear();
        }
      },
      nullptr, threads);
  return out;
}

}  // namespace drill
