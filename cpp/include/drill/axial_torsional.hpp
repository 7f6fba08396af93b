// Axial-torsional coupling at the bit: the reduced torsional model (modal.hpp) and the reduced
// axial model (axial_string.hpp) of the same string, coupled by the Richard-Germay-Detournay bit law
// (rgd_bit.hpp) through the depth of cut and its state-dependent delay (bit_profile.hpp).
//
// Equations (modal coordinates with M = I; torsion in the frame turning with the top, as Eq. 2.9):
//   z'' + D z' + diag(w^2) z = -b T - l Omega'(t),          bit speed  Omega_b = Omega(t) + b . z'
//   e'' + C e' + diag(k^2) e = -c W + h F_top,              bit advance U = V0 t + c . e   (feed)
//                                                                       U = c . e        (hook_load)
// (C diagonal: 2 zeta k_j with axial.damping = modal, 2 k_d on the elastic modes with distributed,
// D = 2 k_d M; axial_string.hpp)
// with F_top the constant net force at the top (hook_load; 0 with feed), and W, T the RGD weight and
// torque on bit at the depth of cut d = N [U - S(Phi_b - 2 pi / N)] (the rock surface S of the blade
// ahead, bit_profile.hpp). A uniform string with infinite axial stiffness and one torsional mode is
// RGD's own two-degree-of-freedom model (their M U'' = W_0 - W, I Phi'' + C (Phi - Omega_0 t) = -T).
//
// Scheme: the modified Euler step of appendix A (Eqs. A.5-A.6: velocities first, then the
// displacements with the new velocities) on both sets of coordinates, the depth of cut explicit (at the
// step's start), and the set-valued contact laws solved implicitly for the velocities at the step's
// end, one scalar inclusion each (the bit's axial then angular velocity):
//   axial    V+ = V_a - dt g_a (W - W_lo),  W in W_lo + [0, W_f] H(V+)    (H the set-valued step)
//   torsion  Omega+ = Omega_a - dt g_t T,    T in T_max Sgn(Omega+)       (T_max = T_c + T_f forwards,
//                                                                           T_f backwards)
// The stochastic bit-rock torque of Eq. (4.1) (the Monte Carlo of chapter 4, inputs.eta) scales both
// torque bounds by (1 + eta(t)), floored at 0; the WOB is not scaled.
// V_a, Omega_a the velocities without the contact's variable part, g the bit's modal gains (b . b,
// c . c). While turning forwards the bit cuts (W_lo = W_c); at torsional rest it bears on the rock with
// W in [0, W_c + W_f] (W_lo = 0); above the rock (d <= 0) W = T = 0 and the bit flies (bit bounce).
// A stuck bit's velocity is exactly zero at the end of the step (no chattering). The wear flats'
// share of W, which sets T_f = gamma mu a W_f / 2, is W - W_lo, at most a l sigma.
// Stability: the explicit parts need dt < pi / (5 omega_max) (Eq. A.7) with omega_max the largest of
// the retained torsional frequencies and of the axial ones stiffened by the cutting law's stiffness at
// the bit, sqrt(k_max^2 + N a zeta eps g_a) (the depth of cut is explicit).
//
// Scheme exact_modal (simulation.scheme; issue 34): the torsional engine's exact modal step
// (exact_modal.hpp) on both sets of coordinates. Each torsional mode and each axial mode (the rigid
// mode of hook_load included) is propagated exactly over the step by its 2x2 propagator with the exact
// response to a force varying linearly over the step: the top's acceleration (Omega_i+1 - Omega_i) / dt
// and T from T_i to T_i+1 on the torsional modes, F_top (constant) and W from W_i to W_i+1 on the
// axial ones. No bound of Eq. (A.7) (the modes' own frequencies need none). At the step's end the
// bit's velocities are linear in the end forces, Omega_i+1 = Omega_1 + w - c_t T_i+1 and V_i+1 = V_f -
// c_a W_i+1 (w, V_f the free end velocities holding the start forces' share, c = sum_j bit_j G1p_j),
// and the set-valued laws are solved there as in the modified Euler step above with (Oa, dt g_t) ->
// (Omega_1 + w, c_t) and (Va, dt g_a) -> (V_f, c_a): exact_axial (cutting while turning, the wear
// flats' [0, W_f] at axial rest, lift-off) and exact_rgd_torque (T in [-T_f, T_c + T_f] at rest), or
// with axial.torque = law the torsional engine's exact_bit (Eqs. 3.1-3.3, 5.1, 5.3 at the end speed
// and the step's own acceleration (v_i+1 - v_i) / dt, Eq. A.1; Newton; its stick condition with the
// law's static torque at the current W). A bit at rest at the step's end (torsionally or axially)
// takes the force that holds it there held over the step, as the torsional engine does
// (exact_modal.hpp: interpolated, the holding force of one step would depend on the last one's with a
// factor near -1 and alternate); a stuck bit's speed is exactly zero. The torsional switch (cutting
// while turning) is the bit speed at the step's start, as in the modified Euler step.
// The depth of cut: the rock surface S(Phi - 2 pi / N) is looked up on the history buffer at the angle
// the bit reaches at the step's end with T_i+1 = T_i (explicit in the angle: the surface moves with
// the angle by the advance of one sector back, d S / d Phi = V (t - t_N) / Omega (t - t_N)); in the
// bit's axial position it is implicit, d = d_p - N z_a (W_i+1 - W_i) with d_p the depth at the
// position reached with W_i+1 = W_i and z_a the position's compliance to the end WOB (za1 linear,
// za0 + za1 held), solved by fixed-point iteration with the axial inclusion. Explicit in U the cutting
// law's stiffness k_c = N a zeta eps on the bit (mass 1 / g_a) would be a spring stepped explicitly
// on top of the exact modes (stable on one mass to k_c g_a dt^2 < 2.4, with a numerical damping of
// 0.08 % a step already at k_c g_a dt^2 = 0.1, where the symplectic modified Euler has none, and this
// spring's delayed force is what drives RGD's instability); implicit in U it is trapezoidal (no
// numerical damping on one mass). The iteration contracts by N a zeta eps z_a <= k_c g_a dt^2 / 2 (a
// mode's displacement under a unit force held over the step is at most bit_j^2 dt^2 / 2), so the step
// bound of the scheme is
//   dt < 1 / sqrt(N a zeta eps g_a)        (the iteration's contraction below 1 / 2),
// 28.6 ms on the rgd-field string (its modified Euler bound: 6.1 ms); a larger simulation.dt_s is
// refused naming it. Reported per step: the end state and the step's mean forces ((T_i + T_i+1) / 2,
// the held one where held; the same for W), as the torsional engine reports its torque.
//
// The thesis's laws on the axial state (spec.torque = AxialTorque::law, axial.torque = "law"): the
// axial inclusion is RGD's as above (W its cutting and wear-flat force, its switches and bit bounce),
// and the torque on the bit is the configuration's law (F. F. Real 2018: Eq. 3.1 Tucker-Wang, Eqs.
// 3.2-3.3 hysteretic, Eq. 5.1 polynomial, Eq. 5.3 polynomial hysteretic) at the bit speed Omega_b and
// the step's own bit acceleration, with the WOB the axial state W:
//   T = (1 + eta) T_law(Omega_b, a; W),   T_law(v, a; W) = T_law(v, a; W_ref) W / W_ref   (section 3.3),
// Eq. (A.1) solved for a with the torque as the torsional engine does (solve_euler_accel), and the
// stick condition of the non-regularized laws (Eqs. 5.1, 5.3, a0 > 0: a bit at rest holds up to the
// static torque gain a0 W / W_ref at the current W; stick_euler, both in euler_bit.hpp). Off the rock
// W = 0, so T = 0. Steady drilling: RGD's W0 and V0, the torque T_law(Omega; W0).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include "drill/axial.hpp"
#include "drill/axial_string.hpp"
#include "drill/bit_profile.hpp"
#include "drill/bitrock.hpp"
#include "drill/errors.hpp"
#include "drill/euler_bit.hpp"
#include "drill/integrator.hpp"
#include "drill/modal.hpp"
#include "drill/rgd_bit.hpp"
#include "drill/signal.hpp"

// The coupled step inlines everything it calls (GCC and Clang): the dot products of Eigen, the
// thesis law's at_speed and solve_euler_accel (whose speed derivatives, unused by the Euler step,
// the compiler can then drop), the bit profile's lookup. GCC kept the dot products out of line in
// this large loop, a call each; inlining them changes no result (no floating-point contraction:
// CMakeLists.txt). Issue 34: 10-12 % of the coupled step (docs/axial.md, "Cost of a step").
#if defined(__GNUC__)
#define DRILL_AXIAL_FLATTEN __attribute__((flatten))
#else
#define DRILL_AXIAL_FLATTEN
#endif

namespace drill {

/// What the coupled model reports at every step besides StepState (SI, absolute frame).
struct AxialStep {
  double t = 0.0;
  double wob = 0.0;        ///< W [N]
  double rop = 0.0;        ///< the bit's axial speed V [m/s]
  double position = 0.0;   ///< the bit's axial position U [m]
  double depth = 0.0;      ///< depth of cut per revolution d [m] (negative: above the rock)
  double delay = 0.0;      ///< t_N [s]
  bool contact = true;     ///< false: the bit is off the rock (d <= 0, W = 0)
};

/// The state of the coupled model: the torsional ModelState and the axial modal state.
struct CoupledState {
  ModelState torsion;
  Eigen::VectorXd eta, eta_dot;
};

class AxialTorsional {
 public:
  /// `law`: the thesis law of spec.torque = AxialTorque::law (the configuration's "law" block);
  /// not used with AxialTorque::rgd.
  AxialTorsional(const ReducedModel& torsion, const StringModel& string, const AxialTorsionalSpec& spec,
                 const SimOptions& opt, const BitRockLaw& law = BitRockLaw{})
      : spec_(spec), opt_(opt), law_(law) {
    spec_.validate();
    opt_.validate();
    require(opt_.scheme != Scheme::bdf2, "simulation.scheme", to_string(opt_.scheme),
            "axial.type = rgd is implemented for simulation.scheme = modified_euler and exact_modal only");
    if (spec_.torque == AxialTorque::law) {
      law_.validate();
      require(opt_.acceleration == Acceleration::implicit, "axial.torque", to_string(spec_.torque),
              "is implemented with simulation.acceleration = implicit only (the step's own bit acceleration "
              "in Eq. 3.3), not " + to_string(opt_.acceleration));
    }
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(torsion.K, torsion.M);
    if (es.info() != Eigen::Success) throw std::runtime_error("reduced eigenproblem failed");
    V_ = es.eigenvectors();
    Vinv_ = V_.transpose() * torsion.M;
    w2_ = es.eigenvalues().cwiseMax(0.0);
    D_ = V_.transpose() * torsion.D * V_;
    // modal or Rayleigh damping is diagonal in the modal basis (to round-off): a diagonal product then
    // replaces the dense one (as integrator.hpp does)
    d_ = D_.diagonal();
    const double dscale = std::max(d_.cwiseAbs().maxCoeff(), 1e-300);
    diag_damping_ = (D_ - Eigen::MatrixXd(d_.asDiagonal())).cwiseAbs().maxCoeff() <= 1e-10 * dscale;
    bit_ = (torsion.bit * V_).transpose();
    top_torque_ = (torsion.top_torque * V_).transpose();
    top_load_ = V_.transpose() * torsion.top_load;
    init_vel_ = V_.transpose() * torsion.M * torsion.init_velocity;
    ax_ = build_axial_rom(string, spec_.top, spec_.modes, spec_.modal_damping(), spec_.bit_mass);
    if (opt_.scheme == Scheme::exact_modal) {
      prepare_exact(torsion);
      return;
    }
    // distributed axial damping (D = 2 k M, axial_string.hpp): the modified-Euler step of a mode with
    // damping c and frequency w is stable iff c dt < 2 and w^2 dt^2 + 2 c dt < 4 (Jury's conditions on
    // its 2x2 step matrix, trace 2 - c dt - w^2 dt^2, determinant 1 - c dt); with Eq. (A.7)'s w dt < pi / 5
    // the bound c dt = 2 k dt <= 1 keeps a margin (a modal ratio <= 1 gives c dt <= 2 pi / 5 already)
    if (spec_.damping == AxialDamping::distributed)
      require(2.0 * spec_.damping_rate * opt_.dt <= 1.0, "axial.damping_rate_per_s", spec_.damping_rate,
              "is too large for simulation.dt_s = " + show(opt_.dt) +
                  " s: the modified-Euler step needs 2 k dt <= 1 (a smaller dt or k)");
    const double bound = stability_bound();
    require(opt_.dt < bound, "simulation.dt_s", opt_.dt,
            "exceeds the modified-Euler stability bound of the coupled model dt < pi / (5 omega_max) = " +
                show(bound) + " s (Eq. A.7 over the torsional modes, " + show(std::sqrt(w2_.maxCoeff())) +
                " rad/s, and the axial ones stiffened by the cutting law, " + show(axial_omega_max()) +
                " rad/s: fewer axial.modes or a smaller dt)");
  }

  const AxialROM& axial() const { return ax_; }
  const AxialTorsionalSpec& spec() const { return spec_; }

  /// The largest axial frequency with the cutting law's stiffness N a zeta eps at the bit [rad/s].
  double axial_omega_max() const {
    const double kc = spec_.bit.blades * spec_.bit.cutting_wob_per_depth();
    return std::sqrt(ax_.omega.maxCoeff() * ax_.omega.maxCoeff() + kc * ax_.bit.squaredNorm());
  }
  /// Eq. (A.7) extended to the axial modes: pi / (5 omega_max).
  double stability_bound() const {
    return M_PI / (5.0 * std::max(std::sqrt(w2_.maxCoeff()), axial_omega_max()));
  }

  /// Steady drilling at bit speed omega [rad/s]: the depth of cut d0, the rate of penetration V0,
  /// the WOB W0 and the torque T0 (W0 = a zeta eps d0 + a l sigma, T0 = a^2 eps d0 / 2 + gamma mu a W_f / 2;
  /// with spec.torque = law, T0 = T_law(omega, 0; W0), the law at zero acceleration and W0 / W_ref).
  struct Steady {
    double depth, rop, wob, torque;
  };
  Steady steady(double omega) const {
    const RgdBit& b = spec_.bit;
    Steady s{};
    if (spec_.top == AxialTop::feed) {
      s.rop = spec_.feed_rate;
      s.depth = 2.0 * M_PI * s.rop / omega;
    } else {
      s.depth = spec_.steady_depth(omega);
      s.rop = omega * s.depth / (2.0 * M_PI);
    }
    s.wob = b.steady_wob(s.depth);
    s.torque = spec_.torque == AxialTorque::law ? law_.torque(omega, 0.0, s.wob) : b.steady_torque(s.depth);
    return s;
  }

  /// The torsional state of steady drilling at top speed omega (the static twist carrying T0; the
  /// bit lagging the top by `disturbance` of omega, as Simulation::steady_state).
  ModelState steady_torsion(double omega, double disturbance = 0.01) const {
    const double T0 = steady(omega).torque;
    Eigen::VectorXd z(w2_.size());
    for (Eigen::Index j = 0; j < z.size(); ++j) z(j) = w2_(j) > 0.0 ? -bit_(j) * T0 / w2_(j) : 0.0;
    return {V_ * z, V_ * (-disturbance * omega * init_vel_)};
  }
  /// The axial state of steady drilling at top speed omega (the static compression carrying W0,
  /// moving at V0; the bit's axial speed lagging by spec.disturbance of V0).
  void steady_axial(double omega, Eigen::VectorXd& eta, Eigen::VectorXd& eta_dot) const {
    const Steady s = steady(omega);
    const int m = ax_.size();
    eta = Eigen::VectorXd::Zero(m);
    for (int j = 0; j < m; ++j)
      if (ax_.omega(j) > 0.0) eta(j) = (ax_.top_row(j) * top_force() - ax_.bit(j) * s.wob) / (ax_.omega(j) * ax_.omega(j));
    eta_dot = Eigen::VectorXd::Zero(m);
    if (spec_.top == AxialTop::hook_load) eta_dot = ax_.uniform * s.rop;  // the whole string moves at V0
    // the disturbance: the bit's axial speed (1 - disturbance) V0
    const double g = ax_.bit.squaredNorm();
    if (g > 0.0) eta_dot -= ax_.bit * (spec_.disturbance * s.rop / g);
  }

  /// The top drives the coupled model runs: the ideal one and a controlled one whose steady speed is
  /// its command (integral action: the steady drilling it starts in is that at the command).
  static void require_drive(const TopDrive& td) {
    require(!td.has_inertia() || td.has_controller(), "top_drive.type", TopDrive::kind_name(td.kind),
            "is not implemented with axial.type = rgd (use ideal or controlled)");
    if (td.has_controller() && td.controller.tuned())
      require(!td.droops(), "top_drive.controller.ki_nm_rad", td.controller.ki,
              "must be positive with axial.type = rgd: the coupled model starts in steady drilling at the commanded "
              "speed, which a drive without integral action does not hold (it droops by T / kp)");
  }

  /// Integrate from the torsional state `start` (or steady drilling, disturbed), the axial state at
  /// steady drilling (disturbed) and the rock surface of steady drilling, with the top drive of `in`:
  /// the ideal drive at the top speed of `in`, or a controlled one (drives/controlled.hpp,
  /// controller.hpp: J Omega' = u - T_top with u its controller's torque) commanded at it, the top's
  /// speed then a state and the string's coordinates in the frame turning with it (Eq. 2.9, its
  /// acceleration Omega' the frame's load, as Integrator::run_euler). obs(const StepState&, const
  /// AxialStep&) at every step including t = 0.
  template <class Observer>
  CoupledState run(const Inputs& in, Observer&& obs, const ModelState* start = nullptr) const {
    in.top_speed.validate("operation.top_speed_rad_s");
    require_drive(in.top_drive);
    return TopDrive::visit(in.top_drive.kind, [&](auto drive) {
      if (opt_.scheme == Scheme::exact_modal) return run_exact<decltype(drive)>(in, obs, start);
      return run_drive<decltype(drive)>(in, obs, start);
    });
  }

  /// The exact modal scheme's bound from the cutting law's stiffness at the bit (the header's comment):
  /// dt < 1 / sqrt(N a zeta eps g_a) [s] (infinite without a cutting stiffness at the bit).
  double exact_bound() const {
    const double kg = spec_.bit.blades * spec_.bit.cutting_wob_per_depth() * ax_.bit.squaredNorm();
    return kg > 0.0 ? 1.0 / std::sqrt(kg) : INFINITY;
  }

 private:
  /// What run_drive and run_exact start from: the top speed's first value, the torsional state (the
  /// given one or steady drilling's) in modal coordinates z, p, the axial ones eta, r, and steady drilling.
  struct RunStart {
    double om0;
    ModelState s0;
    Eigen::VectorXd z, p, eta, r;
    Steady st;
  };
  RunStart run_start(const Inputs& in, const ModelState* start) const {
    const double om0 = in.top_speed.at(0.0);
    require_positive(om0, "operation.top_speed_rad_s");
    ModelState s0 = start ? *start : steady_torsion(om0);
    require(s0.q.size() == V_.rows() && s0.qdot.size() == V_.rows(), "initial_state", s0.q.size(),
            "has the wrong size (the model has " + show(V_.rows()) + " coordinates)");
    Eigen::VectorXd z = Vinv_ * s0.q, p = Vinv_ * s0.qdot, eta, r;
    steady_axial(om0, eta, r);
    const Steady st = steady(om0);
    return {om0, std::move(s0), std::move(z), std::move(p), std::move(eta), std::move(r), st};
  }

  template <class Drive, class Observer>
  DRILL_AXIAL_FLATTEN CoupledState run_drive(const Inputs& in, Observer& obs, const ModelState* start) const {
    const double dt = opt_.dt;
    const long n = opt_.steps();
    RunStart run0 = run_start(in, start);
    const double om0 = run0.om0;
    const ModelState& s0 = run0.s0;
    Eigen::VectorXd &z = run0.z, &p = run0.p, &eta = run0.eta, &r = run0.r;
    const Steady& st = run0.st;
    const RgdBit& b = spec_.bit;
    const double v_feed = spec_.top == AxialTop::feed ? spec_.feed_rate : 0.0, F_top = top_force();
    const double cw = b.cutting_wob_per_depth(), ct = b.cutting_torque_per_depth(), Wf_max = b.contact_wob(),
                 ctw = b.contact_torque_per_wob();
    const double gt = bit_.squaredNorm(), ga = ax_.bit.squaredNorm();
    const bool by_law = spec_.torque == AxialTorque::law;
    LawHistory hist;  // Eq. (A.1)'s accelerations of the last steps (by_law)
    double theta_top = 0.0;
    // the bit's twist b . z and axial displacement c . e, computed once a step: at its end for the
    // bit profile's record, which are the next step's (the same numbers)
    double bz = bit_.dot(z), ce = ax_.bit.dot(eta);
    BitProfile profile(b.blades, 0.0, bz, ce, st.depth, om0);
    Eigen::VectorXd ft(z.size()), fa(eta.size());
    // the drive's update of the top speed: the ideal drive reads the command (its speed, next speed and
    // rate); a controlled drive's loop starts in equilibrium with the string's top torque unless the
    // state gives its integral
    double om_state = std::isfinite(s0.top_speed) ? s0.top_speed : om0;
    typename Drive::template Run<TopDrive> drive(in.top_drive, in.top_speed, dt, s0,
                                                 [&] { return top_torque_.dot(z); });
    for (long i = 0;; ++i) {
      const double t = i * dt;
      const double om = drive.speed(t, om_state);
      const double T_top = top_torque_.dot(z);           // the string's elastic torque at the top
      const double om_next = drive.next(t, om, T_top);  // the top's speed at the next step
      const double dom = drive.accel(t, om, om_next);   // and its acceleration over the step
      const double Ob = om + bit_.dot(p), Phi = theta_top + bz;
      const double U = v_feed * t + ce, V = v_feed + ax_.bit.dot(r);
      const BitProfile::Cut cut = profile.cut(t, Phi, U);  // the depth of cut and the delay t_N
      const double d = cut.depth;
      if (diag_damping_) ft = -d_.cwiseProduct(p) - w2_.cwiseProduct(z);
      else ft.noalias() = -D_ * p - w2_.cwiseProduct(z);
      if (dom != 0.0) ft -= top_load_ * dom;
      fa = -ax_.damping.cwiseProduct(r) - (ax_.omega.array().square() * eta.array()).matrix();
      if (F_top != 0.0) fa += ax_.top_row * F_top;
      const double alpha_t = bit_.dot(ft) + dom, alpha_a = ax_.bit.dot(fa);
      const bool contact = d > 0.0;
      const bool turning = Ob > bit_rest_tolerance(om);
      // axial inclusion: W in [W_lo, W_hi] set-valued at V+ = 0 (rgd_bit.hpp's switches)
      double W = 0.0, Wf = 0.0, T = 0.0;
      if (contact) {
        const double Wc = cw * d, W_lo = turning ? Wc : 0.0, W_hi = Wc + Wf_max;
        const double Va = V + dt * (alpha_a - ga * W_lo);
        if (Va <= 0.0) W = W_lo;
        else if (Va - dt * ga * (W_hi - W_lo) >= 0.0) W = W_hi;
        else W = W_lo + Va / (dt * ga);
        Wf = std::min(W - W_lo, Wf_max);
        // torsional inclusion: T in [-T_f, T_c + T_f], set-valued at Omega+ = 0; the bit-rock
        // torque's fluctuation of Eq. (4.1) scales both, (1 + eta) floored at 0 (a set-valued
        // contact cannot drive the bit)
        const double fl = std::max(0.0, 1.0 + in.eta.at(t));
        if (by_law) {
          T = law_torque(Ob, om, alpha_t, gt, dt, fl, W, hist);  // the thesis law on the axial W
        } else {
          const double T_fwd = fl * (ct * d + ctw * Wf), T_bwd = fl * ctw * Wf;
          const double Oa = Ob + dt * alpha_t;
          if (Oa > 0.0) T = Oa - dt * gt * T_fwd >= 0.0 ? T_fwd : Oa / (dt * gt);
          else T = Oa + dt * gt * T_bwd <= 0.0 ? -T_bwd : Oa / (dt * gt);
        }
      }
      if (!std::isfinite(Ob) || !std::isfinite(T) || !std::isfinite(W) || !std::isfinite(V))
        throw std::runtime_error(Integrator::divergence(t));
      const double a_bit = alpha_t - gt * T;
      obs(static_cast<const StepState&>(StepState{i, t, Ob, a_bit, Phi, T, T_top, om, drive.torque(), W}),
          static_cast<const AxialStep&>(AxialStep{t, W, V, U, d, cut.delay, contact}));
      if (i == n) break;
      p += dt * (ft - bit_ * T);  // Eq. (A.5)
      z += dt * p;                // Eq. (A.6)
      r += dt * (fa - ax_.bit * W);
      eta += dt * r;
      theta_top += 0.5 * dt * (om + om_next);
      om_state = om_next;
      bz = bit_.dot(z);
      ce = ax_.bit.dot(eta);
      profile.record(t + dt, theta_top + bz, v_feed * (t + dt) + ce);
    }
    CoupledState out{{V_ * z, V_ * p}, eta, r};
    if (Drive::has_inertia) out.torsion.top_speed = om_state;
    drive.finish(out.torsion);
    return out;
  }

  /// The exact modal scheme (the header's comment) with the top drive `Drive`: run_drive's start,
  /// observer and top drive, each mode of both sets propagated by exact_modal_free/close.
  template <class Drive, class Observer>
  DRILL_AXIAL_FLATTEN CoupledState run_exact(const Inputs& in, Observer& obs, const ModelState* start) const {
    const double dt = opt_.dt;
    const long n = opt_.steps();
    RunStart run0 = run_start(in, start);
    const double om0 = run0.om0;
    const ModelState& s0 = run0.s0;
    Eigen::VectorXd &z = run0.z, &p = run0.p, &eta = run0.eta, &r = run0.r;
    const Steady& st = run0.st;
    const RgdBit& b = spec_.bit;
    const double v_feed = spec_.top == AxialTop::feed ? spec_.feed_rate : 0.0, F_top = top_force();
    const double cw = b.cutting_wob_per_depth(), ct = b.cutting_torque_per_depth(), Wf_max = b.contact_wob(),
                 ctw = b.contact_torque_per_wob();
    const int mt = et_.modes, ma = ea_.modes;
    Eigen::VectorXd zs(mt), ps(mt), es(ma), rs(ma);
    double theta_top = 0.0, om_state = std::isfinite(s0.top_speed) ? s0.top_speed : om0;
    double bz = bit_.dot(z), ce = ax_.bit.dot(eta);
    BitProfile profile(b.blades, 0.0, bz, ce, st.depth, om0);
    typename Drive::template Run<TopDrive> drive(in.top_drive, in.top_speed, dt, s0,
                                                 [&] { return top_torque_.dot(z); });
    // the state at t = 0 and the forces the first step starts from: steady drilling's
    double om = drive.speed(0.0, om_state), Ob = om + bit_.dot(p), V = v_feed + ax_.bit.dot(r);
    double W0 = st.wob, T0 = std::max(0.0, 1.0 + in.eta.at(0.0)) * st.torque;
    double x1 = Ob - om, x2 = x1;  // the relative bit speeds of the last two steps (Newton's start, law)
    {
      const BitProfile::Cut cut = profile.cut(0.0, bz, ce);
      obs(static_cast<const StepState&>(StepState{0, 0.0, Ob, 0.0, bz, T0, top_torque_.dot(z), om, drive.torque(), W0}),
          static_cast<const AxialStep&>(AxialStep{0.0, W0, V, ce, cut.depth, cut.delay, cut.depth > 0.0}));
    }
    for (long i = 0; i < n; ++i) {
      const double t = i * dt, t1 = t + dt;
      om = drive.speed(t, om_state);
      const double om1 = drive.next(t, om, top_torque_.dot(z));
      const double dom = (om1 - om) / dt;  // the top's acceleration averaged over the step
      double w = 0.0, wa = 0.0;
      exact_modal_free(mt, 1, et_.k.data(), bit_.data(), z.data(), p.data(), &dom, &T0, zs.data(), ps.data(), &w);
      exact_modal_free(ma, 1, ea_.k.data(), ax_.bit.data(), eta.data(), r.data(), &F_top, &W0, es.data(), rs.data(),
                       &wa);
      const double theta1 = theta_top + 0.5 * dt * (om + om1);
      // the rock surface at the angle the bit reaches with T_i+1 = T_i (explicit in the angle), and d_p, the
      // depth of cut at the axial position it reaches with W_i+1 = W_i
      const double Phi_p = theta1 + bit_.dot(zs) - zt1_ * T0, U_p = v_feed * t1 + ax_.bit.dot(es) - za1_ * W0;
      const BitProfile::Cut cut = profile.cut(t1, Phi_p, U_p);
      const bool turning = Ob > bit_rest_tolerance(om);
      const double fl = std::max(0.0, 1.0 + in.eta.at(t1));
      // the axial inclusion with the depth of cut implicit in the bit's axial position: d = d_p - N z_a
      // (W - W_i), z_a = za1 (W linear over the step) or za0 + za1 (held), by fixed-point iteration
      // (contraction N a zeta eps z_a <= N a zeta eps g_a dt^2 / 2 < 1 / 2 under the step bound)
      double d = cut.depth, W = 0.0, Wf = 0.0, T = 0.0, x = 0.0;
      bool contact = false, held_a = false, rest_a = false, held_t = false;
      for (int k = 0;; ++k) {
        contact = d > 0.0;
        W = Wf = 0.0;
        held_a = rest_a = false;
        if (contact) {
          const double Wc = cw * d;
          exact_axial(v_feed + wa, W0, turning ? Wc : 0.0, Wc + Wf_max, W, held_a, rest_a);
          Wf = std::min(W - (turning ? Wc : 0.0), Wf_max);
        }
        const double dn = cut.depth - b.blades * (held_a ? za0_ + za1_ : za1_) * (W - W0);
        if (std::fabs(dn - d) <= 1e-14 * std::fabs(cut.depth) || k == 40) break;
        d = dn;
      }
      if (law_step_) {  // the thesis law on the axial W (Eqs. 3.1-3.3, 5.1, 5.3 at the step's end)
        double fric = 0.0;
        law_step_->exact_bit(w, et_.c, et_.c0, T0, om, om1, Ob, W, fl - 1.0, 0.0, 0.0, t1, 2.0 * x1 - x2, x, T,
                             fric, held_t);
      } else if (contact) {
        exact_rgd_torque(w, T0, om, om1, Ob, fl * (ct * d + ctw * Wf), fl * ctw * Wf, x, T, held_t);
      } else {
        x = w;  // off the rock: T = 0
      }
      if (!std::isfinite(x) || !std::isfinite(T) || !std::isfinite(W))
        throw std::runtime_error(Integrator::divergence(t1));
      const double dT0 = held_t ? T - T0 : 0.0, dW0 = held_a ? W - W0 : 0.0;
      exact_modal_close(mt, 1, et_.k.data(), zs.data(), ps.data(), &T, &dT0, z.data(), p.data());
      exact_modal_close(ma, 1, ea_.k.data(), es.data(), rs.data(), &W, &dW0, eta.data(), r.data());
      theta_top = theta1;
      om_state = om1;
      bz = bit_.dot(z);
      ce = ax_.bit.dot(eta);
      const double v1 = om1 + x, V1 = rest_a ? 0.0 : v_feed + ax_.bit.dot(r);
      profile.record(t1, theta_top + bz, v_feed * t1 + ce);
      // the step's mean forces (exact_modal.hpp): the end ones where they are held over the step
      const double Tm = held_t ? T : 0.5 * (T0 + T), Wm = held_a ? W : 0.5 * (W0 + W);
      const double a_bit = (v1 - Ob) / dt;
      obs(static_cast<const StepState&>(
              StepState{i + 1, t1, v1, a_bit, theta_top + bz, Tm, top_torque_.dot(z), om1, drive.torque(), Wm}),
          static_cast<const AxialStep&>(AxialStep{t1, Wm, V1, v_feed * t1 + ce, d, cut.delay, contact}));
      x2 = x1;
      x1 = x;
      Ob = v1;
      V = V1;
      T0 = T;
      W0 = W;
    }
    CoupledState out{{V_ * z, V_ * p}, eta, r};
    if (Drive::has_inertia) out.torsion.top_speed = om_state;
    drive.finish(out.torsion);
    return out;
  }

  /// The axial inclusion at the end of an exact step: W in [W_lo, W_hi], set-valued at V_i+1 = 0, with
  /// V_i+1 = Vf - c W (Vf the free axial speed holding the start WOB's share -c0 W_i). Sliding (the bit
  /// moving up with W_lo or down with W_hi) the WOB varies linearly over the step; at rest at the
  /// step's end it is the WOB that holds it there, held over the step, W = (Vf + c0 W_i) / (c + c0),
  /// clamped to [W_lo, W_hi] (interpolated, the holding WOB of one step would depend on the last one's
  /// with a factor near -1 and alternate: the torsional engine's stick, exact_modal.hpp).
  /// `rest`: the holding WOB lies within the bounds, so the bit's axial speed at the step's end is zero.
  void exact_axial(double Vf, double W_start, double W_lo, double W_hi, double& W, bool& held, bool& rest) const {
    const double c = ea_.c, c0 = ea_.c0, Va = Vf - c * W_lo;
    held = rest = false;
    if (Va <= 0.0) W = W_lo;
    else if (Va - c * (W_hi - W_lo) >= 0.0) W = W_hi;
    else {
      const double W_hold = (Vf + c0 * W_start) / (c + c0);
      W = std::min(std::max(W_hold, W_lo), W_hi);
      held = true;
      rest = W == W_hold;
    }
  }

  /// RGD's torsional inclusion at the end of an exact step: T in [-T_bwd, T_fwd], set-valued at
  /// Omega_i+1 = 0, with Omega_i+1 = Omega1 + x, x = w - c T_i+1 (w holding -c0 T_i); Integrator::
  /// exact_bit's stick condition with RGD's bounds for the law's static torque: a bit at rest (v0 within
  /// bit_rest_tolerance) stays at rest while the torque that holds it there over the step, held,
  /// T_hold = (w + c0 T_i + Omega1) / (c + c0), is within the bounds, and breaks away with the bound
  /// T_hold exceeds otherwise; a sliding bit takes its bound (T linear over the step) and comes to rest
  /// with T_hold held when it would reverse or land (landing_tolerance) and T_hold is within the bounds
  /// or pushes it on in its own direction.
  void exact_rgd_torque(double w, double T_start, double om0, double om1, double v0, double T_fwd, double T_bwd,
                        double& x, double& T, bool& held) const {
    const double c = et_.c, c0 = et_.c0, T_hold = (w + c0 * T_start + om1) / (c + c0);
    const bool inside = T_hold <= T_fwd && T_hold >= -T_bwd;
    const bool at_rest = std::fabs(v0) <= bit_rest_tolerance(om0);
    held = at_rest && inside;
    if (!held) {
      const double dir = at_rest ? (T_hold > 0.0 ? 1.0 : -1.0) : (v0 > 0.0 ? 1.0 : -1.0);
      T = dir > 0.0 ? T_fwd : -T_bwd;
      x = w - c * T;
      const double v1 = om1 + x;
      const bool lands = !at_rest && (v0 * v1 <= 0.0 || std::fabs(v1) <= Integrator::landing_tolerance(om1));
      held = lands && (inside || (T_hold > 0.0 ? 1.0 : -1.0) == dir);
    }
    if (held) {
      T = T_hold;
      x = -om1;
    }
  }

  double top_force() const { return spec_.top == AxialTop::hook_load ? spec_.top_force : 0.0; }

  /// The exact modal scheme's coefficients (exact_modal.hpp) of the torsional modes and of the axial
  /// ones (their top force F_top constant over the step: the "top acceleration" of ExactModal with
  /// the load -top_row), its step bound, and with spec.torque = law the torsional engine whose
  /// exact_bit solves the law at the step's end.
  void prepare_exact(const ReducedModel& torsion) {
    require(diag_damping_, "simulation.scheme", to_string(opt_.scheme),
            "needs a torsional damping that is diagonal in the modal basis (modal or Rayleigh damping)");
    const double bound = exact_bound();
    require(opt_.dt < bound, "simulation.dt_s", opt_.dt,
            "exceeds the exact-modal bound of the coupled model dt < 1 / sqrt(N a zeta eps g_a) = " + show(bound) +
                " s (the cutting law's stiffness N a zeta eps = " +
                show(spec_.bit.blades * spec_.bit.cutting_wob_per_depth()) +
                " N/m on the bit's axial modal gain g_a = " + show(ax_.bit.squaredNorm()) +
                " 1/kg, the depth of cut's iteration in the bit's axial position: a smaller dt)");
    et_ = ExactModal::build(w2_, d_, bit_, top_load_, opt_.dt);
    ea_ = ExactModal::build(ax_.omega.cwiseAbs2(), ax_.damping, ax_.bit, -ax_.top_row, opt_.dt);
    zt1_ = za0_ = za1_ = 0.0;
    for (int j = 0; j < et_.modes; ++j) zt1_ += bit_(j) * et_.at(j, ExactModal::hz1);
    for (int j = 0; j < ea_.modes; ++j) {
      za0_ += ax_.bit(j) * ea_.at(j, ExactModal::hz0);
      za1_ += ax_.bit(j) * ea_.at(j, ExactModal::hz1);
    }
    if (spec_.torque == AxialTorque::law) law_step_.emplace(torsion, law_, opt_);
  }

  /// The last accelerations of Eq. (A.1) (Newton's start: the parabola through them, as run_euler's)
  /// and whether the last step needed Newton.
  struct LawHistory {
    double a1 = 0.0, a2 = 0.0, a3 = 0.0;
    bool newton = false;
  };

  /// The torque on the bit from the thesis law (spec.torque = law) at the bit speed Ob and the WOB W
  /// of the axial inclusion, T = scale T_law(Ob, a; W) with T_law scaling with W / W_ref (section 3.3)
  /// and scale = 1 + eta of Eq. (4.1) floored at 0: Eq. (A.1) solved for the step's bit acceleration
  /// a = alpha - g T(a) (Eqs. 3.2-3.3, 5.3: solve_euler_accel), then the stick condition of Eqs. (5.1),
  /// (5.3) at the static torque scale a0 W / W_ref (stick_euler); om the top speed, alpha the bit
  /// acceleration without the bit torque, g the bit's modal gain.
  double law_torque(double Ob, double om, double alpha, double g, double dt, double scale, double W,
                    LawHistory& h) const {
    const BitRockLaw::AtSpeed ts = law_.at_speed(Ob, W);
    double T = scale * (ts.base + ts.frac), a = alpha - g * T;
    const bool newton_last = h.newton;
    h.newton = false;
    if (ts.frac * ts.c != 0.0 && ts.k != 0.0) {
      const double guess = 3.0 * (h.a1 - h.a2) + h.a3;
      const double th_guess = newton_last ? tanh_sat(ts.k * guess) : 0.0;
      h.newton = solve_euler_accel(ts, alpha, g, scale, 0.0, guess, th_guess, newton_last, a, T);
      h.a3 = h.a2;
      h.a2 = h.a1;
      h.a1 = a;
    }
    const double Ts = scale * law_.static_torque(W);
    double fric = 0.0;
    if (Ts > 0.0) stick_euler(Ob, om, alpha, g, dt, Ts, 0.0, 0.0, a, T, fric);
    return T;
  }

  AxialTorsionalSpec spec_;
  SimOptions opt_;
  ExactModal et_, ea_;        ///< exact_modal: the torsional and the axial modes' step
  double zt1_ = 0.0;          ///< exact_modal: d(b . z_i+1) / d(-T_i+1), the bit's twist per end torque
  double za0_ = 0.0, za1_ = 0.0;  ///< exact_modal: d(c . e_i+1) / d(-W_i), d(c . e_i+1) / d(-W_i+1): the bit's axial
                                 ///< displacement per start and end WOB
  std::optional<Integrator> law_step_;  ///< exact_modal with spec.torque = law: Integrator::exact_bit
  BitRockLaw law_;  ///< the thesis law of spec_.torque = law
  AxialROM ax_;
  Eigen::MatrixXd V_, Vinv_, D_;
  Eigen::VectorXd d_;          ///< diag(D_)
  bool diag_damping_ = false;  ///< D_ is diagonal to round-off: the step uses d_
  Eigen::VectorXd w2_, bit_, top_torque_, top_load_, init_vel_;
};

}  // namespace drill

#undef DRILL_AXIAL_FLATTEN
