// Measurement chain of a recorded channel: a second-order Butterworth low-pass.
//
// The test rig's acquisition applies "a second order filter of Infinite Impulse Response (IIR) ...
// with lowpass band set to 10 Hz for the whole sensors ... including the encoders" (section 5.3.1).
// A model compared with such a record must see its own outputs through the same filter:
//
//   y'' + 2 zeta omega_c y' + omega_c^2 y = omega_c^2 x,     zeta = 1 / sqrt(2),  omega_c = 2 pi f_c
//
// (unit gain at DC, -3 dB and -90 degrees at f_c, group delay 2 zeta / omega_c at low frequency).
// The state (y, y') is what a record shows: the filtered value and its rate, so a filter can be
// started from a measured channel. It is advanced by the trapezoidal rule (A-stable, second order)
// with the input interpolated linearly over the step.
#pragma once

#include <Eigen/Dense>
#include <cmath>

#include "drill/errors.hpp"

namespace drill {

class LowPass2 {
 public:
  /// Filter of cutoff fc [Hz] stepped every dt [s]; fc = 0 means no filter (y = x).
  LowPass2(double fc, double dt) : fc_(fc) {
    require_non_negative(fc, "sensors.lowpass_hz");
    require_positive(dt, "sensor time step [s]");
    if (fc == 0.0) return;
    const double wc = 2.0 * M_PI * fc;
    Eigen::Matrix2d A;
    A << 0.0, 1.0, -wc * wc, -std::sqrt(2.0) * wc;
    B_ << 0.0, wc * wc;
    const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
    const Eigen::Matrix2d L = (I - 0.5 * dt * A).inverse();
    Phi_ = L * (I + 0.5 * dt * A);
    G_ = L * (0.5 * dt * B_);
  }

  bool active() const { return fc_ > 0.0; }
  double cutoff_hz() const { return fc_; }

  /// Start from a filtered value y, its rate dy [unit/s] and the current input x.
  void reset(double y, double dy, double x) {
    s_ << y, dy;
    x_ = x;
    if (!active()) s_ << x, 0.0;
  }

  /// Advance one step to the input x_next; returns the filtered value.
  double step(double x_next) {
    if (!active()) {
      s_ << x_next, 0.0;
    } else {
      s_ = Phi_ * s_ + G_ * (x_ + x_next);
    }
    x_ = x_next;
    return s_(0);
  }

  double value() const { return s_(0); }
  double rate() const { return s_(1); }

 private:
  double fc_ = 0.0;
  Eigen::Matrix2d Phi_ = Eigen::Matrix2d::Identity();
  Eigen::Vector2d B_ = Eigen::Vector2d::Zero(), G_ = Eigen::Vector2d::Zero(), s_ = Eigen::Vector2d::Zero();
  double x_ = 0.0;
};

}  // namespace drill
