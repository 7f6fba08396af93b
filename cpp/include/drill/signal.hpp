// Boundary inputs of a simulation: a constant or a uniformly sampled series.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "drill/errors.hpp"

namespace drill {

/// A scalar input that is either constant (`samples` empty) or sampled at t0 + k dt with linear
/// interpolation in between and held constant outside the sampled span.
struct Signal {
  double value = 0.0;
  std::vector<double> samples;
  double t0 = 0.0, dt = 0.0;

  static Signal constant(double v) { return Signal{v, {}, 0.0, 0.0}; }
  static Signal sampled(std::vector<double> s, double t0, double dt) { return Signal{0.0, std::move(s), t0, dt}; }

  bool is_constant() const { return samples.empty(); }

  void validate(const std::string& field) const {
    if (is_constant()) {
      require_finite(value, field);
      return;
    }
    require_positive(dt, field + ".dt_s");
    require_finite(t0, field + ".t0_s");
    for (std::size_t k = 0; k < samples.size(); ++k)
      if (!std::isfinite(samples[k])) require_finite(samples[k], field + "[" + std::to_string(k) + "]");
  }

  double at(double t) const { return samples.empty() ? value : at_grid(grid(t)); }

  /// Time derivative of the interpolant (slope of the segment holding t; 0 outside).
  double rate(double t) const { return samples.size() < 2 ? 0.0 : rate_grid(grid(t)); }

  /// t on the sampling grid, x = (t - t0) / dt: one division shared by the signals sampled on the
  /// same grid (the same t0 and dt), whose at_grid(x) and rate_grid(x) are at(t) and rate(t).
  double grid(double t) const { return (t - t0) / dt; }
  /// at(t) of a sampled signal from x = grid(t).
  double at_grid(double x) const {
    if (x <= 0.0) return samples.front();
    const std::size_t k = static_cast<std::size_t>(x);
    if (k + 1 >= samples.size()) return samples.back();
    const double f = x - static_cast<double>(k);
    return samples[k] + f * (samples[k + 1] - samples[k]);
  }
  /// rate(t) of a signal of two samples or more from x = grid(t).
  double rate_grid(double x) const {
    if (x < 0.0) return 0.0;
    const std::size_t k = static_cast<std::size_t>(x);
    if (k + 1 >= samples.size()) return 0.0;
    return (samples[k + 1] - samples[k]) / dt;
  }
};

}  // namespace drill
