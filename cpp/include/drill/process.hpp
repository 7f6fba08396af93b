// The random torque fluctuation eta(t) of the stochastic bit-rock law (thesis section 4.1):
// a centred stationary Gaussian process given by its power spectral density (PSD), the PSD model
// of Eq. (4.4), tabulated PSDs, and a generator by the spectral representation with an FFT.
//
// PSD convention (used everywhere in drillpy): S is ONE-SIDED and per HERTZ,
//     Var[eta] = integral_0^inf S(f) df,    f in Hz,  S in 1/Hz (eta is dimensionless).
// A two-sided density S2 over (-inf, inf) is S = 2 S2; a density per rad/s G(omega) is
// S(f) = 2 pi G(2 pi f) one-sided.
//
// Generator (spectral representation, Shinozuka's form with Gaussian amplitudes): on n points
// t_j = j dt (n even, period n dt, df = 1 / (n dt), f_k = k df, k = 0 .. n/2)
//     eta_j = sum_k [A_k cos(2 pi f_k t_j) + B_k sin(2 pi f_k t_j)],
//     A_k, B_k ~ N(0, S(f_k) df) independent for 0 < k < n/2,
//     A_0 ~ N(0, S(0) df / 2), A_{n/2} ~ N(0, S(f_{n/2}) df / 2), B_0 = B_{n/2} = 0.
// The sum is one inverse real FFT (Eigen's FFT module, kissfft back end). eta is exactly Gaussian
// and (circularly) stationary with covariance sum_k w_k S(f_k) df cos(2 pi f_k tau); its variance
// is the trapezoidal rule for integral_0^{1/(2 dt)} S df (variance()). The expected one-sided
// periodogram of one period, (2 dt / n) |DFT_k|^2, equals S(f_k) exactly at 0 < k < n/2.
// Random numbers come from the caller's RandomStream, so a Monte Carlo sample i that draws from
// RandomStream(seed, i, stream) gets the same realization on any thread.
#pragma once

#include <unsupported/Eigen/FFT>

#include <cmath>
#include <complex>
#include <cstddef>
#include <string>
#include <vector>

#include "drill/errors.hpp"
#include "drill/rng.hpp"
#include "drill/signal.hpp"

namespace drill {

/// The PSD model of Eq. (4.4) with the NATURAL logarithm (the only reading continuous at f0):
///   ln S(f) = A0 for f < f0,   ln S(f) = a ln f + b for f >= f0   (S one-sided per Hz, f in Hz).
struct PsdModel {
  double f0 = 0.27, A0 = -7.6, a = -3.13, b = -11.67;  ///< the thesis's calibration (section 4.1)

  void validate() const {
    require_positive(f0, "psd.f0_hz");
    require_finite(A0, "psd.A0");
    require_finite(a, "psd.a");
    require_finite(b, "psd.b");
  }

  /// S(f) [1/Hz] at f >= 0 [Hz].
  double operator()(double f) const {
    require(std::isfinite(f) && f >= 0.0, "psd frequency [Hz]", f, "must be finite and non-negative");
    return f < f0 ? std::exp(A0) : std::exp(a * std::log(f) + b);
  }

  /// integral_0^fmax S(f) df (closed form); fmax = infinity needs a < -1.
  double integral(double fmax = HUGE_VAL) const {
    require(fmax >= 0.0, "psd.integral upper limit [Hz]", fmax, "must be non-negative");
    if (fmax <= f0) return std::exp(A0) * fmax;
    if (std::isinf(fmax))
      require(a < -1.0, "psd.a", a, "must be below -1 for a finite variance (integral to infinity)");
    const double tail = a == -1.0 ? std::exp(b) * std::log(fmax / f0)
                                  : std::exp(b) * ((std::isinf(fmax) ? 0.0 : std::pow(fmax, a + 1.0)) -
                                                   std::pow(f0, a + 1.0)) / (a + 1.0);
    return std::exp(A0) * f0 + tail;
  }
};

/// A tabulated PSD: S linear between the points (f strictly increasing, f >= 0, S >= 0), held at
/// S(f_first) below the first frequency and zero above the last one (band-limited).
struct PsdTable {
  std::vector<double> f, S;

  void validate() const {
    require(f.size() == S.size(), "psd.table.S size", S.size(), "must equal the number of frequencies " + show(f.size()));
    require(f.size() >= 2, "psd.table size", f.size(), "needs at least 2 points");
    for (std::size_t k = 0; k < f.size(); ++k) {
      const std::string i = "[" + std::to_string(k) + "]";
      require(std::isfinite(f[k]) && f[k] >= 0.0, "psd.table.f_hz" + i, f[k], "must be finite and non-negative");
      require(k == 0 || f[k] > f[k - 1], "psd.table.f_hz" + i, f[k], "frequencies must increase strictly");
      require(std::isfinite(S[k]), "psd.table.S" + i, S[k], "must be a finite number");
      require(S[k] >= 0.0, "psd.table.S" + i, S[k], "must not be negative (a PSD is non-negative)");
    }
  }

  double operator()(double x) const {
    if (x <= f.front()) return S.front();
    if (x > f.back()) return 0.0;
    std::size_t k = 1;
    while (f[k] < x) ++k;  // tables are short; linear search keeps this dependency-free
    const double w = (x - f[k - 1]) / (f[k] - f[k - 1]);
    return S[k - 1] + w * (S[k] - S[k - 1]);
  }
};

/// Generator of a centred stationary Gaussian process from a one-sided PSD in Hz (see the header).
class GaussianProcess {
 public:
  static constexpr std::size_t max_points = std::size_t(1) << 26;

  /// Number of points of the FFT grid: the smallest power of two n >= 4 with n dt >= duration
  /// (the realization does not repeat within `duration`).
  static std::size_t grid_size(double dt, double duration) {
    require_positive(dt, "process.dt_s");
    require_positive(duration, "process.duration_s");
    require(duration / dt <= static_cast<double>(max_points), "process.dt_s", dt,
            "too small for duration " + show(duration) + " s (more than 2^26 points)");
    std::size_t n = 4;
    while (static_cast<double>(n) * dt < duration) n *= 2;
    return n;
  }

  /// The frequencies f_k = k / (n dt), k = 0 .. n/2, at which the PSD is needed [Hz].
  static std::vector<double> grid_frequencies(double dt, double duration) {
    const std::size_t n = grid_size(dt, duration);
    std::vector<double> f(n / 2 + 1);
    for (std::size_t k = 0; k < f.size(); ++k) f[k] = static_cast<double>(k) / (static_cast<double>(n) * dt);
    return f;
  }

  /// From the PSD values on grid_frequencies(dt, duration).
  GaussianProcess(std::vector<double> psd_on_grid, double dt, double duration)
      : dt_(dt), n_(grid_size(dt, duration)), S_(std::move(psd_on_grid)) {
    require(S_.size() == n_ / 2 + 1, "process.psd values", S_.size(),
            "must have one value per grid frequency (" + show(n_ / 2 + 1) + ")");
    const double df = 1.0 / (static_cast<double>(n_) * dt_);
    for (std::size_t k = 0; k < S_.size(); ++k) {
      const std::string at = "psd(f = " + show(k * df) + " Hz)";
      require(std::isfinite(S_[k]), at, S_[k], "must be a finite number");
      require(S_[k] >= 0.0, at, S_[k], "must not be negative (a PSD is non-negative)");
    }
    sd_.resize(S_.size());
    for (std::size_t k = 0; k < S_.size(); ++k) {
      const bool edge = k == 0 || k == n_ / 2;
      sd_[k] = std::sqrt(S_[k] * df * (edge ? 0.5 : 1.0));
    }
  }

  /// From any PSD callable S(f) [1/Hz] (PsdModel, PsdTable, a lambda) evaluated on the grid.
  template <class Psd>
  static GaussianProcess from_psd(const Psd& psd, double dt, double duration) {
    std::vector<double> f = grid_frequencies(dt, duration);
    for (double& x : f) x = psd(x);
    return GaussianProcess(std::move(f), dt, duration);
  }

  double dt() const { return dt_; }
  std::size_t size() const { return n_; }
  double df() const { return 1.0 / (static_cast<double>(n_) * dt_); }
  const std::vector<double>& psd() const { return S_; }

  /// Exact variance of the generated process: the trapezoidal sum of S over [0, 1/(2 dt)].
  double variance() const {
    double v = 0.0;
    for (double s : sd_) v += s * s;
    return v;
  }

  /// One realization eta(j dt), j = 0 .. n-1. Draws A_k then B_k for k = 0 .. n/2 in order.
  std::vector<double> sample(RandomStream& rng) const {
    const std::size_t h = n_ / 2;
    std::vector<std::complex<double>> X(h + 1);
    for (std::size_t k = 0; k <= h; ++k) {
      const double A = sd_[k] * rng.normal();
      if (k == 0 || k == h) {
        X[k] = {A, 0.0};
      } else {
        const double B = sd_[k] * rng.normal();
        X[k] = {0.5 * A, -0.5 * B};  // 2 Re(X e^{i theta}) = A cos(theta) + B sin(theta)
      }
    }
    Eigen::FFT<double> fft;  // local: the FFT object caches plans and is not thread-safe
    fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);
    fft.SetFlag(Eigen::FFT<double>::Unscaled);
    std::vector<double> x;
    fft.inv(x, X, static_cast<Eigen::Index>(n_));
    return x;
  }

  /// A realization as a Signal starting at t = 0 (linear interpolation between samples).
  Signal signal(RandomStream& rng) const { return Signal::sampled(sample(rng), 0.0, dt_); }

 private:
  double dt_;
  std::size_t n_;
  std::vector<double> S_, sd_;
};

}  // namespace drill
