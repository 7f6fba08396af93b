// Bit-rock laws (Eqs. 3.1-3.3, 5.1, 5.3): the thesis's values, limits, units and derivatives.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "drill/bitrock.hpp"
#include "drill/config.hpp"

using namespace drill;

namespace {
const double RPM = M_PI / 30.0;  // 1 RPM in rad/s
}

TEST(BitRock, TuckerWangFieldFitInRadPerSecond) {
  // THESIS-NOTES: 10.3 kN m at 1 rad/s and 5.0 kN m at 200 RPM.
  const BitRockLaw tw = thesis_tucker_wang();
  EXPECT_NEAR(tw.torque(1.0, 0.0, 245e3), 10300.0, 60.0);
  EXPECT_NEAR(tw.torque(200 * RPM, 0.0, 245e3), 5000.0, 100.0);
  EXPECT_NEAR(tw.torque(0.0, 0.0, 245e3), 0.0, 1e-9);
  EXPECT_NEAR(tw.torque(-1.0, 0.0, 245e3), -tw.torque(1.0, 0.0, 245e3), 1e-9);  // odd law
}

TEST(BitRock, HystereticFitReadInRpm) {
  // THESIS-NOTES: with RPM the section 3.2 fit goes from about 12.8 kN m at 10 RPM to 7.8 at 200 RPM.
  const BitRockLaw h = thesis_hysteretic(0.0, SpeedUnit::rpm);
  EXPECT_NEAR(h.torque(10 * RPM, 0.0, 245e3), 12.8e3, 0.1e3);
  EXPECT_NEAR(h.torque(200 * RPM, 0.0, 245e3), 7.8e3, 0.1e3);
  // The same numbers read in rad/s peak near 5 rad/s at about 13 kN m.
  const BitRockLaw hr = thesis_hysteretic(0.0, SpeedUnit::rad_s);
  EXPECT_NEAR(hr.torque(5.0, 0.0, 245e3), 13.0e3, 0.2e3);
  EXPECT_NEAR(hr.torque(200 * RPM, 0.0, 245e3), 11.6e3, 0.2e3);
}

TEST(BitRock, HystereticReducesToTuckerWangForB4Is1B5Is2) {
  // Section 3.2: b4 = 1, b5 = 2 and H = 0 retrieve Eq. (3.1).
  BitRockLaw h = thesis_hysteretic(0.0, SpeedUnit::rad_s);
  h.b = {4700.0, 1.67e4, 5.30, 3.45, 1.0, 2.0};
  const BitRockLaw tw = thesis_tucker_wang();
  for (double v : {0.01, 0.3, 1.0, 4.0, 25.0}) EXPECT_NEAR(h.torque(v, 0.0, 245e3), tw.torque(v, 0.0, 245e3), 1e-8);
}

TEST(BitRock, HysteresisBoundsTheFractionTermByOnePlusMinusBeta1) {
  const double v = 30 * RPM;
  const BitRockLaw h0 = thesis_hysteretic(0.0, SpeedUnit::rpm), h = thesis_hysteretic(0.56, SpeedUnit::rpm);
  const double tanh_part = 3478.0 * std::tanh(938.0 * 30.0);
  const double frac = h0.torque(v, 0.0, 245e3) - tanh_part;
  EXPECT_NEAR(h.torque(v, 100.0, 245e3) - tanh_part, 1.56 * frac, 1e-6 * frac);   // accelerating: upper
  EXPECT_NEAR(h.torque(v, -100.0, 245e3) - tanh_part, 0.44 * frac, 1e-6 * frac);  // decelerating: lower
  EXPECT_NEAR(h.torque(v, 0.0, 245e3), h0.torque(v, 0.0, 245e3), 1e-9);
  // the loop thickness shrinks as speed grows (H only multiplies the fraction term)
  const double w_low = h.torque(10 * RPM, 100, 245e3) - h.torque(10 * RPM, -100, 245e3);
  const double w_high = h.torque(300 * RPM, 100, 245e3) - h.torque(300 * RPM, -100, 245e3);
  EXPECT_GT(w_low, w_high);
}

TEST(BitRock, LinearInWeightOnBit) {
  const BitRockLaw h = thesis_hysteretic(0.14, SpeedUnit::rpm);
  const double v = 50 * RPM;
  EXPECT_NEAR(h.torque(v, 3.0, 200e3) / h.torque(v, 3.0, 245e3), 200.0 / 245.0, 1e-12);  // 0.816
}

TEST(BitRock, RpmParametersAreTheRadPerSecondLawWithConvertedArguments) {
  BitRockLaw r = thesis_hysteretic(0.14, SpeedUnit::rpm);
  BitRockLaw s = r;
  s.speed_unit = SpeedUnit::rad_s;
  const double v = 40 * RPM, a = 5.0;
  EXPECT_NEAR(r.torque(v, a, 245e3), s.torque(40.0, a * 30.0 / M_PI, 245e3), 1e-9);
}

TEST(BitRock, PolynomialPiecewiseAndHystereticForm) {
  BitRockLaw p;
  p.kind = BitRockLaw::Kind::polynomial;
  p.speed_unit = SpeedUnit::rpm;
  p.wob_ref = 500.0;
  p.a = {0.5, 100.0, 1.2, 5.0, 1.6, -0.004, 1e-5, 0.0};
  p.ref_speed = 80.0;
  const double g = 1.36;
  EXPECT_NEAR(p.torque(0.5 * RPM, 0, 500), g * (0.5 + 100 * 0.5), 1e-9);   // v <= 0.01 ref
  EXPECT_NEAR(p.torque(2.0 * RPM, 0, 500), g * (1.2 + 5.0 * 2.0), 1e-9);   // 0.01 < v <= 0.05 ref
  EXPECT_NEAR(p.torque(100 * RPM, 0, 500), g * (1.6 - 0.4 + 0.1), 1e-9);   // cubic branch
  BitRockLaw ph = p;
  ph.kind = BitRockLaw::Kind::polynomial_hysteretic;
  ph.beta1 = 0.2;
  ph.beta2 = 1.0;
  EXPECT_NEAR(ph.torque(100 * RPM, 1e3, 500), 1.2 * p.torque(100 * RPM, 0, 500), 1e-9);  // Eq. (5.3)
}

TEST(BitRock, PolynomialIsOddWithItsStaticTorqueAtRest) {
  BitRockLaw p;
  p.kind = BitRockLaw::Kind::polynomial;
  p.speed_unit = SpeedUnit::rpm;
  p.wob_ref = 500.0;
  p.a = {2.5, -0.3, 2.2, -0.01, 1.6, -0.004, 1e-5, 0.0};
  p.ref_speed = 80.0;
  EXPECT_NEAR(p.static_torque(500.0), 1.36 * 2.5, 1e-12);        // Eq. (5.1) at rest: 1.36 a0
  EXPECT_NEAR(p.static_torque(250.0), 0.5 * 1.36 * 2.5, 1e-12);  // scales with W / W_ref
  EXPECT_NEAR(p.torque(0.0, 0, 500), p.static_torque(500.0), 1e-12);
  for (double v : {0.3, 2.0, 50.0, 120.0}) EXPECT_NEAR(p.torque(-v * RPM, 0, 500), -p.torque(v * RPM, 0, 500), 1e-12);
  EXPECT_EQ(thesis_tucker_wang().static_torque(245e3), 0.0);  // regularized laws: zero at rest
  EXPECT_EQ(thesis_hysteretic(0.14, SpeedUnit::rpm).static_torque(245e3), 0.0);
  p.a[0] = 0.0;
  EXPECT_EQ(p.static_torque(500.0), 0.0);
}

TEST(BitRock, DerivativesMatchFiniteDifferences) {
  for (auto law : {thesis_tucker_wang(), thesis_hysteretic(0.56, SpeedUnit::rpm), thesis_hysteretic(0.14, SpeedUnit::rad_s)}) {
    for (double v : {0.5, 3.0, 12.0}) {
      for (double a : {-2.0, 0.01, 3.0}) {
        const TorqueEval e = law.eval(v, a, 245e3);
        const double h = 1e-6;
        const double dv = (law.torque(v + h, a, 245e3) - law.torque(v - h, a, 245e3)) / (2 * h);
        const double da = (law.torque(v, a + h, 245e3) - law.torque(v, a - h, 245e3)) / (2 * h);
        EXPECT_NEAR(e.dT_dv, dv, 1e-4 * (1 + std::fabs(dv))) << v << " " << a;
        EXPECT_NEAR(e.dT_da, da, 1e-4 * (1 + std::fabs(da))) << v << " " << a;
      }
    }
  }
}

TEST(BitRock, BadLawsAreRefusedNamingTheField) {
  auto msg = [](const json& j) {
    try {
      detail::parse_law(j).validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  json ok = {{"type", "hysteretic"}, {"speed_unit", "rpm"}, {"wob_ref_n", 245e3}, {"b0", 3478}, {"b1", 938},
             {"b2", 2.56}, {"b3", 0.38}, {"b4", 0.78}, {"b5", 1.1}, {"beta1", 0.14}, {"beta2", 10.6}};
  EXPECT_EQ(msg(ok), "no error");
  json j = ok;
  j["type"] = "coulomb";
  EXPECT_NE(msg(j).find("law.type = \"coulomb\""), std::string::npos);
  j = ok;
  j["speed_unit"] = "deg_s";
  EXPECT_NE(msg(j).find("law.speed_unit"), std::string::npos);
  j = ok;
  j["beta1"] = 1.5;
  EXPECT_NE(msg(j).find("law.beta1 = 1.5"), std::string::npos);
  j = ok;
  j.erase("b3");
  EXPECT_NE(msg(j).find("law.b3: missing"), std::string::npos);
  j = ok;
  j["b4"] = -1;
  EXPECT_NE(msg(j).find("law.b4 = -1"), std::string::npos);
  j = ok;
  j["alpha0"] = 1;
  EXPECT_NE(msg(j).find("law.alpha0"), std::string::npos);  // key of another law
}

// The value-only torque (used by the explicit scheme at every step) is the torque of eval() bit
// for bit, for every law, sign of speed and acceleration, and beta1 = 0.
TEST(BitRock, ValueOnlyTorqueIsBitIdenticalToEval) {
  std::vector<BitRockLaw> laws = {thesis_tucker_wang(), thesis_hysteretic(0.0, SpeedUnit::rpm),
                                  thesis_hysteretic(0.14, SpeedUnit::rpm), thesis_hysteretic(0.56, SpeedUnit::rad_s)};
  BitRockLaw poly;
  poly.kind = BitRockLaw::Kind::polynomial;
  poly.a = {100.0, -5.0, 95.0, -0.5, 90.0, -0.3, 0.01, -1e-4};
  poly.ref_speed = 100.0;
  laws.push_back(poly);
  poly.kind = BitRockLaw::Kind::polynomial_hysteretic;
  poly.beta1 = 0.3;
  poly.beta2 = 2.0;
  laws.push_back(poly);
  int compared = 0;
  for (const BitRockLaw& law : laws)
    for (double v : {-3.0, -1e-9, 0.0, 1e-12, 1e-3, 0.05, 0.5, 2.0, 16.0, 40.0})
      for (double a : {-50.0, -0.1, 0.0, 0.2, 30.0})
        for (double w : {100e3, 245e3}) {
          EXPECT_EQ(law.torque(v, a, w), law.eval(v, a, w).T)
              << BitRockLaw::kind_name(law.kind) << " v=" << v << " a=" << a << " w=" << w;
          ++compared;
        }
  EXPECT_EQ(compared, 6 * 10 * 5 * 2);
}
