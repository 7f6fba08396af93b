// Bindings: short-horizon predictions restarted from measured states (drillpy loop).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "drill/horizons.hpp"
#include "drill/sensor.hpp"
#include "glue.hpp"

namespace py = pybind11;
using namespace drill;

namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

std::vector<double> as_vector(const py::object& x, const std::string& field) {
  if (x.is_none()) return {};
  auto a = py::cast<py::array_t<double, py::array::c_style | py::array::forcecast>>(x);
  require(a.ndim() == 1, field, a.ndim(), "must be a 1-D array");
  return std::vector<double>(a.data(), a.data() + a.size());
}

}  // namespace

void init_horizons(py::module_& m) {
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
      [](const Simulation& sim, const std::vector<long>& index, const RowMatrix& state, const RowMatrix& sensor,
         double dt, int samples, py::object top_speed, py::object wob, py::object eta, py::object progress,
         int threads) {
        const std::size_t n = index.size();
        require(state.rows() == static_cast<Eigen::Index>(n) && state.cols() == 5, "state shape",
                show(state.rows()) + " x " + show(state.cols()),
                "must be horizons x 5 (bit speed, bit acceleration, torque, top speed, top acceleration)");
        require(sensor.rows() == static_cast<Eigen::Index>(n) && sensor.cols() == 6, "sensor shape",
                show(sensor.rows()) + " x " + show(sensor.cols()),
                "must be horizons x 6 (bit speed, its rate, torque, its rate, top speed, its rate as recorded)");
        std::vector<HorizonStart> starts(n);
        for (std::size_t h = 0; h < n; ++h) {
          const Eigen::Index i = static_cast<Eigen::Index>(h);
          starts[h] = {index[h],         state(i, 0),  state(i, 1),  state(i, 2),  state(i, 3),  state(i, 4),
                       sensor(i, 0),     sensor(i, 1), sensor(i, 2), sensor(i, 3), sensor(i, 4), sensor(i, 5)};
        }
        HorizonInputs hin;
        hin.dt = dt;
        hin.samples = samples;
        hin.top_speed = as_vector(top_speed, "top_speed");
        hin.wob = as_vector(wob, "wob");
        if (!eta.is_none()) hin.eta = py::cast<Eigen::MatrixXd>(eta);
        HorizonResult r;
        {
          py::gil_scoped_release nogil;
          r = predict_horizons(sim, starts, hin, drillpy_glue::progress_callback(progress), threads);
        }
        return py::dict(py::arg("bit_speed") = r.bit_speed, py::arg("torque") = r.torque,
                        py::arg("top_speed") = r.top_speed);
      },
      py::arg("simulation"), py::arg("index"), py::arg("state"), py::arg("sensor"), py::arg("dt"), py::arg("samples"),
      py::arg("top_speed") = py::none(), py::arg("wob") = py::none(), py::arg("eta") = py::none(),
      py::arg("progress") = py::none(), py::arg("threads") = 0,
      "Short-horizon predictions restarted from measured states (drill/horizons.hpp): rows are horizons, "
      "columns the samples dt, 2 dt, ... after each start; bit speed [rad/s], contact torque [N m], top speed "
      "[rad/s], after the configured sensors.");
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
