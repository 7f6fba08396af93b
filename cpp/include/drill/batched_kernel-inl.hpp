// The per-instruction-set kernel of batched_integrator.hpp: Highway compiles this file once per
// x86 target (foreach_target.h re-includes it with HWY_NAMESPACE = N_AVX3, N_AVX2, N_SSE4, ...),
// hence no include guard of its own but Highway's per-target toggle. Not to be included directly.
//
// One call steps one vector of independent runs (one run per lane) through the modified Euler
// scheme of Integrator::run_euler (Eqs. A.5-A.6 with Eq. A.1's bit acceleration solved by the
// safeguarded Newton iteration; the stick condition of Eqs. 5.1, 5.3) with an ideal top drive, or
// with the motor and the jack of run_euler on the lanes that have them (BatchStepsT). Every lane
// performs the scalar path's arithmetic in the same order
// (no FMA contraction: -ffp-contract=off in CMakeLists.txt), except that the modal dot products
// are summed mode by mode and exp/log are Highway's (contrib/math: exp within 1 ulp, log within 4
// ulp of the exact value). The Newton iteration is masked: a lane that has converged keeps its
// values while the others iterate, so a lane's bits never depend on the other lanes.
//
// ExactSteps does the same for the exact modal scheme (exact_modal.hpp, Integrator::run_exact_lanes
// on the scalar path): Eq. (3.3) with Eq. (A.1)'s acceleration at the step's end solved by
// Integrator::exact_newton's iteration masked across the lanes (a lane that leaves it finishes in
// the scalar solve_bit, lane by lane), the stick condition of Integrator::exact_bit, and one pass
// over the modes per step. It uses FMA (Highway's MulAdd: the same bits on AVX2 and AVX-512); a
// shortcut taken when every lane allows it (an exp skipped where every tanh is saturated, the top's
// acceleration term where no lane has one) gives each lane the values it computes otherwise.
//
// The coupled model's pass over the modes of its lanes (EulerPass, euler_lanes-inl.hpp) is compiled
// per target here too, within this file's toggle (one foreach_target.h per translation unit).
#if defined(DRILL_BATCHED_KERNEL_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef DRILL_BATCHED_KERNEL_INL_H_
#undef DRILL_BATCHED_KERNEL_INL_H_
#else
#define DRILL_BATCHED_KERNEL_INL_H_
#endif

#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

HWY_BEFORE_NAMESPACE();
namespace drill {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

/// Lanes of a double vector on this target: the width of a batch.
inline std::size_t BatchLanes() { return hn::Lanes(hn::ScalableTag<double>()); }

namespace batched_detail {
using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;

/// sign(x) = (x > 0) - (x < 0) (0 for NaN), as Integrator::sign.
HWY_INLINE V Sign(D d, V x) {
  return hn::IfThenElse(x > hn::Zero(d), hn::Set(d, 1.0), hn::IfThenElse(x < hn::Zero(d), hn::Set(d, -1.0), hn::Zero(d)));
}

/// tanh_sat of laws/at_speed.hpp: +-1 beyond |x| > 19.1, 1 - 2 / (e^2x + 1) otherwise.
HWY_INLINE V TanhSat(D d, V x) {
  const V lim = hn::Set(d, 19.1), one = hn::Set(d, 1.0);
  const M up = x > lim, dn = x < hn::Neg(lim);
  const V xc = hn::IfThenElse(up, lim, hn::IfThenElse(dn, hn::Neg(lim), x));  // Exp's valid range
  const V th = one - hn::Set(d, 2.0) / (hn::Exp(d, hn::Set(d, 2.0) * xc) + one);
  return hn::IfThenElse(up, one, hn::IfThenElse(dn, hn::Neg(one), th));
}

/// std::max(a, b) and std::min(a, b) bit for bit (NaN handling included).
HWY_INLINE V StdMax(V a, V b) { return hn::IfThenElse(a < b, b, a); }
HWY_INLINE V StdMin(V a, V b) { return hn::IfThenElse(b < a, b, a); }

/// TanhSat without its exp where every lane is saturated (the same values lane by lane).
HWY_INLINE V TanhSatSkip(D d, V x) {
  const V lim = hn::Set(d, 19.1);
  if (hn::AllTrue(d, hn::Or(x > lim, x < hn::Neg(lim)))) return hn::IfThenElse(x > lim, hn::Set(d, 1.0), hn::Set(d, -1.0));
  return TanhSat(d, x);
}

}  // namespace batched_detail
}  // namespace HWY_NAMESPACE
}  // namespace drill
HWY_AFTER_NAMESPACE();

// each law's LawAtSpeed and LawAtSpeedDv for this target (laws/registry.hpp), which use the above
#define DRILL_LAW_LANES
#include "drill/laws/registry.hpp"
#undef DRILL_LAW_LANES

HWY_BEFORE_NAMESPACE();
namespace drill {
namespace HWY_NAMESPACE {
namespace batched_detail {

/// BitRockLaw::at_speed for a vector of SI bit speeds (per-lane WOB factor w = W / W_ref): base,
/// frac and c of T(a) = base + frac (1 + c tanh(k a)); the speed derivatives are not needed here.
/// The law of law.kind by its LawAtSpeed (the switch is written here, not through BitRockLaw::visit,
/// so that the laws' code is inlined into this target's kernel).
HWY_INLINE void AtSpeed(D d, const BitRockLaw& law, double s, V v_si, V w, V& base, V& frac, V& c) {
  const V v = v_si * hn::Set(d, s), sg = Sign(d, v);
  base = hn::Zero(d);
  frac = hn::Zero(d);
  c = hn::Zero(d);
  switch (law.kind) {
#define DRILL_LAW_CASE(name, Law)                                \
  case BitRockLaw::Kind::name:                                   \
    LawAtSpeed(laws::Law{}, d, law, v, sg, base, frac, c);       \
    break;
    DRILL_BIT_ROCK_LAWS(DRILL_LAW_CASE)
#undef DRILL_LAW_CASE
  }
  base = base * w;
  frac = frac * w;
}

/// BitRockLaw::at_speed with the speed derivatives, for the exact modal scheme's Newton iteration
/// (the bit speed moves with the unknown there): T(v, a) = base + frac (1 + c tanh(k a)), SI
/// derivatives dbase, dfrac (Eqs. 3.1-3.3, 5.1, 5.3, WOB factor w applied), by the law's LawAtSpeedDv.
HWY_INLINE void AtSpeedDv(D d, const BitRockLaw& law, double s, V v_si, V w, V& base, V& frac, V& c, V& dbase,
                          V& dfrac) {
  const V v = v_si * hn::Set(d, s), sg = Sign(d, v);
  base = frac = c = dbase = dfrac = hn::Zero(d);
  switch (law.kind) {
#define DRILL_LAW_CASE(name, Law)                                              \
  case BitRockLaw::Kind::name:                                                 \
    LawAtSpeedDv(laws::Law{}, d, law, v, sg, base, frac, c, dbase, dfrac);     \
    break;
    DRILL_BIT_ROCK_LAWS(DRILL_LAW_CASE)
#undef DRILL_LAW_CASE
  }
  const V ws = w * hn::Set(d, s);
  base = base * w;
  frac = frac * w;
  dbase = dbase * ws;
  dfrac = dfrac * ws;
}

constexpr int EK = ExactModal::lane_kinds;

/// Coefficient q of mode j: the lane's own (per_lane) or the batch's shared one.
template <bool PerLane>
HWY_INLINE V Coef(D d, const double* coef, std::size_t N, int j, int q) {
  if constexpr (PerLane) return hn::LoadU(d, coef + (static_cast<std::size_t>(j) * EK + q) * N);
  else return hn::Set(d, coef[static_cast<std::size_t>(j) * EK + q]);
}

/// The modal sum of w = bit . ps over the state z, p at a step's start: mode j adds bpz_j z_j and
/// bpp_j p_j to the partial sums az and ap (even modes to one pair, odd modes to another: four
/// independent chains of FMA in registers), added in a fixed order by WSum.
template <bool PerLane>
HWY_INLINE void WAcc(D d, const double* coef, std::size_t N, int j, V z, V p, V& az, V& ap) {
  az = hn::MulAdd(Coef<PerLane>(d, coef, N, j, ExactModal::bpz), z, az);
  ap = hn::MulAdd(Coef<PerLane>(d, coef, N, j, ExactModal::bpp), p, ap);
}
HWY_INLINE V WSum(V a0, V a1, V a2, V a3) { return (a0 + a1) + (a2 + a3); }

/// w of the step starting at the state z, p (the sums of ExactUpdate without the update).
template <bool PerLane>
HWY_INLINE V ExactW(D d, int m, const double* HWY_RESTRICT coef, const double* HWY_RESTRICT z,
                    const double* HWY_RESTRICT p) {
  const std::size_t N = hn::Lanes(d);
  V a0 = hn::Zero(d), a1 = a0, a2 = a0, a3 = a0;
  int j = 0;
  for (; j + 1 < m; j += 2) {
    WAcc<PerLane>(d, coef, N, j, hn::LoadU(d, z + j * N), hn::LoadU(d, p + j * N), a0, a1);
    WAcc<PerLane>(d, coef, N, j + 1, hn::LoadU(d, z + (j + 1) * N), hn::LoadU(d, p + (j + 1) * N), a2, a3);
  }
  if (j < m) WAcc<PerLane>(d, coef, N, j, hn::LoadU(d, z + j * N), hn::LoadU(d, p + j * N), a0, a1);
  return WSum(a0, a1, a2, a3);
}

/// Mode j to the step's end (exact_modal.hpp): [z; p]_i+1 = Phi [z; p]_i + e Omega' - h0 T0 - h1 T1
/// (T0 the start torque, or the held torque where the bit stays at rest over the step; the Omega'
/// term where it is not zero: Moving, the lanes in `moving`), and its terms of the next step's w.
template <bool PerLane, bool Moving>
HWY_INLINE void ModeUpdate(D d, const double* HWY_RESTRICT coef, double* HWY_RESTRICT z, double* HWY_RESTRICT p,
                           int j, V dom, M moving, V T0, V T1, V& az, V& ap) {
  using Q = ExactModal;
  const std::size_t N = hn::Lanes(d), o = static_cast<std::size_t>(j) * N;
  const V zj = hn::LoadU(d, z + o), pj = hn::LoadU(d, p + o);
  V uz = hn::NegMulSub(Coef<PerLane>(d, coef, N, j, Q::hz1), T1, Coef<PerLane>(d, coef, N, j, Q::hz0) * T0);
  V up = hn::NegMulSub(Coef<PerLane>(d, coef, N, j, Q::hp1), T1, Coef<PerLane>(d, coef, N, j, Q::hp0) * T0);
  if constexpr (Moving) {
    uz = hn::IfThenElse(moving, hn::MulAdd(Coef<PerLane>(d, coef, N, j, Q::ez), dom, uz), uz);
    up = hn::IfThenElse(moving, hn::MulAdd(Coef<PerLane>(d, coef, N, j, Q::ep), dom, up), up);
  }
  const V zn = hn::MulAdd(Coef<PerLane>(d, coef, N, j, Q::zz), zj, hn::MulAdd(Coef<PerLane>(d, coef, N, j, Q::zp), pj, uz));
  const V pn = hn::MulAdd(Coef<PerLane>(d, coef, N, j, Q::pz), zj, hn::MulAdd(Coef<PerLane>(d, coef, N, j, Q::pp), pj, up));
  hn::StoreU(zn, d, z + o);
  hn::StoreU(pn, d, p + o);
  WAcc<PerLane>(d, coef, N, j, zn, pn, az, ap);
}

/// Every mode to the step's end (ModeUpdate), fused with the modal sum of the next step's w (in
/// ExactW's order).
template <bool PerLane, bool Moving>
HWY_INLINE V ExactUpdate(D d, int m, const double* HWY_RESTRICT coef, double* HWY_RESTRICT z,
                         double* HWY_RESTRICT p, V dom, M moving, V T0, V T1) {
  V a0 = hn::Zero(d), a1 = a0, a2 = a0, a3 = a0;
  int j = 0;
  for (; j + 1 < m; j += 2) {
    ModeUpdate<PerLane, Moving>(d, coef, z, p, j, dom, moving, T0, T1, a0, a1);
    ModeUpdate<PerLane, Moving>(d, coef, z, p, j + 1, dom, moving, T0, T1, a2, a3);
  }
  if (j < m) ModeUpdate<PerLane, Moving>(d, coef, z, p, j, dom, moving, T0, T1, a0, a1);
  return WSum(a0, a1, a2, a3);
}

/// sign(F) min(max(|F| - Ts, 0), Tsf): string_share (euler_bit.hpp).
HWY_INLINE V StringShare(D d, V F, V Ts, V Tsf) {
  return Sign(d, F) * StdMin(StdMax(hn::Abs(F) - Ts, hn::Zero(d)), Tsf);
}

/// Steps of the exact modal scheme (ExactSteps below) with the coefficient layout PerLane.
template <bool PerLane>
HWY_INLINE void ExactStepsT(const ExactStepArgs& a) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const BitRockLaw& law = *a.law;
  const double s = a.speed_factor;
  const V dt = hn::Set(d, a.dt), ca = hn::Set(d, 1.0 / a.dt), zero = hn::Zero(d), one = hn::Set(d, 1.0);
  const V c = hn::LoadU(d, a.c), c0 = hn::LoadU(d, a.c0), ce = hn::LoadU(d, a.ce);
  const V cv = hn::LoadU(d, a.bit_viscous), Tsf = hn::LoadU(d, a.string_friction);
  const M friction = Tsf > zero;
  const bool any_friction = !hn::AllFalse(d, friction);
  const V kv = hn::Set(d, law.beta2 * s);  // tanh(beta2 a_unit) = tanh(beta2 s a_si)
  const bool hysteresis = law.beta2 * s != 0.0 && law.beta1 != 0.0;
  V v0 = hn::LoadU(d, a.v0), T0 = hn::LoadU(d, a.T0), x1 = hn::LoadU(d, a.x1), x2 = hn::LoadU(d, a.x2);
  // the top's acceleration over step first + s, averaged (exact_modal.hpp)
  auto dom_at = [&](long r) { return (hn::LoadU(d, a.om + (r + 1) * N) - hn::LoadU(d, a.om + r * N)) / dt; };
  V dom = dom_at(0);
  V w = hn::NegMulAdd(c0, T0, hn::MulAdd(ce, dom, ExactW<PerLane>(d, a.modes, a.coef, a.z, a.p)));
  for (long r = 0; r < a.count; ++r) {
    const V om0 = hn::LoadU(d, a.om + r * N), om1 = hn::LoadU(d, a.om + (r + 1) * N);
    const V ws = hn::LoadU(d, a.wob_scale + (r + 1) * N), scale = one + hn::LoadU(d, a.eta + (r + 1) * N);
    const M live = hn::And(hn::IsFinite(w), hn::And(hn::IsFinite(v0), hn::IsFinite(T0)));
    // the stick condition of Eqs. (5.1), (5.3) (Integrator::exact_bit): a bit at rest stays at rest
    // while the torque that holds it over the step is within the static capacity
    const V Ts = scale * hn::LoadU(d, a.static_torque + (r + 1) * N), cap = Ts + Tsf;
    const M sticky = cap > zero;
    const bool any_sticky = !hn::AllFalse(d, sticky);
    M at_rest = hn::FirstN(d, 0), hold = at_rest;
    V T_hold = zero;
    if (any_sticky) {
      at_rest = hn::And(sticky, hn::Abs(v0) <= hn::Set(d, 1e-12) * (one + hn::Abs(om0)));  // bit_rest_tolerance (euler_bit.hpp)
      T_hold = (w + hn::MulAdd(c0, T0, om1)) / (c + c0);
      hold = hn::And(at_rest, hn::Abs(T_hold) <= cap);
    }
    // x + c T(Omega_i+1 + x, (Omega_i+1 + x - v_i) / dt) = w (Eq. 3.3 with Eq. A.1's acceleration):
    // Integrator::exact_newton masked across the lanes, from the line through the last two solutions
    const V a0 = (om1 - v0) / dt, tol = hn::Set(d, 1e-12) * (one + hn::Abs(om1) + hn::Abs(w));
    V x = hn::NegMulAdd(one, x2, x1 + x1), T = hn::Set(d, NAN);
    M active = hn::AndNot(hold, live), fb = hn::FirstN(d, 0);
    for (int it = 0; it < 8 && !hn::AllFalse(d, active); ++it) {
      const V vv = om1 + x, acc = hn::MulAdd(ca, x, a0);
      V base, frac, cl, dbase, dfrac;
      AtSpeedDv(d, law, s, vv, ws, base, frac, cl, dbase, dfrac);
      V h = one, dTa = zero;
      if (hysteresis) {
        const V th = TanhSatSkip(d, kv * acc);
        h = hn::MulAdd(cl, th, one);
        dTa = frac * cl * kv * hn::NegMulAdd(th, th, one) * scale;
      }
      V TT = hn::MulAdd(hn::MulAdd(frac, h, base), scale, cv * vv);
      if (any_friction) TT = hn::IfThenElse(friction, hn::MulAdd(Tsf, Sign(d, vv), TT), TT);
      const V dT = hn::MulAdd(dTa, ca, hn::MulAdd(hn::MulAdd(dfrac, h, dbase), scale, cv));
      const V F = hn::MulAdd(c, TT, x) - w, dF = hn::MulAdd(c, dT, one);
      const M bad = hn::Not(hn::And(dF > zero, hn::And(hn::IsFinite(F), hn::IsFinite(dF))));
      const V xn = x - F / dF;
      // at rest the law is set-valued: a step onto or across v = 0 leaves it to the safeguarded solve
      const M cross = hn::Or(vv == zero, Sign(d, om1 + xn) != Sign(d, vv));
      const M out = hn::And(active, hn::Or(bad, cross));
      fb = hn::Or(fb, out);
      const M go = hn::AndNot(out, active);
      const M conv = hn::And(go, hn::Abs(xn - x) <= tol);
      T = hn::IfThenElse(conv, hn::MulAdd(dT, xn - x, TT), T);  // the torque linearized to the last step
      x = hn::IfThenElse(go, xn, x);
      active = hn::AndNot(conv, go);
    }
    fb = hn::Or(fb, active);
    if (!hn::AllFalse(d, fb)) {
      HWY_ALIGN double xs[16], Tl[16], wl[16],
          cl[16], o1[16], vl[16];
      HWY_ALIGN std::uint8_t fbits[16] = {};
      hn::StoreMaskBits(d, fb, fbits);
      hn::Store(x, d, xs);
      hn::Store(T, d, Tl);
      hn::Store(w, d, wl);
      hn::Store(c, d, cl);
      hn::Store(om1, d, o1);
      hn::Store(v0, d, vl);
      for (std::size_t l = 0; l < N; ++l)
        if (fbits[l / 8] >> (l % 8) & 1) xs[l] = a.fallback(a.ctx, l, a.first + r, wl[l], cl[l], o1[l], vl[l], xs[l], Tl[l]);
      x = hn::Load(d, xs);
      T = hn::Load(d, Tl);
    }
    V fric = zero, T0e = T0;
    if (any_sticky || any_friction) {
      // a landing bit comes to rest under the torque that stops it over the step, held constant too
      const V v1 = om1 + x;
      const M lands = hn::Or(v0 * v1 <= zero, hn::Abs(v1) <= hn::Set(d, 1e-9) * (one + hn::Abs(om1)));  // Integrator::landing_tolerance
      const M holds = hn::Or(hn::Abs(T_hold) <= cap, Sign(d, T_hold) == Sign(d, v0));
      const M stuck = hn::AndNot(hold, hn::AndNot(at_rest, hn::And(sticky, hn::And(lands, holds))));
      hold = hn::Or(hold, stuck);
      fric = hn::IfThenElse(friction, Tsf * Sign(d, v1), zero);
      fric = hn::IfThenElse(hold, hn::IfThenElse(friction, StringShare(d, T_hold, Ts, Tsf), zero), fric);
      x = hn::IfThenElse(hold, hn::Neg(om1), x);
      T = hn::IfThenElse(hold, T_hold, T);
      T0e = hn::IfThenElse(hold, T, T0);  // held over the step
    }
    const V v1 = om1 + x;
    hn::StoreU(v1, d, a.v + r * N);
    hn::StoreU((v1 - v0) / dt, d, a.a + r * N);  // Eq. (A.1)
    const V Tm = hn::Set(d, 0.5) * (T0e + T);  // the step's mean torque (exact_modal.hpp): T where held
    hn::StoreU(hn::IfThenElse(fric != zero, Tm - fric, Tm), d, a.T + r * N);
    const M moving = dom != zero;
    const V wn = hn::AllFalse(d, moving) ? ExactUpdate<PerLane, false>(d, a.modes, a.coef, a.z, a.p, dom, moving, T0e, T)
                                         : ExactUpdate<PerLane, true>(d, a.modes, a.coef, a.z, a.p, dom, moving, T0e, T);
    x2 = x1;
    x1 = x;
    v0 = v1;
    T0 = T;
    if (r + 1 < a.count) {
      dom = dom_at(r + 1);
      w = hn::NegMulAdd(c0, T0, hn::MulAdd(ce, dom, wn));
    }
  }
  hn::StoreU(v0, d, a.v0);
  hn::StoreU(T0, d, a.T0);
  hn::StoreU(x1, d, a.x1);
  hn::StoreU(x2, d, a.x2);
}

/// Motor::step (drives/motor.hpp) lane by lane: the motor speed after one step from om at the
/// command cmd and the string's top torque Tt (k = dt / J_m, c = c_m, den = 1 + dt c_m / J_m).
HWY_INLINE V MotorStep(V om, V cmd, V Tt, V k, V c, V den, V Tmax) {
  const V next = (om + k * (c * cmd - Tt)) / den;
  return hn::IfThenElse(c * (cmd - next) <= Tmax, next, om + k * (Tmax - Tt));
}

/// The steps of BatchSteps with a motor top drive on some lanes (Motor) and the rig's jack on
/// some lanes (Jack): Integrator::run_euler's Motor::Run and Axial::step lane by lane. With the
/// motor the top's acceleration of a step follows from the string's top torque at its start, so
/// the modes are passed twice per step (the update with the top torque's sum, then the forces).
template <bool Motor, bool Jack>
HWY_INLINE void BatchStepsT(const BatchStepArgs& a) {
  const D d;
  const std::size_t N = hn::Lanes(d);
  const int m = a.modes;
  const BitRockLaw& law = *a.law;
  const V dt = hn::Set(d, a.dt), g = hn::Set(d, a.g), zero = hn::Zero(d), one = hn::Set(d, 1.0);
  const V cv = hn::LoadU(d, a.bit_viscous), Tsf = hn::LoadU(d, a.string_friction);
  const double k = law.beta2 * a.speed_factor;                   // r.k of at_speed
  const V kv = hn::Set(d, k);
  const bool hysteresis = k != 0.0;
  // the accelerations of the last three solves of Eq. (A.1) (a1 the latest), as Integrator::run_euler keeps them
  V a1 = hn::LoadU(d, a.a_guess), a2 = hn::LoadU(d, a.a_guess + N), a3 = hn::LoadU(d, a.a_guess + 2 * N);
  // the motor's lanes, parameters and speed (Motor::Run: the speed a state, stepped from the top torque)
  M mot = hn::FirstN(d, 0);
  V mk = zero, mc = zero, mden = one, mmax = zero, oms = zero, om_next = zero;
  auto top_torque = [&]() {  // the string's elastic torque at the top, mode by mode
    V Tt = zero;
    for (int j = 0; j < m; ++j) Tt = Tt + hn::Set(d, a.top_torque[j]) * hn::LoadU(d, a.z + j * N);
    return Tt;
  };
  // the top's acceleration of step s: the motor's (om_next - om) / dt from the top torque Tt, or the input
  auto top_accel = [&](long s, V Tt) {
    const V in = hn::LoadU(d, a.domega + s * N);
    if constexpr (Motor) {
      om_next = MotorStep(oms, hn::LoadU(d, a.om + s * N), Tt, mk, mc, mden, mmax);
      return hn::IfThenElse(mot, (om_next - oms) / dt, in);
    } else {
      (void)Tt;
      return in;
    }
  };
  if constexpr (Motor) {
    mot = hn::LoadU(d, a.motor) != zero;
    mk = hn::LoadU(d, a.motor_k);
    mc = hn::LoadU(d, a.motor_c);
    mden = hn::LoadU(d, a.motor_den);
    mmax = hn::LoadU(d, a.motor_max);
    oms = hn::LoadU(d, a.om_state);
  }
  // the jack's lanes, parameters and WOB (Axial::step)
  M jk = hn::FirstN(d, 0);
  V je = zero, j1e = zero, jg = zero, jtau = zero, jfeed = zero, W = zero;
  const V wref = hn::Set(d, a.wob_ref), s_per = hn::Set(d, a.static_per_scale);
  if constexpr (Jack) {
    jk = hn::LoadU(d, a.jack) != zero;
    je = hn::LoadU(d, a.jack_e);
    j1e = hn::LoadU(d, a.jack_1me);
    jg = hn::LoadU(d, a.jack_gain);
    jtau = hn::LoadU(d, a.jack_tau);
    jfeed = hn::LoadU(d, a.jack_feed);
    W = hn::LoadU(d, a.wob_state);
  }
  // the modal forces f = -D p - w2 z - top_load dOmega/dt (the last term where dOmega/dt != 0) and bf = bit . f
  auto forces = [&](V dom) {
    V bf = zero;
    const M accel = dom != zero;
    for (int j = 0; j < m; ++j) {
      const V p = hn::LoadU(d, a.p + j * N), z = hn::LoadU(d, a.z + j * N);
      V f = hn::LoadU(d, a.negd + j * N) * p - hn::Set(d, a.w2[j]) * z;
      f = hn::IfThenElse(accel, f - hn::Set(d, a.top_load[j]) * dom, f);
      hn::StoreU(f, d, a.f + j * N);
      bf = bf + hn::Set(d, a.bit[j]) * f;
    }
    return bf;
  };
  // the modal sums of the first step: v = Omega + bit . p, alpha = bit . f + dOmega/dt
  V bp = zero;
  for (int j = 0; j < m; ++j) bp = bp + hn::Set(d, a.bit[j]) * hn::LoadU(d, a.p + j * N);
  V dom = top_accel(0, Motor ? top_torque() : zero);
  V bf = forces(dom);
  for (long s = 0; s < a.count; ++s) {
    const long i = a.first + s;
    V om = hn::LoadU(d, a.om + s * N), w = hn::LoadU(d, a.wob_scale + s * N);
    V static0 = hn::LoadU(d, a.static_torque + s * N);
    if constexpr (Motor) {
      om = hn::IfThenElse(mot, oms, om);
      hn::StoreU(om, d, a.top + s * N);
    }
    if constexpr (Jack) {  // the law at the jack's WOB (BitRockLaw: W / W_ref; static torques linear in W)
      const V wj = W / wref;
      w = hn::IfThenElse(jk, wj, w);
      static0 = hn::IfThenElse(jk, s_per * wj, static0);
      hn::StoreU(hn::IfThenElse(jk, W, hn::LoadU(d, a.force + s * N)), d, a.wob + s * N);
    }
    const V v = om + bp, alpha = bf + dom;
    const V eta = hn::LoadU(d, a.eta + s * N);
    V base, frac, c;
    AtSpeed(d, law, a.speed_factor, v, w, base, frac, c);
    const V scale = one + eta, visc = cv * v;
    V fric = hn::IfThenElse(Tsf > zero, Tsf * Sign(d, v), zero);
    const M moving_fric = fric != zero;
    const V rest = hn::IfThenElse(moving_fric, visc + fric, visc);
    V T = scale * (base + frac) + rest;
    V acc = alpha - g * T;
    if (hysteresis) {
      const M branch = frac * c != zero;
      if (!hn::AllFalse(d, branch)) {
        // saturated branches first, then the safeguarded Newton iteration of run_euler
        const V T_up = scale * (base + frac * (one + c)) + rest, T_dn = scale * (base + frac * (one - c)) + rest;
        const V up = alpha - g * T_up, dn = alpha - g * T_dn;
        const M m_up = hn::And(branch, kv * up > hn::Set(d, 19.1));
        const M m_dn = hn::AndNot(m_up, hn::And(branch, kv * dn < hn::Set(d, -19.1)));
        M active = hn::AndNot(hn::Or(m_up, m_dn), branch);
        // Newton's start: run_euler's parabola through the last three solutions extrapolated to this step
        const V guess = hn::Set(d, 3.0) * (a1 - a2) + a3;
        V x = guess, Tn = hn::Set(d, NAN);
        if (!hn::AllFalse(d, active)) {
          V lo = StdMin(up, dn), hi = StdMax(up, dn);
          x = StdMin(StdMax(guess, lo), hi);
          const V tol = hn::Set(d, 1e-9) * (one + hn::Abs(alpha));
          const V width_tol = hn::Set(d, 1e-15) * (one + hn::Abs(alpha));
          V dx_old = hn::Set(d, HUGE_VAL);
          for (int it = 0; it < 200 && !hn::AllFalse(d, active); ++it) {
            const V th = TanhSat(d, kv * x), h = one + c * th;
            const V eT = base + frac * h, edT = frac * c * kv * (one - th * th);
            const V F = x + g * (scale * eT + rest) - alpha;
            const M neg = F < zero;
            lo = hn::IfThenElse(hn::And(active, neg), x, lo);
            hi = hn::IfThenElse(hn::AndNot(neg, active), x, hi);
            V xn = x - F / (one + g * scale * edT);
            const M inside = hn::And(xn >= lo, xn <= hi);
            const M bisect = hn::Or(hn::Not(inside), hn::Abs(xn - x) > hn::Set(d, 0.5) * dx_old);
            xn = hn::IfThenElse(bisect, hn::Set(d, 0.5) * (lo + hi), xn);
            const V step = hn::Abs(xn - x);
            dx_old = hn::IfThenElse(active, step, dx_old);
            const M conv = hn::And(active, hn::Or(step <= tol, hi - lo <= width_tol));
            Tn = hn::IfThenElse(conv, scale * (eT + edT * (xn - x)) + rest, Tn);
            x = hn::IfThenElse(active, xn, x);
            active = hn::AndNot(conv, active);
          }
        }
        acc = hn::IfThenElse(m_up, up, hn::IfThenElse(m_dn, dn, hn::IfThenElse(branch, x, acc)));
        T = hn::IfThenElse(m_up, T_up, hn::IfThenElse(m_dn, T_dn, hn::IfThenElse(branch, Tn, T)));
        a3 = hn::IfThenElse(branch, a2, a3);
        a2 = hn::IfThenElse(branch, a1, a2);
        a1 = hn::IfThenElse(branch, acc, a1);
      }
    }
    // the stick condition (stick_euler, euler_bit.hpp) where the static capacity is positive
    const V Ts = scale * static0, cap = Ts + Tsf;
    const M sticky = cap > zero;
    if (!hn::AllFalse(d, sticky)) {
      const V T_req = (alpha + v / dt) / g, F_req = T_req - visc;
      const V sv = Sign(d, v), sf = Sign(d, F_req);
      const M at_rest = hn::Abs(v) <= hn::Set(d, 1e-12) * (one + hn::Abs(om));  // bit_rest_tolerance (euler_bit.hpp)
      const M crossing = hn::AndNot(at_rest, v * (v + dt * acc) <= zero);
      const M holds = hn::Or(hn::Abs(F_req) <= cap, hn::And(crossing, sf == sv));
      const M stuck = hn::And(sticky, hn::And(hn::Or(at_rest, crossing), holds));
      const M breaks = hn::AndNot(stuck, hn::And(sticky, at_rest));
      const V share = sf * StdMin(StdMax(hn::Abs(F_req) - Ts, zero), Tsf);  // string_share (euler_bit.hpp)
      const V T_brk = sf * cap + visc;
      T = hn::IfThenElse(stuck, T_req, hn::IfThenElse(breaks, T_brk, T));
      acc = hn::IfThenElse(stuck, hn::Neg(v) / dt, hn::IfThenElse(breaks, alpha - g * T_brk, acc));
      fric = hn::IfThenElse(stuck, hn::IfThenElse(Tsf > zero, share, zero), hn::IfThenElse(breaks, sf * Tsf, fric));
    }
    hn::StoreU(v, d, a.v + s * N);
    hn::StoreU(acc, d, a.a + s * N);
    hn::StoreU(hn::IfThenElse(fric != zero, T - fric, T), d, a.T + s * N);
    if (i == a.last) break;
    if constexpr (Jack) {  // Axial::step from the step's bit speed towards its set force
      const V F = hn::LoadU(d, a.force + s * N);
      const V Wn = F + (W - F) * je + jg * (jfeed - v) * jtau * j1e;
      W = hn::IfThenElse(jk, hn::IfThenElse(Wn > zero, Wn, zero), W);
    }
    // Eqs. (A.5), (A.6), fused with the modal sums of the next step
    bp = zero;
    if constexpr (Motor) {
      // the update with the top torque's sum, the motor's step from it, then the forces
      V Tt = zero;
      for (int j = 0; j < m; ++j) {
        const V bj = hn::Set(d, a.bit[j]);
        const V p = hn::LoadU(d, a.p + j * N) + dt * (hn::LoadU(d, a.f + j * N) - bj * T);
        const V z = hn::LoadU(d, a.z + j * N) + dt * p;
        hn::StoreU(p, d, a.p + j * N);
        hn::StoreU(z, d, a.z + j * N);
        bp = bp + bj * p;
        Tt = Tt + hn::Set(d, a.top_torque[j]) * z;
      }
      oms = hn::IfThenElse(mot, om_next, oms);
      dom = top_accel(s + 1, Tt);
      bf = forces(dom);
      continue;
    }
    bf = zero;
    dom = hn::LoadU(d, a.domega + (s + 1) * N);
    const M accel1 = dom != zero;
    for (int j = 0; j < m; ++j) {
      const V bj = hn::Set(d, a.bit[j]);
      const V p = hn::LoadU(d, a.p + j * N) + dt * (hn::LoadU(d, a.f + j * N) - bj * T);
      const V z = hn::LoadU(d, a.z + j * N) + dt * p;
      hn::StoreU(p, d, a.p + j * N);
      hn::StoreU(z, d, a.z + j * N);
      V f = hn::LoadU(d, a.negd + j * N) * p - hn::Set(d, a.w2[j]) * z;
      f = hn::IfThenElse(accel1, f - hn::Set(d, a.top_load[j]) * dom, f);
      hn::StoreU(f, d, a.f + j * N);
      bp = bp + bj * p;
      bf = bf + bj * f;
    }
  }
  hn::StoreU(a1, d, a.a_guess);
  hn::StoreU(a2, d, a.a_guess + N);
  hn::StoreU(a3, d, a.a_guess + 2 * N);
  if constexpr (Motor) hn::StoreU(oms, d, a.om_state);
  if constexpr (Jack) hn::StoreU(W, d, a.wob_state);
}
}  // namespace batched_detail

/// Steps a.first .. a.first + a.count - 1 of one vector of runs (see BatchStepArgs).
inline void BatchSteps(const BatchStepArgs& a) {
  using namespace batched_detail;
  if (a.motor && a.jack)
    BatchStepsT<true, true>(a);
  else if (a.motor)
    BatchStepsT<true, false>(a);
  else if (a.jack)
    BatchStepsT<false, true>(a);
  else
    BatchStepsT<false, false>(a);
}

/// Steps a.first .. a.first + a.count - 1 of the exact modal scheme (exact_modal.hpp) on one vector
/// of runs (see ExactStepArgs).
inline void ExactSteps(const ExactStepArgs& a) {
  if (a.per_lane)
    batched_detail::ExactStepsT<true>(a);
  else
    batched_detail::ExactStepsT<false>(a);
}

}  // namespace HWY_NAMESPACE
}  // namespace drill
HWY_AFTER_NAMESPACE();

// the coupled model's pass over the modes of its lanes (euler_lanes.hpp) for this target
#include "drill/euler_lanes-inl.hpp"

#endif  // toggle
