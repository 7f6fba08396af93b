// Independent runs stepped in SIMD lockstep (issue 16): one run per lane of a vector register,
// structure-of-arrays state (mode-major, one vector per modal coordinate), masked Newton solve of
// the bit acceleration, vectorized exp/log.
//
// Scope: the modified Euler scheme (appendix A, Eqs. A.5-A.6) with the implicit bit acceleration
// of Eq. (A.1), an ideal top drive with any top speed Omega(t) or the rig's open-loop motor
// (drives/motor.hpp, its speed a state of the lane), any WOB W(t) or the rig's jack (axial.hpp, the
// WOB a state of the lane), eta(t) of Eq. (4.1), any bit-rock law (Eqs. 3.1-3.3, 5.1, 5.3) with its
// stick condition, bit viscous torque, string friction, and diagonal modal damping, which may
// differ from lane to lane: the constant-speed sweeps and the Monte Carlo of section 4.2, the
// loop's horizon predictions (horizons.hpp, its motor and jack candidates included) and the damping
// scans of several configurations (run_many.hpp). Other runs (a controlled drive, the motor or the
// jack on the exact modal scheme, bdf2, the lagged acceleration, dense damping) are refused by
// supports() and stay on Integrator, which is also the reference of this path.
// The exact modal scheme (exact_modal.hpp) runs here too, on the same inputs, in its own kernel
// (ExactSteps, batched_kernel-inl.hpp): the bit's equation, Eq. (3.3) with Eq. (A.1)'s acceleration
// at the step's end, solved by Integrator::exact_newton's iteration masked across the lanes (its
// tolerance, its fallback to the safeguarded solve_bit lane by lane), the stick condition of
// Integrator::exact_bit, and one pass over the modes per step for the step's end state and the
// next step's modal sum. Its results differ from Integrator's by rounding, as this path's do.
//
// Library: Google Highway (Debian libhwy-dev). One source gives the kernel for every x86 target
// (SSSE3, SSE4, AVX2, AVX-512) compiled with the baseline flags, with Highway's runtime dispatch
// (HWY_DYNAMIC_DISPATCH picks the host's widest target: `pip install .` stays portable, no
// -march=native), its vector ops for the whole step and its contrib/math Exp and Log. xsimd 8
// (Debian) needs one translation unit per instruction set compiled with -m flags, where the
// engine's inline Eigen code would then be compiled for AVX-512 too and could be picked by the
// linker for the baseline path; SLEEF gives the transcendentals only; Eigen's packet math is fixed
// at compile time by the -m flags (no runtime dispatch).
//
// Reproducibility: lanes never mix (the masked Newton freezes a converged lane), a batch is padded
// with copies of its first run, and the target is fixed for the life of the process, so a run's
// bits do not depend on the runs that share its batch, its lane, the batch count, the thread count
// or the chunking. AVX2 (4 lanes) and AVX-512 (8 lanes) give the same bits (both evaluate Exp and
// Log with FMA); the SSE targets, without FMA, differ from them by rounding. Against Integrator the
// results differ by rounding only: exp/log within 1-4 ulp of libm's and another summation order of
// the modal dot products (tests/cpp/test_batched_integrator.cpp states the tolerances).
#pragma once

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "drill/bitrock.hpp"
#include "drill/errors.hpp"
#include "drill/euler_lanes.hpp"
#include "drill/integrator.hpp"
#include "drill/parallel.hpp"

namespace drill {

/// Arguments of one kernel call: steps first .. first + count - 1 of one vector of runs. Arrays
/// marked [lanes] hold one value per lane, [modes][lanes] and [count][lanes] are row-major; the
/// inputs have a row for step first + count too.
struct BatchStepArgs {
  long first = 0, count = 0;
  long last = 0;  ///< the final step: no update after it
  int modes = 0;
  double dt = 0.0, g = 0.0, speed_factor = 1.0;
  const BitRockLaw* law = nullptr;
  const double* negd = nullptr;                                 ///< -diag(D) of each lane's model [modes][lanes]
  const double *w2 = nullptr, *bit = nullptr;                   ///< omega^2, bit [modes]
  const double* top_load = nullptr;                             ///< load of the top's acceleration [modes]
  double *z = nullptr, *p = nullptr, *f = nullptr;              ///< modal state and forces [modes][lanes]
  double* a_guess = nullptr;  ///< the last three solutions of Eq. (A.1), Newton's start, carried over [3][lanes]
  const double *bit_viscous = nullptr, *string_friction = nullptr;  ///< [lanes]
  /// Omega, dOmega/dt, W / W_ref, the static torque at W, eta [count + 1][lanes]
  const double *om = nullptr, *domega = nullptr, *wob_scale = nullptr, *static_torque = nullptr, *eta = nullptr;
  double *v = nullptr, *a = nullptr, *T = nullptr;  ///< bit speed, acceleration, torque on bit [count][lanes]
  /// The motor top drive (drives/motor.hpp) on the lanes where motor[lanes] is 1 (nullptr: no lane
  /// has one): there the om rows are the command Omega_c, the top speed is the state om_state
  /// [lanes] and each step's top speed goes to top [count][lanes]. Per lane: dt / J_m, c_m,
  /// 1 + dt c_m / J_m and T_max; top_torque: the string's top torque per mode [modes].
  const double *motor = nullptr, *motor_k = nullptr, *motor_c = nullptr, *motor_den = nullptr, *motor_max = nullptr;
  const double* top_torque = nullptr;
  double *om_state = nullptr, *top = nullptr;
  /// The rig's jack (axial.hpp) on the lanes where jack[lanes] is 1 (nullptr: no lane has one):
  /// there the WOB is the state wob_state [lanes], stepped towards the set force rows force
  /// [count + 1][lanes], and each step's WOB goes to wob [count][lanes]. Per lane: e = exp(-dt /
  /// tau), 1 - e, the gain, tau and the feed speed; static_per_scale: the law's static torque at
  /// W = W_ref (static torques are linear in W).
  const double *jack = nullptr, *jack_e = nullptr, *jack_1me = nullptr, *jack_gain = nullptr, *jack_tau = nullptr,
               *jack_feed = nullptr, *force = nullptr;
  double static_per_scale = 0.0, wob_ref = 1.0;
  double *wob_state = nullptr, *wob = nullptr;
};

/// Arguments of one exact modal kernel call (ExactSteps; the scheme of exact_modal.hpp): steps
/// first .. first + count - 1 (each from t_i to t_i+1) of one vector of runs. [lanes] one value per
/// lane; the input rows [count + 1][lanes] hold row s at t_first+s, the outputs [count][lanes] row s
/// at t_first+s+1.
struct ExactStepArgs {
  long first = 0, count = 0;
  int modes = 0;
  bool per_lane = false;  ///< coef per lane, [(j lane_kinds + kind)][lanes]; else shared, [j][lane_kinds]
  double dt = 0.0, speed_factor = 1.0;
  const BitRockLaw* law = nullptr;
  const double* coef = nullptr;                                ///< ExactModal::kl of the lanes' models
  const double *c = nullptr, *c0 = nullptr, *ce = nullptr;     ///< ExactModal::c, c0, ce [lanes]
  double *z = nullptr, *p = nullptr;                           ///< modal state [modes][lanes]
  /// carried over [lanes]: bit speed and total torque at t_first, the last two relative bit speeds
  double *v0 = nullptr, *T0 = nullptr, *x1 = nullptr, *x2 = nullptr;
  const double *bit_viscous = nullptr, *string_friction = nullptr;  ///< [lanes]
  /// Omega, W / W_ref, the static torque at W, eta [count + 1][lanes]
  const double *om = nullptr, *wob_scale = nullptr, *static_torque = nullptr, *eta = nullptr;
  double *v = nullptr, *a = nullptr, *T = nullptr;  ///< bit speed, acceleration, torque on bit [count][lanes]
  /// The safeguarded solve (Integrator::solve_bit) of lane l's bit equation at step i from x, where
  /// the masked Newton iteration leaves it (rare: the law's jump at v = 0, no convergence in 8 steps):
  /// returns x, T the total torque (NaN where it diverges).
  double (*fallback)(const void* ctx, std::size_t l, long i, double w, double c, double om1, double v0, double x,
                     double& T) = nullptr;
  const void* ctx = nullptr;
};

}  // namespace drill

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "drill/batched_kernel-inl.hpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>
// the kernel of the static (baseline) target, which foreach_target.h leaves to this file
#include "drill/batched_kernel-inl.hpp"

namespace drill {

HWY_EXPORT(BatchLanes);
HWY_EXPORT(BatchSteps);
HWY_EXPORT(ExactSteps);
HWY_EXPORT(EulerPass);

/// euler_lanes.hpp's pass over the modes on the host's widest vectors.
inline void EulerModes::pass(bool update, const double* F, double* bz, double* bp, double* bf, double* tz) const {
  HWY_DYNAMIC_DISPATCH(EulerPass)(*this, EulerPassIO{update, F, bz, bp, bf, tz});
}

class BatchedIntegrator {
 public:
  /// The batched path of `integ`'s model, law and options (the integrator must outlive it).
  explicit BatchedIntegrator(const Integrator& integ) : in_(integ) {}

  /// Runs per batch: the lanes of a double vector on the host's instruction set (8 with AVX-512,
  /// 4 with AVX2, 2 below).
  static std::size_t width() { return HWY_DYNAMIC_DISPATCH(BatchLanes)(); }

  /// Whether the batched path can run these inputs (see the header's scope); otherwise use Integrator.
  bool supports(const Inputs& in) const {
    const SimOptions& o = in_.opt_;
    const bool euler = o.scheme == Scheme::modified_euler && o.acceleration == Acceleration::implicit;
    // the motor and the jack on the modified Euler scheme only (BatchSteps); no controlled drive
    const bool drive = !in.top_drive.has_inertia() || (euler && in.top_drive.kind == TopDrive::Kind::motor);
    const bool axial = !in.axial.coupled() && (!in.axial.active() || euler);
    // the static torque's ageing (law.static_ageing) is Integrator::run_euler's only
    return (euler || o.scheme == Scheme::exact_modal) && in_.diag_damping_ && drive && axial && !in_.law_.ages();
  }

  /// Whether `other` can step in lockstep with this integrator's runs with its own damping: the
  /// same scheme, time step, duration and law, the same modal basis, frequencies and couplings,
  /// and a damping that is diagonal in that basis (the models differ at most in their modal damping).
  bool shares_model(const Integrator& other) const {
    const Integrator& I = in_;
    const SimOptions &a = I.opt_, &b = other.opt_;
    return &other == &I ||
           (a.scheme == b.scheme && a.acceleration == b.acceleration && a.dt == b.dt && a.steps() == b.steps() &&
            other.diag_damping_ && I.V_ == other.V_ && I.Vinv_ == other.Vinv_ && I.w2_ == other.w2_ &&
            I.bit_ == other.bit_ && I.top_load_ == other.top_load_ && I.law_ == other.law_);
  }

  /// Runs in[0 .. n) from start[r] (nullptr: Eq. 2.10), calling obs[r](const StepState&) at every
  /// step including t = 0, as Integrator::run does; the observers see the step, t, the bit speed,
  /// acceleration and torque on bit and the top speed (bit_angle and top_torque are NaN). Run r
  /// has the modal damping of damping[r] (an integrator that shares_model(); nullptr, or a null
  /// `damping`: this integrator's), so that a damping scan steps in lockstep too. Returns the final
  /// states. Throws like Integrator::run (the lowest diverging run's time), unless `diverged_at` is
  /// given: then diverged_at[r] is the time run r diverged at (NaN: it did not), its observer is
  /// not called from that step on, and the other runs go on.
  template <class Observer>
  std::vector<ModelState> run(const Inputs* in, const ModelState* const* start, std::size_t n, Observer* obs,
                              const Integrator* const* damping = nullptr, double* diverged_at = nullptr) const {
    std::vector<const Integrator*> model(n, &in_);
    for (std::size_t r = 0; r < n; ++r) {
      in_.check_inputs(in[r]);
      require(supports(in[r]), "batched run", r, "is outside the batched path (BatchedIntegrator::supports)");
      if (damping && damping[r]) {
        require(shares_model(*damping[r]), "batched run", r,
                "has a model that differs from the batch's in more than its modal damping");
        model[r] = damping[r];
      }
    }
    std::vector<ModelState> out(n);
    if (diverged_at) std::fill(diverged_at, diverged_at + n, NAN);
    const std::size_t N = width();
    for (std::size_t b = 0; b < n; b += N)
      if (in_.opt_.scheme == Scheme::exact_modal)
        run_exact(in + b, start + b, model.data() + b, std::min(N, n - b), obs + b, out.data() + b,
                  diverged_at ? diverged_at + b : nullptr);
      else
        run_vector(in + b, start + b, model.data() + b, std::min(N, n - b), obs + b, out.data() + b,
                 diverged_at ? diverged_at + b : nullptr);
    return out;
  }

 private:
  /// The lanes' inputs at t = (first + s) dt in row s, s = 0..count (row-major, width lane.size()):
  /// the top speed (and its rate when `dom` is given), the law's WOB scale W / W_ref and static torque,
  /// eta, and the WOB itself (the observers' and the jack's set force). A constant signal's rows are
  /// filled once (`sampled` false), a sampled one's at every block.
  static void fill_inputs(const BitRockLaw& law, const std::vector<const Inputs*>& lane, double dt, long first,
                          long count, bool sampled, double* om, double* dom, double* ws, double* st, double* eta,
                          double* wob_raw) {
    const std::size_t N = lane.size();
    for (long s = 0; s <= count; ++s) {
      const double t = (first + s) * dt;
      // the position on the sampling grid of the last sampled signal, reused by the next signal on
      // the same grid (the loop's horizons: every lane's slices share one): Signal::at's bits
      const Signal* on = nullptr;
      double x = 0.0;
      auto grid = [&](const Signal& sig) {
        if (!on || sig.t0 != on->t0 || sig.dt != on->dt) {
          on = &sig;
          x = sig.grid(t);
        }
        return x;
      };
      for (std::size_t l = 0; l < N; ++l) {
        const Inputs& in = *lane[l];
        const std::size_t k = s * N + l;
        if (in.top_speed.is_constant() != sampled) {
          if (sampled) {
            const double xt = grid(in.top_speed);
            om[k] = in.top_speed.at_grid(xt);
            if (dom) dom[k] = in.top_speed.samples.size() < 2 ? 0.0 : in.top_speed.rate_grid(xt);
          } else {
            om[k] = in.top_speed.value;
            if (dom) dom[k] = 0.0;
          }
        }
        if (in.wob.is_constant() != sampled) {
          const double wob = sampled ? in.wob.at_grid(grid(in.wob)) : in.wob.value;
          ws[k] = wob / law.wob_ref;
          st[k] = law.static_torque(wob);
          wob_raw[k] = wob;
        }
        if (in.eta.is_constant() != sampled) eta[k] = sampled ? in.eta.at_grid(grid(in.eta)) : in.eta.value;
      }
    }
  }
  /// True when an input of one of the n runs is a sampled signal (fill_inputs at every block).
  static bool any_sampled(const Inputs* in, std::size_t n) {
    for (std::size_t l = 0; l < n; ++l)
      if (!in[l].top_speed.is_constant() || !in[l].wob.is_constant() || !in[l].eta.is_constant()) return true;
    return false;
  }

  /// One batch of the exact modal scheme (exact_modal.hpp): ExactSteps on width() lanes in blocks
  /// of steps, each lane with its model's coefficients (shared by the batch when its models are
  /// one), the padding lanes repeating the first run. The initial state's torque is the scalar
  /// path's (Integrator::run_exact_lanes).
  template <class Observer>
  void run_exact(const Inputs* in, const ModelState* const* start, const Integrator* const* model, std::size_t n,
                 Observer* obs, ModelState* out, double* diverged_at) const {
    const Integrator& I = in_;
    const std::size_t N = width();
    const int m = static_cast<int>(I.w2_.size());
    const double dt = I.opt_.dt;
    const long last = I.opt_.steps();
    constexpr long block = 256;
    constexpr int K = ExactModal::lane_kinds;
    std::vector<double> z(m * N), p(m * N), c(N), c0(N), ce(N), cv(N), sf(N), v0(N), T0(N), x1(N), x2(N);
    std::vector<double> om((block + 1) * N), ws((block + 1) * N), st((block + 1) * N), eta((block + 1) * N);
    std::vector<double> wob_in((block + 1) * N);  // the WOB input (the observers')
    std::vector<double> v(block * N), a(block * N), T(block * N);
    std::vector<const Inputs*> lane(N);
    bool per_lane = false;
    for (std::size_t l = 0; l < N; ++l) {
      const std::size_t r = l < n ? l : 0;
      lane[l] = &in[r];
      per_lane = per_lane || model[r] != model[0];
      const ExactModal& em = model[r]->em_;
      c[l] = em.c;
      c0[l] = em.c0;
      ce[l] = em.ce;
      cv[l] = in[r].bit_viscous;
      sf[l] = in[r].string_friction;
      const ModelState s0 = start[r] ? *start[r] : I.initial_state(in[r].top_speed.at(0.0));
      require(s0.q.size() == I.V_.rows() && s0.qdot.size() == I.V_.rows(), "initial_state", s0.q.size(),
              "has the wrong size (the model has " + show(I.V_.rows()) + " coordinates)");
      const Eigen::VectorXd zl = I.Vinv_ * s0.q, pl = I.Vinv_ * s0.qdot;
      for (int j = 0; j < m; ++j) {
        z[j * N + l] = zl(j);
        p[j * N + l] = pl(j);
      }
    }
    std::vector<double> coef;
    if (per_lane) {  // [(j K + kind)][lanes]
      coef.resize(static_cast<std::size_t>(m) * K * N);
      for (std::size_t l = 0; l < N; ++l)
        for (std::size_t q = 0; q < static_cast<std::size_t>(m) * K; ++q)
          coef[q * N + l] = model[l < n ? l : 0]->em_.kl[q];
    }
    auto drop = [&](std::size_t l, double t) {
      if (!diverged_at) Integrator::diverged(t);
      diverged_at[l] = t;
      for (int j = 0; j < m; ++j) z[j * N + l] = p[j * N + l] = 0.0;  // a finite lane: no Newton spin on NaN
      v0[l] = T0[l] = x1[l] = x2[l] = 0.0;
    };
    std::vector<char> live(N, 1);
    // step 0: the initial state, its torque the law's at zero acceleration (as on the scalar path)
    exact_modal_dot(m, N, I.bit_.data(), p.data(), v0.data());
    for (std::size_t l = 0; l < N; ++l) {
      const Inputs& x = *lane[l];
      const double om0 = x.top_speed.at(0.0), wob = x.wob.at(0.0);
      v0[l] = om0 + v0[l];
      T0[l] = I.total_torque(v0[l], 0.0, wob, x.eta.at(0.0), x.bit_viscous, x.string_friction).T;
      x1[l] = x2[l] = v0[l] - om0;
      if (l >= n) continue;
      if (!std::isfinite(v0[l]) || !std::isfinite(T0[l])) {
        drop(l, 0.0);
        live[l] = 0;
        continue;
      }
      obs[l](static_cast<const StepState&>(
          StepState{0, 0.0, v0[l], 0.0, NAN, T0[l] - x.string_friction * Integrator::sign(v0[l]), NAN, om0, NAN, wob}));
    }
    const Fallback fb{&I, lane.data()};
    ExactStepArgs args;
    args.modes = m;
    args.per_lane = per_lane;
    args.dt = dt;
    args.speed_factor = speed_factor(I.law_.speed_unit);
    args.law = &I.law_;
    args.coef = per_lane ? coef.data() : model[0]->em_.kl.data();
    args.c = c.data();
    args.c0 = c0.data();
    args.ce = ce.data();
    args.z = z.data();
    args.p = p.data();
    args.v0 = v0.data();
    args.T0 = T0.data();
    args.x1 = x1.data();
    args.x2 = x2.data();
    args.bit_viscous = cv.data();
    args.string_friction = sf.data();
    args.om = om.data();
    args.wob_scale = ws.data();
    args.static_torque = st.data();
    args.eta = eta.data();
    args.v = v.data();
    args.a = a.data();
    args.T = T.data();
    args.fallback = &BatchedIntegrator::exact_fallback;
    args.ctx = &fb;
    // the inputs at t_first+s in row s; a constant signal's rows are filled once, a sampled one's at every block
    auto fill = [&](long first, long count, bool sampled) {
      fill_inputs(I.law_, lane, dt, first, count, sampled, om.data(), nullptr, ws.data(), st.data(), eta.data(),
                  wob_in.data());
    };
    fill(0, block, false);
    const bool sampled = any_sampled(in, n);
    for (long first = 0; first < last; first += block) {
      const long count = std::min(block, last - first);
      if (sampled) fill(first, count, true);
      args.first = first;
      args.count = count;
      HWY_DYNAMIC_DISPATCH(ExactSteps)(args);
      for (std::size_t l = 0; l < n; ++l) {
        if (!live[l]) continue;
        for (long s = 0; s < count; ++s) {
          const std::size_t k = s * N + l;
          const long i = first + s + 1;
          const double t = i * dt;
          if (!std::isfinite(v[k]) || !std::isfinite(T[k])) {
            drop(l, t);
            live[l] = 0;
            break;
          }
          obs[l](static_cast<const StepState&>(StepState{i, t, v[k], a[k], NAN, T[k], NAN, om[k + N], NAN, wob_in[k + N]}));
        }
      }
    }
    for (std::size_t l = 0; l < n; ++l) {
      Eigen::VectorXd zl(m), pl(m);
      for (int j = 0; j < m; ++j) {
        zl(j) = z[j * N + l];
        pl(j) = p[j * N + l];
      }
      out[l] = I.to_model(zl, pl);
    }
  }

  /// ExactStepArgs::fallback: Integrator::solve_bit (exact_newton's own fallback) for lane l.
  struct Fallback {
    const Integrator* I;
    const Inputs* const* in;
  };
  static double exact_fallback(const void* ctx, std::size_t l, long i, double w, double c, double om1, double v0,
                               double x, double& T) {
    const Fallback& f = *static_cast<const Fallback*>(ctx);
    const Inputs& r = *f.in[l];
    const double dt = f.I->opt_.dt, t1 = (i + 1) * dt;
    try {
      return f.I->solve_bit(w, c, om1, 1.0 / dt, (om1 - v0) / dt, r.wob.at(t1), r.eta.at(t1), r.bit_viscous,
                            r.string_friction, x, t1, T);
    } catch (const std::runtime_error&) {
      T = NAN;
      return NAN;
    }
  }

  template <class Observer>
  void run_vector(const Inputs* in, const ModelState* const* start, const Integrator* const* model, std::size_t n,
                  Observer* obs, ModelState* out, double* diverged_at) const {
    const Integrator& I = in_;
    const std::size_t N = width();
    const int m = static_cast<int>(I.w2_.size());
    const double dt = I.opt_.dt;
    const long last = I.opt_.steps();
    constexpr long block = 256;
    std::vector<double> z(m * N), p(m * N), f(m * N), negd(m * N), a_guess(3 * N, 0.0), cv(N), sf(N);
    std::vector<double> om((block + 1) * N), dom((block + 1) * N), ws((block + 1) * N), st((block + 1) * N);
    std::vector<double> eta((block + 1) * N), v(block * N), a(block * N), T(block * N);
    // the motor's and the jack's lanes (Motor::Run, Axial::step of Integrator::run_euler)
    bool motor = false, jack = false;
    for (std::size_t r = 0; r < n; ++r) {
      motor = motor || in[r].top_drive.has_inertia();
      jack = jack || in[r].axial.active();
    }
    std::vector<double> mon, mk, mc, mden, mmax, oms, top, jon, je, j1e, jg, jtau, jfeed, W, wob;
    std::vector<double> wob_in((block + 1) * N);  // the WOB input (the observers', the jack's set force)
    if (motor) {
      for (auto* x : {&mon, &mk, &mc, &mden, &mmax, &oms}) x->assign(N, 0.0);
      top.assign(block * N, 0.0);
    }
    if (jack) {
      for (auto* x : {&jon, &je, &j1e, &jg, &jtau, &jfeed, &W}) x->assign(N, 0.0);
      wob.assign(block * N, 0.0);
    }
    for (std::size_t l = 0; l < N; ++l) {
      const std::size_t r = l < n ? l : 0;  // padding lanes repeat the first run
      cv[l] = in[r].bit_viscous;
      sf[l] = in[r].string_friction;
      const ModelState s0 = start[r] ? *start[r] : I.initial_state(in[r].top_speed.at(0.0));
      const TopDrive& td = in[r].top_drive;
      if (td.has_inertia()) {  // Motor::step's constants, as it computes them
        mon[l] = 1.0;
        mk[l] = dt / td.inertia;
        mc[l] = td.slope;
        mden[l] = 1.0 + dt * td.slope / td.inertia;
        mmax[l] = td.max_torque;
        oms[l] = std::isfinite(s0.top_speed) ? s0.top_speed : in[r].top_speed.at(0.0);
      }
      const Axial& ax = in[r].axial;
      if (ax.active()) {  // Axial::step's constants, as it computes them
        jon[l] = 1.0;
        je[l] = std::exp(-dt / ax.relaxation);
        j1e[l] = 1.0 - je[l];
        jg[l] = ax.gain;
        jtau[l] = ax.relaxation;
        jfeed[l] = ax.feed_speed;
        W[l] = std::isfinite(s0.wob) ? s0.wob : in[r].wob.at(0.0);
      }
      require(s0.q.size() == I.V_.rows() && s0.qdot.size() == I.V_.rows(), "initial_state", s0.q.size(),
              "has the wrong size (the model has " + show(I.V_.rows()) + " coordinates)");
      const Eigen::VectorXd zl = I.Vinv_ * s0.q, pl = I.Vinv_ * s0.qdot;
      for (int j = 0; j < m; ++j) {
        z[j * N + l] = zl(j);
        p[j * N + l] = pl(j);
        negd[j * N + l] = -model[r]->d_(j);
      }
    }
    BatchStepArgs args;
    args.last = last;
    args.modes = m;
    args.dt = dt;
    args.g = I.bit_.squaredNorm();
    args.speed_factor = speed_factor(I.law_.speed_unit);
    args.law = &I.law_;
    args.negd = negd.data();
    args.w2 = I.w2_.data();
    args.bit = I.bit_.data();
    args.top_load = I.top_load_.data();
    args.z = z.data();
    args.p = p.data();
    args.f = f.data();
    args.a_guess = a_guess.data();
    args.om = om.data();
    args.domega = dom.data();
    args.wob_scale = ws.data();
    args.static_torque = st.data();
    args.bit_viscous = cv.data();
    args.string_friction = sf.data();
    args.eta = eta.data();
    args.v = v.data();
    args.a = a.data();
    args.T = T.data();
    if (motor) {
      args.motor = mon.data();
      args.motor_k = mk.data();
      args.motor_c = mc.data();
      args.motor_den = mden.data();
      args.motor_max = mmax.data();
      args.top_torque = I.top_torque_.data();
      args.om_state = oms.data();
      args.top = top.data();
    }
    if (jack) {
      args.jack = jon.data();
      args.jack_e = je.data();
      args.jack_1me = j1e.data();
      args.jack_gain = jg.data();
      args.jack_tau = jtau.data();
      args.jack_feed = jfeed.data();
      args.force = wob_in.data();
      args.static_per_scale = I.law_.static_torque(I.law_.wob_ref);
      args.wob_ref = I.law_.wob_ref;
      args.wob_state = W.data();
      args.wob = wob.data();
    }
    // the inputs of Integrator::run_euler's step first + s, in row s; a constant signal's rows are
    // filled once, a sampled one's at every block
    std::vector<const Inputs*> lane(N);
    for (std::size_t l = 0; l < N; ++l) lane[l] = &in[l < n ? l : 0];  // padding lanes repeat the first run
    auto fill = [&](long first, long count, bool sampled) {
      fill_inputs(I.law_, lane, dt, first, count, sampled, om.data(), dom.data(), ws.data(), st.data(), eta.data(),
                  wob_in.data());
    };
    fill(0, block, false);
    const bool sampled = any_sampled(in, n);
    for (long first = 0; first <= last; first += block) {
      const long count = std::min(block, last + 1 - first);
      if (sampled) fill(first, count, true);
      args.first = first;
      args.count = count;
      HWY_DYNAMIC_DISPATCH(BatchSteps)(args);
      for (std::size_t l = 0; l < n; ++l)
        for (long s = 0; s < count; ++s) {
          const std::size_t k = s * N + l;
          const long i = first + s;
          const double t = i * dt;
          if (diverged_at && !std::isnan(diverged_at[l])) break;
          if (!std::isfinite(v[k]) || !std::isfinite(T[k])) {
            if (!diverged_at) Integrator::diverged(t);
            diverged_at[l] = t;
            for (int j = 0; j < m; ++j) z[j * N + l] = p[j * N + l] = 0.0;  // a finite lane: no Newton spin on NaN
            a_guess[l] = a_guess[N + l] = a_guess[2 * N + l] = 0.0;
            break;
          }
          obs[l](static_cast<const StepState&>(StepState{i, t, v[k], a[k], NAN, T[k], NAN, motor ? top[k] : om[k], NAN,
                                                         jack ? wob[k] : wob_in[k]}));
        }
    }
    for (std::size_t l = 0; l < n; ++l) {
      Eigen::VectorXd zl(m), pl(m);
      for (int j = 0; j < m; ++j) {
        zl(j) = z[j * N + l];
        pl(j) = p[j * N + l];
      }
      out[l] = I.to_model(zl, pl);
      if (motor && mon[l] != 0.0) out[l].top_speed = oms[l];
      if (jack && jon[l] != 0.0) out[l].wob = W[l];
    }
  }

  const Integrator& in_;
};

/// parallel_for over n independent runs in batches of BatchedIntegrator::width():
/// batch(first, count) runs first .. first + count - 1. progress counts runs; chunk counts batches.
template <class BatchJob>
bool parallel_batches(std::size_t n, BatchJob&& batch, const ProgressFn& progress = nullptr, int threads = 0,
                      std::size_t chunk = 0) {
  const std::size_t w = BatchedIntegrator::width(), nb = (n + w - 1) / w;
  ProgressFn runs;
  if (progress) runs = [&](std::size_t done, std::size_t) { return progress(std::min(n, done * w), n); };
  return parallel_for(
      nb, [&](std::size_t b) { batch(b * w, std::min(w, n - b * w)); }, runs, threads, chunk);
}
}  // namespace drill
