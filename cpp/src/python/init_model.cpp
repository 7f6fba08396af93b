// Bindings: configuration, presets, FE/ROM quantities and the bit-rock laws.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "drill/config.hpp"
#include "drill/exact.hpp"
#include "drill/modal.hpp"
#include "drill/parallel.hpp"
#include "drill/presets.hpp"

namespace py = pybind11;
using namespace drill;

void init_model(py::module_& m) {
  m.def("preset_names", &preset_names, "Names of the built-in presets.");
  m.def("preset_json", [](const std::string& name) { return preset_json(name).dump(); },
        "JSON text of a built-in preset.");
  m.def("normalize_config", [](const std::string& text) { return to_json(parse_config_text(text)).dump(); },
        "Parse and validate a JSON configuration; return it with every default made explicit.");
  m.def(
      "with_total_elements",
      [](const std::string& text, int n) {
        Config c = parse_config_text(text);
        c.set_total_elements(n);
        c.validate();
        return to_json(c).dump();
      },
      py::arg("config"), py::arg("elements"),
      "Re-mesh with n elements split in proportion to the section lengths (largest remainder).");
  m.def(
      "natural_frequencies",
      [](const std::string& text, int n) { return natural_frequencies_hz(parse_config_text(text).string, n); },
      py::arg("config"), py::arg("n"), "First n natural frequencies [Hz] of the clamped string (Eq. 2.7).");
  m.def(
      "exact_frequencies",
      [](const std::string& text, int n) { return exact_frequencies_hz(parse_config_text(text).string, n); },
      py::arg("config"), py::arg("n"),
      "First n exact natural frequencies [Hz] of the continuous string (transfer matrices).");
  m.def(
      "fe_matrices",
      [](const std::string& text) {
        const Config c = parse_config_text(text);
        const FEMatrices fe = assemble(c.string);
        return py::dict(py::arg("M") = fe.M, py::arg("K") = fe.K, py::arg("x") = fe.x);
      },
      py::arg("config"), "Unconstrained global mass and stiffness matrices and node depths.");
  m.def(
      "law_torque",
      [](const std::string& law_json, py::array_t<double, py::array::c_style | py::array::forcecast> v,
         py::array_t<double, py::array::c_style | py::array::forcecast> a,
         py::array_t<double, py::array::c_style | py::array::forcecast> wob) {
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
