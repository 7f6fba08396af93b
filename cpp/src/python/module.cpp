// The drillpy._core extension module: one init_xxx per area of the engine.
#include <pybind11/pybind11.h>

namespace py = pybind11;

void init_model(py::module_& m);
void init_simulation(py::module_& m);
void init_uncertainty(py::module_& m);
void init_stochastic(py::module_& m);
void init_horizons(py::module_& m);

PYBIND11_MODULE(_core, m) {
  m.doc() = "drillpy engine: FE/ROM torsional drill-string model, bit-rock laws, integrators";
  init_model(m);
  init_simulation(m);
  init_uncertainty(m);
  init_stochastic(m);
  init_horizons(m);
}
