// Bindings: configuration, presets, FE/ROM quantities and the bit-rock laws.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>

#include "drill/config.hpp"
#include "drill/exact.hpp"
#include "drill/modal.hpp"
#include "drill/parallel.hpp"
#include "drill/presets.hpp"
#include "glue.hpp"

namespace py = pybind11;
using namespace drill;
using drillpy_glue::Array;

namespace {

/// JSON carries no NaN or inf (drillpy.model.config.to_json_text refuses them too).
double finite(double v) {
  require(std::isfinite(v), "config", v, "has a non-finite number (JSON cannot carry it)");
  return v;
}

/// A Python value as JSON, as json.dumps then the engine's parser would read it (dict, list or
/// tuple, str, bool, int, float and their numpy scalars, None); nesting deeper than
/// max_json_depth and other types are refused with ValueError.
json from_python(const py::handle& x, int depth) {
  require(depth <= max_json_depth, "config", depth, "is nested too deep (at most " + show(max_json_depth) + " levels)");
  if (x.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(x)) return x.cast<bool>();
  if (py::isinstance<py::str>(x)) return x.cast<std::string>();
  if (py::isinstance<py::float_>(x)) return finite(x.cast<double>());
  if (py::isinstance<py::int_>(x)) return x.cast<long long>();
  if (py::isinstance<py::dict>(x)) {
    json o = json::object();
    for (auto kv : py::reinterpret_borrow<py::dict>(x)) {
      require(py::isinstance<py::str>(kv.first), "config key", py::str(kv.first).cast<std::string>(), "must be a string");
      o[kv.first.cast<std::string>()] = from_python(kv.second, depth + 1);
    }
    return o;
  }
  if (py::isinstance<py::list>(x) || py::isinstance<py::tuple>(x)) {
    json a = json::array();
    for (auto v : py::reinterpret_borrow<py::sequence>(x)) a.push_back(from_python(v, depth + 1));
    return a;
  }
  if (py::hasattr(x, "dtype") && py::hasattr(x, "item")) {  // a numpy scalar: its Python value
    const py::object v = x.attr("item")();
    if (!py::hasattr(v, "dtype")) return from_python(v, depth);
  }
  require(false, "config value", py::str(py::type::of(x)).cast<std::string>(), "is not a JSON type");
  return nullptr;
}

}  // namespace

void init_model(py::module_& m) {
  py::class_<Config>(m, "Config",
                     "A validated engine configuration (the JSON schema drillsim reads), parsed once. Pass it to "
                     "Simulation, StochasticModel, MonteCarlo and the model functions (built from a dict by "
                     "drillpy.model.config.engine_config).")
      .def(py::init([](const std::string& text) { return parse_config_text(text); }), py::arg("json"),
           "Parse and validate a JSON configuration (ValueError naming the field when invalid).")
      .def_static("from_dict", [](const py::dict& d) { return parse_config(from_python(d, 0)); }, py::arg("config"),
                  "Parse and validate a configuration given as a dict, without JSON text: the same Config as "
                  "Config(json.dumps(config)) (ValueError naming the field when invalid). No plausibility "
                  "warnings (drillpy.model.config.engine_config gives those): for a program's configurations, e.g. "
                  "the trials of drillpy loop's calibration.")
      .def("to_json", [](const Config& c) { return to_json(c).dump(); },
           "JSON text of the configuration with every default made explicit.")
      .def("to_dict", [](const Config& c) { return drillpy_glue::to_python_dict(to_json(c)); },
           "The configuration as a dict with every default made explicit (the normalized form).")
      .def_readonly("name", &Config::name, "Name of the configuration (config.name).")
      .def_readonly("modes", &Config::modes, "Number of retained modes of the reduced model (rom.modes).")
      .def_readonly("top_speed_rad_s", &Config::top_speed, "Top speed of the operating point [rad/s].")
      .def_readonly("wob_n", &Config::wob, "Weight on bit of the operating point [N].")
      .def_property_readonly("dt_s", [](const Config& c) { return c.sim.dt; }, "Integration time step [s].")
      .def_property_readonly("duration_s", [](const Config& c) { return c.sim.duration; },
                             "Simulated duration [s].")
      .def_readonly("transient_s", &Config::transient, "Transient discarded before the metrics [s].")
      .def_property_readonly("start", [](const Config& c) { return to_string(c.start); },
                             "Initial state of runs and sweeps (simulation.start): rest, rigid or steady.")
      .def("__repr__", [](const Config& c) { return "<drillpy._core.Config " + c.name + ">"; });

  m.def("preset_names", &preset_names, "Names of the built-in presets.");
  m.def("preset_json", [](const std::string& name) { return preset_json(name).dump(); },
        "JSON text of a built-in preset.");
  m.def("normalize_config", [](const Config& c) { return to_json(c).dump(); }, py::arg("config"),
        "Validated configuration as JSON text with every default made explicit.");
  m.def(
      "with_total_elements",
      [](Config c, int n) {
        c.set_total_elements(n);
        c.validate();
        return c;
      },
      py::arg("config"), py::arg("elements"),
      "Re-mesh with n elements split in proportion to the section lengths (largest remainder).");
  m.def(
      "natural_frequencies", [](const Config& c, int n) { return natural_frequencies_hz(c.string, n); },
      py::arg("config"), py::arg("n"), "First n natural frequencies [Hz] of the clamped string (Eq. 2.7).");
  m.def(
      "exact_frequencies", [](const Config& c, int n) { return exact_frequencies_hz(c.string, n); },
      py::arg("config"), py::arg("n"),
      "First n exact natural frequencies [Hz] of the continuous string (transfer matrices).");
  m.def(
      "fe_matrices",
      [](const Config& c) {
        const FEMatrices fe = assemble(c.string);
        return py::dict(py::arg("M") = fe.M, py::arg("K") = fe.K, py::arg("x") = fe.x);
      },
      py::arg("config"), "Unconstrained global mass and stiffness matrices and node depths.");
  m.def(
      "law_torque",
      [](const std::string& law_json, const Array& v, const Array& a, const Array& wob) {
        json j;
        try {
          j = json::parse(law_json);
        } catch (const json::parse_error& e) {
          throw std::invalid_argument(std::string("law: malformed JSON: ") + e.what());
        }
        const BitRockLaw law = detail::parse_law(j);
        law.validate();
        auto bv = v.request(), ba = a.request(), bw = wob.request();
        const py::ssize_t n = bv.size;
        require(ba.size == n || ba.size == 1, "acceleration", ba.size, "must match the speed array size " + show(n));
        require(bw.size == n || bw.size == 1, "wob", bw.size, "must match the speed array size " + show(n));
        py::array_t<double> T(n), dv(n), da(n);
        const double *pv = v.data(), *pa = a.data(), *pw = wob.data();
        double *pT = T.mutable_data(), *pdv = dv.mutable_data(), *pda = da.mutable_data();
        for (py::ssize_t i = 0; i < n; ++i) {
          const TorqueEval e = law.eval(pv[i], pa[ba.size == 1 ? 0 : i], pw[bw.size == 1 ? 0 : i]);
          pT[i] = e.T;
          pdv[i] = e.dT_dv;
          pda[i] = e.dT_da;
        }
        return py::make_tuple(T, dv, da);
      },
      py::arg("law"), py::arg("speed"), py::arg("acceleration"), py::arg("wob"),
      "Torque on bit [N m] and its derivatives w.r.t. bit speed [rad/s] and acceleration [rad/s^2] "
      "(Eqs. 3.1-3.3, 5.1, 5.3).");
  m.def("max_threads", &max_threads, "Number of OpenMP threads the engine uses by default.");
}
