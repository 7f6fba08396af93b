// The value-only torque of the bit-rock laws (used by the explicit scheme at every step) is the
// torque of eval() bit for bit, for every law, sign of speed and acceleration, and beta1 = 0.
#include <gtest/gtest.h>

#include <vector>

#include "drill/bitrock.hpp"

using namespace drill;

TEST(BitRockTorque, ValueOnlyPathIsBitIdenticalToEval) {
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
