// Time integration of the reduced drill-string model with the torque on bit (appendices A, B).
//
// Equation of motion in the rotating frame (Eqs. 2.5, 2.9), with a top speed Omega(t):
//   M~ q'' + D~ q' + K~ q = -bit^T T_bit - top_load Omega'(t),
//   bit speed  = Omega(t) + bit q',   T_bit = T_law(v, a, W(t)) (1 + eta(t)) + c_v v + T_sf sign(v)
// (Eq. 4.1 for the law term). The viscous torque c_v v (`operation.bit_viscous_nms`) and the
// Coulomb string friction T_sf sign(v) (`operation.string_friction_nm`: the string rubbing on its
// guides or the borehole, lumped at the bit DOF) are not in the thesis: both are extensions that
// act on the bit outside its torque sensor. The torque on bit reported to observers excludes
// T_sf sign(v) (it is the law's contact torque plus c_v v). At rest T_sf is set-valued like the
// law's static torque: the stick condition holds the bit while |string torque at the bit| <=
// static_torque(W) (1 + eta) + T_sf, and it applies whenever that capacity is positive (so T_sf
// alone makes the laws without a static torque stick).
// Omega(t) is the commanded speed (ideal top drive) or the state of a motor model driven by it
// (drives/motor.hpp: J_m Omega' = c_m (Omega_c - Omega) - T_top; modified Euler and exact modal),
// or of a controlled drive J Omega' = u - T_top with the motor torque u of a speed controller
// (drives/controlled.hpp, controller.hpp; the same coupling and stability bound as the motor). The
// drives are listed in drives/registry.hpp; run_euler and run_exact are instantiated once per
// drive, with its update of the top speed (its Run) inlined.
// The reduced matrices are first brought to M = I, K = diag(omega^2) by the generalized
// eigenvectors of (K~, M~); D~ stays diagonal for modal or Rayleigh damping and is used dense
// otherwise (random matrices, Craig-Bampton).
//
// Schemes:
//  * modified_euler (appendix A, Eqs. A.5-A.6): semi-implicit Euler, velocity first, then the
//    displacement with the new velocity; the torque on bit is explicit in the bit speed of the
//    current step. Its bit acceleration is the one Eq. (A.1) defines, the forward difference
//    (v_{i+1} - v_i) / dt, which the update (A.5) itself produces: since the torque depends on it
//    (Eq. 3.3) it is found from the scalar equation a = alpha_i - g T(v_i, a) (g = bit . bit, alpha_i
//    the bit acceleration without the bit torque), monotone in a, by safeguarded Newton. (A lagged
//    backward difference instead makes H flip sign at every step: docs/numerics.md.) First order.
//    Refused when dt >= pi / (5 omega_max) (Eq. A.7) with omega_max the highest retained frequency
//    (with a motor top drive: of the string stiffened by the motor inertia, K - top_load top_torque / J_m).
//  * bdf2: second-order backward differentiation (backward Euler for the first step), L-stable,
//    with the torque on bit implicit: the scalar equation for the new bit speed is solved by a
//    safeguarded Newton iteration, and the bit acceleration in Eq. (3.3) is the BDF2 derivative
//    of the bit speed at the new step. No stability bound; no chattering at stick.
//  * exact_modal (exact_modal.hpp): each mode's linear part integrated exactly over the step (its
//    2x2 propagator and the exact response to a forcing linear over the step), the bit torque
//    implicit at the step's end with Eq. (A.1)'s forward-difference acceleration in Eq. (3.3) and
//    the stick condition of the bdf2 step. No stability bound of its own; diagonal modal damping
//    only. A drive with inertia and the rig's jack are stepped as run_euler steps them (explicit in
//    the string's top torque, in the bit speed), with the modified Euler's bound of the string
//    coupled to the drive's inertia.
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "drill/axial.hpp"
#include "drill/bitrock.hpp"
#include "drill/errors.hpp"
#include "drill/euler_bit.hpp"
#include "drill/exact_modal.hpp"
#include "drill/modal.hpp"
#include "drill/names.hpp"
#include "drill/signal.hpp"
#include "drill/topdrive.hpp"

namespace drill {

enum class Scheme { modified_euler, bdf2, exact_modal };

inline constexpr Named<Scheme> scheme_names[] = {
    {Scheme::modified_euler, "modified_euler"}, {Scheme::bdf2, "bdf2"}, {Scheme::exact_modal, "exact_modal"}};
inline Scheme parse_scheme(const std::string& s) { return parse_name(scheme_names, s, "simulation.scheme", "scheme"); }
inline std::string to_string(Scheme s) { return name_of(scheme_names, s); }

/// The bit acceleration in the hysteretic term of Eq. (3.3). `implicit`: the one the step itself
/// produces (Eq. A.1's forward difference, solved with the torque; BDF2's derivative with bdf2).
/// `lagged`: the backward difference of the last two bit speeds, (v_i - v_{i-1}) / dt, known
/// before the step (Algorithm 1 read literally: the acceleration of step i from the speeds already
/// computed); modified Euler only. The thesis does not say which it used (docs/numerics.md).
enum class Acceleration { implicit, lagged };

inline constexpr Named<Acceleration> acceleration_names[] = {{Acceleration::implicit, "implicit"},
                                                             {Acceleration::lagged, "lagged"}};
inline Acceleration parse_acceleration(const std::string& s) {
  return parse_name(acceleration_names, s, "simulation.acceleration", "reading");
}
inline std::string to_string(Acceleration a) { return name_of(acceleration_names, a); }

struct SimOptions {
  Scheme scheme = Scheme::modified_euler;
  Acceleration acceleration = Acceleration::implicit;  ///< bit acceleration in Eq. (3.3)
  double dt = 5.12e-4;      ///< time step [s] (the thesis's 0.512 ms)
  double duration = 100.0;  ///< simulated time [s]
  static constexpr double max_steps = 2e9;  ///< most time steps of a run (a step count fits a long)
  /// Refusals name the field and value; too many steps names both dt_s and duration_s (either can
  /// be the one typed in the wrong unit), with a hint when one is outside any real run.
  void validate() const {
    require_positive(dt, "simulation.dt_s");
    require_positive(duration, "simulation.duration_s");
    require(duration >= dt, "simulation.duration_s", duration, "must be at least one time step (simulation.dt_s = " + show(dt) + ")");
    if (!(duration / dt < max_steps)) {  // either value may be the one typed wrong: name both
      std::ostringstream os;
      os.precision(3);
      os << duration / dt;
      const std::string hint = dt < 1e-6         ? "; a time step below 1 us: in ms or us typed as s?"
                               : duration > 8.64e6 ? "; a duration over 100 days: in ms typed as s?"
                                                   : "";
      throw std::invalid_argument("simulation.dt_s = " + show(dt) + " with simulation.duration_s = " + show(duration) +
                                  ": " + os.str() + " steps, at most 2e+09" + hint);
    }
    require(acceleration == Acceleration::implicit || scheme == Scheme::modified_euler, "simulation.acceleration",
            to_string(acceleration), "is implemented for simulation.scheme = modified_euler only");
  }
  long steps() const { return std::lround(duration / dt); }
};

/// Boundary inputs and the extra bit terms of one run.
struct Inputs {
  Signal top_speed = Signal::constant(10.0);  ///< [rad/s]
  Signal wob = Signal::constant(245e3);       ///< [N]
  Signal eta = Signal::constant(0.0);         ///< multiplicative torque fluctuation (Eq. 4.1)
  double bit_viscous = 0.0;                   ///< extra viscous torque at the bit [N m s/rad]
  double string_friction = 0.0;               ///< Coulomb string friction T_sf at the bit [N m] (not reported)
  TopDrive top_drive;                         ///< ideal (Omega = top_speed) or motor (commanded by it)
  Axial axial;                                ///< none (W = wob) or the jack: W a state, wob its set force
  void validate() const {
    top_drive.validate();
    axial.validate();
    require(!axial.active() || std::isfinite(axial.feed_speed), "axial.feed_speed", axial.feed_speed,
            "must be set (Simulation::inputs sets it to the drive's steady speed)");
    top_speed.validate("operation.top_speed_rad_s");
    wob.validate("operation.wob_n");
    eta.validate("eta");
    require_non_negative(bit_viscous, "operation.bit_viscous_nms");
    require_non_negative(string_friction, "operation.string_friction_nm");
  }
};

/// What an observer sees at every time step (absolute frame, SI).
struct StepState {
  long step = 0;
  double t = 0.0;
  double bit_speed = 0.0;      ///< [rad/s]
  double bit_accel = 0.0;      ///< [rad/s^2] (the value used by the law)
  double bit_angle = 0.0;      ///< [rad]
  double torque_on_bit = 0.0;  ///< [N m]: law (1 + eta) + c_v v; the string friction is not part of it
  double top_torque = 0.0;     ///< elastic torque applied by the top drive [N m]
  double top_speed = 0.0;      ///< [rad/s]
  double drive_torque = NAN;   ///< motor torque u of a controlled top drive [N m] (NaN otherwise)
  double wob = NAN;            ///< weight on bit the law saw [N] (the input, or the axial state)
};

/// Generalized coordinates and velocities of the reduced model (original basis).
struct ModelState {
  Eigen::VectorXd q, qdot;
  double top_speed = NAN;  ///< motor speed [rad/s] (motor top drive; NaN: the command at t = 0)
  /// Controlled top drive: the PI's integral torque T_I and z_torque's low-passed top torque
  /// T_mean [N m] (NaN: the top torque of the initial state, the drive starting in equilibrium).
  double drive_integral = NAN, drive_mean = NAN;
  double wob = NAN;  ///< the axial state W [N] (axial jack; NaN: the set force at t = 0)
};

class Integrator {
  friend class BatchedIntegrator;  // batched_integrator.hpp: the same scheme on runs in SIMD lockstep
  friend class AxialTorsional;     // axial_torsional.hpp: exact_bit at the end of its exact modal step

 public:
  Integrator(const ReducedModel& model, const BitRockLaw& law, const SimOptions& opt)
      : law_(law), opt_(opt) {
    law_.validate();
    opt_.validate();
    const int m = model.size();
    require(m >= 1, "rom.modes", m, "the reduced model is empty");
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(model.K, model.M);
    if (es.info() != Eigen::Success) throw std::runtime_error("reduced eigenproblem failed");
    V_ = es.eigenvectors();  // V^T M V = I
    w2_ = es.eigenvalues().cwiseMax(0.0);
    omega_max_ = std::sqrt(w2_.maxCoeff());
    D_ = V_.transpose() * model.D * V_;
    const double dscale = std::max(D_.diagonal().cwiseAbs().maxCoeff(), 1e-300);
    diag_damping_ = (D_ - Eigen::MatrixXd(D_.diagonal().asDiagonal())).cwiseAbs().maxCoeff() <= 1e-10 * dscale;
    d_ = D_.diagonal();
    bit_ = (model.bit * V_).transpose();
    top_torque_ = (model.top_torque * V_).transpose();
    top_load_ = V_.transpose() * model.top_load;
    init_vel_ = V_.transpose() * model.M * model.init_velocity;  // V^-1 = V^T M
    Vinv_ = V_.transpose() * model.M;
    if (opt_.scheme == Scheme::modified_euler) {
      const double bound = stability_bound();
      require(opt_.dt < bound, "simulation.dt_s", opt_.dt,
              "exceeds the modified-Euler stability bound dt < pi / (5 omega_max) = " + show(bound) +
                  " s (Eq. A.7, omega_max = " + show(omega_max_) + " rad/s of the retained modes)");
    } else if (opt_.scheme == Scheme::exact_modal) {
      require(diag_damping_, "simulation.scheme", to_string(opt_.scheme),
              "needs a damping that is diagonal in the modal basis (modal or Rayleigh damping)");
      em_ = ExactModal::build(w2_, d_, bit_, top_load_, opt_.dt);
    } else {
      prepare_implicit(opt_.dt, be_);
      prepare_implicit(2.0 * opt_.dt / 3.0, bdf_);
    }
  }

  /// Eq. (A.7): dt < pi / (5 omega_max) with omega_max the highest retained natural frequency.
  double stability_bound() const { return M_PI / (5.0 * omega_max_); }

  /// Eq. (A.7) with a motor top drive: omega_max of the string coupled to the motor inertia, the
  /// largest |eigenvalue| of diag(omega^2) - top_load top_torque^T / J_m (the motor's own damping
  /// is implicit and needs no bound).
  /// The same bound holds for a controlled drive of inertia J (its own loop is implicit when
  /// continuous; a sampled loop holds its torque over the step and is checked by Jury's criterion).
  double stability_bound(const TopDrive& td) const {
    if (!td.has_inertia()) return stability_bound();
    return M_PI / (5.0 * drive_omega_max(w2_, top_load_, top_torque_, td.inertia));
  }

  /// The largest frequency [rad/s] of the modes of squared frequencies w2 (modal basis, M = I) coupled
  /// to a free top inertia J through the top's load and torque rows: the largest |eigenvalue| of
  /// diag(w2) - top_load top_torque^T / J, at least the modes' own (stability_bound(td); the
  /// axial-torsional model's bound with a top drive of inertia, axial_torsional.hpp).
  static double drive_omega_max(const Eigen::VectorXd& w2, const Eigen::VectorXd& top_load,
                                const Eigen::VectorXd& top_torque, double inertia) {
    const Eigen::MatrixXd Ka = Eigen::MatrixXd(w2.asDiagonal()) - top_load * top_torque.transpose() / inertia;
    return std::sqrt(std::max(Ka.eigenvalues().cwiseAbs().maxCoeff(), w2.maxCoeff()));
  }

  /// Elastic torque the top drive applies for a state of the model [N m].
  double top_torque(const ModelState& s) const { return top_torque_.dot(Vinv_ * s.q); }

  /// The state of the model that reproduces, at one instant, a measured bit speed v [rad/s], bit
  /// acceleration a [rad/s^2], torque on bit T [N m] (the torque acting on the bit), top speed
  /// omega [rad/s] and top acceleration domega [rad/s^2] (Eq. 2.9 solved for the coordinates).
  /// In the modal basis (M = I) the lowest mode in which the bit moves carries the motion,
  ///   p_1 = (v - omega) / bit_1,  p_1' = (a - domega) / bit_1,
  ///   z_1 = -(p_1' + D_11 p_1 + top_load_1 domega + bit_1 T) / omega_1^2,
  /// and the other modes are quasi-static (p_j = p_j' = 0, z_j = -(top_load_j domega + bit_j T) / omega_j^2).
  /// With one retained mode (the test rig) the state is exact; the motor speed is set to omega.
  /// With a motor top drive the top's acceleration follows from the motor equation instead, as the
  /// scheme's motor step makes it, (J_m + c_m dt) domega = c_m (command - omega) - T_top(domega), with
  /// T_top linear in domega through the state: domega = (c_m (command - omega) - T_top(0)) /
  /// (J_m + c_m dt + dT_top/ddomega).
  /// (The drive's equation: TopDrive::top_accel, drives/motor.hpp; refused for a drive without one.)
  ModelState state_from_bit(double v, double a, double T, double omega, const TopDrive& td, double command) const {
    require(td.accel_from_torque(), "top_drive.type", TopDrive::kind_name(td.kind),
            "has no equation for the top's acceleration here");
    const double t0 = top_torque(state_from_bit(v, a, T, omega, 0.0));
    const double slope = top_torque(state_from_bit(v, a, T, omega, 1.0)) - t0;
    return state_from_bit(v, a, T, omega, td.top_accel(command, omega, opt_.dt, t0, slope));
  }

  ModelState state_from_bit(double v, double a, double T, double omega, double domega) const {
    for (double x : {v, a, T, omega, domega}) require_finite(x, "measured state (v, a, T, omega, domega)");
    const Eigen::Index m = w2_.size();
    const double bmax = bit_.cwiseAbs().maxCoeff();
    Eigen::Index j0 = 0;
    while (j0 < m && std::fabs(bit_(j0)) <= 1e-9 * bmax) ++j0;
    require(j0 < m && bmax > 0.0, "rom.modes", m, "no retained mode moves the bit");
    Eigen::VectorXd z(m), p = Eigen::VectorXd::Zero(m);
    for (Eigen::Index j = 0; j < m; ++j) {
      require(w2_(j) > 0.0, "rom.modes", m, "a retained mode has zero stiffness");
      z(j) = -(top_load_(j) * domega + bit_(j) * T) / w2_(j);
    }
    p(j0) = (v - omega) / bit_(j0);
    const double pd = (a - domega) / bit_(j0);
    z(j0) = -(pd + D_(j0, j0) * p(j0) + top_load_(j0) * domega + bit_(j0) * T) / w2_(j0);
    ModelState s = to_model(z, p);
    s.top_speed = omega;
    return s;
  }
  double omega_max() const { return omega_max_; }
  /// The error of a run whose bit speed or torque became non-finite at time t [s].
  static std::string divergence(double t) {
    return "simulation diverged at t = " + show(t) + " s (non-finite bit speed or torque); check the law parameters and dt";
  }
  const SimOptions& options() const { return opt_; }
  const BitRockLaw& law() const { return law_; }

  /// Initial state of Eq. (2.10) for a top speed Omega0: q = 0, q' = -Omega0 M~^-1 Phi^T M 1.
  ModelState initial_state(double omega0) const {
    return {Eigen::VectorXd::Zero(V_.rows()), V_ * (-omega0 * init_vel_)};
  }

  /// Integrate from `start` (or Eq. 2.10) and call obs(const StepState&) at every step
  /// including t = 0. Returns the final state.
  template <class Observer>
  ModelState run(const Inputs& in, Observer&& obs, const ModelState* start = nullptr) const {
    check_inputs(in);
    const ModelState s0 = start ? *start : initial_state(in.top_speed.at(0.0));
    require(s0.q.size() == V_.rows() && s0.qdot.size() == V_.rows(), "initial_state", s0.q.size(),
            "has the wrong size (the model has " + show(V_.rows()) + " coordinates)");
    Eigen::VectorXd z = Vinv_ * s0.q, p = Vinv_ * s0.qdot;
    if (opt_.scheme == Scheme::bdf2) return run_bdf2(in, obs, z, p);
    if (opt_.scheme == Scheme::exact_modal)
      return TopDrive::visit(in.top_drive.kind,
                             [&](auto drive) { return run_exact<decltype(drive)>(in, obs, z, p, s0); });
    return TopDrive::visit(in.top_drive.kind,
                           [&](auto drive) { return run_euler<decltype(drive)>(in, obs, z, p, s0); });
  }

  /// The checks of run() on its inputs (BatchedIntegrator's too): valid, not the coupled model, a
  /// tuned controller, and a drive with inertia on a scheme that has it, within Eq. (A.7)'s bound.
  void check_inputs(const Inputs& in) const {
    in.validate();
    require(!in.axial.coupled(), "axial.type", Axial::kind_name(in.axial.kind),
            "runs through Simulation::run only (drillpy simulate, drillsim --job run): sweeps, maps, Monte Carlo, "
            "control and horizons are not implemented for the axial-torsional model");
    if (in.top_drive.has_controller()) {
      const Controller& c = in.top_drive.controller;
      require(c.tuned(), "top_drive.controller", Controller::kind_name(c.kind),
              "has no gains: tune it (TopDrive::tune_controller; Simulation does it from the string)");
      require(!c.sampled() || opt_.dt <= c.sample_time * (1.0 + 1e-12), "simulation.dt_s", opt_.dt,
              "is larger than top_drive.controller.sample_time_s = " + show(c.sample_time) + " s");
    }
    if (in.top_drive.has_inertia()) {
      require(opt_.scheme != Scheme::bdf2, "top_drive.type", TopDrive::kind_name(in.top_drive.kind),
              "is implemented for simulation.scheme = modified_euler and exact_modal only");
      // the drive's step is explicit in the string's top torque in both schemes: Eq. (A.7)'s bound
      // of the string coupled to the drive's inertia holds for both (exact_modal's modes need none)
      const double bound = stability_bound(in.top_drive);
      require(opt_.dt < bound, "simulation.dt_s", opt_.dt,
              "exceeds the stability bound with the " + TopDrive::kind_name(in.top_drive.kind) +
                  " top drive, dt < " + show(bound) + " s (Eq. A.7 for the string coupled to top_drive.inertia_kg_m2 = " +
                  show(in.top_drive.inertia) + ")");
    }
  }

 private:
  struct Implicit {
    double gamma = 0.0, g = 0.0;
    Eigen::VectorXd sdiag_inv;  ///< 1 / diag(S) when the damping is diagonal
    Eigen::MatrixXd Sinv;       ///< S^-1 otherwise
    Eigen::VectorXd s;          ///< S^-1 bit^T
  };

  void prepare_implicit(double gamma, Implicit& im) const {
    im.gamma = gamma;
    const int m = static_cast<int>(w2_.size());
    if (diag_damping_) {
      im.sdiag_inv = (Eigen::VectorXd::Ones(m) + gamma * d_ + gamma * gamma * w2_).cwiseInverse();
      im.s = im.sdiag_inv.cwiseProduct(bit_);
    } else {
      Eigen::MatrixXd S = Eigen::MatrixXd::Identity(m, m) + gamma * D_;
      S.diagonal() += gamma * gamma * w2_;
      im.Sinv = S.inverse();
      im.s = im.Sinv * bit_;
    }
    im.g = bit_.dot(im.s);
  }

  /// Total torque on bit (law x (1 + eta) + viscous + string friction T_sf sign(v)) with derivatives.
  TorqueEval total_torque(double v, double a, double wob, double eta, double cv, double sf = 0.0) const {
    TorqueEval e = law_.eval(v, a, wob);
    const double f = 1.0 + eta;
    TorqueEval out{e.T * f + cv * v, e.dT_dv * f + cv, e.dT_da * f};
    if (sf != 0.0) out.T += sf * sign(v);  // a jump at v = 0 (solve_root finds it as a bracket limit)
    return out;
  }

  static double sign(double v) { return (v > 0.0) - (v < 0.0); }

  ModelState to_model(const Eigen::VectorXd& z, const Eigen::VectorXd& p) const { return {V_ * z, V_ * p}; }

  /// Modified Euler with the top drive `Drive` of drives/registry.hpp (one instantiation per drive:
  /// its update of the top speed, Drive::Run, is inlined in the step).
  template <class Drive, class Observer>
  ModelState run_euler(const Inputs& in, Observer& obs, Eigen::VectorXd& z, Eigen::VectorXd& p,
                       const ModelState& s0) const {
    const double top0 = s0.top_speed;
    const double dt = opt_.dt;
    const long n = opt_.steps();
    const double g = bit_.squaredNorm();
    Eigen::VectorXd f(z.size());
    double theta_top = 0.0, v_prev = NAN;
    double a1 = 0.0, a2 = 0.0, a3 = 0.0;  // the accelerations of the last three solves of Eq. (A.1)
    bool newton = false;                  // the last step solved Eq. (A.1) by Newton
    // the time the bit has been stuck [s], for the static torque's ageing (a run starts it at 0)
    const bool ages = law_.ages();
    double stuck_s = 0.0;
    const double k_law = law_.beta2 * speed_factor(law_.speed_unit);  // k of BitRockLaw::AtSpeed
    const bool lagged = opt_.acceleration == Acceleration::lagged;
    double om_state = std::isfinite(top0) ? top0 : in.top_speed.at(0.0);  // motor speed
    const bool axial = in.axial.active();
    double wob_state = std::isfinite(s0.wob) ? s0.wob : in.wob.at(0.0);  // the axial state (axial.hpp)
    // the drive's update of the top speed (a controlled drive's loop starts in equilibrium with
    // the string's top torque unless the state gives it)
    typename Drive::template Run<TopDrive> drive(in.top_drive, in.top_speed, dt, s0,
                                                 [&] { return top_torque_.dot(z); });
    for (long i = 0;; ++i) {
      const double t = i * dt;
      const double om = drive.speed(t, om_state);
      const double T_top = top_torque_.dot(z);  // the string's elastic torque at the top (reported too)
      // the motor's speed at the next step, from the string's top torque of this step
      const double om_next = drive.next(t, om, T_top);
      // the top's acceleration; a controlled drive's by a product (off a division's latency; the
      // motor's division stays: drillpy loop's results move with its rounding)
      const double domega = drive.accel(t, om, om_next);
      const double wob = axial ? wob_state : in.wob.at(t), eta = in.eta.at(t);
      // Newton's start for Eq. (A.1) (below). Its tanh does not depend on this step: evaluated
      // here, where it overlaps the step's chain of dependent operations (the controller's, the
      // law's exp and log), when the last step needed Newton too (a smooth run)
      const double guess = 3.0 * (a1 - a2) + a3;
      const double th_guess = newton ? tanh_sat(k_law * guess) : 0.0;
      const bool newton_last = newton;
      newton = false;
      const double v = om + bit_.dot(p);
      // modal forces other than the bit torque: damping, stiffness, accelerating frame
      if (diag_damping_)
        f.array() = -d_.array() * p.array() - w2_.array() * z.array();
      else
        f = -D_ * p - w2_.cwiseProduct(z);
      if (domega != 0.0) f -= top_load_ * domega;  // exactly zero at constant top speed
      const double alpha = bit_.dot(f) + domega;
      // Eq. (A.1): a = (v_{i+1} - v_i) / dt = alpha - g T(v_i, a), with
      // T(a) = (1 + eta) (base + frac (1 + c tanh(k a))) + c_v v increasing in a.
      const BitRockLaw::AtSpeed ts = law_.at_speed(v, wob);
      const double scale = 1.0 + eta, visc = in.bit_viscous * v;
      // string friction T_sf sign(v) of the moving bit (at rest the stick condition sets it)
      double fric = in.string_friction > 0.0 ? in.string_friction * sign(v) : 0.0;
      const double rest = fric != 0.0 ? visc + fric : visc;
      double a = alpha - g * (scale * (ts.base + ts.frac) + rest);
      double T = scale * (ts.base + ts.frac) + rest;
      if (lagged) {
        // the acceleration of the last step enters the law; the step's own follows from it
        const double a_lag = std::isfinite(v_prev) ? (v - v_prev) / dt : 0.0;
        T = scale * ts.eval(a_lag).T + rest;
        a = alpha - g * T;
      } else if (ts.frac * ts.c != 0.0 && ts.k != 0.0) {
        newton = solve_euler_accel(ts, alpha, g, scale, rest, guess, th_guess, newton_last, a, T);  // euler_bit.hpp
        a3 = a2;
        a2 = a1;
        a1 = a;
      }
      // the static torque, aged by the time the bit has been stuck (law.static_ageing; 1 without)
      const double Ts = ages ? scale * law_.static_torque(wob) * law_.ageing_factor(stuck_s)
                             : scale * law_.static_torque(wob);
      const bool stuck =
          Ts + in.string_friction > 0.0 && stick_euler(v, om, alpha, g, dt, Ts, in.string_friction, visc, a, T, fric);
      stuck_s = stuck ? stuck_s + dt : 0.0;
      if (!std::isfinite(v) || !std::isfinite(T)) diverged(t);
      const double T_bit = fric != 0.0 ? T - fric : T;  // the string friction acts outside the torque sensor
      obs(static_cast<const StepState&>(
          StepState{i, t, v, a, theta_top + bit_.dot(z), T_bit, T_top, om, drive.torque(), wob}));
      if (i == n) break;
      v_prev = v;
      p += dt * (f - bit_ * T);  // Eq. (A.5): velocity first, with the torque of step i ...
      z += dt * p;               // Eq. (A.6): ... then the displacement with the new velocity.
      theta_top += 0.5 * dt * (om + om_next);
      om_state = om_next;
      if (axial) wob_state = in.axial.step(wob_state, v, in.wob.at(t), dt);
    }
    ModelState out = to_model(z, p);
    out.top_speed = om_state;
    if (axial) out.wob = wob_state;
    drive.finish(out);
    return out;
  }

  template <class Observer>
  ModelState run_bdf2(const Inputs& in, Observer& obs, Eigen::VectorXd& z, Eigen::VectorXd& p) const {
    const double dt = opt_.dt;
    const long n = opt_.steps();
    const int m = static_cast<int>(z.size());
    Eigen::VectorXd z_old = z, p_old = p, cz(m), cp(m), rhs(m), pstar(m);
    double theta_top = 0.0;
    double x_n = bit_.dot(p), x_old = x_n;  // relative bit speeds at n and n-1
    // Step 0: report the initial state with the explicit torque (zero acceleration).
    {
      const double om = in.top_speed.at(0.0);
      const double v = om + x_n;
      const double T = total_torque(v, 0.0, in.wob.at(0.0), in.eta.at(0.0), in.bit_viscous).T;
      obs(static_cast<const StepState&>(StepState{0, 0.0, v, 0.0, bit_.dot(z), T, top_torque_.dot(z), om, NAN, in.wob.at(0.0)}));
    }
    // backward Euler on the first step and on the step after each stuck step (the BDF2 history of a
    // bit that has just been stopped by the stick condition is not smooth: restart the multistep)
    bool restart = true;
    for (long i = 0; i < n; ++i) {
      const bool first = restart;
      const Implicit& im = first ? be_ : bdf_;
      const double t1 = (i + 1) * dt;
      if (first) {
        cz = z;
        cp = p;
      } else {
        cz = (4.0 * z - z_old) / 3.0;
        cp = (4.0 * p - p_old) / 3.0;
      }
      const double om1 = in.top_speed.at(t1), domega = in.top_speed.rate(t1 - 0.5 * dt);
      const double wob = in.wob.at(t1), eta = in.eta.at(t1);
      rhs = cp - im.gamma * (w2_.cwiseProduct(cz) + top_load_ * domega);
      if (diag_damping_)
        pstar = im.sdiag_inv.cwiseProduct(rhs);
      else
        pstar = im.Sinv * rhs;
      const double w = bit_.dot(pstar);
      // Bit acceleration consistent with the scheme: BDF2 (or backward Euler) derivative.
      const double ca = first ? 1.0 / dt : 1.5 / dt;
      const double a0 = first ? -x_n / dt : (-2.0 * x_n + 0.5 * x_old) / dt;
      double Tnew = 0.0;
      const double c = im.gamma * im.g;
      const double Ts = (1.0 + eta) * law_.static_torque(wob), Tsf = in.string_friction, cap = Ts + Tsf;
      const double om0 = in.top_speed.at(t1 - dt), v_n = om0 + x_n;
      const bool at_rest = cap > 0.0 && std::fabs(v_n) <= bit_rest_tolerance(om0);
      // Stick condition of Eqs. (5.1), (5.3) (see stick_euler, euler_bit.hpp): at rest (x = -om1) the friction
      // needed is T_req = (w + om1) / c, held by the static torque and the string friction.
      const double T_req = (w + om1) / c, sf = (T_req > 0.0) - (T_req < 0.0);
      bool stuck = at_rest && std::fabs(T_req) <= cap;
      double x = -om1, fric = 0.0;
      if (!stuck) {
        x = solve_bit(w, c, om1, ca, a0 + domega, wob, eta, in.bit_viscous, Tsf, x_n, t1, Tnew);
        const double v1 = om1 + x, sv = (v_n > 0.0) - (v_n < 0.0);
        const bool lands = v_n * v1 <= 0.0 || std::fabs(v1) <= bit_rest_tolerance(om1);  // at the jump of the law
        stuck = cap > 0.0 && !at_rest && lands && (std::fabs(T_req) <= cap || sf == sv);
        if (Tsf > 0.0) fric = Tsf * sign(v1);
      }
      if (stuck) {
        x = -om1;
        Tnew = T_req;
        fric = Tsf > 0.0 ? string_share(T_req, Ts, Tsf) : 0.0;
      }
      restart = stuck;
      z_old = z;
      p_old = p;
      p = pstar - (im.gamma * Tnew) * im.s;
      z = cz + im.gamma * p;
      theta_top += 0.5 * dt * (in.top_speed.at(t1 - dt) + om1);
      x_old = x_n;
      x_n = x;
      const StepState st{i + 1, t1, om1 + x, ca * x + a0 + domega, theta_top + bit_.dot(z),
                         fric != 0.0 ? Tnew - fric : Tnew, top_torque_.dot(z), om1, NAN, in.wob.at(t1)};
      obs(st);
    }
    return to_model(z, p);
  }

  /// Solve x + c T(om + x, ca x + a0) = w for the relative bit speed x; Tout receives T at x (the
  /// total torque, string friction sf sign(v) included).
  double solve_bit(double w, double c, double om, double ca, double a0, double wob, double eta, double cv,
                   double sf, double guess, double t, double& Tout) const {
    return solve_root(
        [&](double x, double& dF) {
          const TorqueEval e = total_torque(om + x, ca * x + a0, wob, eta, cv, sf);
          Tout = e.T;
          dF = 1.0 + c * (e.dT_dv + e.dT_da * ca);
          return x + c * e.T - w;
        },
        guess, std::max(1e-3, std::fabs(w - guess)), 1e-12 * (1.0 + std::fabs(om) + std::fabs(w)), t);
  }

  /// Root of an increasing scalar function F(x, dF) by Newton steps safeguarded by a bracket
  /// (march downhill until bracketed, then Newton while it halves the step, else bisection; a
  /// jump of a discontinuous law is found as the limit of the bracket). F is last evaluated at
  /// the returned root.
  template <class F>
  static double solve_root(F&& func, double x, double step, double tol, double t) {
    double lo = -HUGE_VAL, hi = HUGE_VAL, dF = 0.0, dx_old = HUGE_VAL;
    double f = func(x, dF);
    for (int it = 0; it < 300 && std::fabs(f) > tol; ++it) {
      (f < 0.0 ? lo : hi) = x;
      const bool bracketed = std::isfinite(lo) && std::isfinite(hi);
      if (bracketed && hi - lo <= tol) break;
      const bool newton = dF > 0.0 && std::isfinite(dF);
      double xn = newton ? x - f / dF : x;
      if (bracketed) {
        if (!newton || !(xn > lo && xn < hi) || std::fabs(xn - x) > 0.5 * dx_old) xn = 0.5 * (lo + hi);
      } else if (!newton || std::fabs(xn - x) <= tol) {
        xn = f > 0.0 ? x - step : x + step;
        step *= 2.0;
      }
      dx_old = std::fabs(xn - x);
      x = xn;
      f = func(x, dF);
      if (!std::isfinite(f)) diverged(t);
    }
    return x;
  }

  /// The exact modal scheme on one run: run_exact_lanes with one lane, the top drive `Drive` of
  /// drives/registry.hpp. An ideal drive's top speed is the command (the step's top acceleration its
  /// average over the step); a drive with inertia (the motor, a controlled drive) is stepped as in
  /// run_euler, by Drive::Run from the string's top torque at the step's start, explicit in it, and
  /// the modes then see the top's acceleration (Omega_i+1 - Omega_i) / dt over the step, the scheme's
  /// own assumption (exact_modal.hpp). The rig's jack (axial.hpp) is stepped the same way: its WOB at
  /// the step's end from the bit speed at its start, before the bit's equation is solved there.
  template <class Drive, class Observer>
  ModelState run_exact(const Inputs& in, Observer& obs, Eigen::VectorXd& z, Eigen::VectorXd& p,
                       const ModelState& s0) const {
    const Inputs* lane = &in;
    const double dt = opt_.dt;
    double theta_top = 0.0, om_prev = in.top_speed.at(0.0);
    const int m = static_cast<int>(w2_.size());
    constexpr bool stepped = Drive::has_inertia || Drive::has_controller;
    double om_state = std::isfinite(s0.top_speed) ? s0.top_speed : in.top_speed.at(0.0);  // a drive's speed
    const bool axial = in.axial.active();
    double wob_state = std::isfinite(s0.wob) ? s0.wob : in.wob.at(0.0), wob_next = wob_state;  // the jack's
    typename Drive::template Run<TopDrive> drive(in.top_drive, in.top_speed, dt, s0,
                                                 [&] { return top_torque_.dot(z); });
    auto top = [&](double t0, double t1, double& om0, double& om1, double& dom) {
      if constexpr (stepped) {
        om0 = drive.speed(t0, om_state);
        om1 = drive.next(t0, om0, top_torque_.dot(z));
        dom = (om1 - om0) / dt;
        om_state = om1;
      } else {
        om0 = in.top_speed.at(t0);
        om1 = in.top_speed.at(t1);
        dom = (om1 - om0) / dt;  // the top's acceleration averaged over the step
      }
    };
    auto wob_at = [&](double t1, double v0) {
      if (!axial) return in.wob.at(t1);
      wob_next = in.axial.step(wob_state, v0, in.wob.at(t1 - dt), dt);
      return wob_next;
    };
    if constexpr (stepped) om_prev = om_state;
    run_exact_lanes(
        &lane, 1, em_.k.data(), &em_.c, &em_.c0, z.data(), p.data(), stepped ? om_state : NAN,
        axial ? wob_state : NAN, top, wob_at,
        [&](const double* dom, const double* T0, double* zs, double* ps, double* w) {
          exact_modal_free(m, 1, em_.k.data(), bit_.data(), z.data(), p.data(), dom, T0, zs, ps, w);
        },
        [&](const double* zs, const double* ps, const double* T1, const double* dT0) {
          exact_modal_close(m, 1, em_.k.data(), zs, ps, T1, dT0, z.data(), p.data());
        },
        [&](std::size_t, long i, double t, double v, double a, double T, double om) {
          theta_top += 0.5 * opt_.dt * (om_prev + om);
          if (i == 0) theta_top = 0.0;
          om_prev = om;
          if (i > 0) wob_state = wob_next;
          const double wob = axial ? wob_state : in.wob.at(t);
          obs(static_cast<const StepState&>(
              StepState{i, t, v, a, theta_top + bit_.dot(z), T, top_torque_.dot(z), om, drive.torque(), wob}));
        },
        [](std::size_t, double t) { diverged(t); });
    ModelState out = to_model(z, p);
    if constexpr (stepped) out.top_speed = om_state;
    if (axial) out.wob = wob_state;
    drive.finish(out);
    return out;
  }

  /// Eqs. (3.3), (5.1), (5.3) at the end of an exact modal step (exact_modal.hpp): the relative bit
  /// speed x = v_i+1 - Omega_i+1, the total torque T_i+1 and its string-friction part, from the free
  /// relative speed w, the compliances c and c0 (v_i+1 = Omega_i+1 + w - c T_i+1, w holding -c0 T_i),
  /// the start torque T0, the top speeds at both ends of the step and the bit speed v0 at its start.
  /// The bit acceleration in the law is Eq. (A.1)'s (v_i+1 - v_i) / dt. Stick condition as in
  /// run_bdf2: a bit at rest stays at rest while the torque that holds it there over the step,
  /// held constant (T_i = T_i+1 = (w + c0 T0 + Omega_i+1) / (c + c0)), is within the static capacity
  /// (the law's static torque times 1 + eta, plus the string friction); `hold` is then true. A moving
  /// bit that would reverse (or land at rest) comes to rest when the capacity can hold the torque that
  /// stops it over the step, held constant as well (the same T_hold; or the friction opposes the
  /// motion), and `hold` is true too: the bit stops within the step and its friction jumps there from
  /// the sliding torque to the holding one, which a torque interpolated from the sliding T_i cannot
  /// follow (it needed an end torque beyond the capacity, of the wrong sign, where the string pulled
  /// the landing bit backwards, and broke the bit away backwards for a step: issue 33). As the
  /// modified Euler's stick_euler holds the torque over the landing step. `guess` starts the Newton
  /// iteration.
  void exact_bit(double w, double c, double c0, double T0, double om0, double om1, double v0, double wob,
                 double eta, double cv, double Tsf, double t1, double guess, double& x, double& T, double& fric,
                 bool& hold) const {
    const double dt = opt_.dt;
    const double Ts = (1.0 + eta) * law_.static_torque(wob), cap = Ts + Tsf;
    const bool at_rest = cap > 0.0 && std::fabs(v0) <= bit_rest_tolerance(om0);
    const double T_hold = (w + c0 * T0 + om1) / (c + c0);
    hold = at_rest && std::fabs(T_hold) <= cap;
    fric = 0.0;
    if (hold) {
      x = -om1;
      T = T_hold;
      if (Tsf > 0.0) fric = string_share(T_hold, Ts, Tsf);
      return;
    }
    x = exact_newton(w, c, om1, v0, wob, eta, cv, Tsf, guess, t1, T);
    const double v1 = om1 + x, sv = sign(v0);
    const bool lands = v0 * v1 <= 0.0 || std::fabs(v1) <= landing_tolerance(om1);
    const bool stuck = cap > 0.0 && !at_rest && lands && (std::fabs(T_hold) <= cap || sign(T_hold) == sv);
    if (Tsf > 0.0) fric = Tsf * sign(v1);
    if (stuck) {
      x = -om1;
      T = T_hold;
      hold = true;
      fric = Tsf > 0.0 ? string_share(T_hold, Ts, Tsf) : 0.0;
    }
  }

  /// The bit speed at a step's end below which a moving bit of exact_bit has come to rest: the
  /// solution of the bit's equation at the law's jump at v = 0 is known only to the solvers'
  /// tolerance, 1e-12 (1 + |Omega| + |w|), and one found at 1.05e-11 rad/s (Omega 9 rad/s) with the
  /// law's static torque, counted as moving, broke the bit away backwards on the next step (issue 33).
  static double landing_tolerance(double om) { return 1e-9 * (1.0 + std::fabs(om)); }

  /// x + c T(Omega_i+1 + x, (Omega_i+1 + x - v0) / dt) = w for x (exact_bit), T receiving the torque:
  /// Newton from `guess`, stopping on a step below the tolerance with the torque linearized to it
  /// (as run_euler's solve of Eq. A.1: one evaluation of the law fewer than solve_bit's test on the
  /// residual); solve_bit's safeguarded iteration from the last iterate where 8 Newton steps do not
  /// converge, the derivative is not positive, an iterate is at v = 0 or a step crosses it (the jump
  /// of the law).
  double exact_newton(double w, double c, double om1, double v0, double wob, double eta, double cv, double Tsf,
                      double guess, double t1, double& T) const {
    const double ca = 1.0 / opt_.dt, a0 = (om1 - v0) / opt_.dt;
    const double tol = 1e-12 * (1.0 + std::fabs(om1) + std::fabs(w));
    double x = guess;
    for (int it = 0; it < 8; ++it) {
      const TorqueEval e = total_torque(om1 + x, ca * x + a0, wob, eta, cv, Tsf);
      const double F = x + c * e.T - w, dT = e.dT_dv + e.dT_da * ca, dF = 1.0 + c * dT;
      if (!(dF > 0.0) || !std::isfinite(F) || !std::isfinite(dF)) break;
      const double xn = x - F / dF;
      if (om1 + x == 0.0 || sign(om1 + xn) != sign(om1 + x)) break;  // at rest the law is set-valued
      if (std::fabs(xn - x) <= tol) {
        T = e.T + dT * (xn - x);
        return xn;
      }
      x = xn;
    }
    return solve_bit(w, c, om1, ca, a0, wob, eta, cv, Tsf, x, t1, T);
  }

  /// The exact modal scheme (exact_modal.hpp) on N runs in lanes (the scalar path: N = 1; the
  /// batched path has its own vector kernel, ExactSteps of batched_kernel-inl.hpp): in[l] the lane's inputs, coef its coefficients
  /// [(j kinds + kind) N + l] and c[l] its compliance, z and p its modal state [modes][lanes] (the
  /// final state on return). emit(l, i, t, v, a, T_bit, Omega) is called at every step, i = 0 the
  /// initial state (its torque the law's at zero acceleration), after the step's state is in z, p.
  /// fail(l, t) is called when lane l's bit speed or torque is non-finite at t (it throws, or
  /// returns and the lane is dropped: its state set to zero, emit no longer called for it).
  /// free(dom, T0, zs, ps, w) and close(zs, ps, T1, dT0) are exact_modal_free and exact_modal_close on these
  /// lanes. One lane (N = 1, run_exact): top0 and wob0 its top speed and WOB at t = 0 (NaN: the
  /// inputs'), top(t0, t1, om0, om1, dom) its step's top speeds and top acceleration, wob_at(t1, v0)
  /// its WOB at the step's end from the bit speed v0 at its start.
  template <class Top, class Wob, class Free, class Close, class Emit, class Fail>
  void run_exact_lanes(const Inputs* const* in, std::size_t N, const double* coef, const double* c,
                       const double* c0, double* z, double* p, double top0, double wob0, Top&& top, Wob&& wob_at,
                       Free&& free, Close&& close, Emit&& emit, Fail&& fail) const {
    const double dt = opt_.dt;
    const long n = opt_.steps();
    const int m = static_cast<int>(w2_.size());
    const std::size_t mN = static_cast<std::size_t>(m) * N;
    std::vector<double> zs(mN), ps(mN), w(N), v(N), T0(N), T1(N), om0(N), om1(N), dom(N), x(N), T(N), fr(N);
    std::vector<double> x1(N), x2(N);  // the relative bit speeds of the last two steps (Newton's start)
    std::vector<double> dT0(N);        // T_i+1 - T_i where the torque is held over the step (exact_bit)
    std::vector<char> held(N, 0);      // whether it is
    std::vector<char> live(N, 1);
    auto drop = [&](std::size_t l, double t) {
      fail(l, t);
      live[l] = 0;
      for (int j = 0; j < m; ++j) z[j * N + l] = p[j * N + l] = 0.0;
      v[l] = T0[l] = 0.0;
    };
    exact_modal_dot(m, N, bit_.data(), p, v.data());
    for (std::size_t l = 0; l < N; ++l) {
      const Inputs& x0 = *in[l];
      om0[l] = std::isfinite(top0) ? top0 : x0.top_speed.at(0.0);
      v[l] = om0[l] + v[l];
      const double wob = std::isfinite(wob0) ? wob0 : x0.wob.at(0.0);
      const TorqueEval e = total_torque(v[l], 0.0, wob, x0.eta.at(0.0), x0.bit_viscous, x0.string_friction);
      T0[l] = e.T;
      if (!std::isfinite(v[l]) || !std::isfinite(e.T)) {
        drop(l, 0.0);
        continue;
      }
      emit(l, 0L, 0.0, v[l], 0.0, e.T - x0.string_friction * sign(v[l]), om0[l]);
      x1[l] = x2[l] = v[l] - om0[l];
    }
    for (long i = 0; i < n; ++i) {
      const double t0 = i * dt, t1 = (i + 1) * dt;
      for (std::size_t l = 0; l < N; ++l) top(t0, t1, om0[l], om1[l], dom[l]);
      free(dom.data(), T0.data(), zs.data(), ps.data(), w.data());
      for (std::size_t l = 0; l < N; ++l) {
        const Inputs& r = *in[l];
        T1[l] = dT0[l] = 0.0;
        held[l] = 0;
        if (!live[l]) continue;
        bool hold = false;
        try {
          // Newton starts from the line through the last two relative bit speeds, extrapolated
          exact_bit(w[l], c[l], c0[l], T0[l], om0[l], om1[l], v[l], wob_at(t1, v[l]), r.eta.at(t1), r.bit_viscous,
                    r.string_friction, t1, 2.0 * x1[l] - x2[l], x[l], T[l], fr[l], hold);
        } catch (const std::runtime_error&) {
          x[l] = NAN;
        }
        if (!std::isfinite(x[l]) || !std::isfinite(T[l])) continue;
        T1[l] = T[l];
        held[l] = hold;
        if (hold) dT0[l] = T[l] - T0[l];
      }
      close(zs.data(), ps.data(), T1.data(), dT0.data());
      for (std::size_t l = 0; l < N; ++l) {
        if (!live[l]) continue;
        if (!std::isfinite(x[l]) || !std::isfinite(T[l])) {
          drop(l, t1);
          continue;
        }
        const double v1 = om1[l] + x[l], a = (v1 - v[l]) / dt;
        // the step's mean torque (exact_modal.hpp): T_i+1 where it is held over the step
        const double Tm = held[l] ? T[l] : 0.5 * (T0[l] + T[l]);
        emit(l, i + 1, t1, v1, a, fr[l] != 0.0 ? Tm - fr[l] : Tm, om1[l]);
        x2[l] = x1[l];
        x1[l] = x[l];
        v[l] = v1;
        T0[l] = T[l];
      }
    }
  }

  [[noreturn]] static void diverged(double t) { throw std::runtime_error(divergence(t)); }

  BitRockLaw law_;
  SimOptions opt_;
  Eigen::MatrixXd V_, Vinv_, D_;
  Eigen::VectorXd w2_, d_, bit_, top_torque_, top_load_, init_vel_;
  double omega_max_ = 0.0;
  bool diag_damping_ = true;
  Implicit be_, bdf_;
  ExactModal em_;  ///< the exact modal scheme's step (exact_modal.hpp)
};

}  // namespace drill
