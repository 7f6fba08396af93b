// The per-instruction-set kernel of batched_integrator.hpp: Highway compiles this file once per
// x86 target (foreach_target.h re-includes it with HWY_NAMESPACE = N_AVX3, N_AVX2, N_SSE4, ...),
// hence no include guard of its own but Highway's per-target toggle. Not to be included directly.
//
// One call steps one vector of independent runs (one run per lane) through the modified Euler
// scheme of Integrator::run_euler (Eqs. A.5-A.6 with Eq. A.1's bit acceleration solved by the
// safeguarded Newton iteration; the stick condition of Eqs. 5.1, 5.3) with an ideal top drive. Every lane performs the scalar path's arithmetic in the same order
// (no FMA contraction: -ffp-contract=off in CMakeLists.txt), except that the modal dot products
// are summed mode by mode and exp/log are Highway's (contrib/math: exp within 1 ulp, log within 4
// ulp of the exact value). The Newton iteration is masked: a lane that has converged keeps its
// values while the others iterate, so a lane's bits never depend on the other lanes.
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

/// tanh_sat of bitrock.hpp: +-1 beyond |x| > 19.1, 1 - 2 / (e^2x + 1) otherwise.
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

/// BitRockLaw::at_speed for a vector of SI bit speeds (per-lane WOB factor w = W / W_ref): base,
/// frac and c of T(a) = base + frac (1 + c tanh(k a)); the speed derivatives are not needed here.
HWY_INLINE void AtSpeed(D d, const BitRockLaw& law, double s, V v_si, V w, V& base, V& frac, V& c) {
  const V v = v_si * hn::Set(d, s), sg = Sign(d, v), one = hn::Set(d, 1.0);
  base = hn::Zero(d);
  frac = hn::Zero(d);
  c = hn::Zero(d);
  switch (law.kind) {
    case BitRockLaw::Kind::tucker_wang: {  // Eq. (3.1)
      const V t = TanhSat(d, hn::Set(d, law.alpha0) * v), den = one + hn::Set(d, law.alpha2) * v * v;
      base = hn::Set(d, law.c0) * (t + hn::Set(d, law.alpha1) * v / den);
      break;
    }
    case BitRockLaw::Kind::hysteretic: {  // Eq. (3.2)
      const auto& b = law.b;
      base = hn::Set(d, b[0]) * TanhSat(d, hn::Set(d, b[1]) * v);
      const V av = StdMax(hn::Abs(v), hn::Set(d, 1e-300)), lv = hn::Log(d, av);
      const V p4 = hn::Exp(d, hn::Set(d, b[4]) * lv), p5 = hn::Exp(d, hn::Set(d, b[5]) * lv);
      const V den = one + hn::Set(d, b[3]) * p5;
      frac = hn::Set(d, b[0]) * sg * hn::Set(d, b[2]) * p4 / den;
      c = hn::Set(d, law.beta1) * sg;  // Eq. (3.3)
      break;
    }
    case BitRockLaw::Kind::polynomial:
    case BitRockLaw::Kind::polynomial_hysteretic: {  // Eqs. (5.1), (5.3)
      const auto& a = law.a;
      const bool odd = a[0] > 0.0;
      const V u = odd ? hn::Abs(v) : v;
      const V p1 = hn::Set(d, a[0]) + hn::Set(d, a[1]) * u, p2 = hn::Set(d, a[2]) + hn::Set(d, a[3]) * u;
      const V p3 = hn::Set(d, a[4]) + u * (hn::Set(d, a[5]) + u * (hn::Set(d, a[6]) + u * hn::Set(d, a[7])));
      V p = hn::IfThenElse(u <= hn::Set(d, 0.01 * law.ref_speed), p1,
                           hn::IfThenElse(u <= hn::Set(d, 0.05 * law.ref_speed), p2, p3));
      if (odd) p = hn::IfThenElse(v < hn::Zero(d), hn::Set(d, -1.0), one) * p;
      if (law.kind == BitRockLaw::Kind::polynomial) {
        base = hn::Set(d, law.gain) * p;
      } else {
        frac = hn::Set(d, law.gain) * p;
        c = hn::Set(d, law.beta1) * sg;
      }
      break;
    }
  }
  base = base * w;
  frac = frac * w;
}
}  // namespace batched_detail

/// Steps a.first .. a.first + a.count - 1 of one vector of runs (see BatchStepArgs).
inline void BatchSteps(const BatchStepArgs& a) {
  using namespace batched_detail;
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
  // the modal sums of the first step: v = Omega + bit . p, f = -D p - w2 z - top_load dOmega/dt
  // (the last term where dOmega/dt != 0), alpha = bit . f
  V bp = zero, bf = zero;
  const V dom0 = hn::LoadU(d, a.domega);
  const M accel0 = dom0 != zero;
  for (int j = 0; j < m; ++j) {
    const V p = hn::LoadU(d, a.p + j * N), z = hn::LoadU(d, a.z + j * N);
    V f = hn::LoadU(d, a.negd + j * N) * p - hn::Set(d, a.w2[j]) * z;
    f = hn::IfThenElse(accel0, f - hn::Set(d, a.top_load[j]) * dom0, f);
    hn::StoreU(f, d, a.f + j * N);
    bp = bp + hn::Set(d, a.bit[j]) * p;
    bf = bf + hn::Set(d, a.bit[j]) * f;
  }
  for (long s = 0; s < a.count; ++s) {
    const long i = a.first + s;
    const V om = hn::LoadU(d, a.om + s * N), w = hn::LoadU(d, a.wob_scale + s * N);
    const V static0 = hn::LoadU(d, a.static_torque + s * N);
    const V v = om + bp, alpha = bf + hn::LoadU(d, a.domega + s * N);
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
    // the stick condition (Integrator::stick_euler) where the static capacity is positive
    const V Ts = scale * static0, cap = Ts + Tsf;
    const M sticky = cap > zero;
    if (!hn::AllFalse(d, sticky)) {
      const V T_req = (alpha + v / dt) / g, F_req = T_req - visc;
      const V sv = Sign(d, v), sf = Sign(d, F_req);
      const M at_rest = hn::Abs(v) <= hn::Set(d, 1e-12) * (one + hn::Abs(om));  // Integrator::rest_tolerance
      const M crossing = hn::AndNot(at_rest, v * (v + dt * acc) <= zero);
      const M holds = hn::Or(hn::Abs(F_req) <= cap, hn::And(crossing, sf == sv));
      const M stuck = hn::And(sticky, hn::And(hn::Or(at_rest, crossing), holds));
      const M breaks = hn::AndNot(stuck, hn::And(sticky, at_rest));
      const V share = sf * StdMin(StdMax(hn::Abs(F_req) - Ts, zero), Tsf);  // Integrator::string_share
      const V T_brk = sf * cap + visc;
      T = hn::IfThenElse(stuck, T_req, hn::IfThenElse(breaks, T_brk, T));
      acc = hn::IfThenElse(stuck, hn::Neg(v) / dt, hn::IfThenElse(breaks, alpha - g * T_brk, acc));
      fric = hn::IfThenElse(stuck, hn::IfThenElse(Tsf > zero, share, zero), hn::IfThenElse(breaks, sf * Tsf, fric));
    }
    hn::StoreU(v, d, a.v + s * N);
    hn::StoreU(acc, d, a.a + s * N);
    hn::StoreU(hn::IfThenElse(fric != zero, T - fric, T), d, a.T + s * N);
    if (i == a.last) break;
    // Eqs. (A.5), (A.6), fused with the modal sums of the next step
    bp = zero;
    bf = zero;
    const V dom1 = hn::LoadU(d, a.domega + (s + 1) * N);
    const M accel1 = dom1 != zero;
    for (int j = 0; j < m; ++j) {
      const V bj = hn::Set(d, a.bit[j]);
      const V p = hn::LoadU(d, a.p + j * N) + dt * (hn::LoadU(d, a.f + j * N) - bj * T);
      const V z = hn::LoadU(d, a.z + j * N) + dt * p;
      hn::StoreU(p, d, a.p + j * N);
      hn::StoreU(z, d, a.z + j * N);
      V f = hn::LoadU(d, a.negd + j * N) * p - hn::Set(d, a.w2[j]) * z;
      f = hn::IfThenElse(accel1, f - hn::Set(d, a.top_load[j]) * dom1, f);
      hn::StoreU(f, d, a.f + j * N);
      bp = bp + bj * p;
      bf = bf + bj * f;
    }
  }
  hn::StoreU(a1, d, a.a_guess);
  hn::StoreU(a2, d, a.a_guess + N);
  hn::StoreU(a3, d, a.a_guess + 2 * N);
}

/// exact_modal_free (exact_modal.hpp) on one vector of lanes: the same operations in the same order.
inline void ExactFree(const ExactLaneArgs& a) {
  using namespace batched_detail;
  const D d;
  const std::size_t N = hn::Lanes(d);
  constexpr int K = ExactModal::kinds;
  const V dom = hn::LoadU(d, a.dom), T0 = hn::LoadU(d, a.T0);
  V w = hn::Zero(d);
  for (int j = 0; j < a.modes; ++j) {
    const double* c = a.coef + static_cast<std::size_t>(j) * K * N;
    const std::size_t o = static_cast<std::size_t>(j) * N;
    const V z = hn::LoadU(d, a.z + o), p = hn::LoadU(d, a.p + o);
    const V zn = hn::LoadU(d, c + ExactModal::zz * N) * z + hn::LoadU(d, c + ExactModal::zp * N) * p +
                 hn::LoadU(d, c + ExactModal::ez * N) * dom - hn::LoadU(d, c + ExactModal::hz0 * N) * T0;
    const V pn = hn::LoadU(d, c + ExactModal::pz * N) * z + hn::LoadU(d, c + ExactModal::pp * N) * p +
                 hn::LoadU(d, c + ExactModal::ep * N) * dom - hn::LoadU(d, c + ExactModal::hp0 * N) * T0;
    hn::StoreU(zn, d, a.zs + o);
    hn::StoreU(pn, d, a.ps + o);
    w = w + hn::Set(d, a.bit[j]) * pn;
  }
  hn::StoreU(w, d, a.w);
}

/// exact_modal_close (exact_modal.hpp) on one vector of lanes.
inline void ExactClose(const ExactLaneArgs& a) {
  using namespace batched_detail;
  const D d;
  const std::size_t N = hn::Lanes(d);
  constexpr int K = ExactModal::kinds;
  const V T1 = hn::LoadU(d, a.T1), dT0 = hn::LoadU(d, a.dT0);
  for (int j = 0; j < a.modes; ++j) {
    const double* c = a.coef + static_cast<std::size_t>(j) * K * N;
    const std::size_t o = static_cast<std::size_t>(j) * N;
    hn::StoreU(hn::LoadU(d, a.zs + o) - hn::LoadU(d, c + ExactModal::hz1 * N) * T1 -
                   hn::LoadU(d, c + ExactModal::hz0 * N) * dT0,
               d, a.z + o);
    hn::StoreU(hn::LoadU(d, a.ps + o) - hn::LoadU(d, c + ExactModal::hp1 * N) * T1 -
                   hn::LoadU(d, c + ExactModal::hp0 * N) * dT0,
               d, a.p + o);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace drill
HWY_AFTER_NAMESPACE();

#endif  // toggle
