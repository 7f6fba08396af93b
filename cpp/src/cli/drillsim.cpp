// drillsim: batch runs from a JSON configuration (the same schema drillpy reads).
//
//   drillsim (--config FILE | --preset NAME) [--job run|sweep] [--out DIR] [--format csv|npy]
//            [--threads N] [--progress | --no-progress]
//   drillsim --schema | --version | --help
//
// job run:   one simulation at the configured operation point; writes the time series
//            (series.csv or one .npy per channel) and summary.json (SS, stick/slip, periodicity).
// job sweep: SS over sweep.top_speeds_rad_s x sweep.wobs_n; writes severity.csv/.npy and
//            summary.json (with threshold_rad_s for a single WOB).
// --schema prints the configuration's JSON Schema (config_schema.hpp). A progress report (points
// or simulated time, and the elapsed time) goes to stderr when it is a terminal, or with --progress.
// Arguments are parsed by CLI11. Any error prints one line "drillsim: error: ..." naming the option
// and the value, and exits with status 2.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "drill/config.hpp"
#include "drill/config_schema.hpp"
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

/// --threads N: an int >= 0 (0: the OpenMP default), the whole argument.
int parse_threads(const std::string& text) {
  int n = -1;
  const char* end = text.data() + text.size();
  const auto [stop, err] = std::from_chars(text.data(), end, n);
  if (err != std::errc() || stop != end || n < 0)
    throw CLI::ValidationError("--threads = " + text + ": must be an integer >= 0 (0: the OpenMP default)");
  return n;
}

/// A progress report on stderr: rewritten in place on a terminal (else one line per report), at
/// most 4 times a second, always at the end.
class Progress {
 public:
  using clock = std::chrono::steady_clock;
  explicit Progress(bool enabled) : enabled_(enabled), tty_(isatty(STDERR_FILENO) != 0) {}
  ~Progress() {
    if (open_) std::cerr << "\n";
  }

  /// Report text() (e.g. "sweep: 8/22 points") and the elapsed time; `last`: the final report.
  template <class Text>
  void operator()(bool last, Text&& text) {
    if (!enabled_) return;
    const clock::time_point now = clock::now();
    if (!last && now - shown_ < std::chrono::milliseconds(250)) return;
    shown_ = now;
    std::ostringstream line;
    line << (tty_ ? "\r\033[K" : "") << text() << ", " << std::fixed << std::setprecision(1)
         << std::chrono::duration<double>(now - start_).count() << " s elapsed";
    open_ = tty_ && !last;
    std::cerr << line.str() << (open_ ? "" : "\n") << std::flush;
  }

 private:
  bool enabled_, tty_, open_ = false;
  clock::time_point start_ = clock::now(), shown_ = start_;
};

int run(int argc, char** argv) {
  std::string config_path, preset_name, job = "run", out = "drillsim-out", format = "csv";
  int threads = 0;
  bool progress_on = false, progress_off = false;
  CLI::App app{"drillsim: batch runs of the drill-string model from a JSON configuration", "drillsim"};
  app.footer(
      "job run: one simulation at the configured operation point (series and summary.json).\n"
      "job sweep: SS over sweep.top_speeds_rad_s x sweep.wobs_n (severity and summary.json).");
  CLI::Option* config = app.add_option("--config", config_path, "JSON configuration file")->check(CLI::ExistingFile);
  app.add_option("--preset", preset_name, "built-in configuration")
      ->check(CLI::IsMember(preset_names()))
      ->excludes(config);
  app.add_option("--job", job, "what to run")->check(CLI::IsMember({"run", "sweep"}))->capture_default_str();
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--format", format, "series and severity files")
      ->check(CLI::IsMember({"csv", "npy"}))
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--threads", [&](const std::string& text) { threads = parse_threads(text); },
         "sweep threads (0: the OpenMP default)")
      ->type_name("N")
      ->default_str("0");
  app.add_flag("--progress", progress_on, "report progress on stderr (default: when it is a terminal)");
  app.add_flag("--no-progress,--quiet", progress_off, "no progress report (overrides --progress)");
  app.add_flag_callback(
      "--schema",
      [] {
        std::cout << config_schema().dump(2) << "\n";
        throw CLI::Success();
      },
      "print the configuration's JSON Schema (draft 2020-12) and exit");
  app.set_version_flag("--version", std::string("drillsim ") + DRILLPY_VERSION);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version, --schema
    throw std::invalid_argument(e.what());
  }
  if (config_path.empty() && preset_name.empty()) throw std::invalid_argument("give --config FILE or --preset NAME");
  if (fs::exists(out) && !fs::is_directory(out)) throw std::invalid_argument("--out: " + out + " is a file, not a folder");
  Progress progress(!progress_off && (progress_on || isatty(STDERR_FILENO)));
  Config cfg;
  if (!preset_name.empty()) {
    cfg = preset(preset_name);
  } else {
    std::ifstream f(config_path);
    if (!f) throw std::invalid_argument("--config: cannot read " + config_path);
    std::stringstream ss;
    ss << f.rdbuf();
    cfg = parse_config(parse_json_text(ss.str(), "--config " + config_path));  // JSON errors name the file
  }
  const Simulation sim(cfg);
  fs::create_directories(out);
  json summary{{"config", to_json(cfg)}, {"job", job}};
  if (job == "run") {
    const double duration = cfg.sim.duration;
    auto report = [&](bool last, double t) {
      progress(last, [&] {
        std::ostringstream os;
        os << "run: " << std::fixed << std::setprecision(1) << t << "/" << duration << " s simulated";
        return os.str();
      });
    };
    const RunReport r = sim.run(sim.inputs(), true, nullptr, [&](double t, double) { report(false, t); });
    report(true, duration);
    write_series(out, format, r.series);
    summary.update(run_summary<json>(r));
    std::cout << "SS = " << r.severity << ", stick fraction = " << r.stick_fraction << ", periodic over "
              << r.periodic.period_cycles << " cycle(s)\n";
  } else {
    if (cfg.sweep_speeds.empty()) throw std::invalid_argument("sweep.top_speeds_rad_s: missing or empty for --job sweep");
    const ProgressFn points = [&](std::size_t done, std::size_t total) {
      progress(done == total, [&] { return "sweep: " + std::to_string(done) + "/" + std::to_string(total) + " points"; });
      return true;
    };
    const std::vector<double> ss = sim.sweep_severity(cfg.sweep_speeds, cfg.sweep_wobs, points, threads);
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
