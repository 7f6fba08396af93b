// drillsim: batch runs from a JSON configuration (the same schema drillpy reads).
//
//   drillsim (--config FILE | --preset NAME) [--job run|sweep] [--out DIR] [--format csv|npy]
//            [--threads N]
//   drillsim --version
//
// job run:   one simulation at the configured operation point; writes the time series
//            (series.csv or one .npy per channel) and summary.json (SS, stick/slip, periodicity).
// job sweep: SS over sweep.top_speeds_rad_s x sweep.wobs_n; writes severity.csv/.npy and
//            summary.json (with threshold_rad_s for a single WOB).
// Any error prints one line "drillsim: error: ..." and exits with status 2.
#include <climits>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "drill/config.hpp"
#include "drill/metrics.hpp"
#include "drill/presets.hpp"
#include "drill/run_summary.hpp"
#include "drill/simulation.hpp"

#ifndef DRILLPY_VERSION
#define DRILLPY_VERSION "unknown"
#endif

namespace fs = std::filesystem;
using namespace drill;

namespace {

void usage() {
  std::cerr << "usage: drillsim (--config FILE | --preset NAME) [--job run|sweep] [--out DIR] "
               "[--format csv|npy] [--threads N]\n       drillsim --version\n";
}

/// Write a 1-D or 2-D float64 array in NPY format version 1.0 (C order).
void write_npy(const fs::path& path, const std::vector<double>& data, std::size_t rows, std::size_t cols) {
  std::ostringstream hdr;
  hdr << "{'descr': '<f8', 'fortran_order': False, 'shape': (";
  if (rows == 0) hdr << cols << ",), }";
  else hdr << rows << ", " << cols << "), }";
  std::string h = hdr.str();
  const std::size_t total = 10 + h.size() + 1;
  h.append((64 - total % 64) % 64, ' ');
  h.push_back('\n');
  std::ofstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot write " + path.string());
  f.write("\x93NUMPY\x01\x00", 8);
  const std::uint16_t len = static_cast<std::uint16_t>(h.size());
  const char le[2] = {static_cast<char>(len & 0xff), static_cast<char>(len >> 8)};
  f.write(le, 2);
  f << h;
  f.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size() * sizeof(double)));
}

void write_series(const fs::path& dir, const std::string& format, const Recorder& r) {
  const std::vector<std::pair<std::string, const std::vector<double>*>> cols = {
      {"time_s", &r.t},
      {"bit_speed_rad_s", &r.bit_speed},
      {"bit_accel_rad_s2", &r.bit_accel},
      {"bit_angle_rad", &r.bit_angle},
      {"torque_on_bit_Nm", &r.torque_on_bit},
      {"top_torque_Nm", &r.top_torque},
      {"top_speed_rad_s", &r.top_speed}};
  if (format == "npy") {
    for (const auto& [name, v] : cols) write_npy(dir / (name + ".npy"), *v, 0, v->size());
    return;
  }
  std::ofstream f(dir / "series.csv");
  if (!f) throw std::runtime_error("cannot write " + (dir / "series.csv").string());
  for (std::size_t k = 0; k < cols.size(); ++k) f << (k ? "," : "") << cols[k].first;
  f << "\n";
  f.precision(10);
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    for (std::size_t k = 0; k < cols.size(); ++k) f << (k ? "," : "") << (*cols[k].second)[i];
    f << "\n";
  }
}

json nan_to_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

/// --threads N: a non-negative integer (0: the OpenMP default), the whole argument.
int parse_threads(const std::string& text) {
  std::size_t used = 0;
  long n = 0;
  try {
    n = std::stol(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || n > INT_MAX || n < INT_MIN)
    throw std::invalid_argument("--threads = \"" + text + "\": must be an integer");
  require(n >= 0, "--threads", n, "must not be negative (0: the OpenMP default)");
  return static_cast<int>(n);
}

int run(int argc, char** argv) {
  std::string config_path, preset_name, job = "run", out = "drillsim-out", format = "csv";
  int threads = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const std::string& flag) -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(flag + ": missing value");
      return argv[++i];
    };
    if (a == "--config") config_path = value(a);
    else if (a == "--preset") preset_name = value(a);
    else if (a == "--job") job = value(a);
    else if (a == "--out") out = value(a);
    else if (a == "--format") format = value(a);
    else if (a == "--threads") threads = parse_threads(value(a));
    else if (a == "--version") {
      std::cout << "drillsim " << DRILLPY_VERSION << "\n";
      return 0;
    } else if (a == "-h" || a == "--help") {
      usage();
      return 0;
    } else
      throw std::invalid_argument("argument \"" + a + "\": unknown option");
  }
  if (config_path.empty() == preset_name.empty())
    throw std::invalid_argument("give exactly one of --config FILE or --preset NAME");
  if (format != "csv" && format != "npy") throw std::invalid_argument("--format = \"" + format + "\": use csv or npy");
  if (job != "run" && job != "sweep") throw std::invalid_argument("--job = \"" + job + "\": use run or sweep");
  Config cfg;
  if (!preset_name.empty()) {
    cfg = preset(preset_name);
  } else {
    std::ifstream f(config_path);
    if (!f) throw std::invalid_argument("--config = \"" + config_path + "\": cannot open file");
    std::stringstream ss;
    ss << f.rdbuf();
    cfg = parse_config_text(ss.str());
  }
  const Simulation sim(cfg);
  fs::create_directories(out);
  json summary{{"config", to_json(cfg)}, {"job", job}};
  if (job == "run") {
    const RunReport r = sim.run(sim.inputs());
    write_series(out, format, r.series);
    summary.update(run_summary<json>(r));
    std::cout << "SS = " << r.severity << ", stick fraction = " << r.stick_fraction << ", periodic over "
              << r.periodic.period_cycles << " cycle(s)\n";
  } else {
    if (cfg.sweep_speeds.empty()) throw std::invalid_argument("sweep.top_speeds_rad_s: missing or empty for --job sweep");
    const std::vector<double> ss = sim.sweep_severity(cfg.sweep_speeds, cfg.sweep_wobs, nullptr, threads);
    const std::size_t nw = cfg.sweep_wobs.empty() ? 1 : cfg.sweep_wobs.size();
    if (format == "npy") {
      write_npy(fs::path(out) / "severity.npy", ss, nw, cfg.sweep_speeds.size());
    } else {
      std::ofstream f(fs::path(out) / "severity.csv");
      f << "wob_n";
      for (double s : cfg.sweep_speeds) f << ",ss_at_" << s << "_rad_s";
      f << "\n";
      f.precision(10);
      for (std::size_t w = 0; w < nw; ++w) {
        f << (cfg.sweep_wobs.empty() ? cfg.wob : cfg.sweep_wobs[w]);
        for (std::size_t s = 0; s < cfg.sweep_speeds.size(); ++s) f << "," << ss[w * cfg.sweep_speeds.size() + s];
        f << "\n";
      }
    }
    summary["top_speeds_rad_s"] = cfg.sweep_speeds;
    summary["wobs_n"] = cfg.sweep_wobs.empty() ? std::vector<double>{cfg.wob} : cfg.sweep_wobs;
    summary["severity"] = ss;
    if (nw == 1) {
      const double thr = severity_threshold(cfg.sweep_speeds, ss);
      summary["threshold_rad_s"] = nan_to_null(thr);
      std::cout << "SS > 0.5 below " << thr << " rad/s\n";
    }
  }
  std::ofstream(fs::path(out) / "summary.json") << summary.dump(2) << "\n";
  std::cout << "wrote " << out << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "drillsim: error: " << e.what() << "\n";
    return 2;
  }
}
