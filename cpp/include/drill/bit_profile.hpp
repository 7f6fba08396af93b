// The rock surface under a drag bit's blades: the history buffer of the Richard-Germay-Detournay
// depth of cut with its state-dependent delay (rgd_bit.hpp).
//
// RGD (J. Sound Vib. 2007) define the depth of cut per revolution d(t) = N [U(t) - U(t - t_N)] with
// the delay t_N solved from Phi(t) - Phi(t - t_N) = 2 pi / N: each blade cuts the rock the blade
// ahead of it left one sector (2 pi / N) earlier in angle. This buffer holds that surface as a
// function of the bit angle: samples (t, Phi, S) at every step at which the bit turns past the
// farthest angle reached so far (a stuck or back-turning bit adds none), S the height of the rock it
// leaves at that angle. While the bit never leaves the rock S = U and d is the paper's; when it has
// bounced off (U above the surface cut by the blade ahead) the rock there keeps the older surface,
// S(Phi) = max(U, S(Phi - 2 pi / N)) (U down positive), so a bounce leaves the rock uncut instead of
// letting the next blade cut the air.
//
// Lookup: the angle Phi - 2 pi / N is found by bisection over the samples (the angles increase) and the
// surface and the time there are interpolated linearly in the angle between the two samples around
// it. The samples are the integrator's steps, so the interpolated history is exact for a bit whose
// angle and axial position vary linearly over each step (the first-order scheme's own assumption);
// for smooth motion the error of S is at most (dt Omega)^2 max|d^2 U / dPhi^2| / 8 per lookup and of
// t_N is O(dt^2) (tests/cpp/test_bit_profile.cpp: t_N = 2 pi / (N Omega) to 1e-12 relative at
// constant speed, and the second-order convergence on a non-uniform rotation). The buffer keeps two
// sectors of samples (older ones are dropped; memory is bounded by the steps of two sectors).
// A step looks up one angle: record() finds the surface one sector behind the angle it is given,
// which is the next step's Phi - 2 pi / N, and keeps that lookup for at() (the same numbers, one
// lookup a step instead of three), and the lookup starts from the last one's samples, about one
// sample back (a bisection over the two sectors only when the bit has moved far: issue 34).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include "drill/errors.hpp"

namespace drill {

class BitProfile {
 public:
  BitProfile() = default;
  /// The surface of steady drilling before t0: the bit at angle phi0 and axial position u0 [m],
  /// having turned at omega0 [rad/s] with a depth of cut per revolution d0 [m] over the last sector.
  BitProfile(int blades, double t0, double phi0, double u0, double d0, double omega0) : blades_(blades) {
    require(blades >= 1, "axial.bit.blades", blades, "must be at least 1");
    require_positive(omega0, "bit speed of the initial surface [rad/s]");
    sector_ = 2.0 * M_PI / blades;
    const int n = 8;  // samples of the initial sector (linear: two would do; more exercise the bisection)
    for (int k = -n; k <= 0; ++k) {
      const double f = static_cast<double>(k) / n;
      push(t0 + f * sector_ / omega0, phi0 + f * sector_, u0 + f * d0 / blades);
    }
  }

  double sector() const { return sector_; }
  int blades() const { return blades_; }
  /// The farthest angle the bit has reached [rad].
  double reach() const { return phi_.back(); }

  /// The rock surface and the time at angle phi (linear interpolation between samples; the first
  /// sample's values before it, the last one's after it).
  struct At {
    double t, surface;
  };
  At at(double phi) const { return phi == last_phi_ ? last_ : interpolate(phi); }
  /// at() without the kept lookup of record() (the same numbers).
  At interpolate(double phi) const {
    std::size_t k = hint_;
    return interpolate(phi, k);
  }

  /// The depth of cut per revolution d = N [U - S(Phi - 2 pi / N)] [m] of a bit at angle phi and
  /// axial position u (negative: the bit is above the rock, lift-off).
  double depth_of_cut(double phi, double u) const { return blades_ * (u - at(phi - sector_).surface); }
  /// The delay t_N: t - t_N is when the bit was last at phi - 2 pi / N [s].
  double delay(double t, double phi) const { return t - at(phi - sector_).t; }
  /// depth_of_cut(phi, u) and delay(t, phi) from one lookup.
  struct Cut {
    double depth, delay;
  };
  Cut cut(double t, double phi, double u) const {
    const At a = at(phi - sector_);
    return {blades_ * (u - a.surface), t - a.t};
  }

  /// Record the bit at time t, angle phi and axial position u (after a step): a sample when it
  /// turned past its reach, the surface it leaves there max(u, S(phi - 2 pi / N)).
  void record(double t, double phi, double u) {
    // the lookup one sector back, kept for at(): a sample pushed ahead of it leaves its two
    // neighbours (and the dropped samples lie more than a sector behind it), unless the lookup
    // read the last sample (phi - 2 pi / N at or beyond the reach: push() forgets it then)
    last_phi_ = phi - sector_;
    last_ = interpolate(last_phi_, hint_);
    if (!(phi > phi_.back())) return;
    const double s = std::max(u, last_.surface);
    push(t, phi, s);
    // drop what lies more than two sectors behind (keeping one sample before that angle)
    const double keep = phi - 2.0 * sector_;
    while (head_ + 2 < phi_.size() && phi_[head_ + 1] < keep) ++head_;
    if (head_ > 4096 && head_ * 2 > phi_.size()) compact();
  }

  std::size_t size() const { return phi_.size() - head_; }

 private:
  /// interpolate(phi), k on entry a guess of the first sample above phi and on return that sample
  /// (when phi lies inside the samples).
  At interpolate(double phi, std::size_t& k) const {
    const std::size_t n = phi_.size();
    if (phi <= phi_[head_]) return {t_[head_], s_[head_]};
    if (phi >= phi_[n - 1]) return {t_[n - 1], s_[n - 1]};
    // the first sample above phi, in (head_, n - 1] (the angles increase, so it is the k with
    // phi_[k - 1] <= phi < phi_[k]): within a few samples of the guess, the last lookup's (a step
    // moves the lookup by the step's turn, about one sample of the history a sector back unless the
    // bit turns much faster than it did then), else by bisection
    k = std::min(std::max(k, head_ + 1), n - 1);
    for (int walk = 0;; ++walk) {
      if (walk == 4) {
        const auto it = std::upper_bound(phi_.begin() + static_cast<std::ptrdiff_t>(head_), phi_.end(), phi);
        k = static_cast<std::size_t>(it - phi_.begin());
        break;
      }
      if (phi_[k] <= phi) ++k;           // k < n - 1 here, as phi < phi_[n - 1]
      else if (phi_[k - 1] > phi) --k;   // k - 1 > head_ here, as phi_[head_] < phi
      else break;
    }
    const double w = (phi - phi_[k - 1]) / (phi_[k] - phi_[k - 1]);
    return {t_[k - 1] + w * (t_[k] - t_[k - 1]), s_[k - 1] + w * (s_[k] - s_[k - 1])};
  }

  void push(double t, double phi, double s) {
    if (!phi_.empty() && !(last_phi_ < phi_.back())) last_phi_ = NAN;  // at() interpolates anew
    t_.push_back(t);
    phi_.push_back(phi);
    s_.push_back(s);
  }
  void compact() {
    const auto h = static_cast<std::ptrdiff_t>(head_);
    t_.erase(t_.begin(), t_.begin() + h);
    phi_.erase(phi_.begin(), phi_.begin() + h);
    s_.erase(s_.begin(), s_.begin() + h);
    hint_ = hint_ > head_ ? hint_ - head_ : 0;
    head_ = 0;
  }

  int blades_ = 1;
  double sector_ = 2.0 * M_PI;
  std::size_t head_ = 0;
  std::size_t hint_ = 0;  ///< the sample above record()'s last lookup (interpolate's first guess)
  std::vector<double> t_, phi_, s_;
  double last_phi_ = NAN;  ///< the angle of record()'s lookup (NaN: none kept)
  At last_{};              ///< at(last_phi_)
};

}  // namespace drill
