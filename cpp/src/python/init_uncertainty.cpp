// Bindings: Craig-Bampton substructuring, random matrices (SE+, SE+0), stochastic models
// (SM_full, SM_CB1, SM_CB2), FRF envelopes and SS under structural uncertainty (chapter 6).
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "drill/config.hpp"
#include "drill/craig_bampton.hpp"
#include "drill/frf.hpp"
#include "drill/randmat.hpp"
#include "drill/stochastic_model.hpp"
#include "drill/structural_severity.hpp"
#include "glue.hpp"

namespace py = pybind11;
using namespace drill;

namespace {

using drillpy_glue::Array;

/// (ns, 3, 2) array -> one Dispersions per substructure.
std::vector<Dispersions> to_dispersions(const Array& a) {
  require(a.ndim() == 3 && a.shape(1) == 3 && a.shape(2) == 2, "delta (shape)", a.ndim(),
          "must be an array of shape (substructures, 3, 2): [M, D, K] x [inner, interface]");
  std::vector<Dispersions> d(static_cast<std::size_t>(a.shape(0)));
  auto r = a.unchecked<3>();
  for (py::ssize_t k = 0; k < a.shape(0); ++k)
    for (int i = 0; i < 3; ++i)
      for (int s = 0; s < 2; ++s) d[static_cast<std::size_t>(k)](i, s) = r(k, i, s);
  return d;
}

Array from_dispersions(const std::vector<Dispersions>& d) {
  Array a({static_cast<py::ssize_t>(d.size()), py::ssize_t(3), py::ssize_t(2)});
  auto w = a.mutable_unchecked<3>();
  for (std::size_t k = 0; k < d.size(); ++k)
    for (int i = 0; i < 3; ++i)
      for (int s = 0; s < 2; ++s) w(static_cast<py::ssize_t>(k), i, s) = d[k](i, s);
  return a;
}

py::dict matrices(const Eigen::MatrixXd& M, const Eigen::MatrixXd& D, const Eigen::MatrixXd& K) {
  return py::dict(py::arg("M") = M, py::arg("D") = D, py::arg("K") = K);
}

py::dict envelope_to_dict(const FrfEnvelope& e) {
  return py::dict(py::arg("freq_hz") = e.freq_hz, py::arg("nodes") = e.nodes, py::arg("nominal_db") = e.nominal_db,
                  py::arg("mean_db") = e.mean_db, py::arg("lower_db") = e.lower_db, py::arg("upper_db") = e.upper_db,
                  py::arg("energy") = e.energy, py::arg("samples") = e.samples);
}

void bind_frf_envelope(py::module_& m) {
  py::class_<FrfEnvelope>(m, "FrfEnvelope",
                          "Monte Carlo envelope of the acceleration FRF for a unit torque at the bit (section 6.6, "
                          "StochasticModel.envelope). Matrices are n_freq x n_nodes unless stated.")
      .def_readonly("freq_hz", &FrfEnvelope::freq_hz, "Frequencies [Hz].")
      .def_readonly("nodes", &FrfEnvelope::nodes, "Observed FE nodes (1 = first free node).")
      .def_readonly("nominal_db", &FrfEnvelope::nominal_db,
                    "Acceleration FRF of the mean (deterministic) model [dB re 1 rad/s^2 per N m].")
      .def_readonly("mean_db", &FrfEnvelope::mean_db, "Sample mean of the dB response [dB].")
      .def_readonly("lower_db", &FrfEnvelope::lower_db, "Quantile (1 - P)/2 of the dB response [dB].")
      .def_readonly("upper_db", &FrfEnvelope::upper_db, "Quantile (1 + P)/2 of the dB response [dB].")
      .def_readonly("energy", &FrfEnvelope::energy,
                    "n_samples x n_nodes: int_B |a_i(omega)|^2 d omega over the band (Eq. C.2) [(rad/s^2 / N m)^2 rad/s].")
      .def_readonly("samples", &FrfEnvelope::samples, "Number of realizations (0 when cancelled).")
      .def("to_dict", &envelope_to_dict, "Every field in a dict keyed by the field names.");
}

}  // namespace

void init_uncertainty(py::module_& m) {
  bind_frf_envelope(m);
  m.def(
      "craig_bampton",
      [](const Config& c) {
        const CraigBampton cb(c);
        py::list subs;
        for (const Substructure& s : cb.substructures())
          subs.append(py::dict(py::arg("name") = s.name, py::arg("modes") = s.modes,
                               py::arg("fixed_interface_hz") = Eigen::VectorXd(s.omega / (2 * M_PI)),
                               py::arg("inner_nodes") = s.inner_nodes, py::arg("interface_nodes") = s.interface_nodes,
                               py::arg("psi") = s.psi, py::arg("M") = s.M, py::arg("D") = s.D, py::arg("K") = s.K));
        return py::dict(py::arg("M") = cb.M(), py::arg("D") = cb.D(), py::arg("K") = cb.K(), py::arg("psi") = cb.psi(),
                        py::arg("interface_offset") = cb.interface_offset(), py::arg("substructures") = subs);
      },
      py::arg("config"),
      "Craig-Bampton model of the configuration (Eqs. 6.8-6.18): assembled M, D, K, recovery Psi and "
      "the reduced blocks of each substructure.");
  m.def(
      "cb_frequencies", [](const Config& c, int n) { return CraigBampton(c).frequencies_hz(n); },
      py::arg("config"), py::arg("n"), "First n natural frequencies [Hz] of the assembled Craig-Bampton model.");
  m.def(
      "thesis_case_dispersions",
      [](int case_id, double delta) { return from_dispersions(thesis_case_dispersions(case_id, delta)); },
      py::arg("case"), py::arg("delta") = 0.1,
      "Dispersions (2, 3, 2) of case studies 1-7 (Tables 6.1-6.7): [DP, BHA] x [M, D, K] x [inner, interface].");
  m.def("max_dispersion", &max_dispersion, py::arg("n"),
        "Upper bound sqrt((n+1)/(n+5)) of the dispersion of SG+ in dimension n (excluded).");
  m.def(
      "random_matrix",
      [](const Eigen::MatrixXd& mean, double delta, std::uint64_t seed, std::uint64_t sample) {
        const RandomMatrixEnsemble e(mean, "mean");
        RandomStream rs(seed, sample, 0);
        return e.sample(delta, rs);
      },
      py::arg("mean"), py::arg("delta"), py::arg("seed") = 1, py::arg("sample") = 0,
      "One realization of SE+ (positive-definite mean, Eqs. 6.1-6.2) or SE+0 (semi-definite mean, "
      "Eqs. 6.24-6.25) with dispersion delta (Eq. 6.3).");

  py::class_<StochasticModel>(m, "StochasticModel", "SM_full, SM_CB1 or SM_CB2 on a configuration (chapter 6).")
      .def(py::init([](const Config& c, const std::string& kind, const Array& delta) {
             return StochasticModel(c, parse_stochastic_kind(kind), to_dispersions(delta));
           }),
           py::arg("config"), py::arg("model"), py::arg("delta"))
      .def_property_readonly("model", [](const StochasticModel& s) { return to_string(s.kind()); })
      .def_property_readonly("delta", [](const StochasticModel& s) { return from_dispersions(s.dispersions()); })
      .def_property_readonly("size", &StochasticModel::size)
      .def_property_readonly("mean_matrices",
                             [](const StochasticModel& s) { return matrices(s.mean().M, s.mean().D, s.mean().K); })
      .def(
          "sample_matrices",
          [](const StochasticModel& s, std::uint64_t seed, std::uint64_t i) {
            Eigen::MatrixXd M, D, K;
            s.sample_matrices(seed, i, M, D, K);
            return matrices(M, D, K);
          },
          py::arg("seed"), py::arg("sample"), "Realization `sample` of the random M, D, K.")
      .def(
          "envelope",
          [](const StochasticModel& s, const Eigen::VectorXd& freq_hz, const std::vector<int>& nodes, std::size_t samples,
             std::uint64_t seed, double probability, py::object progress, int threads) {
            EnvelopeOptions o;
            o.samples = samples;
            o.seed = seed;
            o.probability = probability;
            o.threads = threads;
            FrfEnvelope e;
            {
              py::gil_scoped_release nogil;
              e = frf_envelope(s, nodes, freq_hz, o, drillpy_glue::progress_callback(progress));
            }
            return e;
          },
          py::arg("freq_hz"), py::arg("nodes"), py::arg("samples") = 2500, py::arg("seed") = 1,
          py::arg("probability") = 0.95, py::arg("progress") = py::none(), py::arg("threads") = 0,
          "Monte Carlo envelope of the acceleration FRF (dB) for a unit torque at the bit.")
      .def(
          "frf_samples",
          [](const StochasticModel& s, const Eigen::VectorXd& freq_hz, const std::vector<int>& nodes,
             std::uint64_t first_sample, std::size_t samples, std::uint64_t seed, py::object progress, int threads) {
            FrfSamples r;
            {
              py::gil_scoped_release nogil;
              r = frf_sample_db(s, nodes, freq_hz, seed, first_sample, samples, threads,
                                drillpy_glue::progress_callback(progress));
            }
            const py::ssize_t ns = r.db.rows(), no = static_cast<py::ssize_t>(nodes.size()), nf = freq_hz.size();
            auto* db = new FrfDbRows(std::move(r.db));
            const py::capsule owner(db, [](void* p) { delete static_cast<FrfDbRows*>(p); });
            const py::array_t<float> a({ns, no, nf}, db->data(), owner);
            return py::make_tuple(a, r.energy);
          },
          py::arg("freq_hz"), py::arg("nodes"), py::arg("first_sample"), py::arg("samples"), py::arg("seed") = 1,
          py::arg("progress") = py::none(), py::arg("threads") = 0,
          "Per-sample acceleration FRF of samples first_sample .. first_sample + samples - 1 (row r: sample "
          "first_sample + r): (db, energy) with db float32 (samples, n_nodes, n_freq) [dB] and energy (samples, "
          "n_nodes), int_B |a|^2 d omega (Eq. C.2).")
      .def(
          "envelope_from_samples",
          [](const StochasticModel& s, const Eigen::VectorXd& freq_hz, const std::vector<int>& nodes,
             const py::array_t<float, py::array::c_style | py::array::forcecast>& db, const Eigen::MatrixXd& energy,
             double probability, py::object progress, int threads) {
            const py::ssize_t no = static_cast<py::ssize_t>(nodes.size()), nf = freq_hz.size();
            require(db.ndim() == 3 && db.shape(1) == no && db.shape(2) == nf, "db (shape)", db.ndim(),
                    "must be an array of shape (samples, " + show(no) + " nodes, " + show(nf) + " frequencies)");
            const Eigen::Map<const FrfDbRows> rows(db.data(), db.shape(0), no * nf);
            FrfEnvelope e;
            {
              py::gil_scoped_release nogil;
              e = frf_statistics(s, nodes, freq_hz, rows, energy, probability, threads,
                                 drillpy_glue::progress_callback(progress));
            }
            return e;
          },
          py::arg("freq_hz"), py::arg("nodes"), py::arg("db"), py::arg("energy"), py::arg("probability") = 0.95,
          py::arg("progress") = py::none(), py::arg("threads") = 0,
          "Envelope of the acceleration FRF from frf_samples results stacked in sample order (db (samples, "
          "n_nodes, n_freq), energy (samples, n_nodes)) and the mean model's response; progress counts "
          "frequencies.")
      .def(
          "frf_db",
          [](const StochasticModel& s, const Eigen::VectorXd& freq_hz, const std::vector<int>& nodes, py::object sample,
             std::uint64_t seed) {
            Eigen::MatrixXd M = s.mean().M, D = s.mean().D, K = s.mean().K;
            if (!sample.is_none()) s.sample_matrices(seed, py::cast<std::uint64_t>(sample), M, D, K);
            for (std::size_t o = 0; o < nodes.size(); ++o)
              require(nodes[o] >= 1 && nodes[o] < s.mean().basis.rows() + 1, "nodes[" + std::to_string(o) + "]",
                      nodes[o], "must be a free node (1 .. " + show(s.mean().basis.rows()) + ")");
            return bit_torque_response(s.mean(), M, D, K, nodes).acceleration_db(2.0 * M_PI * freq_hz.array());
          },
          py::arg("freq_hz"), py::arg("nodes"), py::arg("sample") = py::none(), py::arg("seed") = 1,
          "Acceleration FRF [dB] of the mean model or of one realization (n_freq x n_nodes).")
      .def(
          "severity_samples",
          [](const StochasticModel& s, const std::vector<double>& speeds, std::size_t samples, std::uint64_t seed,
             bool structural, py::object eta, py::object eta_psd, double eta_dt, py::object progress, int threads,
             std::uint64_t first_sample) {
            SeverityStudyOptions o;
            o.speeds = speeds;
            o.samples = samples;
            o.first_sample = first_sample;
            o.seed = seed;
            o.structural = structural;
            o.threads = threads;
            require(eta.is_none() || eta_psd.is_none(), "eta", "series and PSD", "give either eta or eta_psd");
            EtaProvider provider;
            std::vector<Signal> series;
            if (!eta.is_none()) {
              const Array a = py::cast<Array>(eta);
              require(a.ndim() == 2 && static_cast<std::size_t>(a.shape(0)) >= samples && a.shape(1) >= 1,
                      "eta (shape)", a.ndim(), "must be a 2-D array with one row per sample (" + show(samples) + ")");
              for (std::size_t i = 0; i < samples; ++i) {
                const double* row = a.data(static_cast<py::ssize_t>(i), 0);
                series.push_back(Signal::sampled(std::vector<double>(row, row + a.shape(1)), 0.0, eta_dt));
                series.back().validate("eta[" + std::to_string(i) + "]");
              }
              provider = [&series, first_sample](std::size_t i) { return series[i - first_sample]; };
            } else if (!eta_psd.is_none()) {
              const Array S = py::cast<Array>(eta_psd);
              provider = psd_eta(GaussianProcess(std::vector<double>(S.data(), S.data() + S.size()), eta_dt,
                                                 s.config().sim.duration),
                                 seed);
            }
            Eigen::MatrixXd ss;
            {
              py::gil_scoped_release nogil;
              ss = severity_samples(s, o, provider, drillpy_glue::progress_callback(progress));
            }
            return ss;
          },
          py::arg("speeds"), py::arg("samples"), py::arg("seed") = 1, py::arg("structural") = true,
          py::arg("eta") = py::none(), py::arg("eta_psd") = py::none(), py::arg("eta_dt") = 0.05,
          py::arg("progress") = py::none(), py::arg("threads") = 0, py::arg("first_sample") = 0,
          "SS (Eq. 3.4) of samples first_sample .. first_sample + samples - 1 (row r: sample first_sample + r) x "
          "top speeds with random structure; bit-rock uncertainty (Eq. 4.1) from eta rows (row r for row r of the "
          "result) sampled every eta_dt, or from a PSD on the generator grid of (eta_dt, duration) (Eq. 4.4).");
  m.def("observation_nodes", [](const Config& c) { return thesis_observation_nodes(c.string); },
        py::arg("config"), "P_obs,1 (first free node), P_obs,2 (first interface), P_obs,3 (bit) of section 6.6.");
}
