// Bindings: short-horizon predictions restarted from measured states (drillpy loop).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <exception>
#include <iterator>
#include <new>
#include <stdexcept>

#include "drill/horizons.hpp"
#include "drill/sensor.hpp"
#include "glue.hpp"

namespace py = pybind11;
using namespace drill;

namespace {

using drillpy_glue::Array;

std::vector<double> as_vector(const py::object& x, const std::string& field) {
  if (x.is_none()) return {};
  auto a = py::cast<Array>(x);
  require(a.ndim() == 1, field, a.ndim(), "must be a 1-D array");
  return std::vector<double>(a.data(), a.data() + a.size());
}

/// The Python exception object pybind11 would raise for a C++ exception (not raised).
py::object python_error(const std::exception_ptr& e) {
  const py::module_ builtins = py::module_::import("builtins");
  try {
    std::rethrow_exception(e);
  } catch (const py::error_already_set& x) {
    return x.value();
  } catch (const std::invalid_argument& x) {
    return builtins.attr("ValueError")(x.what());
  } catch (const std::domain_error& x) {
    return builtins.attr("ValueError")(x.what());
  } catch (const std::length_error& x) {
    return builtins.attr("ValueError")(x.what());
  } catch (const std::out_of_range& x) {
    return builtins.attr("IndexError")(x.what());
  } catch (const std::range_error& x) {
    return builtins.attr("ValueError")(x.what());
  } catch (const std::overflow_error& x) {
    return builtins.attr("OverflowError")(x.what());
  } catch (const std::bad_alloc&) {
    return builtins.attr("MemoryError")();
  } catch (const std::exception& x) {
    return builtins.attr("RuntimeError")(x.what());
  } catch (...) {
    return builtins.attr("RuntimeError")("unknown C++ exception");
  }
}

/// Field name, member and docstring of the double fields of HorizonStart, in declaration order.
struct StartField {
  const char* name;
  double HorizonStart::*member;
  const char* doc;
};
const StartField start_fields[] = {
    {"bit_speed", &HorizonStart::bit_speed, "Bit speed of the model state [rad/s] (sensor effects removed)."},
    {"bit_accel", &HorizonStart::bit_accel, "Bit acceleration of the model state [rad/s^2]."},
    {"torque", &HorizonStart::torque, "Torque on bit of the model state [N m]."},
    {"top_speed", &HorizonStart::top_speed, "Top speed of the model state [rad/s]."},
    {"top_accel", &HorizonStart::top_accel, "Top acceleration of the model state [rad/s^2]."},
    {"y_bit_speed", &HorizonStart::y_bit_speed, "Recorded (filtered) bit speed [rad/s]: sensor filter state."},
    {"dy_bit_speed", &HorizonStart::dy_bit_speed, "Rate of the recorded bit speed [rad/s^2]."},
    {"y_torque", &HorizonStart::y_torque, "Recorded (filtered) torque on bit [N m]: sensor filter state."},
    {"dy_torque", &HorizonStart::dy_torque, "Rate of the recorded torque [N m/s]."},
    {"y_top_speed", &HorizonStart::y_top_speed, "Recorded (filtered) top speed [rad/s]: sensor filter state."},
    {"dy_top_speed", &HorizonStart::dy_top_speed, "Rate of the recorded top speed [rad/s^2]."},
};

void bind_horizons(py::module_& m) {
  py::class_<HorizonStart> hs(m, "HorizonStart",
                              "Where one prediction horizon starts (drill/horizons.hpp): the model's state read off "
                              "the record and the recorded channels that start the sensor filters.");
  hs.def(py::init([](long index, double v, double a, double T, double om, double dom, double yv, double dyv,
                     double yT, double dyT, double ytop, double dytop, double wob, double dywob) {
           return HorizonStart{index, v, a, T, om, dom, yv, dyv, yT, dyT, ytop, dytop, wob, dywob};
         }),
         py::kw_only(), py::arg("index"), py::arg("bit_speed"), py::arg("bit_accel"), py::arg("torque"),
         py::arg("top_speed"), py::arg("top_accel"), py::arg("y_bit_speed"), py::arg("dy_bit_speed"),
         py::arg("y_torque"), py::arg("dy_torque"), py::arg("y_top_speed"), py::arg("dy_top_speed"),
         py::arg("wob") = NAN, py::arg("dy_wob") = 0.0);
  hs.def_readonly("index", &HorizonStart::index, "Sample of the input grid at which the horizon starts.");
  hs.def_readonly("wob", &HorizonStart::wob,
                  "WOB state of an axial jack at the restart [N] (drill/axial.hpp; NaN: the set force).");
  hs.def_readonly("dy_wob", &HorizonStart::dy_wob,
                  "Rate of the recorded WOB at the restart [N/s]: with wob, the WOB sensor filter's state.");
  for (const StartField& f : start_fields) hs.def_readonly(f.name, f.member, f.doc);
  hs.def_static(
      "from_arrays",
      [](const std::vector<long>& index, const Eigen::VectorXd& v, const Eigen::VectorXd& a, const Eigen::VectorXd& T,
         const Eigen::VectorXd& om, const Eigen::VectorXd& dom, const Eigen::VectorXd& yv, const Eigen::VectorXd& dyv,
         const Eigen::VectorXd& yT, const Eigen::VectorXd& dyT, const Eigen::VectorXd& ytop,
         const Eigen::VectorXd& dytop, py::object wob, py::object dy_wob) {
        const Eigen::Index n = static_cast<Eigen::Index>(index.size());
        const Eigen::VectorXd* cols[] = {&v, &a, &T, &om, &dom, &yv, &dyv, &yT, &dyT, &ytop, &dytop};
        for (std::size_t k = 0; k < std::size(cols); ++k)
          require(cols[k]->size() == n, start_fields[k].name, cols[k]->size(),
                  "must have one entry per horizon (" + show(n) + ")");
        const std::vector<double> w = as_vector(wob, "wob");
        require(w.empty() || static_cast<Eigen::Index>(w.size()) == n, "wob", w.size(),
                "must have one entry per horizon (" + show(n) + ")");
        const std::vector<double> dw = as_vector(dy_wob, "dy_wob");
        require(dw.empty() || dw.size() == w.size(), "dy_wob", dw.size(),
                "must have one entry per entry of wob (" + show(w.size()) + ")");
        std::vector<HorizonStart> starts(index.size());
        for (Eigen::Index h = 0; h < n; ++h) {
          HorizonStart& s = starts[static_cast<std::size_t>(h)];
          s.index = index[static_cast<std::size_t>(h)];
          for (std::size_t k = 0; k < std::size(cols); ++k) s.*(start_fields[k].member) = (*cols[k])(h);
          if (!w.empty()) s.wob = w[static_cast<std::size_t>(h)];
          if (!dw.empty()) s.dy_wob = dw[static_cast<std::size_t>(h)];
        }
        return starts;
      },
      py::kw_only(), py::arg("index"), py::arg("bit_speed"), py::arg("bit_accel"), py::arg("torque"),
      py::arg("top_speed"), py::arg("top_accel"), py::arg("y_bit_speed"), py::arg("dy_bit_speed"),
      py::arg("y_torque"), py::arg("dy_torque"), py::arg("y_top_speed"), py::arg("dy_top_speed"),
      py::arg("wob") = py::none(), py::arg("dy_wob") = py::none(),
      "One HorizonStart per horizon from arrays with one entry per horizon (units of the fields; wob: the "
      "axial jack's WOB state [N], None: the set force; dy_wob: the recorded WOB's rate [N/s], None: 0).");
  hs.def("__repr__", [](const HorizonStart& s) {
    return "<drillpy._core.HorizonStart index=" + std::to_string(s.index) + ">";
  });

  py::class_<HorizonResult>(m, "HorizonResult",
                            "Predictions after the configured sensors (predict_horizons): row h, column j is the "
                            "value (j + 1) dt after the start of horizon h.")
      .def_readonly("bit_speed", &HorizonResult::bit_speed, "Bit speed [rad/s], horizons x samples.")
      .def_readonly("torque", &HorizonResult::torque, "Contact torque on bit [N m], horizons x samples.")
      .def_readonly("top_speed", &HorizonResult::top_speed, "Top speed [rad/s], horizons x samples.")
      .def_readonly("wob", &HorizonResult::wob,
                    "WOB the law saw [N] (the axial jack's state, or the input), horizons x samples.")
      .def(
          "to_dict",
          [](const HorizonResult& r) {
            return py::dict(py::arg("bit_speed") = r.bit_speed, py::arg("torque") = r.torque,
                            py::arg("top_speed") = r.top_speed, py::arg("wob") = r.wob);
          },
          "Every field in a dict keyed by the field names.");
}

}  // namespace

void init_horizons(py::module_& m) {
  bind_horizons(m);
  m.def(
      "lowpass2",
      [](const Eigen::VectorXd& x, double cutoff_hz, double dt) {
        LowPass2 f(cutoff_hz, dt);
        Eigen::VectorXd y(x.size());
        if (x.size() == 0) return y;
        require(x.allFinite(), "lowpass2 input", "non-finite values", "must be finite (clean the signal first)");
        f.reset(x(0), 0.0, x(0));
        y(0) = x(0);
        for (Eigen::Index k = 1; k < x.size(); ++k) y(k) = f.step(x(k));
        return y;
      },
      py::arg("x"), py::arg("cutoff_hz"), py::arg("dt"),
      "The measurement chain of drill/sensor.hpp (second-order Butterworth, trapezoidal rule) over a series "
      "sampled every dt [s], started at rest on its first value.");
  m.def(
      "predict_horizons",
      [](const Simulation& sim, const std::vector<HorizonStart>& starts, double dt, int samples, py::object top_speed,
         py::object wob, py::object eta, py::object progress, int threads, bool batched) {
        HorizonInputs hin;
        hin.dt = dt;
        hin.samples = samples;
        hin.top_speed = as_vector(top_speed, "top_speed");
        hin.wob = as_vector(wob, "wob");
        if (!eta.is_none()) hin.eta = py::cast<Eigen::MatrixXd>(eta);
        HorizonResult r;
        {
          py::gil_scoped_release nogil;
          r = predict_horizons(sim, starts, hin, drillpy_glue::progress_callback(progress), threads, batched);
        }
        return r;
      },
      py::arg("simulation"), py::arg("starts"), py::arg("dt"), py::arg("samples"), py::arg("top_speed") = py::none(),
      py::arg("wob") = py::none(), py::arg("eta") = py::none(), py::arg("progress") = py::none(),
      py::arg("threads") = 0, py::arg("batched") = true,
      "Short-horizon predictions restarted from measured states (drill/horizons.hpp), one per HorizonStart, "
      "samples dt [s] apart; top_speed [rad/s] and wob [N] are input series on the record's grid (default: the "
      "operating point), eta horizons x (samples + 1) the bit-rock fluctuation of Eq. (4.1); batched: horizons in "
      "SIMD lockstep with an ideal top drive (False: the scalar reference integrator).");
  m.def(
      "predict_horizons_many",
      [](const py::sequence& simulations, const std::vector<std::vector<HorizonStart>>& starts, double dt,
         const std::vector<int>& samples, const py::object& top_speed, const py::object& wob, const py::object& eta,
         int threads, bool batched) {
        const std::size_t n = static_cast<std::size_t>(py::len(simulations));
        require(starts.size() == n && samples.size() == n, "predict_horizons_many", show(starts.size()) + " starts, " +
                show(samples.size()) + " samples", "must have one entry per simulation (" + show(n) + ")");
        // per job: None, or a sequence with one entry (None or an array) per simulation
        auto per_job = [&](const py::object& x, const char* field) {
          std::vector<py::object> out(n, py::none());
          if (x.is_none()) return out;
          auto seq = py::cast<py::sequence>(x);
          require(static_cast<std::size_t>(py::len(seq)) == n, field, py::len(seq),
                  "must have one entry per simulation (" + show(n) + ")");
          for (std::size_t i = 0; i < n; ++i) out[i] = seq[i];
          return out;
        };
        const auto tops = per_job(top_speed, "top_speed"), wobs = per_job(wob, "wob"), etas = per_job(eta, "eta");
        std::vector<HorizonJob> jobs(n);
        for (std::size_t i = 0; i < n; ++i) {
          jobs[i].sim = &py::cast<const Simulation&>(simulations[i]);
          jobs[i].starts = starts[i];
          jobs[i].inputs.dt = dt;
          jobs[i].inputs.samples = samples[i];
          jobs[i].inputs.top_speed = as_vector(tops[i], "top_speed");
          jobs[i].inputs.wob = as_vector(wobs[i], "wob");
          if (!etas[i].is_none()) jobs[i].inputs.eta = py::cast<Eigen::MatrixXd>(etas[i]);
        }
        std::vector<std::exception_ptr> errors;
        std::vector<HorizonResult> r;
        {
          py::gil_scoped_release nogil;
          r = predict_horizons_many(jobs, errors, threads, batched);
        }
        py::list out;
        for (std::size_t i = 0; i < n; ++i)
          out.append(errors[i] ? python_error(errors[i]) : py::cast(std::move(r[i])));
        return out;
      },
      py::arg("simulations"), py::arg("starts"), py::arg("dt"), py::arg("samples"), py::arg("top_speed") = py::none(),
      py::arg("wob") = py::none(), py::arg("eta") = py::none(), py::arg("threads") = 0, py::arg("batched") = true,
      "predict_horizons for several simulations in one parallel region (the loop's Jacobian: one simulation per "
      "perturbed model): entry i of starts, samples and of the optional top_speed, wob, eta lists (None or an "
      "array per simulation) are call i's arguments. Returns one entry per simulation: the HorizonResult "
      "predict_horizons gives, bit for bit, or the exception it raises (ValueError, RuntimeError, ...) as an "
      "object, not raised: one model's failure leaves the others' predictions.");
  m.def(
      "top_torque_from_bit",
      [](const Simulation& sim, const Eigen::VectorXd& v, const Eigen::VectorXd& a, const Eigen::VectorXd& T,
         const Eigen::VectorXd& omega, const Eigen::VectorXd& domega) {
        const Eigen::Index n = v.size();
        for (const Eigen::VectorXd* x : {&a, &T, &omega, &domega})
          require(x->size() == n, "top_torque_from_bit arrays", x->size(), "must all have " + show(n) + " entries");
        Eigen::VectorXd out(n);
        const Integrator& integ = sim.integrator();
        for (Eigen::Index i = 0; i < n; ++i)
          out(i) = integ.top_torque(integ.state_from_bit(v(i), a(i), T(i), omega(i), domega(i)));
        return out;
      },
      py::arg("simulation"), py::arg("bit_speed"), py::arg("bit_accel"), py::arg("torque"), py::arg("top_speed"),
      py::arg("top_accel"),
      "Elastic torque at the top [N m] of the states reproducing measured bit states (one per sample).");
  m.def(
      "state_from_bit",
      [](const Simulation& sim, double v, double a, double T, double omega, double domega) {
        const ModelState s = sim.integrator().state_from_bit(v, a, T, omega, domega);
        return py::make_tuple(s.q, s.qdot);
      },
      py::arg("simulation"), py::arg("bit_speed"), py::arg("bit_accel"), py::arg("torque"), py::arg("top_speed"),
      py::arg("top_accel"), "Reduced state (q, q') reproducing a measured bit state (Eq. 2.9).");
}
