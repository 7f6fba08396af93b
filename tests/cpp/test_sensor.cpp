// The sensors' second-order Butterworth low-pass: unit DC gain, -3 dB and -90 degrees at the cutoff,
// the Butterworth step overshoot, the low-frequency group delay, second-order accuracy, restart
// from a recorded value and rate, and the pass-through when there is no filter.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "drill/sensor.hpp"
#include "error_text.hpp"

using namespace drill;

namespace {

/// Steady-state gain and phase [rad] of the filter for a sine of frequency f [Hz].
std::pair<double, double> response(double fc, double f, double dt) {
  LowPass2 lp(fc, dt);
  lp.reset(0.0, 0.0, 0.0);
  const double w = 2.0 * M_PI * f, T = 40.0 / f;  // settle, then fit the last 10 periods
  const long n = std::lround(T / dt);
  double sc = 0.0, ss = 0.0, cnt = 0.0;
  for (long i = 1; i <= n; ++i) {
    const double t = i * dt, y = lp.step(std::sin(w * t));
    if (t > 30.0 / f) {
      sc += y * std::cos(w * t);
      ss += y * std::sin(w * t);
      cnt += 1.0;
    }
  }
  // y = A sin(wt + phi) = A cos(phi) sin(wt) + A sin(phi) cos(wt)
  const double a = 2.0 * ss / cnt, b = 2.0 * sc / cnt;
  return {std::hypot(a, b), std::atan2(b, a)};
}

}  // namespace

TEST(LowPass2, GainAndPhaseOfASecondOrderButterworth) {
  const double fc = 10.0, dt = 1e-4;
  auto [g0, p0] = response(fc, 0.5, dt);
  EXPECT_NEAR(g0, 1.0, 1e-3);
  auto [gc, pc] = response(fc, fc, dt);
  EXPECT_NEAR(gc, 1.0 / std::sqrt(2.0), 1e-3);  // -3 dB at the cutoff
  EXPECT_NEAR(pc, -M_PI / 2.0, 2e-3);           // -90 degrees
  auto [g2, p2] = response(fc, 2.0 * fc, dt);
  EXPECT_NEAR(g2, 1.0 / std::sqrt(1.0 + 16.0), 1e-3);  // |H|^2 = 1 / (1 + (f/fc)^4)
  // low-frequency group delay 2 zeta / omega_c = sqrt(2) / (2 pi fc)
  auto [g1, p1] = response(fc, 1.0, dt);
  EXPECT_NEAR(-p1 / (2.0 * M_PI * 1.0), std::sqrt(2.0) / (2.0 * M_PI * fc), 3e-4);
}

TEST(LowPass2, StepOvershootIsTheButterworthOne) {
  const double fc = 10.0, dt = 1e-5;
  LowPass2 lp(fc, dt);
  lp.reset(0.0, 0.0, 1.0);  // a unit step at t = 0
  double peak = 0.0, y = 0.0;
  for (int i = 0; i < 50000; ++i) {
    y = lp.step(1.0);
    peak = std::max(peak, y);
  }
  EXPECT_NEAR(peak - 1.0, std::exp(-M_PI / std::sqrt(1.0 / 0.5 - 1.0)), 1e-4);  // 4.32 % for zeta = 1/sqrt(2)
  EXPECT_NEAR(y, 1.0, 1e-9);
}

TEST(LowPass2, TrapezoidalRuleIsSecondOrder) {
  // response at t = 0.1 s to x = sin(2 pi 7 t) against a reference with dt = 1e-6
  auto at = [](double dt) {
    LowPass2 lp(10.0, dt);
    lp.reset(0.0, 0.0, 0.0);
    const long n = std::lround(0.1 / dt);
    double y = 0.0;
    for (long i = 1; i <= n; ++i) y = lp.step(std::sin(2.0 * M_PI * 7.0 * i * dt));
    return y;
  };
  const double ref = at(1e-6);
  const double e1 = std::fabs(at(2e-3) - ref), e2 = std::fabs(at(1e-3) - ref);
  EXPECT_NEAR(std::log2(e1 / e2), 2.0, 0.1);
}

TEST(LowPass2, RestartsFromARecordedValueAndRate) {
  // a filter started from (y, y') at rest input 0 follows the free response of the ODE
  const double fc = 5.0, wc = 2.0 * M_PI * fc, dt = 1e-5;
  LowPass2 lp(fc, dt);
  lp.reset(1.0, 0.0, 0.0);
  const double z = 1.0 / std::sqrt(2.0), wd = wc * std::sqrt(1.0 - z * z);
  double y = 0.0;
  const long n = std::lround(0.05 / dt);
  for (long i = 1; i <= n; ++i) y = lp.step(0.0);
  const double t = n * dt, exact = std::exp(-z * wc * t) * (std::cos(wd * t) + z * wc / wd * std::sin(wd * t));
  EXPECT_NEAR(y, exact, 1e-8);
  EXPECT_NEAR(lp.value(), y, 0.0);
}

TEST(LowPass2, ZeroCutoffPassesTheInputAndBadValuesAreRefused) {
  LowPass2 lp(0.0, 1e-3);
  EXPECT_FALSE(lp.active());
  lp.reset(5.0, 1.0, 2.0);
  EXPECT_EQ(lp.value(), 2.0);
  EXPECT_EQ(lp.step(3.5), 3.5);
  EXPECT_NE(error_of([] { LowPass2(-1.0, 1e-3); }).find("sensors.lowpass_hz = -1"), std::string::npos);
  EXPECT_NE(error_of([] { LowPass2(10.0, 0.0); }).find("must be positive"), std::string::npos);
}
