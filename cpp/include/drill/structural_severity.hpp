// Stick-slip severity under structural uncertainty in the time domain: the thesis's future work,
// item 1 (chapter 7): the stochastic reduced model (SM_CB2, or SM_CB1 / SM_full) driven by the
// bit-rock law, optionally with the stochastic law T_sto = T_hys (1 + eta(t)) (Eq. 4.1).
//
// Sample i takes realization i of the random matrices (RandomStream(seed, i, .), see
// stochastic_model.hpp) and the eta series the caller's EtaProvider returns for i; the same
// sample is run at every top speed (common random numbers), and SS (Eq. 3.4) is stored per
// (sample, speed), so the results do not depend on the thread count or on the chunking.
//
// The bit-rock uncertainty is a hook: the EtaProvider maps a sample index to its eta(t) Signal.
// It must be thread-safe and depend only on the sample index (and its own seed). psd_eta() gives
// the chapter-4 one: the PSD-based Gaussian process (Eq. 4.4, process.hpp) drawn from
// RandomStream(seed, i, MonteCarlo::eta_stream), the same eta as sample i of the chapter-4 Monte
// Carlo with that seed; the random matrices use other streams of the same sample, so the two
// sources are independent. Without a provider only the structure is uncertain.
//
// Top drive: the configuration's. A `controlled` drive (controller.hpp, issue 15) runs on every
// random string exactly as in an ordinary simulation: the top is the free inertia J of
// J Omega' = u - T_top, its acceleration enters the reduced model as the rotating frame's top load
// (Eq. 2.9: -top_load Omega'), and T_top = top_torque q. A realization (StochasticModel::sample)
// keeps the mean model's bit row and initial velocity (the deterministic basis of the nonparametric
// approach, Eqs. 6.4, 6.23) and carries the top load and top torque of its random M~ and K~
// (StochasticModel::top_coupling: with the mean model's vectors the random strings fed the drive
// spurious energy), so the controlled path of the integrator has what it needs for each sample;
// the time step is checked against Eq. (A.7) for each random string coupled to J. The ideal drive
// at a constant speed uses neither vector. The controller is tuned once, on the nominal string, as
// a field engineer tunes it (the drive does not know the realization): the top section's
// characteristic impedance Z = J_p sqrt(G rho) and the first natural frequency w_1 of the mean
// reduced model (string clamped at the top); every sample and speed runs with the same gains
// (study_top_drive).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "drill/config.hpp"
#include "drill/errors.hpp"
#include "drill/integrator.hpp"
#include "drill/metrics.hpp"
#include "drill/montecarlo.hpp"
#include "drill/parallel.hpp"
#include "drill/process.hpp"
#include "drill/signal.hpp"
#include "drill/stochastic_model.hpp"

namespace drill {

/// eta(t) of Monte Carlo sample i (Eq. 4.1): the bit-rock uncertainty hook.
using EtaProvider = std::function<Signal(std::size_t sample)>;

static_assert(StochasticModel::first_stream > MonteCarlo::eta_stream, "eta and the random matrices share a stream");

/// The stochastic bit-rock law of chapter 4 as an EtaProvider (Eqs. 4.1-4.4).
inline EtaProvider psd_eta(GaussianProcess process, std::uint64_t seed) {
  return [process = std::move(process), seed](std::size_t i) {
    RandomStream rng(seed, i, MonteCarlo::eta_stream);
    return process.signal(rng);
  };
}

struct SeverityStudyOptions {
  std::vector<double> speeds;  ///< constant top speeds [rad/s]
  std::size_t samples = 100;
  std::uint64_t first_sample = 0;  ///< runs samples first_sample .. first_sample + samples - 1
  std::uint64_t seed = 1;
  bool structural = true;      ///< false: every sample uses the mean structure (bit-rock only)
  int threads = 0;
};

/// The first natural frequency w_1 [rad/s] of a reduced model (top clamped): sqrt of the lowest
/// generalized eigenvalue of (K~, M~).
inline double first_natural_frequency(const ReducedModel& m) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(m.K, m.M, Eigen::EigenvaluesOnly);
  require(es.info() == Eigen::Success, "rom", m.size(), "the reduced eigenproblem failed");
  return std::sqrt(std::max(es.eigenvalues()(0), 0.0));
}

/// The top drive of the study's runs: the configuration's; a controlled one tuned on the nominal
/// string (the top section's Z and w_1 of the mean reduced model, header comment), the same gains
/// for every realization.
inline TopDrive study_top_drive(const StochasticModel& sm) {
  TopDrive td = sm.config().top_drive;
  if (td.has_controller()) td.tune_controller(top_impedance(sm.config().string), first_natural_frequency(sm.mean()));
  return td;
}

/// SS for every (sample, speed): a samples x speeds matrix, row r for sample first_sample + r;
/// empty if cancelled.
/// The law, WOB, time step, transient and top drive come from the model's configuration (a
/// controlled drive: study_top_drive). Every run starts from the string at rest (Eq. 2.10).
inline Eigen::MatrixXd severity_samples(const StochasticModel& sm, const SeverityStudyOptions& opt,
                                        const EtaProvider& eta = nullptr, const ProgressFn& progress = nullptr) {
  const Config& cfg = sm.config();
  require(!opt.speeds.empty(), "speeds", opt.speeds.size(), "needs at least one top speed");
  for (std::size_t k = 0; k < opt.speeds.size(); ++k) {
    require_finite(opt.speeds[k], "speeds[" + std::to_string(k) + "]");
    require(opt.speeds[k] > 0.0, "speeds[" + std::to_string(k) + "]", opt.speeds[k], "must be positive");
  }
  require(opt.samples >= 1, "samples", opt.samples, "must be at least 1");
  require(opt.first_sample <= (std::uint64_t(1) << 62), "first_sample", opt.first_sample, "must be below 2^62");
  const TopDrive drive = study_top_drive(sm);
  const std::size_t nsp = opt.speeds.size();
  Eigen::MatrixXd ss(static_cast<Eigen::Index>(opt.samples), static_cast<Eigen::Index>(nsp));
  const bool done = parallel_for(
      opt.samples * nsp,
      [&](std::size_t job) {
        const std::size_t r = job / nsp, k = job % nsp;
        const std::uint64_t i = opt.first_sample + r;
        const ReducedModel model = opt.structural ? sm.sample(opt.seed, i) : sm.mean();
        const Integrator integ(model, cfg.law, cfg.sim);
        Inputs in;
        in.top_speed = Signal::constant(opt.speeds[k]);
        in.wob = Signal::constant(cfg.wob);
        in.bit_viscous = cfg.bit_viscous;
        in.string_friction = cfg.string_friction;
        in.top_drive = drive;
        if (eta) in.eta = eta(i);
        SeverityObserver sev(cfg.transient);
        integ.run(in, sev);
        ss(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(k)) = sev.severity();
      },
      progress, opt.threads);
  if (!done) ss.resize(0, 0);
  return ss;
}

}  // namespace drill
