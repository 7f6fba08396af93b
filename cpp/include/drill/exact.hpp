// Exact natural frequencies of the continuous string (Eq. 2.1) by the transfer-matrix method:
// the reference against which the FE frequencies converge.
//
// In a uniform section the state (angle, torque) at angular frequency w propagates as
//   [theta; T](x + L) = [cos kL, sin kL / Z; -Z sin kL, cos kL] [theta; T](x),  k = w / c, Z = G J k,
// a lumped inertia I at a section end takes the torque I theta'' = -w^2 I theta, so the shaft torque
// beyond it is T - w^2 I theta. Clamped top: theta = 0, T = 1; frequencies are the roots of T(bit) = 0.
#pragma once

#include <cmath>
#include <vector>

#include "drill/fem.hpp"

namespace drill {

/// Residual torque at the free bit for a unit torque at the clamped top, at frequency w [rad/s].
/// Lumped inertias must sit at section ends (node indices of the FE mesh).
inline double bit_torque_residual(const StringModel& s, double w) {
  double theta = 0.0, T = 1.0;
  int node = 0;
  auto add_lumped = [&](int n) {
    for (const auto& li : s.lumped)
      if (s.resolve_node(li.node) == n) T -= w * w * li.inertia * theta;
  };
  for (const Section& sec : s.sections) {
    const double k = w / sec.wave_speed(), Z = sec.shear_modulus() * sec.polar_moment() * k;
    const double c = std::cos(k * sec.length), sn = std::sin(k * sec.length);
    const double th = c * theta + sn / Z * T, tq = -Z * sn * theta + c * T;
    theta = th;
    T = tq;
    node += sec.elements;
    add_lumped(node);
  }
  return T;
}

/// First n exact natural frequencies [Hz] (scan with step dw [rad/s], then bisection).
inline std::vector<double> exact_frequencies_hz(const StringModel& s, int n, double dw = 1e-3) {
  require(n >= 1, "n", n, "must be at least 1");
  std::vector<double> out;
  double w0 = 1e-9, f0 = bit_torque_residual(s, w0);
  for (long it = 0; static_cast<int>(out.size()) < n; ++it) {
    require(it < 100000000L, "exact_frequencies_hz", n, "roots not found (increase dw)");
    const double w1 = w0 + dw, f1 = bit_torque_residual(s, w1);
    if (f0 * f1 < 0.0) {
      double lo = w0, hi = w1, flo = f0;
      for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
        const double mid = 0.5 * (lo + hi), fm = bit_torque_residual(s, mid);
        if (flo * fm <= 0.0) hi = mid;
        else lo = mid, flo = fm;
      }
      out.push_back(0.5 * (lo + hi) / (2.0 * M_PI));
    }
    w0 = w1;
    f0 = f1;
  }
  return out;
}

}  // namespace drill
