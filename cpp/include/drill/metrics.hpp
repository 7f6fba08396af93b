// Metrics of a bit-speed history, computed on line by observers of the integrator:
// stick-slip severity (Eq. 3.4), stick and slip phase durations, periodic-regime detection,
// and a decimating recorder of the time series.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "drill/errors.hpp"
#include "drill/integrator.hpp"

namespace drill {

/// SS = (max v_bit - min v_bit) / (2 Omega) over t >= t_start (Eq. 3.4); Omega is the top speed
/// averaged over the same window (the constant top speed when it is constant).
struct SeverityObserver {
  double t_start = 0.0;
  double vmax = -std::numeric_limits<double>::infinity();
  double vmin = std::numeric_limits<double>::infinity();
  double top_sum = 0.0;
  double bit_sum = 0.0;
  long count = 0;

  explicit SeverityObserver(double t_start_ = 0.0) : t_start(t_start_) {}
  void operator()(const StepState& s) {
    if (s.t < t_start) return;
    vmax = std::max(vmax, s.bit_speed);
    vmin = std::min(vmin, s.bit_speed);
    top_sum += s.top_speed;
    bit_sum += s.bit_speed;
    ++count;
  }
  double mean_top_speed() const { return count ? top_sum / count : std::nan(""); }
  double mean_bit_speed() const { return count ? bit_sum / count : std::nan(""); }
  double severity() const {
    if (!count) return std::nan("");
    return (vmax - vmin) / (2.0 * std::fabs(mean_top_speed()));
  }
};

/// Stick phases are the intervals where the bit speed is at or below `threshold`; slip phases are
/// the rest. A change of phase counts only if the new phase lasts at least `debounce` seconds
/// (the explicit scheme chatters around zero speed during stick). With `slip_level` > 0 a slip
/// phase whose bit speed never exceeds `slip_level` is chatter too, however long: it is merged with
/// the stick phases around it (the modified Euler scheme with many modes lifts a stuck bit above the
/// threshold for tens of ms without a real slip). Only phases that start and end after t_start
/// are recorded; stick[j] is followed by slip[j] when slip_first is false.
struct PhaseObserver {
  double t_start = 0.0, threshold = 0.0, debounce = 0.0, slip_level = 0.0;
  std::vector<double> stick, slip;  ///< durations [s] of complete phases, in time order
  bool slip_first = false;          ///< the first recorded phase is a slip
  double stick_time = 0.0, slip_time = 0.0;  ///< total time in each phase after t_start [s]

  PhaseObserver(double t_start_, double threshold_, double debounce_ = 0.0, double slip_level_ = 0.0)
      : t_start(t_start_), threshold(threshold_), debounce(debounce_), slip_level(slip_level_) {}

  void operator()(const StepState& s) {
    const bool raw = s.bit_speed <= threshold;
    if (!started_) {
      started_ = true;
      sticking_ = raw;
      peak_ = s.bit_speed;
      return;
    }
    if (s.t >= t_start) (sticking_ ? stick_time : slip_time) += s.t - t_prev_;
    t_prev_ = s.t;
    if (!sticking_) {
      peak_ = std::max(peak_, s.bit_speed);
      if (held_ && peak_ >= slip_level) {  // the slip is real: the stick before it is complete
        record(true, held_duration_);
        held_ = false;
      }
    }
    if (raw == sticking_) {
      pending_ = false;
      return;
    }
    if (!pending_) {
      pending_ = true;
      t_candidate_ = s.t;
    }
    if (s.t - t_candidate_ < debounce) return;
    // confirmed switch at t_candidate_
    pending_ = false;
    if (!sticking_ && held_ && peak_ < slip_level) {
      // the slip that ends here was chatter: the stick before it goes on from its own start
      const double from = std::max(t_switch_, t_start);
      if (t_candidate_ > from) {
        slip_time -= t_candidate_ - from;
        stick_time += t_candidate_ - from;
      }
      t_switch_ = held_start_;
      held_ = false;
      sticking_ = true;
      return;
    }
    if (t_candidate_ >= t_start) {
      if (have_switch_) {
        const double d = t_candidate_ - t_switch_;
        if (sticking_ && slip_level > 0.0) {  // hold the stick until the slip after it proves real
          held_ = true;
          held_start_ = t_switch_;
          held_duration_ = d;
        } else {
          record(sticking_, d);
        }
      }
      have_switch_ = true;
      t_switch_ = t_candidate_;
    }
    sticking_ = raw;
    peak_ = s.bit_speed;
  }

  /// Fraction of the time after t_start spent in stick.
  double stick_fraction() const {
    const double tot = stick_time + slip_time;
    return tot > 0.0 ? stick_time / tot : std::nan("");
  }

 private:
  void record(bool is_stick, double d) {
    if (stick.empty() && slip.empty()) slip_first = !is_stick;
    (is_stick ? stick : slip).push_back(d);
  }
  bool started_ = false, sticking_ = false, pending_ = false, have_switch_ = false, held_ = false;
  double t_prev_ = 0.0, t_candidate_ = 0.0, t_switch_ = 0.0, peak_ = 0.0, held_start_ = 0.0, held_duration_ = 0.0;
};

/// Result of the periodic-regime detection on the sequence of stick-slip cycles.
struct Periodicity {
  int period_cycles = 0;           ///< k: the stick and slip durations repeat every k cycles (0: none found)
  std::vector<double> stick, slip; ///< the k stick and slip durations of the last period [s]
  double mismatch = 0.0;           ///< max |d_j - d_{j+k}| over the compared cycles [s]
};

/// Smallest k <= max_k such that over the last `repeats` periods every stick and slip duration
/// equals the one k cycles later within tol + rel_tol x the longer of the two [s]. The thesis finds
/// k = 3 for the deterministic field model (section 4.2.1). The relative part absorbs the timing
/// jitter of the explicit scheme, whose stuck bit chatters: with 100 modes at 16 rad/s its 3-cycle
/// stick durations vary by up to 0.045 s over 2.3 s from one period to the next.
inline Periodicity detect_periodicity(const PhaseObserver& ph, int max_k = 8, int repeats = 3, double tol = 0.02,
                                      double rel_tol = 0.03) {
  Periodicity out;
  // Pair each stick with the slip that follows it.
  const std::size_t off = ph.slip_first ? 1 : 0;
  std::vector<double> st, sl;
  for (std::size_t j = 0; j < ph.stick.size() && j + off < ph.slip.size(); ++j) {
    st.push_back(ph.stick[j]);
    sl.push_back(ph.slip[j + off]);
  }
  const int nc = static_cast<int>(st.size());
  for (int k = 1; k <= max_k; ++k) {
    const int need = k * (repeats + 1);
    if (nc < need) break;
    double mism = 0.0;
    bool same = true;
    for (int j = nc - need; j + k < nc; ++j) {
      const double ds = std::fabs(st[j] - st[j + k]), dl = std::fabs(sl[j] - sl[j + k]);
      mism = std::max({mism, ds, dl});
      same = same && ds <= tol + rel_tol * std::max(st[j], st[j + k]) && dl <= tol + rel_tol * std::max(sl[j], sl[j + k]);
    }
    if (same) {
      out.period_cycles = k;
      out.mismatch = mism;
      out.stick.assign(st.end() - k, st.end());
      out.slip.assign(sl.end() - k, sl.end());
      return out;
    }
  }
  return out;
}

/// Keeps every `stride`-th step of the time series.
struct Recorder {
  long stride = 1;
  std::vector<double> t, bit_speed, bit_accel, bit_angle, torque_on_bit, top_torque, top_speed, wob;

  explicit Recorder(long stride_ = 1, long expected = 0) : stride(std::max(1L, stride_)) {
    for (auto* v : {&t, &bit_speed, &bit_accel, &bit_angle, &torque_on_bit, &top_torque, &top_speed, &wob})
      v->reserve(static_cast<std::size_t>(expected / stride + 1));
  }
  void operator()(const StepState& s) {
    if (s.step < next_) return;  // steps increase: one integer division per kept sample, not per step
    if (s.step % stride) {
      next_ = s.step - s.step % stride + stride;
      return;
    }
    next_ = s.step + stride;
    t.push_back(s.t);
    bit_speed.push_back(s.bit_speed);
    bit_accel.push_back(s.bit_accel);
    bit_angle.push_back(s.bit_angle);
    torque_on_bit.push_back(s.torque_on_bit);
    top_torque.push_back(s.top_torque);
    top_speed.push_back(s.top_speed);
    wob.push_back(s.wob);
  }

 private:
  long next_ = 0;  ///< the next step that may be kept
};

}  // namespace drill

namespace drill {

/// Top speed at which the SS curve last crosses `level` going up in speed: the speed below which
/// SS > level (section 4.2.2, 16 rad/s in the thesis). Linear interpolation between grid points.
/// NaN when SS stays on one side of the level over the whole grid.
inline double severity_threshold(const std::vector<double>& speeds, const std::vector<double>& ss,
                                 double level = 0.5) {
  require(speeds.size() == ss.size(), "severities", ss.size(), "must have one value per speed");
  std::vector<std::size_t> idx(speeds.size());
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return speeds[a] < speeds[b]; });
  for (std::size_t k = idx.size(); k-- > 1;) {
    const std::size_t lo = idx[k - 1], hi = idx[k];
    if (ss[lo] > level && ss[hi] <= level) {
      const double f = (ss[lo] - level) / (ss[lo] - ss[hi]);
      return speeds[lo] + f * (speeds[hi] - speeds[lo]);
    }
  }
  return std::nan("");
}

}  // namespace drill
