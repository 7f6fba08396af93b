// The rock surface under the blades (bit_profile.hpp): the RGD delay t_N of Phi(t) - Phi(t - t_N) =
// 2 pi / N and the depth of cut d = N [U(t) - U(t - t_N)] from the interpolated history, and a bounce
// leaving the rock uncut.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "drill/bit_profile.hpp"

using namespace drill;

namespace {

/// The history of a bit turning at phi(t) and advancing at u(t), sampled every dt up to t_end.
template <class Phi, class U>
BitProfile history(int N, double dt, double t_end, Phi phi, U u, double omega0, double d0) {
  BitProfile p(N, 0.0, phi(0.0), u(0.0), d0, omega0);
  const long n = std::lround(t_end / dt);
  for (long i = 1; i <= n; ++i) p.record(i * dt, phi(i * dt), u(i * dt));
  return p;
}

}  // namespace

TEST(BitProfile, DelayAtConstantSpeedIsTwoPiOverNOmega) {
  const int N = 4;
  const double om = 6.3, V = 0.007, dt = 5e-4, T = 3.0;
  const BitProfile p = history(N, dt, T, [&](double t) { return om * t; }, [&](double t) { return V * t; }, om,
                               2.0 * M_PI * V / om);
  const double tN = 2.0 * M_PI / (N * om);
  EXPECT_NEAR(p.delay(T, om * T), tN, 1e-12 * tN);
  // d = N [U(t) - U(t - t_N)] = N V t_N: the depth of cut per revolution 2 pi V / Omega
  EXPECT_NEAR(p.depth_of_cut(om * T, V * T), N * V * tN, 1e-9 * N * V * tN);
  // the initial surface (steady drilling before t = 0) gives the same numbers at t = 0
  const BitProfile p0(N, 0.0, 0.0, 0.0, 2.0 * M_PI * V / om, om);
  EXPECT_NEAR(p0.delay(0.0, 0.0), tN, 1e-12 * tN);
  EXPECT_NEAR(p0.depth_of_cut(0.0, 0.0), 2.0 * M_PI * V / om, 1e-12);
  // bounded memory: two sectors of samples, not the whole run
  EXPECT_LT(p.size(), static_cast<std::size_t>(2.0 * tN / dt) + 8);
}

TEST(BitProfile, DelayConvergesAtSecondOrderOnANonUniformRotation) {
  // Phi = om t + A sin(w t) (increasing: om > A w), U = V t + B sin(w t)
  const int N = 4;
  const double om = 6.0, A = 0.5, w = 7.0, V = 0.005, B = 1e-3, T = 2.0;
  auto phi = [&](double t) { return om * t + A * std::sin(w * t); };
  auto u = [&](double t) { return V * t + B * std::sin(w * t); };
  // exact t - t_N: phi(s) = phi(T) - 2 pi / N by bisection
  double lo = T - 1.0, hi = T;
  for (int k = 0; k < 200; ++k) (phi(0.5 * (lo + hi)) < phi(T) - 2.0 * M_PI / N ? lo : hi) = 0.5 * (lo + hi);
  const double s = 0.5 * (lo + hi), tN = T - s, d = N * (u(T) - u(s));
  double err_t[2], err_d[2];
  const double dts[2] = {2e-3, 1e-3};
  for (int k = 0; k < 2; ++k) {
    const BitProfile p = history(N, dts[k], T, phi, u, om, 2.0 * M_PI * V / om);
    err_t[k] = std::fabs(p.delay(T, phi(T)) - tN);
    err_d[k] = std::fabs(p.depth_of_cut(phi(T), u(T)) - d);
  }
  EXPECT_LT(err_t[0], 1e-5 * tN);
  EXPECT_LT(err_d[0], 1e-4 * std::fabs(d));
  EXPECT_GT(err_t[0] / err_t[1], 3.0);  // halving dt divides the error by about 4
  EXPECT_GT(err_d[0] / err_d[1], 3.0);
}

TEST(BitProfile, ABounceLeavesTheRockUncut) {
  // steady drilling (u = 0 at t = 0, 10 mm per revolution, two blades), then the bit lifted to
  // u = -2 mm for one sector (half a revolution), then back at u = 0 for the next sector
  const int N = 2;
  const double om = 2.0 * M_PI, V = 0.01, dt = 1e-3;
  BitProfile p(N, 0.0, 0.0, 0.0, 2.0 * M_PI * V / om, om);  // the surface one sector back: u = -5 mm to 0
  double t = 0.0;
  for (int i = 0; i < 1000; ++i) {
    t += dt;
    p.record(t, om * t, i < 500 ? -0.002 : 0.0);
  }
  // half a sector into the bounce the blade ahead had left -2.5 mm: the lifted bit cut it to -2 mm,
  // so the next blade at u = 0 cuts 2 mm: d = N 2 mm
  EXPECT_NEAR(p.depth_of_cut(1.5 * M_PI, 0.0), N * 0.002, 1e-9);
  // at the end of the bounce sector the rock (left at 0 before the bounce) was above the lifted bit:
  // it stays uncut, and the blade back at u = 0 cuts nothing (not the 2 mm of a surface that followed the bit)
  EXPECT_NEAR(p.depth_of_cut(2.0 * M_PI, 0.0), 0.0, 1e-9);
  EXPECT_LT(p.depth_of_cut(2.0 * M_PI, -0.001), 0.0);  // a bit above the surface: off the rock
}

TEST(BitProfile, TheLookupKeptByRecordIsTheInterpolation) {
  // record() keeps its lookup one sector back for the next step's at() and starts the next lookup
  // from its samples: on a bit that turns forwards, stops, turns back (less than a sector), bounces
  // and once jumps more than a sector in a step, at() and interpolate() there are the interpolation
  // over every sample (the test's own copy, bisected), to the bit, and cut() is depth_of_cut() and
  // delay(); the run is long enough for the buffer to drop and compact its old samples
  const int N = 3;
  const double om = 5.0, dt = 1e-3, d0 = 0.004;
  BitProfile p(N, 0.0, 0.0, 0.0, d0, om);
  std::vector<double> ts, ps, ss;  // every sample, as the constructor and record() push them
  for (int k = -8; k <= 0; ++k) {
    const double f = static_cast<double>(k) / 8;
    ts.push_back(f * p.sector() / om);
    ps.push_back(f * p.sector());
    ss.push_back(f * d0 / N);
  }
  auto ref = [&](double q) -> BitProfile::At {
    if (q <= ps.front()) return {ts.front(), ss.front()};
    if (q >= ps.back()) return {ts.back(), ss.back()};
    const std::size_t k = static_cast<std::size_t>(std::upper_bound(ps.begin(), ps.end(), q) - ps.begin());
    const double w = (q - ps[k - 1]) / (ps[k] - ps[k - 1]);
    return {ts[k - 1] + w * (ts[k] - ts[k - 1]), ss[k - 1] + w * (ss[k] - ss[k - 1])};
  };
  double phi = 0.0;
  for (int i = 1; i <= 30000; ++i) {
    const double t = i * dt;
    if (i == 3000) phi += 1.5 * p.sector();  // beyond the reach by more than a sector
    else phi += dt * om * (std::sin(0.003 * i) + 0.5) * (i % 700 < 100 ? 0.0 : 1.0);  // stuck, forwards, back
    const double u = 0.001 * t + (i % 1100 < 60 ? -0.003 : 0.0);                      // lifted off now and then
    if (phi > ps.back()) {
      ts.push_back(t);
      ss.push_back(std::max(u, ref(phi - p.sector()).surface));
      ps.push_back(phi);
    }
    p.record(t, phi, u);
    const double q = phi - p.sector();
    const BitProfile::At r = ref(q), a = p.at(q), b = p.interpolate(q);
    ASSERT_EQ(a.t, r.t) << "step " << i;
    ASSERT_EQ(a.surface, r.surface) << "step " << i;
    ASSERT_EQ(b.t, r.t) << "step " << i;
    ASSERT_EQ(b.surface, r.surface) << "step " << i;
    const BitProfile::Cut c = p.cut(t, phi, u + 1e-4);
    ASSERT_EQ(c.depth, p.depth_of_cut(phi, u + 1e-4)) << "step " << i;
    ASSERT_EQ(c.delay, p.delay(t, phi)) << "step " << i;
    ASSERT_EQ(c.depth, N * (u + 1e-4 - r.surface)) << "step " << i;
    ASSERT_EQ(c.delay, t - r.t) << "step " << i;
  }
  EXPECT_GT(ps.size(), 3u * 4096);  // the buffer has dropped and compacted samples
  EXPECT_LT(p.size(), ps.size() / 4);
}
