// Axial-torsional coupling at the bit: the reduced torsional model (modal.hpp) and the reduced
// axial model (axial_string.hpp) of the same string, coupled by the Richard-Germay-Detournay bit law
// (rgd_bit.hpp) through the depth of cut and its state-dependent delay (bit_profile.hpp).
//
// Equations (modal coordinates with M = I; torsion in the frame turning with the top, as Eq. 2.9):
//   z'' + D z' + diag(w^2) z = -b T - l Omega'(t),          bit speed  Omega_b = Omega(t) + b . z'
//   e'' + C e' + diag(k^2) e = -c W + h F_top,              bit advance U = V0 t + c . e   (feed)
//                                                                       U = c . e        (hook_load)
//   e'' + C e' + diag(k^2) e = -c W - l_a X'',              U = X(t) + c . e,  X' = V0 + kappa (W_s - f . e)  (jack)
// (C diagonal: 2 zeta k_j with axial.damping = modal, 2 k_d on the elastic modes with distributed,
// D = 2 k_d M; axial_string.hpp)
// with F_top the constant net force at the top (hook_load; 0 with feed and jack), the jack's top X(t)
// fed at V0 less kappa per N of the string's force on it f . e above its set force W_s (the rig's
// electrical jack, thesis section 5.1; l_a its inertia load, axial_string.hpp), and W, T the RGD weight and
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
//
// Runs in lanes (run_lanes; issue 34: the Monte Carlo and the sweeps of coupled models): n independent
// runs of one model are stepped together, the modal coordinates of both sets laid out [modes][lanes]
// and advanced in one pass over the modes for all lanes (euler_lanes.hpp for the modified Euler step,
// exact_modal_free/close for the exact one, the bit's rows summed mode by mode in euler_lanes.hpp's passes);
// the bit's part of a step (the top drive, the rock surface's lookup and record with the delay t_N of
// each run's own history, the axial and torsional inclusions or the thesis law's Newton iteration) is
// scalar code run lane by lane, since its branches, iterations and history differ from run to run. A
// lane does the same operations in the same order whatever the number of lanes and the other runs
// (no floating-point contraction: CMakeLists.txt; a lane's sums never mix lanes), and run() is
// run_lanes with one lane, so a run has the same bits alone, on the scalar path, and in any lane of
// any batch (tests/cpp/test_axial_batched.cpp).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "drill/axial.hpp"
#include "drill/axial_string.hpp"
#include "drill/batched_integrator.hpp"
#include "drill/bit_profile.hpp"
#include "drill/bitrock.hpp"
#include "drill/errors.hpp"
#include "drill/euler_bit.hpp"
#include "drill/euler_lanes.hpp"
#include "drill/exact_modal.hpp"
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

  /// The speed [rad/s] of steady drilling under the top drive td at a top-speed command [rad/s]: the
  /// command for the ideal drive and a controller with integral action; for the rig's open-loop motor
  /// (drives/motor.hpp) the speed where its characteristic carries the steady torque on the bit,
  /// Omega = Omega_c - T0(Omega) / c_m, below its torque limit (and for a controller without integral
  /// action, Omega = Omega_c - T0(Omega) / kp: TopDrive::steady_speed). T0 depends on Omega with
  /// top = feed (d0 = 2 pi V0 / Omega) and with axial.torque = law, and can have two such speeds: the
  /// highest is taken (a scan down from the command, then bisection). NaN when the drive cannot carry
  /// steady drilling at any speed: it stalls (its limit is below T0, or with a feed the two speeds
  /// have merged: the slower the bit, the deeper its cut and the larger the torque).
  double steady_speed(const TopDrive& td, double command) const {
    if (!td.droops() || !(command > 0.0)) return command;
    // g(x) = x - Omega_c + T0(x) / c_m: positive at the command (T0 >= 0), at 0 with feed; a stall: no root
    auto g = [&](double x) { return x - td.steady_speed(command, steady(x).torque); };
    constexpr int scan = 1000;
    double hi = command, lo = NAN;
    for (int k = scan - 1; k >= 1 && std::isnan(lo); --k) {
      const double x = command * k / scan;
      if (g(x) < 0.0) lo = x;
      else hi = x;
    }
    if (std::isnan(lo)) return NAN;
    for (int it = 0; it < 200 && hi - lo > 1e-13 * command; ++it) (g(0.5 * (lo + hi)) < 0.0 ? lo : hi) = 0.5 * (lo + hi);
    return 0.5 * (lo + hi);
  }

  /// The speed a run under td at `command` starts from: steady_speed, or the command where the drive
  /// cannot carry steady drilling (the run then starts from the command's steady drilling, which the
  /// drive cannot hold: it stalls, and the run shows how).
  double start_speed(const TopDrive& td, double command) const {
    const double om = steady_speed(td, command);
    return std::isnan(om) ? command : om;
  }

  /// Steady drilling (disturbed by `disturbance`) under the top drive td at a top-speed command: the
  /// torsional state at the drive's steady speed (start_speed), with the top's speed in it for a
  /// drive that droops, and a controller without integral action started with a zero integral and
  /// mean torque, its proportional part carrying T0 at the drooped speed (as Simulation::steady_state
  /// starts the torsional engine). A controller with integral action starts in equilibrium with the
  /// string's top torque (drives/controlled.hpp).
  ModelState steady_start(const TopDrive& td, double command, double disturbance = 0.01) const {
    const double om = start_speed(td, command);
    ModelState s = steady_torsion(om, disturbance);
    if (td.droops()) s.top_speed = om;
    if (td.has_controller() && td.droops()) s.drive_integral = s.drive_mean = 0.0;
    return s;
  }

  /// Integrate from the torsional state `start` (or steady drilling, disturbed), the axial state at
  /// steady drilling (disturbed) and the rock surface of steady drilling, with the top drive of `in`:
  /// the ideal drive at the top speed of `in`, or a controlled one (drives/controlled.hpp,
  /// controller.hpp: J Omega' = u - T_top with u its controller's torque) commanded at it, the top's
  /// speed then a state and the string's coordinates in the frame turning with it (Eq. 2.9, its
  /// acceleration Omega' the frame's load, as Integrator::run_euler). obs(const StepState&, const
  /// AxialStep&) at every step including t = 0. One run of run_lanes (the same bits as in a batch).
  template <class Observer>
  CoupledState run(const Inputs& in, Observer&& obs, const ModelState* start = nullptr) const {
    CoupledState out;
    run_lanes(&in, &start, 1, &obs, &out);
    return out;
  }

  /// n independent runs stepped together (the batched path of the coupled model): run r from
  /// in[r] and start[r] (nullptr: steady drilling, disturbed) with its observer obs[r], its final
  /// state in out[r]. The modes of all runs are stepped in one pass, [modes][lanes] (euler_lanes.hpp,
  /// exact_modal.hpp); the bit's laws, the rock surface's lookup (bit_profile.hpp) and the top drive
  /// are each run's own, lane by lane. A run's numbers do not depend on n nor on the other runs (each
  /// lane does run()'s arithmetic in run()'s order: run() is this with n = 1). The runs share the
  /// top drive's kind. Throws like run() (the first run to diverge, at its time) unless `diverged_at`
  /// is given: then diverged_at[r] is the time run r diverged at (NaN: it did not), its observer is
  /// not called from that step on, and the other runs go on.
  template <class Observer>
  void run_lanes(const Inputs* in, const ModelState* const* start, std::size_t n, Observer* obs, CoupledState* out,
                 double* diverged_at = nullptr) const {
    if (n == 0) return;
    for (std::size_t r = 0; r < n; ++r) {
      in[r].top_speed.validate("operation.top_speed_rad_s");
      in[r].eta.validate("eta");
      require_drive_bound(in[r].top_drive);
      require(in[r].top_drive.kind == in[0].top_drive.kind, "top_drive.type", TopDrive::kind_name(in[r].top_drive.kind),
              "differs from the first run's (" + TopDrive::kind_name(in[0].top_drive.kind) +
                  "): the runs stepped together share the top drive's kind");
    }
    if (diverged_at) std::fill(diverged_at, diverged_at + n, NAN);
    TopDrive::visit(in[0].top_drive.kind, [&](auto drive) {
      Lanes<decltype(drive)> L(*this, in, start, n);
      if (opt_.scheme == Scheme::exact_modal) run_exact(L, in, obs, diverged_at);
      else run_drive(L, in, obs, diverged_at);
      L.finish(*this, out);
    });
  }

  /// A top drive with inertia (motor, controlled) is stepped explicitly in the string's top torque on
  /// both schemes, as in the torsional engine (Integrator::check_inputs): Eq. (A.7)'s bound of the
  /// torsional modes coupled to the drive's inertia, and with modified Euler the axial modes' too.
  void require_drive_bound(const TopDrive& td) const {
    if (!td.has_inertia()) return;
    const double w = Integrator::drive_omega_max(w2_, top_load_, top_torque_, td.inertia);
    const double bound = M_PI / (5.0 * (opt_.scheme == Scheme::exact_modal ? w : std::max(w, axial_omega_max())));
    require(opt_.dt < bound, "simulation.dt_s", opt_.dt,
            "exceeds the stability bound with the " + TopDrive::kind_name(td.kind) + " top drive, dt < " + show(bound) +
                " s (Eq. A.7 for the string coupled to top_drive.inertia_kg_m2 = " + show(td.inertia) + ")");
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
    const double command = in.top_speed.at(0.0);
    require_positive(command, "operation.top_speed_rad_s");
    const double om0 = start_speed(in.top_drive, command);  // a drive's droop
    ModelState s0 = start ? *start : steady_start(in.top_drive, command);
    require(s0.q.size() == V_.rows() && s0.qdot.size() == V_.rows(), "initial_state", s0.q.size(),
            "has the wrong size (the model has " + show(V_.rows()) + " coordinates)");
    Eigen::VectorXd z = Vinv_ * s0.q, p = Vinv_ * s0.qdot, eta, r;
    steady_axial(om0, eta, r);
    const Steady st = steady(om0);
    return {om0, std::move(s0), std::move(z), std::move(p), std::move(eta), std::move(r), st};
  }

  /// The n runs of run_lanes: the modal states of both sets [modes][lanes], and per lane its start
  /// (RunStart), its rock surface, its top drive, the top's angle and speed, the bit's twist b . z, its
  /// axial displacement c . e and the string's elastic torque at the top (at the step's start), and
  /// whether it still runs.
  template <class Drive>
  struct Lanes {
    using DriveRun = typename Drive::template Run<TopDrive>;
    std::size_t n;
    std::vector<RunStart> run0;
    std::vector<double> z, p, eta, r;
    std::vector<BitProfile> profile;
    std::vector<std::unique_ptr<DriveRun>> drive;
    std::vector<double> theta_top, om_state, bz, ce, T_top;
    std::vector<char> live;

    Lanes(const AxialTorsional& m, const Inputs* in, const ModelState* const* start, std::size_t n_)
        : n(n_), theta_top(n_, 0.0), om_state(n_), bz(n_), ce(n_), T_top(n_), live(n_, 1) {
      const int mt = static_cast<int>(m.w2_.size()), ma = m.ax_.size();
      z.resize(mt * n);
      p.resize(mt * n);
      eta.resize(ma * n);
      r.resize(ma * n);
      for (std::size_t l = 0; l < n; ++l) {
        run0.push_back(m.run_start(in[l], start[l]));
        const RunStart& s = run0.back();
        for (int j = 0; j < mt; ++j) {
          z[j * n + l] = s.z(j);
          p[j * n + l] = s.p(j);
        }
        for (int j = 0; j < ma; ++j) {
          eta[j * n + l] = s.eta(j);
          r[j * n + l] = s.r(j);
        }
        om_state[l] = std::isfinite(s.s0.top_speed) ? s.s0.top_speed : s.om0;
      }
      std::vector<double> unused(n);  // b . p, c . e': the schemes' own passes sum them
      EulerModes{mt, n, 0.0, m.bit_.data(), m.top_torque_.data(), nullptr, nullptr, nullptr, 0.0, z.data(), p.data(),
                 nullptr}
          .pass(false, nullptr, bz.data(), unused.data(), nullptr, T_top.data());
      EulerModes{ma, n, 0.0, m.ax_.bit.data(), nullptr, nullptr, nullptr, nullptr, 0.0, eta.data(), r.data(), nullptr}
          .pass(false, nullptr, ce.data(), unused.data(), nullptr, nullptr);
      for (std::size_t l = 0; l < n; ++l) {
        profile.emplace_back(m.spec_.bit.blades, 0.0, bz[l], ce[l], run0[l].st.depth, run0[l].om0);
        // a controlled drive's loop starts in equilibrium with the string's top torque unless the state gives its integral
        drive.push_back(std::make_unique<DriveRun>(in[l].top_drive, in[l].top_speed, m.opt_.dt, run0[l].s0,
                                                   [&] { return T_top[l]; }));
      }
    }

    /// Lane l diverged at time t: throws (no `diverged_at`) or records it and stops the lane (its
    /// state set to zero, so that the lane's arithmetic stays finite).
    void diverge(std::size_t l, double t, double* diverged_at) {
      if (!diverged_at) throw std::runtime_error(Integrator::divergence(t));
      diverged_at[l] = t;
      live[l] = 0;
      for (std::vector<double>* v : {&z, &p, &eta, &r}) {
        const std::size_t m = v->size() / n;
        for (std::size_t j = 0; j < m; ++j) (*v)[j * n + l] = 0.0;
      }
    }

    /// The final states.
    void finish(const AxialTorsional& m, CoupledState* out) const {
      const int mt = static_cast<int>(m.w2_.size()), ma = m.ax_.size();
      for (std::size_t l = 0; l < n; ++l) {
        Eigen::VectorXd zl(mt), pl(mt), el(ma), rl(ma);
        for (int j = 0; j < mt; ++j) {
          zl(j) = z[j * n + l];
          pl(j) = p[j * n + l];
        }
        for (int j = 0; j < ma; ++j) {
          el(j) = eta[j * n + l];
          rl(j) = r[j * n + l];
        }
        out[l] = CoupledState{{m.V_ * zl, m.V_ * pl}, el, rl};
        if (Drive::has_inertia) out[l].torsion.top_speed = om_state[l];
        drive[l]->finish(out[l].torsion);
      }
    }
  };

  /// The axial top of the lanes, the frame the axial coordinates are relative to: feed (X = V0 t),
  /// hook_load (none: X = 0, the string free) or the jack, whose feed speed is a state of each lane,
  /// V_i+1 = V0 + kappa (W_s - F_top,i) with F_top,i = top_force . eta at the step's start (explicit in
  /// the string's force, as a top drive's step is in its torque), X advanced by the trapezoid; its
  /// acceleration dV = (V_i+1 - V_i) / dt loads the axial modes through -top_load (axial_string.hpp).
  struct AxialFrame {
    bool jack = false;
    double v0 = 0.0, kappa = 0.0, set_force = 0.0, dt = 0.0;
    std::vector<double> X, V, V1, dV, F;  ///< per lane: position, speed, next speed, acceleration, F_top

    template <class Run0>
    AxialFrame(const AxialTorsionalSpec& spec, const std::vector<Run0>& run0, double dt_)
        : jack(spec.top == AxialTop::jack), v0(moving_frame(spec.top) ? spec.feed_rate : 0.0),
          kappa(jack ? spec.jack_admittance : 0.0), set_force(jack ? spec.top_force : 0.0), dt(dt_) {
      const std::size_t n = run0.size();
      X.assign(n, 0.0);
      V1.assign(n, 0.0);
      dV.assign(n, 0.0);
      F.assign(n, 0.0);
      V.resize(n);
      for (std::size_t l = 0; l < n; ++l) V[l] = jack ? run0[l].st.rop : v0;  // steady drilling's feed
    }
    /// The string's force on the top of every lane, for the jack (nullptr: no sum needed).
    double* force() { return jack ? F.data() : nullptr; }
    /// The jack's next speeds and the step's accelerations (nothing for feed and hook_load).
    void next() {
      if (!jack) return;
      for (std::size_t l = 0; l < V.size(); ++l) {
        V1[l] = v0 + kappa * (set_force - F[l]);
        dV[l] = (V1[l] - V[l]) / dt;
      }
    }
    double position(std::size_t l, double t) const { return jack ? X[l] : v0 * t; }
    double speed(std::size_t l) const { return jack ? V[l] : v0; }
    /// The position and speed at the step's end (after next()).
    double end_position(std::size_t l, double t1) const { return jack ? X[l] + 0.5 * dt * (V[l] + V1[l]) : v0 * t1; }
    double end_speed(std::size_t l) const { return jack ? V1[l] : v0; }
    /// Lane l takes the step.
    void advance(std::size_t l) {
      if (!jack) return;
      X[l] += 0.5 * dt * (V[l] + V1[l]);
      V[l] = V1[l];
    }
  };

  /// The modified Euler scheme (the header's comment) on the lanes of L.
  template <class Drive, class Observer>
  DRILL_AXIAL_FLATTEN void run_drive(Lanes<Drive>& L, const Inputs* in, Observer* obs, double* diverged_at) const {
    const double dt = opt_.dt;
    const long steps = opt_.steps();
    const std::size_t n = L.n;
    const int mt = static_cast<int>(w2_.size()), ma = ax_.size();
    const RgdBit& b = spec_.bit;
    const double F_top = top_force();
    AxialFrame frame(spec_, L.run0, dt);
    const double cw = b.cutting_wob_per_depth(), ct = b.cutting_torque_per_depth(), Wf_max = b.contact_wob(),
                 ctw = b.contact_torque_per_wob();
    const double gt = bit_.squaredNorm(), ga = ax_.bit.squaredNorm();
    const bool by_law = spec_.torque == AxialTorque::law;
    // Eq. (A.5)'s modal forces: -D p - w2 z and the top's acceleration (load -top_load) on the torsional
    // modes, -C e' - k^2 e and the top force (load top_row) on the axial ones; the passes over the modes
    // (euler_lanes.hpp) also sum the bit's rows: b . z, b . p, b . f and the top's torque, c . e, c . e', c . f
    const Eigen::VectorXd negd = -d_, neg_top_load = -top_load_, negc = -ax_.damping,
                          k2 = ax_.omega.cwiseProduct(ax_.omega), neg_ax_top_load = -ax_.top_load;
    const Eigen::MatrixXd Drow = D_.transpose();  // row-major D (dense damping)
    std::vector<double> ft(mt * n), fa(ma * n), om(n), om_next(n), dom(n), bp(n), ar(n), at(n), aa(n), T(n, 0.0),
        W(n, 0.0);
    const EulerModes tor{mt, n, dt, bit_.data(), top_torque_.data(), diag_damping_ ? negd.data() : nullptr,
                         w2_.data(), nullptr, 0.0, L.z.data(), L.p.data(), ft.data()};
    // the jack's top: the string's force on it summed with the axial pass (its row top_force)
    const EulerModes axl{ma, n, dt, ax_.bit.data(), frame.jack ? ax_.top_force.data() : nullptr, negc.data(),
                         k2.data(), ax_.top_row.data(), F_top, L.eta.data(), L.r.data(), fa.data()};
    auto modes = [&](bool update) {  // Eqs. (A.5)-(A.6) with the step's T and W, then the next step's forces and sums
      tor.pass(update, T.data(), L.bz.data(), bp.data(), at.data(), L.T_top.data());
      if (!diag_damping_) tor.dense_forces(Drow.data(), at.data());
      axl.pass(update, W.data(), L.ce.data(), ar.data(), aa.data(), frame.force());
    };
    modes(false);
    std::vector<LawHistory> hist(n);  // Eq. (A.1)'s accelerations of the last steps (by_law)
    for (long i = 0;; ++i) {
      const double t = i * dt;
      for (std::size_t l = 0; l < n; ++l) {
        om[l] = L.drive[l]->speed(t, L.om_state[l]);
        om_next[l] = L.drive[l]->next(t, om[l], L.T_top[l]);  // the top's speed at the next step
        dom[l] = L.drive[l]->accel(t, om[l], om_next[l]);    // and its acceleration over the step
      }
      tor.add_load(neg_top_load.data(), dom.data(), at.data());
      if (frame.jack) {  // the jack's speed at the next step and the load of its acceleration
        frame.next();
        axl.add_load(neg_ax_top_load.data(), frame.dV.data(), aa.data());
      }
      for (std::size_t l = 0; l < n; ++l) {
        T[l] = W[l] = 0.0;
        if (!L.live[l]) continue;
        const double Ob = om[l] + bp[l], Phi = L.theta_top[l] + L.bz[l];
        const double U = frame.position(l, t) + L.ce[l], V = frame.speed(l) + ar[l];
        const double alpha_t = at[l] + dom[l], alpha_a = aa[l];
        const BitProfile::Cut cut = L.profile[l].cut(t, Phi, U);  // the depth of cut and the delay t_N
        const double d = cut.depth;
        const bool contact = d > 0.0;
        const bool turning = Ob > bit_rest_tolerance(om[l]);
        // axial inclusion: W in [W_lo, W_hi] set-valued at V+ = 0 (rgd_bit.hpp's switches)
        double Wl = 0.0, Wf = 0.0, Tl = 0.0;
        if (contact) {
          const double Wc = cw * d, W_lo = turning ? Wc : 0.0, W_hi = Wc + Wf_max;
          const double Va = V + dt * (alpha_a - ga * W_lo);
          if (Va <= 0.0) Wl = W_lo;
          else if (Va - dt * ga * (W_hi - W_lo) >= 0.0) Wl = W_hi;
          else Wl = W_lo + Va / (dt * ga);
          Wf = std::min(Wl - W_lo, Wf_max);
          // torsional inclusion: T in [-T_f, T_c + T_f], set-valued at Omega+ = 0; the bit-rock
          // torque's fluctuation of Eq. (4.1) scales both, (1 + eta) floored at 0 (a set-valued
          // contact cannot drive the bit)
          const double fl = std::max(0.0, 1.0 + in[l].eta.at(t));
          if (by_law) {
            Tl = law_torque(Ob, om[l], alpha_t, gt, dt, fl, Wl, hist[l]);  // the thesis law on the axial W
          } else {
            const double T_fwd = fl * (ct * d + ctw * Wf), T_bwd = fl * ctw * Wf;
            const double Oa = Ob + dt * alpha_t;
            if (Oa > 0.0) Tl = Oa - dt * gt * T_fwd >= 0.0 ? T_fwd : Oa / (dt * gt);
            else Tl = Oa + dt * gt * T_bwd <= 0.0 ? -T_bwd : Oa / (dt * gt);
          }
        }
        if (!std::isfinite(Ob) || !std::isfinite(Tl) || !std::isfinite(Wl) || !std::isfinite(V)) {
          L.diverge(l, t, diverged_at);
          continue;
        }
        T[l] = Tl;
        W[l] = Wl;
        const double a_bit = alpha_t - gt * Tl;
        obs[l](static_cast<const StepState&>(
                   StepState{i, t, Ob, a_bit, Phi, Tl, L.T_top[l], om[l], L.drive[l]->torque(), Wl}),
               static_cast<const AxialStep&>(AxialStep{t, Wl, V, U, d, cut.delay, contact}));
      }
      if (i == steps) break;
      modes(true);  // Eqs. (A.5), (A.6)
      for (std::size_t l = 0; l < n; ++l) {
        if (!L.live[l]) continue;
        L.theta_top[l] += 0.5 * dt * (om[l] + om_next[l]);
        L.om_state[l] = om_next[l];
        frame.advance(l);
        L.profile[l].record(t + dt, L.theta_top[l] + L.bz[l], frame.position(l, t + dt) + L.ce[l]);
      }
    }
  }

  /// The exact modal scheme (the header's comment) on the lanes of L: run_drive's start, observer and
  /// top drive, each mode of both sets propagated by exact_modal_free/close.
  template <class Drive, class Observer>
  DRILL_AXIAL_FLATTEN void run_exact(Lanes<Drive>& L, const Inputs* in, Observer* obs, double* diverged_at) const {
    const double dt = opt_.dt;
    const long steps = opt_.steps();
    const std::size_t n = L.n;
    const RgdBit& b = spec_.bit;
    const double F_top = top_force();
    AxialFrame frame(spec_, L.run0, dt);
    const double cw = b.cutting_wob_per_depth(), ct = b.cutting_torque_per_depth(), Wf_max = b.contact_wob(),
                 ctw = b.contact_torque_per_wob();
    const int mt = et_.modes, ma = ea_.modes;
    // the coefficients [mode][kind][lane] of exact_modal_free/close: each lane the model's
    const std::vector<double> kt = lane_coefficients(et_, n), ka = lane_coefficients(ea_, n);
    std::vector<double> zs(mt * n), ps(mt * n), es(ma * n), rs(ma * n);
    std::vector<double> om(n), om1(n), dom(n), top(n, F_top), w(n), wa(n), bzs(n), ces(n), ar(n), T0(n), W0(n), T(n),
        W(n), dT0(n), dW0(n), Ob(n), x1(n), x2(n);
    // the bit's rows summed over the modes (euler_lanes.hpp's passes without an update or forces):
    // b . z, b . p and the top's torque at the step's end, c . e and c . e', and b . z, c . e of the free part
    std::vector<double> unused(n);
    const EulerModes tor{mt, n, dt, bit_.data(), top_torque_.data(), nullptr, nullptr, nullptr, 0.0, L.z.data(),
                         L.p.data(), nullptr};
    const EulerModes axl{ma, n, dt, ax_.bit.data(), frame.jack ? ax_.top_force.data() : nullptr, nullptr, nullptr,
                         nullptr, 0.0, L.eta.data(), L.r.data(), nullptr};
    const EulerModes tor_free{mt, n, dt, bit_.data(), nullptr, nullptr, nullptr, nullptr, 0.0, zs.data(), ps.data(),
                              nullptr};
    const EulerModes axl_free{ma, n, dt, ax_.bit.data(), nullptr, nullptr, nullptr, nullptr, 0.0, es.data(), rs.data(),
                              nullptr};
    // the state at t = 0 and the forces the first step starts from: steady drilling's
    tor.pass(false, nullptr, L.bz.data(), Ob.data(), nullptr, L.T_top.data());
    axl.pass(false, nullptr, L.ce.data(), ar.data(), nullptr, frame.force());
    for (std::size_t l = 0; l < n; ++l) {
      const Steady& st = L.run0[l].st;
      om[l] = L.drive[l]->speed(0.0, L.om_state[l]);
      Ob[l] = om[l] + Ob[l];
      W0[l] = st.wob;
      T0[l] = std::max(0.0, 1.0 + in[l].eta.at(0.0)) * st.torque;
      x1[l] = x2[l] = Ob[l] - om[l];  // the relative bit speeds of the last two steps (Newton's start, law)
      const BitProfile::Cut cut = L.profile[l].cut(0.0, L.bz[l], L.ce[l]);
      obs[l](static_cast<const StepState&>(
                 StepState{0, 0.0, Ob[l], 0.0, L.bz[l], T0[l], L.T_top[l], om[l], L.drive[l]->torque(), W0[l]}),
             static_cast<const AxialStep&>(
                 AxialStep{0.0, W0[l], frame.speed(l) + ar[l], L.ce[l], cut.depth, cut.delay, cut.depth > 0.0}));
    }
    std::vector<double> V(n), d(n), delay(n);
    std::vector<char> contact(n), rest_a(n), held_t(n), held_a(n);
    for (long i = 0; i < steps; ++i) {
      const double t = i * dt, t1 = t + dt;
      for (std::size_t l = 0; l < n; ++l) {
        om[l] = L.drive[l]->speed(t, L.om_state[l]);
        om1[l] = L.drive[l]->next(t, om[l], L.T_top[l]);
        dom[l] = (om1[l] - om[l]) / dt;  // the top's acceleration averaged over the step
      }
      frame.next();  // the jack's speed at the step's end: its acceleration loads the axial modes (prepare_exact)
      exact_modal_free(mt, n, kt.data(), bit_.data(), L.z.data(), L.p.data(), dom.data(), T0.data(), zs.data(),
                       ps.data(), w.data());
      exact_modal_free(ma, n, ka.data(), ax_.bit.data(), L.eta.data(), L.r.data(),
                       frame.jack ? frame.dV.data() : top.data(), W0.data(), es.data(), rs.data(), wa.data());
      tor_free.pass(false, nullptr, bzs.data(), unused.data(), nullptr, nullptr);
      axl_free.pass(false, nullptr, ces.data(), unused.data(), nullptr, nullptr);
      for (std::size_t l = 0; l < n; ++l) {
        dT0[l] = dW0[l] = T[l] = W[l] = 0.0;
        if (!L.live[l]) continue;
        const double theta1 = L.theta_top[l] + 0.5 * dt * (om[l] + om1[l]);
        // the rock surface at the angle the bit reaches with T_i+1 = T_i (explicit in the angle), and d_p,
        // the depth of cut at the axial position it reaches with W_i+1 = W_i
        const double Phi_p = theta1 + bzs[l] - zt1_ * T0[l], U_p = frame.end_position(l, t1) + ces[l] - za1_ * W0[l];
        const BitProfile::Cut cut = L.profile[l].cut(t1, Phi_p, U_p);
        const bool turning = Ob[l] > bit_rest_tolerance(om[l]);
        const double fl = std::max(0.0, 1.0 + in[l].eta.at(t1));
        // the axial inclusion with the depth of cut implicit in the bit's axial position: d = d_p - N z_a
        // (W - W_i), z_a = za1 (W linear over the step) or za0 + za1 (held), by fixed-point iteration
        // (contraction N a zeta eps z_a <= N a zeta eps g_a dt^2 / 2 < 1 / 2 under the step bound)
        double dl = cut.depth, Wl = 0.0, Wf = 0.0, Tl = 0.0, x = 0.0;
        bool cont = false, ha = false, ra = false, ht = false;
        for (int k = 0;; ++k) {
          cont = dl > 0.0;
          Wl = Wf = 0.0;
          ha = ra = false;
          if (cont) {
            const double Wc = cw * dl;
            exact_axial(frame.end_speed(l) + wa[l], W0[l], turning ? Wc : 0.0, Wc + Wf_max, Wl, ha, ra);
            Wf = std::min(Wl - (turning ? Wc : 0.0), Wf_max);
          }
          const double dn = cut.depth - b.blades * (ha ? za0_ + za1_ : za1_) * (Wl - W0[l]);
          if (std::fabs(dn - dl) <= 1e-14 * std::fabs(cut.depth) || k == 40) break;
          dl = dn;
        }
        if (law_step_) {  // the thesis law on the axial W (Eqs. 3.1-3.3, 5.1, 5.3 at the step's end)
          double fric = 0.0;
          law_step_->exact_bit(w[l], et_.c, et_.c0, T0[l], om[l], om1[l], Ob[l], Wl, fl - 1.0, 0.0, 0.0, t1,
                               2.0 * x1[l] - x2[l], x, Tl, fric, ht);
        } else if (cont) {
          exact_rgd_torque(w[l], T0[l], om[l], om1[l], Ob[l], fl * (ct * dl + ctw * Wf), fl * ctw * Wf, x, Tl, ht);
        } else {
          x = w[l];  // off the rock: T = 0
        }
        if (!std::isfinite(x) || !std::isfinite(Tl) || !std::isfinite(Wl)) {
          L.diverge(l, t1, diverged_at);
          continue;
        }
        T[l] = Tl;
        W[l] = Wl;
        dT0[l] = ht ? Tl - T0[l] : 0.0;
        dW0[l] = ha ? Wl - W0[l] : 0.0;
        L.theta_top[l] = theta1;
        x2[l] = x1[l];
        x1[l] = x;
        d[l] = dl;
        delay[l] = cut.delay;
        contact[l] = cont;
        rest_a[l] = ra;
        held_t[l] = ht;
        held_a[l] = ha;
      }
      exact_modal_close(mt, n, kt.data(), zs.data(), ps.data(), T.data(), dT0.data(), L.z.data(), L.p.data());
      exact_modal_close(ma, n, ka.data(), es.data(), rs.data(), W.data(), dW0.data(), L.eta.data(), L.r.data());
      tor.pass(false, nullptr, L.bz.data(), unused.data(), nullptr, L.T_top.data());
      axl.pass(false, nullptr, L.ce.data(), ar.data(), nullptr, frame.force());
      for (std::size_t l = 0; l < n; ++l) {
        if (!L.live[l]) continue;
        L.om_state[l] = om1[l];
        frame.advance(l);
        const double v1 = om1[l] + x1[l], V1 = rest_a[l] ? 0.0 : frame.speed(l) + ar[l];
        L.profile[l].record(t1, L.theta_top[l] + L.bz[l], frame.position(l, t1) + L.ce[l]);
        // the step's mean forces (exact_modal.hpp): the end ones where they are held over the step
        const double Tm = held_t[l] ? T[l] : 0.5 * (T0[l] + T[l]), Wm = held_a[l] ? W[l] : 0.5 * (W0[l] + W[l]);
        const double a_bit = (v1 - Ob[l]) / dt;
        obs[l](static_cast<const StepState&>(StepState{i + 1, t1, v1, a_bit, L.theta_top[l] + L.bz[l], Tm, L.T_top[l],
                                                       om1[l], L.drive[l]->torque(), Wm}),
               static_cast<const AxialStep&>(
                   AxialStep{t1, Wm, V1, frame.position(l, t1) + L.ce[l], d[l], delay[l], contact[l] != 0}));
        Ob[l] = v1;
        T0[l] = T[l];
        W0[l] = W[l];
      }
    }
  }

  /// The exact step's coefficients [mode][kind] laid out [mode][kind][lane] for n lanes (each lane the
  /// model's), as exact_modal_free and exact_modal_close read them.
  static std::vector<double> lane_coefficients(const ExactModal& e, std::size_t n) {
    std::vector<double> out(e.k.size() * n);
    for (std::size_t q = 0; q < e.k.size(); ++q)
      for (std::size_t l = 0; l < n; ++l) out[q * n + l] = e.k[q];
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
    // the axial modes' "top acceleration": the hook load's F_top on the load -(-top_row), or the jack's
    // acceleration on -top_load (the moving frame's inertia)
    ea_ = ExactModal::build(ax_.omega.cwiseAbs2(), ax_.damping, ax_.bit,
                            spec_.top == AxialTop::jack ? Eigen::VectorXd(ax_.top_load) : Eigen::VectorXd(-ax_.top_row),
                            opt_.dt);
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
