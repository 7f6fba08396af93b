// The thesis's torsional laws driven by the coupled model's axial state (axial.torque = "law",
// axial_torsional.hpp): the torque on the bit is the "law" block's (Eqs. 3.1, 3.2-3.3, 5.1, 5.3) at
// the bit speed and acceleration with the WOB the RGD axial inclusion's W, scaling with W / W_ref.
// Steady drilling is an equilibrium at T_law(Omega; W0), the torque halves when W_ref doubles, a
// non-regularized law (Eq. 5.1, a0 > 0) sticks and breaks away at its static torque at the current W,
// a bounce (W = 0) gives T = 0, and inconsistent configurations are refused naming axial.torque.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "drill/presets.hpp"
#include "coupled_trace.hpp"
#include "drill/simulation.hpp"
#include "error_text.hpp"

using namespace drill;

namespace {

/// The rgd-field preset with its torque on bit from `law` at the axial WOB.
Config config_by_law(const BitRockLaw& law, double duration = 2.0) {
  Config c = preset("rgd-field");
  c.sim.duration = duration;
  c.transient = 0.5 * duration;
  c.axial.rgd.torque = AxialTorque::law;
  c.law = law;
  return c;
}

/// Eq. (5.1) reduced to a Coulomb law with static torque: gain a0 = a2 = a4 = T0, the rest 0, so
/// T = T0 sign(v) W / W_ref moving and |T| <= T0 W / W_ref at rest.
BitRockLaw axial_coulomb_law(double T0, double wob_ref = 150e3) {
  BitRockLaw l;
  l.kind = BitRockLaw::Kind::polynomial;
  l.speed_unit = SpeedUnit::rad_s;
  l.wob_ref = wob_ref;
  l.a = {T0, 0.0, T0, 0.0, T0, 0.0, 0.0, 0.0};
  l.ref_speed = 4.0;
  l.gain = 1.0;
  return l;
}

/// The thesis-field law (Eqs. 3.2-3.3, section 3.2, beta1 = 0.14, RPM) with its level set by W_ref.
BitRockLaw hysteretic_field_law(double wob_ref = 245e3) {
  BitRockLaw l = thesis_hysteretic(0.14, SpeedUnit::rpm);
  l.wob_ref = wob_ref;
  return l;
}

using test::coupled_trace;

}  // namespace

TEST(AxialLawTorque, SteadyDrillingIsAnEquilibriumAtTheLawsTorqueOnTheSteadyWob) {
  // W0 is RGD's closed form (a zeta eps d0 + a l sigma, docs/axial.md), the torque the law's at the
  // bit speed Omega, zero acceleration and W0: T_law(Omega; W0) = T_law(Omega; W_ref) W0 / W_ref
  for (const BitRockLaw& law : {hysteretic_field_law(), thesis_tucker_wang(), axial_coulomb_law(9000.0)}) {
    for (AxialTop top : {AxialTop::hook_load, AxialTop::feed}) {
      Config c = config_by_law(law);
      test::steady_start(c, top);
      Simulation sim(c);
      const AxialTorsional& m = *sim.coupled();
      const double om = c.top_speed;
      const AxialTorsional::Steady st = m.steady(om);
      const RgdBit& b = c.axial.rgd.bit;
      const std::string what = BitRockLaw::kind_name(law.kind) + " " + to_string(top);
      EXPECT_NEAR(st.wob, test::rgd_steady_wob(b, st.depth), 1e-9 * st.wob) << what;
      if (top == AxialTop::hook_load) EXPECT_NEAR(st.wob, 150e3, 1e-9 * 150e3) << what;
      const double T0 = law.torque(om, 0.0, st.wob);
      EXPECT_EQ(st.torque, T0) << what;
      EXPECT_NEAR(T0, law.torque(om, 0.0, law.wob_ref) * st.wob / law.wob_ref, 1e-12 * T0) << what;
      EXPECT_GT(T0, 0.0) << what;
      const ModelState s0 = m.steady_torsion(om, 0.0);
      const test::CoupledTrace tr = coupled_trace(sim, &s0);
      ASSERT_EQ(static_cast<long>(tr.s.size()), c.sim.steps() + 1);
      for (std::size_t i = 0; i < tr.a.size(); i += 97) {
        ASSERT_NEAR(tr.a[i].wob, st.wob, 1e-7 * st.wob) << what << " t = " << tr.a[i].t;
        ASSERT_NEAR(tr.s[i].torque_on_bit, T0, 1e-7 * T0) << what << " t = " << tr.a[i].t;
        ASSERT_NEAR(tr.a[i].rop, st.rop, 1e-7 * st.rop) << what << " t = " << tr.a[i].t;
        ASSERT_NEAR(tr.s[i].bit_speed, om, 1e-9 * om) << what << " t = " << tr.a[i].t;
      }
    }
  }
}

TEST(AxialLawTorque, DoublingTheReferenceWobHalvesTheTorqueAtTheSameState) {
  // T_law scales with W / W_ref (section 3.3): the same state (the same W at the step's start) with
  // W_ref doubled gives half the torque, to the last bit for the laws without hysteresis
  for (const BitRockLaw& law : {thesis_tucker_wang(), axial_coulomb_law(9000.0), hysteretic_field_law()}) {
    BitRockLaw twice = law;
    twice.wob_ref = 2.0 * law.wob_ref;
    Simulation a(config_by_law(law, 0.01)), b(config_by_law(twice, 0.01));
    const double om = a.config().top_speed;
    EXPECT_EQ(b.coupled()->steady(om).torque, 0.5 * a.coupled()->steady(om).torque);
    // the bit slipping slower and faster than the top (a bit coming to rest is held by whatever the
    // string applies, up to the static torque: not a torque of the law's level)
    for (const ModelState& s0 : {a.coupled()->steady_torsion(om, 0.3), a.coupled()->steady_torsion(om, -0.5)}) {
      const test::CoupledTrace ta = coupled_trace(a, &s0), tb = coupled_trace(b, &s0);
      const std::string what = BitRockLaw::kind_name(law.kind) + " from v = " + std::to_string(ta.s[0].bit_speed);
      ASSERT_EQ(ta.a[0].wob, tb.a[0].wob) << what;
      ASSERT_EQ(ta.s[0].bit_speed, tb.s[0].bit_speed) << what;
      if (law.beta1 == 0.0) EXPECT_EQ(tb.s[0].torque_on_bit, 0.5 * ta.s[0].torque_on_bit) << what;
      else EXPECT_NEAR(tb.s[0].torque_on_bit, 0.5 * ta.s[0].torque_on_bit, 0.2 * ta.s[0].torque_on_bit) << what;
    }
  }
  // with hysteresis the law at a fixed acceleration scales exactly; at steady drilling (a = 0) so does
  // the run's torque
  const BitRockLaw h = hysteretic_field_law(), h2 = [&] {
    BitRockLaw x = h;
    x.wob_ref *= 2.0;
    return x;
  }();
  EXPECT_EQ(h2.torque(3.0, 0.7, 150e3), 0.5 * h.torque(3.0, 0.7, 150e3));
}

TEST(AxialLawTorque, ANonRegularizedLawSticksAndBreaksAwayAtItsStaticTorqueAtTheCurrentWob) {
  // from rest (Eq. 2.10: the string untwisted, the bit at rest to the modal truncation, which leaves
  // it turning slowly at first) with Eq. (5.1) as a Coulomb law: the bit comes to rest and stays
  // there, its torque the string's, within the static torque a0 W / W_ref at the step's W, until the
  // string's torque reaches it; it breaks away with exactly that torque
  const BitRockLaw law = axial_coulomb_law(9000.0);
  Simulation sim(config_by_law(law, 3.0));
  const double om = sim.config().top_speed;
  const ModelState rest = sim.integrator().initial_state(om);
  const test::CoupledTrace tr = coupled_trace(sim, &rest);
  const double tol = 1e-12 * (1.0 + om);  // bit_rest_tolerance
  std::size_t k0 = 0;
  while (k0 < tr.s.size() && std::fabs(tr.s[k0].bit_speed) > tol) ++k0;
  ASSERT_LT(k0, 20u) << "the bit did not come to rest at once";
  std::size_t i = k0;
  for (; i < tr.s.size() && std::fabs(tr.s[i].bit_speed) <= tol; ++i) {
    const double Ts = law.static_torque(tr.a[i].wob);
    ASSERT_GT(Ts, 0.0) << tr.s[i].t;
    if (i + 1 < tr.s.size() && std::fabs(tr.s[i + 1].bit_speed) > tol) {
      EXPECT_EQ(tr.s[i].torque_on_bit, Ts) << "break-away at t = " << tr.s[i].t;  // T = Ts(W), sign(0) = 0
    } else {
      ASSERT_LE(std::fabs(tr.s[i].torque_on_bit), Ts * (1.0 + 1e-12)) << "stuck at t = " << tr.s[i].t;
    }
  }
  ASSERT_LT(i, tr.s.size()) << "never broke away";
  EXPECT_GT(i - k0, 100u);               // stuck for a while: the string winds up first
  EXPECT_GT(tr.s[i].bit_speed, 0.0);     // then it turns forwards
  EXPECT_GT(tr.s[i - 1].torque_on_bit, 0.5 * law.static_torque(150e3));
  // every step at rest, the first stick and any later one of the stick-slip: within the static torque
  // at that step's W, and at it exactly on the step the bit breaks away
  long stuck = 0, breaks = 0;
  for (std::size_t k = 0; k + 1 < tr.s.size(); ++k) {
    if (std::fabs(tr.s[k].bit_speed) > tol) continue;
    ++stuck;
    const double Ts = law.static_torque(tr.a[k].wob);
    ASSERT_LE(std::fabs(tr.s[k].torque_on_bit), Ts * (1.0 + 1e-12)) << "t = " << tr.s[k].t;
    if (std::fabs(tr.s[k + 1].bit_speed) > tol) {
      ++breaks;
      EXPECT_EQ(std::fabs(tr.s[k].torque_on_bit), Ts) << "break-away at t = " << tr.s[k].t;
    }
  }
  EXPECT_GE(stuck, static_cast<long>(i - k0));
  EXPECT_GE(breaks, 1);
}

TEST(AxialLawTorque, BitBounceGivesZeroTorqueAndNoNaN) {
  for (const BitRockLaw& law : {hysteretic_field_law(), axial_coulomb_law(9000.0)}) {
    Config c = config_by_law(law, 3.0);
    c.axial.rgd.disturbance = 50.0;  // the bit thrown up at 49 V0
    Simulation sim(c);
    const test::CoupledTrace tr = coupled_trace(sim);
    long off = 0, back = 0;
    for (std::size_t i = 0; i < tr.a.size(); ++i) {
      const AxialStep& a = tr.a[i];
      ASSERT_TRUE(std::isfinite(a.wob) && std::isfinite(tr.s[i].torque_on_bit) && std::isfinite(tr.s[i].bit_speed))
          << a.t;
      ASSERT_GE(a.wob, 0.0);
      if (!a.contact) {
        ++off;
        ASSERT_EQ(a.wob, 0.0);
        ASSERT_EQ(tr.s[i].torque_on_bit, 0.0);
      } else if (off > 0) {
        ++back;
      }
    }
    EXPECT_GT(off, 10) << BitRockLaw::kind_name(law.kind);
    EXPECT_GT(back, 10) << BitRockLaw::kind_name(law.kind);  // it lands
  }
}

TEST(AxialLawTorque, DefaultIsRgdAndTheLawChangesOnlyTheTorque) {
  // the default torque is RGD's; with the law the axial side is the same RGD inclusion, so steady
  // drilling has the same W0, V0 and depth of cut
  const Config rgd = preset("rgd-field");
  EXPECT_EQ(rgd.axial.rgd.torque, AxialTorque::rgd);
  Simulation a(rgd), b(config_by_law(hysteretic_field_law()));
  const AxialTorsional::Steady sa = a.coupled()->steady(4.0), sb = b.coupled()->steady(4.0);
  EXPECT_EQ(sa.wob, sb.wob);
  EXPECT_EQ(sa.rop, sb.rop);
  EXPECT_EQ(sa.depth, sb.depth);
  EXPECT_NE(sa.torque, sb.torque);
}

TEST(AxialLawTorque, ConfigurationErrorsNameAxialTorque) {
  const json j = preset_json("rgd-field");
  auto refused = [](json x, const std::string& field) {
    try {
      parse_config(x);
      ADD_FAILURE() << "accepted; expected an error naming " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  const json law = preset_json("thesis-field")["law"];
  {
    json x = j;
    x["axial"]["torque"] = "xyz";
    refused(x, "axial.torque");
    x["law"] = law;  // named as an unknown torque, not as an unused law block
    refused(x, "axial.torque");
  }
  {
    json x = j;
    x["axial"]["torque"] = 3;
    refused(x, "axial.torque");
  }
  {
    json x = j;
    x["axial"]["torque"] = "law";  // without a "law" block: nothing to evaluate
    refused(x, "axial.torque");
  }
  {
    json x = j;
    x["axial"]["torque"] = "law";
    x["law"] = law;
    x["simulation"]["acceleration"] = "lagged";  // the coupled step solves Eq. (A.1) with the torque
    refused(x, "axial.torque");
  }
  {
    json x = j;
    x["axial"]["torque"] = "law";
    x["law"] = law;
    x["law"]["type"] = "xyz";
    refused(x, "law.type");
    x["law"] = law;
    x["law"]["b3"] = -1.0;
    refused(x, "law.b3");
  }
  {
    json x = j;
    x["law"] = law;  // a law block with RGD's torque: refused, pointing at axial.torque = "law"
    refused(x, "config.law");
    refused(x, "axial.torque");
  }
  // the option round-trips through JSON; RGD's default is written explicitly
  json x = j;
  x["axial"]["torque"] = "law";
  x["law"] = law;
  const Config c = parse_config(x);
  EXPECT_EQ(c.axial.rgd.torque, AxialTorque::law);
  EXPECT_EQ(c.law, parse_config(preset_json("thesis-field")).law);
  EXPECT_EQ(to_json(parse_config(to_json(c))), to_json(c));
  EXPECT_EQ(to_json(c).at("axial").at("torque"), "law");
  EXPECT_TRUE(to_json(c).contains("law"));
  const json d = to_json(parse_config(j));
  EXPECT_EQ(d.at("axial").at("torque"), "rgd");
  EXPECT_FALSE(d.contains("law"));
}
