// The bit-rock law registry (laws/registry.hpp): every registered law has a unique name and keys,
// is parsed from its name and written back through the configuration, and runs the same in both
// SIMD kernels (its LawAtSpeed, LawAtSpeedDv) as on the scalar path (its at_speed).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "drill/batched_integrator.hpp"
#include "drill/config.hpp"
#include "drill/presets.hpp"
#include "drill/simulation.hpp"
#include "varied_runs.hpp"

using namespace drill;

namespace {

/// A "law" block of kind k with every key of its variant at 0.5, a value all their bounds admit; the
/// static torque's ageing (optional, for the laws with a static torque, on the scalar path only) left
/// absent: test_integrator.cpp and test_config.cpp test it.
json law_json(BitRockLaw::Kind k) {
  const std::string type = BitRockLaw::kind_name(k);
  json j = {{"type", type}, {"speed_unit", "rad_s"}, {"wob_ref_n", 1000.0}};
  for (const std::string& key : schema::keys("law", type))
    if (!j.contains(key) && key != "static_ageing" && key != "static_ageing_s") j[key] = 0.5;
  return j;
}

/// The test rig (Table 5.1, one mode) with the law of kind k, 4 s long, in `scheme`.
Config rig_with(BitRockLaw::Kind k, Scheme scheme) {
  json j = preset_json("thesis-rig");
  j["law"] = law_json(k);
  Config c = parse_config(j);
  c.sim.scheme = scheme;
  c.sim.duration = 4.0;
  c.transient = 1.0;
  return c;
}

}  // namespace

TEST(LawRegistry, NamesAndKeysAreUniqueAndInTheListsOrder) {
  const schema::Block& block = schema::block("law");
  ASSERT_EQ(block.variants.size(), std::size(BitRockLaw::kinds));
  std::set<std::string> names;
  for (std::size_t i = 0; i < std::size(BitRockLaw::kinds); ++i) {
    const Named<BitRockLaw::Kind>& k = BitRockLaw::kinds[i];
    EXPECT_TRUE(names.insert(k.name).second) << k.name;
    EXPECT_EQ(static_cast<std::size_t>(k.value), i) << k.name;
    EXPECT_EQ(BitRockLaw::parse_kind(k.name), k.value);
    EXPECT_EQ(block.variants[i].type, k.name);
    std::set<std::string> keys;  // the block's keys and the variant's, none twice
    for (const schema::Field& f : block.fields) keys.insert(f.key);
    for (const schema::Field& f : block.variants[i].fields) EXPECT_TRUE(keys.insert(f.key).second) << k.name << "." << f.key;
  }
}

TEST(LawRegistry, EveryLawRoundTripsThroughTheConfiguration) {
  for (const Named<BitRockLaw::Kind>& k : BitRockLaw::kinds) {
    const Config c = rig_with(k.value, Scheme::modified_euler);
    EXPECT_EQ(c.law.kind, k.value);
    const json written = to_json(c);
    EXPECT_EQ(written.at("law"), law_json(k.value)) << k.name;
    const Config again = parse_config(written);
    EXPECT_TRUE(again.law == c.law) << k.name;
    BitRockLaw other = c.law;
    other.wob_ref *= 2.0;
    EXPECT_FALSE(other == c.law);
  }
}

TEST(LawRegistry, EveryLawRunsInTheKernelsAsOnTheScalarPath) {
  // The kernels' exp and log are Highway's (within a few ulp of libm's) and the exact modal kernel
  // uses FMA: the torques agree to rounding, and bit for bit for Eq. (5.1) in modified Euler (no
  // transcendental function, BatchedIntegrator.ReproducesTheScalarBitsWithoutExpLogOnOneMode).
  for (const Named<BitRockLaw::Kind>& k : BitRockLaw::kinds)
    for (Scheme scheme : {Scheme::modified_euler, Scheme::exact_modal}) {
      const Simulation sim(rig_with(k.value, scheme));
      const BatchedIntegrator b(sim.integrator());
      const std::vector<Inputs> in = varied_inputs(sim, 3);
      ASSERT_TRUE(b.supports(in[0]));
      std::vector<StepTrace> tr(in.size());
      const std::vector<const ModelState*> start(in.size(), nullptr);
      b.run(in.data(), start.data(), in.size(), tr.data());
      for (std::size_t r = 0; r < in.size(); ++r) {
        StepTrace ref;
        sim.integrator().run(in[r], ref);
        ASSERT_EQ(tr[r].T.size(), ref.T.size());
        if (k.value == BitRockLaw::Kind::polynomial && scheme == Scheme::modified_euler) {
          EXPECT_TRUE(tr[r] == ref) << "run " << r;
          continue;
        }
        double scale = 0.0, err = 0.0;
        for (std::size_t i = 0; i < ref.T.size(); ++i) {
          scale = std::max(scale, std::fabs(ref.T[i]));
          err = std::max(err, std::fabs(tr[r].T[i] - ref.T[i]));
        }
        EXPECT_GT(scale, 0.0);
        EXPECT_LE(err, 1e-9 * scale) << k.name << " " << to_string(scheme) << " run " << r;
      }
    }
}
