// Bindings: PSD model and tables, the Gaussian process generator, the Monte Carlo study of the
// stochastic bit-rock law and its statistics (glue only; GIL released, Ctrl-C aware).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <functional>

#include "drill/config.hpp"
#include "drill/montecarlo.hpp"
#include "drill/process.hpp"
#include "glue.hpp"

namespace py = pybind11;
using namespace drill;

namespace {

using drillpy_glue::Array;
using drillpy_glue::as_array;
using drillpy_glue::to_vector;

PsdModel make_model(double f0, double A0, double a, double b) {
  PsdModel m{f0, A0, a, b};
  m.validate();
  return m;
}

py::array_t<double> map_values(const Array& f, const std::function<double(double)>& fn) {
  py::array_t<double> out(f.size());
  const double* pf = f.data();
  double* po = out.mutable_data();
  for (py::ssize_t k = 0; k < f.size(); ++k) po[k] = fn(pf[k]);
  return out;
}

py::dict statistics_to_dict(const SeverityStatistics& st) {
  return py::dict(py::arg("mean") = as_array(st.mean), py::arg("q_low") = as_array(st.q_low),
                  py::arg("q_high") = as_array(st.q_high), py::arg("p_exceed") = as_array(st.p_exceed),
                  py::arg("p_speed") = st.p_speed);
}

void bind_severity_statistics(py::module_& m) {
  py::class_<SeverityStatistics>(m, "SeverityStatistics",
                                 "Statistics per top speed of SS samples (severity_statistics, section 4.2.2); "
                                 "arrays have one entry per speed.")
      .def_property_readonly("mean", [](const SeverityStatistics& s) { return as_array(s.mean); },
                             "Sample mean of the stick-slip severity SS, Eq. (3.4), dimensionless.")
      .def_property_readonly("q_low", [](const SeverityStatistics& s) { return as_array(s.q_low); },
                             "Lower quantile (q_low) of SS, dimensionless.")
      .def_property_readonly("q_high", [](const SeverityStatistics& s) { return as_array(s.q_high); },
                             "Upper quantile (q_high) of SS, dimensionless.")
      .def_property_readonly("p_exceed", [](const SeverityStatistics& s) { return as_array(s.p_exceed); },
                             "Probability P(SS > level), dimensionless.")
      .def_readonly("p_speed", &SeverityStatistics::p_speed,
                    "Lowest top speed from which P(SS > level) <= prob [rad/s] (NaN: no crossing).")
      .def("to_dict", &statistics_to_dict, "Every field in a dict keyed by the field names.");
}

}  // namespace

void init_stochastic(py::module_& m) {
  bind_severity_statistics(m);
  m.def(
      "psd_model_values",
      [](const Array& f, double f0, double A0, double a, double b) {
        const PsdModel mod = make_model(f0, A0, a, b);
        return map_values(f, [&](double x) { return mod(x); });
      },
      py::arg("f"), py::arg("f0"), py::arg("A0"), py::arg("a"), py::arg("b"),
      "PSD model of Eq. (4.4) (natural log; one-sided, per Hz) at frequencies f [Hz].");
  m.def(
      "psd_model_integral",
      [](double f0, double A0, double a, double b, double fmax) { return make_model(f0, A0, a, b).integral(fmax); },
      py::arg("f0"), py::arg("A0"), py::arg("a"), py::arg("b"), py::arg("fmax") = HUGE_VAL,
      "integral_0^fmax S(f) df of the model of Eq. (4.4) (the variance of eta for fmax = inf).");
  m.def(
      "psd_table_values",
      [](const Array& ft, const Array& St, const Array& f) {
        PsdTable t{to_vector(ft), to_vector(St)};
        t.validate();
        return map_values(f, [&](double x) { return t(x); });
      },
      py::arg("table_f"), py::arg("table_S"), py::arg("f"),
      "Tabulated PSD (linear between points, held below the first, zero above the last) at f [Hz].");
  m.def("process_grid", &GaussianProcess::grid_frequencies, py::arg("dt"), py::arg("duration"),
        "Frequencies [Hz] at which the generator needs the PSD (k / (n dt), k = 0 .. n/2).");
  m.def(
      "process_variance",
      [](const Array& S, double dt, double duration) { return GaussianProcess(to_vector(S), dt, duration).variance(); },
      py::arg("psd"), py::arg("dt"), py::arg("duration"),
      "Exact variance of the generated process (trapezoidal sum of the PSD on the grid).");
  m.def(
      "generate_process",
      [](const Array& S, double dt, double duration, std::uint64_t seed, std::uint64_t first, std::size_t count) {
        const GaussianProcess proc(to_vector(S), dt, duration);
        require(count >= 1 && count <= 100000, "samples", count, "must be between 1 and 100000");
        py::array_t<double> out({count, proc.size()});
        double* po = out.mutable_data();
        for (std::size_t i = 0; i < count; ++i) {
          RandomStream rng(seed, first + i, MonteCarlo::eta_stream);
          const std::vector<double> x = proc.sample(rng);
          std::copy(x.begin(), x.end(), po + i * proc.size());
        }
        return out;
      },
      py::arg("psd"), py::arg("dt"), py::arg("duration"), py::arg("seed"), py::arg("first_sample"),
      py::arg("samples"),
      "Realizations of eta on the grid t = j dt (rows: samples first_sample ..), the same as the Monte "
      "Carlo samples with that seed.");

  py::class_<MonteCarlo>(m, "MonteCarlo", "Monte Carlo of the stochastic drill-string model (Algorithm 1).")
      .def(py::init([](Config c, const Array& S, double eta_dt, std::uint64_t seed, double warmup) {
             GaussianProcess proc(to_vector(S), eta_dt, c.sim.duration);
             return MonteCarlo(std::move(c), std::move(proc), seed, warmup);
           }),
           py::arg("config"), py::arg("psd"), py::arg("eta_dt"), py::arg("seed"), py::arg("warmup") = 0.0)
      .def_property_readonly("eta_variance", [](const MonteCarlo& mc) { return mc.process().variance(); })
      .def_property_readonly("lockstep", &MonteCarlo::lockstep,
                             "Whether severity(batched=True) steps the samples in lockstep, one per lane (the torsional "
                             "model where the batched integrator supports it; the axial-torsional model, axial.type = "
                             "rgd, always): the same numbers as one by one.")
      .def(
          "eta",
          [](const MonteCarlo& mc, std::uint64_t sample) {
            const Signal s = mc.eta(sample);
            return as_array(s.samples);
          },
          py::arg("sample"), "The eta realization of one sample on its grid.")
      .def(
          "severity",
          [](const MonteCarlo& mc, const std::vector<double>& speeds, std::uint64_t first, std::size_t count,
             py::object progress, int threads, bool batched) {
            Eigen::MatrixXd out;
            {
              py::gil_scoped_release nogil;
              out = mc.severity(speeds, first, count, drillpy_glue::progress_callback(progress), threads, nullptr, batched);
            }
            return out;
          },
          py::arg("speeds"), py::arg("first_sample"), py::arg("samples"), py::arg("progress") = py::none(),
          py::arg("threads") = 0, py::arg("batched") = true,
          "SS (Eq. 3.4) per sample (rows) and top speed (columns); batched: samples in SIMD lockstep where the "
          "batched integrator supports the configuration (False: the scalar reference integrator).")
      .def(
          "severity_and_bit_speed",
          [](const MonteCarlo& mc, const std::vector<double>& speeds, std::uint64_t first, std::size_t count,
             int threads) {
            Eigen::MatrixXd ss, bit;
            {
              py::gil_scoped_release nogil;
              ss = mc.severity(speeds, first, count, nullptr, threads, &bit);
            }
            return py::make_tuple(ss, bit);
          },
          py::arg("speeds"), py::arg("first_sample"), py::arg("samples"), py::arg("threads") = 0,
          "SS (Eq. 3.4) and the mean bit speed of the SS window [rad/s] per sample (rows) and top speed (columns).")
      .def(
          "phases",
          [](const MonteCarlo& mc, double speed, std::uint64_t first, std::size_t count, py::object progress,
             int threads) {
            std::vector<PhaseSample> out;
            {
              py::gil_scoped_release nogil;
              out = mc.phases(speed, first, count, drillpy_glue::progress_callback(progress), threads);
            }
            py::list stick, slip;
            std::vector<double> ss;
            for (const PhaseSample& p : out) {
              stick.append(as_array(p.stick));
              slip.append(as_array(p.slip));
              ss.push_back(p.severity);
            }
            return py::make_tuple(stick, slip, as_array(ss));
          },
          py::arg("speed"), py::arg("first_sample"), py::arg("samples"), py::arg("progress") = py::none(),
          py::arg("threads") = 0, "Stick and slip durations [s] per sample at one top speed, and SS.");

  m.def(
      "severity_statistics",
      [](const Eigen::MatrixXd& ss, const std::vector<double>& speeds, double level, double prob, double q_low,
         double q_high) {
        return severity_statistics(ss, speeds, level, prob, q_low, q_high);
      },
      py::arg("severity"), py::arg("speeds"), py::arg("level") = 0.5, py::arg("prob") = 0.05,
      py::arg("q_low") = 0.05, py::arg("q_high") = 0.95,
      "Mean, quantiles and P(SS > level) per speed; the speed from which P(SS > level) <= prob.");
  m.def("conv1", &conv1, py::arg("severity"), py::arg("speeds"), "Convergence function Conv1(n_s) of Eq. (C.1).");
}
