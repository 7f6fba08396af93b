// Monte Carlo simulation of the stochastic drill-string dynamics (thesis section 4.2, Algorithm 1,
// appendix C): each sample i draws one realization of eta(t) (process.hpp) from
// RandomStream(seed, i, eta_stream) and runs the configured model with
// T_sto = T_hys (1 + eta(t)) (Eq. 4.1) at every requested top speed (common random numbers: the
// same realization at all speeds, so SS_i(Omega) is one random function of the speed, as in C.1).
// With warmup = 0 every run starts from Eq. (2.10), as in Algorithm 1; with warmup > 0 it starts
// from the deterministic state at t = warmup (shared by all samples of a speed).
//
// Reproducibility: sample i depends only on (seed, i). Each sample writes its own row, rows are
// reduced in index order, so results are bit-identical for any thread count and for any split of
// the sample range into chunks [first, first + count).
#pragma once

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "drill/batched_integrator.hpp"
#include "drill/config.hpp"
#include "drill/errors.hpp"
#include "drill/metrics.hpp"
#include "drill/parallel.hpp"
#include "drill/process.hpp"
#include "drill/quantile.hpp"
#include "drill/rng.hpp"
#include "drill/simulation.hpp"

namespace drill {

/// Stick and slip phases of one sample (complete phases after the transient, in time order).
struct PhaseSample {
  std::vector<double> stick, slip;
  bool slip_first = false;
  double severity = 0.0;
};

class MonteCarlo {
 public:
  /// The RandomStream stream number of the eta realizations.
  static constexpr std::uint32_t eta_stream = 1;
  /// Largest number of samples in one call (memory guard; larger studies run in chunks).
  static constexpr std::size_t max_samples = 10000000;

  /// `cfg` gives the model, the time step, the simulated duration and the transient of every
  /// stochastic run; `process` must cover that duration. `warmup` [s] > 0 starts every run from
  /// the deterministic state reached at t = warmup from Eq. (2.10) at the same top speed (computed
  /// once per speed and shared by all samples): the start-up transient from rest, which decays
  /// with the 0.13 Hz mode's 9.5 % damping, is then not paid again by every sample.
  MonteCarlo(Config cfg, GaussianProcess process, std::uint64_t seed, double warmup = 0.0)
      : sim_(std::move(cfg)), proc_(std::move(process)), seed_(seed), warmup_(warmup) {
    require(!sim_.coupled() || warmup_ == 0.0, "montecarlo.warmup_s", warmup_,
            "must be 0 with axial.type = rgd: every coupled run starts in RGD's steady drilling");
    const double span = static_cast<double>(proc_.size()) * proc_.dt();
    require(span >= sim_.config().sim.duration, "process.duration_s", span,
            "the eta realization is shorter than simulation.duration_s = " + show(sim_.config().sim.duration));
    require_non_negative(warmup_, "montecarlo.warmup_s");
    require(warmup_ / sim_.config().sim.dt < 2e9, "montecarlo.warmup_s", warmup_, "needs more than 2e9 steps");
  }

  double warmup() const { return warmup_; }

  /// Whether severity(batched = true) steps its samples in lockstep: the torsional model where
  /// BatchedIntegrator supports it, the axial-torsional model (axial.type = rgd) always
  /// (AxialTorsional::run_lanes).
  bool lockstep() const {
    const Config& c = sim_.config();
    return sim_.coupled() || BatchedIntegrator(sim_.integrator()).supports(sim_.inputs(c.top_speed, c.wob));
  }

  /// The deterministic state at t = warmup for each top speed (nothing when warmup = 0).
  std::vector<ModelState> warm_states(const std::vector<double>& speeds, int threads = 0) const {
    std::vector<ModelState> out;
    if (warmup_ <= 0.0) return out;
    out.resize(speeds.size());
    const Config& c = sim_.config();
    SimOptions o = c.sim;
    o.duration = warmup_;
    const Integrator warm(sim_.rom().model, c.law, o);
    parallel_for(
        speeds.size(),
        [&](std::size_t s) { out[s] = warm.run(sim_.inputs(speeds[s], c.wob), [](const StepState&) {}); }, nullptr,
        threads);
    return out;
  }

  const Simulation& simulation() const { return sim_; }
  const GaussianProcess& process() const { return proc_; }
  std::uint64_t seed() const { return seed_; }

  /// The eta realization of sample i.
  Signal eta(std::uint64_t sample) const {
    RandomStream rng(seed_, sample, eta_stream);
    return proc_.signal(rng);
  }

  /// SS (Eq. 3.4) of samples first .. first + count - 1 at each top speed [rad/s]:
  /// result(r, s) for sample first + r and speeds[s]. An empty matrix if cancelled.
  /// With `mean_bit_speed`, also the mean bit speed of each run's SS window [rad/s] (a bit that
  /// stays stuck has a small SS: SS alone cannot tell it from smooth drilling).
  /// `batched`: the samples go in lockstep (one sample per lane, one task per batch and speed) when
  /// lockstep(): through BatchedIntegrator (batched_integrator.hpp), or with axial.type = rgd through
  /// AxialTorsional::run_lanes (the same numbers as one by one); else one by one through Integrator,
  /// the reference (false: always).
  Eigen::MatrixXd severity(const std::vector<double>& speeds, std::uint64_t first, std::size_t count,
                           const ProgressFn& progress = nullptr, int threads = 0,
                           Eigen::MatrixXd* mean_bit_speed = nullptr, bool batched = true) const {
    check_speeds(speeds);
    check_range(first, count);
    Eigen::MatrixXd out(static_cast<Eigen::Index>(count), static_cast<Eigen::Index>(speeds.size()));
    if (mean_bit_speed) mean_bit_speed->resize(out.rows(), out.cols());
    const Config& c = sim_.config();
    const std::vector<ModelState> warm = warm_states(speeds, threads);
    if (batched && lockstep()) {
      // one task per (batch of samples, speed): enough tasks for every thread even with few samples
      const BatchedIntegrator torsional(sim_.integrator());
      const AxialTorsional* coupled = sim_.coupled();
      const std::size_t w = BatchedIntegrator::width(), ns = speeds.size(), nb = (count + w - 1) / w;
      ProgressFn runs;
      if (progress) runs = [&](std::size_t tasks, std::size_t) { return progress(std::min(count, tasks / ns * w), count); };
      const bool done = parallel_for(
          nb * ns,
          [&](std::size_t task) {
            const std::size_t s = task % ns, r0 = task / ns * w, n = std::min(w, count - r0);
            std::vector<Inputs> in(n, sim_.inputs(speeds[s], c.wob));
            for (std::size_t k = 0; k < n; ++k) in[k].eta = eta(first + r0 + k);
            std::vector<SeverityObserver> sev(n, SeverityObserver(c.transient));
            if (coupled) {  // axial.type = rgd: the runs start in steady drilling (Simulation::run_observed)
              const ModelState s0 = sim_.coupled_start(*coupled, speeds[s], c.start);
              const std::vector<const ModelState*> s0p(n, &s0);
              std::vector<Simulation::TorsionOnly<SeverityObserver&>> obs;
              for (SeverityObserver& o : sev) obs.push_back({o});
              std::vector<CoupledState> last(n);
              coupled->run_lanes(in.data(), s0p.data(), n, obs.data(), last.data());
            } else {
              const std::vector<const ModelState*> s0(n, warm.empty() ? nullptr : &warm[s]);
              torsional.run(in.data(), s0.data(), n, sev.data());
            }
            for (std::size_t k = 0; k < n; ++k) {
              const Eigen::Index r = static_cast<Eigen::Index>(r0 + k), j = static_cast<Eigen::Index>(s);
              out(r, j) = sev[k].severity();
              if (mean_bit_speed) (*mean_bit_speed)(r, j) = sev[k].mean_bit_speed();
            }
          },
          runs, threads);
      if (!done) return Eigen::MatrixXd();
      return out;
    }
    const bool done = parallel_for(
        count,
        [&](std::size_t r) {
          Inputs in = sim_.inputs(c.top_speed, c.wob);
          in.eta = eta(first + r);
          for (std::size_t s = 0; s < speeds.size(); ++s) {
            in.top_speed = Signal::constant(speeds[s]);
            SeverityObserver sev(c.transient);
            sim_.run_observed(in, sev, warm.empty() ? nullptr : &warm[s]);
            out(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(s)) = sev.severity();
            if (mean_bit_speed)
              (*mean_bit_speed)(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(s)) = sev.mean_bit_speed();
          }
        },
        progress, threads);
    if (!done) return Eigen::MatrixXd();
    return out;
  }

  /// Stick and slip durations of samples first .. first + count - 1 at one top speed (Fig. 4.7).
  /// An empty vector if cancelled.
  std::vector<PhaseSample> phases(double speed, std::uint64_t first, std::size_t count,
                                  const ProgressFn& progress = nullptr, int threads = 0) const {
    check_speeds({speed});
    check_range(first, count);
    std::vector<PhaseSample> out(count);
    const Config& c = sim_.config();
    const std::vector<ModelState> warm = warm_states({speed}, threads);
    const bool done = parallel_for(
        count,
        [&](std::size_t r) {
          Inputs in = sim_.inputs(speed, c.wob);
          in.eta = eta(first + r);
          SeverityObserver sev(c.transient);
          PhaseObserver ph(c.transient, c.metrics.stick_threshold_fraction * std::fabs(speed),
                           c.metrics.stick_debounce_s, c.metrics.slip_level_fraction * std::fabs(speed));
          sim_.run_observed(
              in,
              [&](const StepState& s) {
                sev(s);
                ph(s);
              },
              warm.empty() ? nullptr : &warm[0]);
          out[r] = {ph.stick, ph.slip, ph.slip_first, sev.severity()};
        },
        progress, threads);
    if (!done) out.clear();
    return out;
  }

 private:
  static void check_speeds(const std::vector<double>& speeds) {
    require(!speeds.empty(), "montecarlo.top_speeds_rad_s", speeds.size(), "is empty (give at least one speed)");
    for (std::size_t k = 0; k < speeds.size(); ++k) {
      const std::string f = "montecarlo.top_speeds_rad_s[" + std::to_string(k) + "]";
      require_finite(speeds[k], f);
      require(speeds[k] > 0.0, f, speeds[k], "must be positive");
    }
  }
  static void check_range(std::uint64_t first, std::size_t count) {
    require(count >= 1 && count <= max_samples, "montecarlo.samples", count,
            "must be between 1 and " + show(max_samples));
    require(first <= (std::uint64_t(1) << 62), "montecarlo.first_sample", first, "must be below 2^62");
  }

  Simulation sim_;
  GaussianProcess proc_;
  std::uint64_t seed_;
  double warmup_;
};

/// Per-speed statistics of a sample of SS curves (Fig. 4.9).
struct SeverityStatistics {
  std::vector<double> mean, q_low, q_high, p_exceed;
  double p_speed = NAN;  ///< lowest speed from which P(SS > level) <= prob (NaN: no crossing)
};

/// Mean, quantiles q_low/q_high and P(SS > level) per speed (columns of `ss`), and the speed at
/// which P(SS > level) last crosses `prob` going up in speed (linear interpolation, section 4.2.2:
/// 20.5 rad/s in the thesis for level 0.5 and prob 0.05).
inline SeverityStatistics severity_statistics(const Eigen::MatrixXd& ss, const std::vector<double>& speeds,
                                              double level = 0.5, double prob = 0.05, double q_low = 0.05,
                                              double q_high = 0.95) {
  require(ss.cols() == static_cast<Eigen::Index>(speeds.size()), "severities columns", ss.cols(),
          "must equal the number of speeds " + show(speeds.size()));
  require(ss.rows() >= 1, "severities rows", ss.rows(), "need at least one sample");
  require_finite(level, "level");
  require(prob >= 0.0 && prob <= 1.0, "probability", prob, "must lie in [0, 1]");
  SeverityStatistics st;
  const Eigen::Index n = ss.rows();
  for (Eigen::Index s = 0; s < ss.cols(); ++s) {
    std::vector<double> col(static_cast<std::size_t>(n));
    double sum = 0.0;
    std::size_t above = 0;
    for (Eigen::Index i = 0; i < n; ++i) {  // index order: the same sums for any chunking
      const double v = ss(i, s);
      require(std::isfinite(v), "severity[" + std::to_string(i) + "][" + std::to_string(s) + "]", v,
              "must be finite");
      col[static_cast<std::size_t>(i)] = v;
      sum += v;
      above += v > level;
    }
    st.mean.push_back(sum / static_cast<double>(n));
    st.q_low.push_back(quantile(col, q_low));
    st.q_high.push_back(quantile(col, q_high));
    st.p_exceed.push_back(static_cast<double>(above) / static_cast<double>(n));
  }
  st.p_speed = severity_threshold(speeds, st.p_exceed, prob);
  return st;
}

/// Convergence function of appendix C, Eq. (C.1):
///   Conv1(n) = sqrt( (1/n) sum_{i<=n} integral_B SS_i(Omega)^2 dOmega ),  n = 1 .. rows,
/// the integral over the speed grid by the trapezoidal rule (speeds sorted internally).
inline std::vector<double> conv1(const Eigen::MatrixXd& ss, const std::vector<double>& speeds) {
  require(ss.cols() == static_cast<Eigen::Index>(speeds.size()), "severities columns", ss.cols(),
          "must equal the number of speeds " + show(speeds.size()));
  require(speeds.size() >= 2, "speeds", speeds.size(), "need at least two speeds to integrate over B");
  std::vector<std::size_t> idx(speeds.size());
  for (std::size_t k = 0; k < idx.size(); ++k) idx[k] = k;
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return speeds[a] < speeds[b]; });
  std::vector<double> out(static_cast<std::size_t>(ss.rows()));
  double acc = 0.0;
  for (Eigen::Index i = 0; i < ss.rows(); ++i) {
    double integral = 0.0;
    for (std::size_t k = 1; k < idx.size(); ++k) {
      const double a = ss(i, static_cast<Eigen::Index>(idx[k - 1])), b = ss(i, static_cast<Eigen::Index>(idx[k]));
      integral += 0.5 * (a * a + b * b) * (speeds[idx[k]] - speeds[idx[k - 1]]);
    }
    acc += integral;
    out[static_cast<std::size_t>(i)] = std::sqrt(acc / static_cast<double>(i + 1));
  }
  return out;
}

}  // namespace drill
