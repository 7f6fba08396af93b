// Bindings: configured simulations, single runs and parallel SS sweeps (GIL released, Ctrl-C aware).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "drill/config.hpp"
#include "drill/metrics.hpp"
#include "drill/run_many.hpp"
#include "drill/run_summary.hpp"
#include "drill/simulation.hpp"
#include "glue.hpp"

namespace py = pybind11;
using namespace drill;

namespace {

using drillpy_glue::Array;
using drillpy_glue::as_array;

Signal to_signal(const py::object& series, double dt, double t0, double constant, const std::string& field) {
  if (series.is_none()) return Signal::constant(constant);
  auto a = py::cast<Array>(series);
  require(a.ndim() == 1, field, a.ndim(), "must be a 1-D array");
  require(a.size() >= 1, field, a.size(), "must not be empty");
  Signal s = Signal::sampled(std::vector<double>(a.data(), a.data() + a.size()), t0, dt);
  s.validate(field);
  return s;
}

/// A read-only 1-D float64 property of RunReport.
template <class Get>
void vector_field(py::class_<RunReport>& c, const char* name, Get get, const char* doc) {
  c.def_property_readonly(name, [get](const RunReport& r) { return as_array(get(r)); }, doc);
}

py::dict report_to_dict(const RunReport& r) {
  py::dict d;
  d["t"] = as_array(r.series.t);
  d["bit_speed"] = as_array(r.series.bit_speed);
  d["bit_accel"] = as_array(r.series.bit_accel);
  d["bit_angle"] = as_array(r.series.bit_angle);
  d["torque_on_bit"] = as_array(r.series.torque_on_bit);
  d["top_torque"] = as_array(r.series.top_torque);
  d["top_speed"] = as_array(r.series.top_speed);
  d["wob"] = as_array(r.series.wob);
  d["severity"] = r.severity;
  d["mean_top_speed"] = r.mean_top_speed;
  d["stick_fraction"] = r.stick_fraction;
  d["stick_durations"] = as_array(r.stick);
  d["slip_durations"] = as_array(r.slip);
  d["slip_first"] = r.slip_first;
  d["period_cycles"] = r.periodic.period_cycles;
  d["period_stick"] = as_array(r.periodic.stick);
  d["period_slip"] = as_array(r.periodic.slip);
  d["period_mismatch"] = r.periodic.mismatch;
  d["final_q"] = r.final_state.q;
  d["final_qdot"] = r.final_state.qdot;
  return d;
}

/// The axial channels of an axial-torsional run (drill/simulation.hpp AxialReport).
void bind_axial_report(py::module_& m) {
  py::class_<AxialReport> c(m, "AxialReport",
                            "Axial channels and metrics of a run of the axial-torsional model (axial.type = rgd, "
                            "drill/axial_torsional.hpp): series every simulation.output_stride steps, metrics over "
                            "t >= transient. Empty (present False) for other models.");
  auto vec = [&](const char* name, std::vector<double> AxialReport::*f, const char* doc) {
    c.def_property_readonly(name, [f](const AxialReport& r) { return as_array(r.*f); }, doc);
  };
  vec("t", &AxialReport::t, "Sample times [s].");
  vec("wob", &AxialReport::wob, "Weight on bit W = W_c + W_f of the RGD law [N] (0 off the rock).");
  vec("rop", &AxialReport::rop, "The bit's axial speed V [m/s] (positive into the rock).");
  vec("position", &AxialReport::position, "The bit's axial position U [m] (down positive).");
  vec("depth_of_cut", &AxialReport::depth_of_cut,
      "Depth of cut per revolution d = N [U(t) - U(t - t_N)] [m] (negative: the bit above the rock).");
  vec("delay", &AxialReport::delay, "The delay t_N of Phi(t) - Phi(t - t_N) = 2 pi / N [s].");
  c.def_readonly("mean_wob", &AxialReport::mean_wob, "Mean WOB after the transient [N].");
  c.def_readonly("wob_std", &AxialReport::wob_std, "Standard deviation of the WOB after the transient [N].");
  c.def_readonly("mean_rop", &AxialReport::mean_rop, "Mean rate of penetration after the transient [m/s].");
  c.def_readonly("rop_std", &AxialReport::rop_std, "Standard deviation of the bit's axial speed [m/s].");
  c.def_readonly("bounce_fraction", &AxialReport::bounce_fraction,
                 "Fraction of the time after the transient with the bit off the rock (W = 0), dimensionless.");
  c.def_readonly("mean_depth_of_cut", &AxialReport::mean_depth_of_cut, "Mean depth of cut per revolution [m].");
  c.def_readonly("steady_wob", &AxialReport::steady_wob, "WOB of RGD's steady drilling at the operating point [N].");
  c.def_readonly("steady_rop", &AxialReport::steady_rop, "Rate of penetration of steady drilling [m/s].");
  c.def_readonly("steady_depth", &AxialReport::steady_depth, "Depth of cut per revolution of steady drilling [m].");
  c.def_readonly("steady_torque", &AxialReport::steady_torque, "Torque on bit of steady drilling [N m].");
  c.def_readonly("mse", &AxialReport::mse,
                 "Mechanical specific energy after the transient: the bit's work on the rock per volume removed "
                 "(torque x bit speed + WOB x axial speed, over pi a^2 x advance) [Pa]; NaN without advance.");
  c.def_readonly("steady_mse", &AxialReport::steady_mse,
                 "MSE of steady drilling, W / A + T Omega / (A V) (Teale 1965) [Pa].");
  c.def_readonly("steady_speed", &AxialReport::steady_speed,
                 "Speed of steady drilling under the top drive [rad/s]: the command, or a drooping drive's (the "
                 "motor's); NaN where the drive cannot carry steady drilling (it stalls; the run starts from the "
                 "command's steady drilling).");
  c.def_property_readonly("present", &AxialReport::present, "True for a run of the axial-torsional model.");
}

void bind_run_report(py::module_& m) {
  py::class_<RunReport> c(m, "RunReport",
                          "Time series (SI, absolute frame) and metrics of one run (Simulation.run). The series are "
                          "sampled every simulation.output_stride steps and are empty with record=False.");
  vector_field(c, "t", [](const RunReport& r) -> const auto& { return r.series.t; }, "Sample times [s].");
  vector_field(c, "bit_speed", [](const RunReport& r) -> const auto& { return r.series.bit_speed; },
               "Bit speed [rad/s].");
  vector_field(c, "bit_accel", [](const RunReport& r) -> const auto& { return r.series.bit_accel; },
               "Bit acceleration [rad/s^2].");
  vector_field(c, "bit_angle", [](const RunReport& r) -> const auto& { return r.series.bit_angle; },
               "Bit angle [rad].");
  vector_field(c, "torque_on_bit", [](const RunReport& r) -> const auto& { return r.series.torque_on_bit; },
               "Torque on bit of the bit-rock law [N m] (Eqs. 3.1-3.3; string friction left out).");
  vector_field(c, "top_torque", [](const RunReport& r) -> const auto& { return r.series.top_torque; },
               "Elastic torque at the top of the string [N m].");
  vector_field(c, "top_speed", [](const RunReport& r) -> const auto& { return r.series.top_speed; },
               "Top speed [rad/s] (the motor's with a motor top drive).");
  vector_field(c, "wob", [](const RunReport& r) -> const auto& { return r.series.wob; },
               "Weight on bit the law saw [N]: the input, or the axial jack's state (axial.hpp).");
  c.def_readonly("severity", &RunReport::severity,
                 "Stick-slip severity SS over t >= transient, Eq. (3.4), dimensionless (NaN when undefined).");
  c.def_readonly("mean_top_speed", &RunReport::mean_top_speed, "Mean top speed over t >= transient [rad/s].");
  c.def_readonly("stick_fraction", &RunReport::stick_fraction,
                 "Fraction of t >= transient spent in stick, dimensionless (NaN when undefined).");
  vector_field(c, "stick_durations", [](const RunReport& r) -> const auto& { return r.stick; },
               "Durations of the complete stick phases after the transient [s].");
  vector_field(c, "slip_durations", [](const RunReport& r) -> const auto& { return r.slip; },
               "Durations of the complete slip phases after the transient [s].");
  c.def_readonly("slip_first", &RunReport::slip_first,
                 "True when the first complete phase after the transient is a slip phase.");
  c.def_property_readonly("period_cycles", [](const RunReport& r) { return r.periodic.period_cycles; },
                          "Stick-slip cycles after which the phase durations repeat (0: no periodic regime).");
  vector_field(c, "period_stick", [](const RunReport& r) -> const auto& { return r.periodic.stick; },
               "Stick durations of the last period [s].");
  vector_field(c, "period_slip", [](const RunReport& r) -> const auto& { return r.periodic.slip; },
               "Slip durations of the last period [s].");
  c.def_property_readonly("period_mismatch", [](const RunReport& r) { return r.periodic.mismatch; },
                          "Largest difference between durations one period apart [s].");
  c.def_property_readonly("final_q", [](const RunReport& r) { return r.final_state.q; },
                          "Reduced coordinates q at the end of the run (Eq. 2.8; modal amplitudes of the rotation "
                          "relative to the top [rad]).");
  c.def_property_readonly("final_qdot", [](const RunReport& r) { return r.final_state.qdot; },
                          "Their time derivative q' at the end of the run [1/s].");
  c.def("to_dict", &report_to_dict,
        "Every field in a dict keyed by the field names (t, bit_speed, ..., final_q, final_qdot).");
  c.def_property_readonly(
      "axial", [](const RunReport& r) -> const AxialReport& { return r.axial; }, py::return_value_policy::reference_internal,
      "Axial channels and metrics (AxialReport) of an axial-torsional run; present is False otherwise.");
  c.def(
      "summary", [](const RunReport& r) { return drillpy_glue::to_python_dict(run_summary(r)); },
      "The run's summary (drill/run_summary.hpp, the summary.json of drillsim and drillpy simulate "
      "without config and job): severity, mean_top_speed_rad_s, stick_fraction, stick_durations_s, "
      "slip_durations_s, period_cycles, period_stick_s, period_slip_s; undefined values are None.");
}

}  // namespace

void init_simulation(py::module_& m) {
  bind_axial_report(m);
  bind_run_report(m);
  py::class_<Simulation>(m, "Simulation", "A configured reduced-order simulation (appendix B).")
      .def(py::init<const Config&>(), py::arg("config"))
      .def_property_readonly("config", [](const Simulation& s) { return s.config(); }, "The configuration (a copy).")
      .def_property_readonly("frequencies_hz", [](const Simulation& s) { return Eigen::VectorXd(s.rom().omega / (2 * M_PI)); },
                             "Natural frequencies of the retained modes [Hz].")
      .def_property_readonly(
          "drive_gains",
          [](const Simulation& s) -> py::object {
            const TopDrive& td = s.config().top_drive;
            if (!td.has_controller()) return py::none();
            const Controller& c = td.controller;
            return py::dict(py::arg("type") = Controller::kind_name(c.kind), py::arg("kp_nms_rad") = c.kp,
                            py::arg("ki_nm_rad") = c.ki, py::arg("impedance_nms_rad") = c.impedance,
                            py::arg("torque_filter_s") = c.torque_filter, py::arg("inertia_kg_m2") = td.inertia,
                            py::arg("torque_limit_nm") = c.torque_limit,
                            py::arg("top_impedance_nms_rad") = s.top_impedance(),
                            py::arg("omega1_rad_s") = s.rom().omega(0));
          },
          "The resolved gains of a controlled top drive (kp, ki, Z, tau, J, L; the top section's impedance and "
          "the first natural frequency they were tuned from), None for another drive.")
      .def_property_readonly("stability_bound", [](const Simulation& s) { return s.integrator().stability_bound(); },
                             "Modified-Euler bound pi / (5 omega_max) [s] (Eq. A.7).")
      .def(
          "motor_stability_bound",
          [](const Simulation& s, double inertia) {
            require_positive(inertia, "top_drive.inertia_kg_m2");
            TopDrive td;
            td.kind = TopDrive::Kind::motor;
            td.inertia = inertia;
            return s.integrator().stability_bound(td);
          },
          py::arg("inertia_kg_m2"),
          "Modified-Euler bound [s] (Eq. A.7) with a motor top drive of this inertia coupled to the string.")
      .def(
          "reduced_matrices",
          [](const Simulation& s) {
            const ReducedModel& r = s.rom().model;
            return py::dict(py::arg("M") = r.M, py::arg("D") = r.D, py::arg("K") = r.K, py::arg("basis") = r.basis,
                            py::arg("bit") = Eigen::VectorXd(r.bit.transpose()),
                            py::arg("top_torque") = Eigen::VectorXd(r.top_torque.transpose()),
                            py::arg("top_load") = r.top_load, py::arg("init_velocity") = r.init_velocity);
          },
          "Generalized matrices and couplings of the reduced model (Eqs. 2.8-2.10).")
      .def(
          "run",
          [](const Simulation& s, py::object top_speed, py::object wob, py::object top_speed_series,
             py::object wob_series, py::object eta_series, double series_dt, double series_t0,
             py::object bit_viscous, py::object string_friction, bool record, py::object q0, py::object qdot0,
             py::object top_speed0) {
            Inputs in = s.inputs();
            const double om = top_speed.is_none() ? s.config().top_speed : py::cast<double>(top_speed);
            const double w = wob.is_none() ? s.config().wob : py::cast<double>(wob);
            in.top_speed = to_signal(top_speed_series, series_dt, series_t0, om, "top_speed_series");
            in.wob = to_signal(wob_series, series_dt, series_t0, w, "wob_series");
            in.eta = to_signal(eta_series, series_dt, series_t0, 0.0, "eta_series");
            if (!bit_viscous.is_none()) in.bit_viscous = py::cast<double>(bit_viscous);
            if (!string_friction.is_none()) in.string_friction = py::cast<double>(string_friction);
            in.axial.feed_speed = NAN;  // the jack's feed follows these inputs (Simulation::axial_feed)
            ModelState start;
            const bool has_start = !q0.is_none();
            if (has_start) {
              start.q = py::cast<Eigen::VectorXd>(q0);
              start.qdot = qdot0.is_none() ? Eigen::VectorXd::Zero(start.q.size()) : py::cast<Eigen::VectorXd>(qdot0);
              if (!top_speed0.is_none()) start.top_speed = py::cast<double>(top_speed0);
            }
            RunReport r;
            {
              py::gil_scoped_release nogil;
              r = s.run(in, record, has_start ? &start : nullptr);
            }
            return r;
          },
          py::arg("top_speed") = py::none(), py::arg("wob") = py::none(), py::arg("top_speed_series") = py::none(),
          py::arg("wob_series") = py::none(), py::arg("eta_series") = py::none(), py::arg("series_dt") = 1e-3,
          py::arg("series_t0") = 0.0, py::arg("bit_viscous") = py::none(), py::arg("string_friction") = py::none(),
          py::arg("record") = true,
          py::arg("q0") = py::none(), py::arg("qdot0") = py::none(), py::arg("top_speed0") = py::none(),
          "Run one simulation; series inputs are sampled every series_dt from series_t0; top_speed0 is the "
          "initial motor speed of a motor top drive (default: its command).")
      .def(
          "sweep",
          [](const Simulation& s, const std::vector<double>& speeds, const std::vector<double>& wobs,
             py::object progress, int threads, std::optional<std::string> start, bool batched) {
            std::optional<StartMode> mode;
            if (start) mode = parse_start(*start);
            std::vector<double> out;
            {
              py::gil_scoped_release nogil;
              out = s.sweep_severity(speeds, wobs, drillpy_glue::progress_callback(progress), threads, mode, batched);
            }
            const std::size_t nw = wobs.empty() ? 1 : wobs.size();
            py::array_t<double> a({nw, speeds.size()});
            std::copy(out.begin(), out.end(), a.mutable_data());
            return a;
          },
          py::arg("speeds"), py::arg("wobs") = std::vector<double>{}, py::arg("progress") = py::none(),
          py::arg("threads") = 0, py::arg("start") = py::none(), py::arg("batched") = true,
          "SS (Eq. 3.4) on a WOB x top-speed grid, in parallel; start: rest (Eq. 2.10), rigid (Eq. 2.3) or steady "
          "(default: the configuration's simulation.start); batched: runs in SIMD lockstep where the batched "
          "integrator supports them (False: one by one through the scalar reference integrator).")
      .def_static("batch_width", &BatchedIntegrator::width,
                  "Runs per SIMD batch of the batched integrator on this host (the lanes of a double vector).")
      .def(
          "steady_state",
          [](const Simulation& s, double top_speed, double wob, bool with_top_speed) -> py::tuple {
            const ModelState m = s.steady_state(top_speed, wob);
            if (with_top_speed) return py::make_tuple(m.q, m.qdot, std::isfinite(m.top_speed) ? m.top_speed : top_speed);
            return py::make_tuple(m.q, m.qdot);
          },
          py::arg("top_speed"), py::arg("wob"), py::arg("with_top_speed") = false,
          "Reduced state (q, q') of steady drilling at a top speed (and the top's speed, which a motor top "
          "drive lowers below its command, with with_top_speed).");
  m.def(
      "run_many",
      [](const std::vector<const Simulation*>& sims, py::object top_speed_series, double series_dt, double series_t0,
         bool record, int threads, bool batched) {
        std::vector<Inputs> in;
        for (const Simulation* s : sims) {
          require(s != nullptr, "run_many simulations", "None", "must all be Simulation objects");
          Inputs x = s->inputs();
          if (!top_speed_series.is_none())
            x.top_speed = to_signal(top_speed_series, series_dt, series_t0, x.top_speed.value, "top_speed_series");
          x.axial.feed_speed = NAN;  // the jack's feed follows these inputs (Simulation::axial_feed)
          in.push_back(x);
        }
        ManyRuns r;
        {
          py::gil_scoped_release nogil;
          r = run_many(sims, in, record, threads, batched);
        }
        py::list reports;
        for (std::size_t k = 0; k < r.reports.size(); ++k)
          reports.append(r.errors[k].empty() ? py::cast(std::move(r.reports[k])) : py::none());
        return py::make_tuple(reports, r.errors);
      },
      py::arg("simulations"), py::arg("top_speed_series") = py::none(), py::arg("series_dt") = 1e-3,
      py::arg("series_t0") = 0.0, py::arg("record") = true, py::arg("threads") = 0, py::arg("batched") = true,
      "Independent runs of several simulations at their configured operation points (drill/run_many.hpp), in "
      "parallel and, where the models differ at most in their modal damping and the batched integrator supports "
      "them, in SIMD lockstep (their series then lack bit_angle and top_torque); top_speed_series, sampled every "
      "series_dt from series_t0, drives every run. Returns (reports, errors): a run that failed has report None "
      "and its error message, the others an empty message.");
  m.def("severity_threshold", &severity_threshold, py::arg("speeds"), py::arg("severities"), py::arg("level") = 0.5,
        "Top speed below which SS > level (NaN if the curve does not cross the level).");
}
