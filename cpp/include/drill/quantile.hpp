// Sample quantiles of Monte Carlo results: the SS bands of Fig. 4.9 and the FRF envelopes of
// chapter 6 (Eq. 6.5 statistics).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "drill/errors.hpp"

namespace drill {

/// Type-7 sample quantile (linear interpolation between order statistics, numpy's default
/// "linear"): h = p (n - 1), x_(floor h) + (h - floor h) (x_(floor h + 1) - x_(floor h)).
/// `v` is reordered (partial selection, O(n)).
inline double quantile(std::vector<double>& v, double p) {
  require(!v.empty(), "quantile sample size", v.size(), "must not be empty");
  require(p >= 0.0 && p <= 1.0, "quantile level", p, "must lie in [0, 1]");
  const double h = (static_cast<double>(v.size()) - 1.0) * p;
  const std::size_t k = static_cast<std::size_t>(std::floor(h));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  const double lo = v[k];
  if (k + 1 >= v.size()) return lo;
  const double hi = *std::min_element(v.begin() + static_cast<std::ptrdiff_t>(k) + 1, v.end());
  return lo + (h - static_cast<double>(k)) * (hi - lo);
}

}  // namespace drill
