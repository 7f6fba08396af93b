// Counter-based random streams (Random123 Philox4x32-10) keyed by (seed, sample, stream).
//
// A Monte Carlo sample i draws only from RandomStream(seed, i, stream): its numbers depend on
// nothing else (not the thread, not the order of samples, not how the range is split into chunks),
// so results are bit-identical for any thread count. The uniform, normal and gamma transforms are
// written here (std:: distributions differ between standard libraries).
#pragma once

#include <Random123/philox.h>

#include <cmath>
#include <cstdint>

#include "drill/errors.hpp"

namespace drill {

class RandomStream {
 public:
  RandomStream(std::uint64_t seed, std::uint64_t sample, std::uint32_t stream = 0) {
    key_ = {{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)}};
    ctr_ = {{static_cast<std::uint32_t>(sample), static_cast<std::uint32_t>(sample >> 32), stream, 0u}};
  }

  /// Next raw 32-bit word.
  std::uint32_t next_u32() {
    if (pos_ == 4) {
      out_ = gen_(ctr_, key_);
      ++ctr_[3];  // block counter; 2^32 blocks = 2^34 words per stream
      pos_ = 0;
    }
    return out_[pos_++];
  }

  /// Uniform on the open interval (0, 1) with 53 random bits.
  double uniform() {
    const std::uint64_t hi = next_u32(), lo = next_u32();
    const std::uint64_t x = ((hi << 32) | lo) >> 11;  // 53 bits
    return (static_cast<double>(x) + 0.5) * 0x1.0p-53;
  }

  /// Standard normal by the Box-Muller transform (the second value is kept for the next call).
  double normal() {
    if (have_spare_) {
      have_spare_ = false;
      return spare_;
    }
    const double r = std::sqrt(-2.0 * std::log(uniform()));
    const double phi = 2.0 * M_PI * uniform();
    spare_ = r * std::sin(phi);
    have_spare_ = true;
    return r * std::cos(phi);
  }

  /// Gamma(shape, scale 1) by Marsaglia and Tsang (2000); shape < 1 by the boost
  /// Gamma(a) = Gamma(a + 1) U^(1/a).
  double gamma(double shape) {
    require(std::isfinite(shape) && shape > 0.0, "gamma shape", shape, "must be positive");
    if (shape < 1.0) return gamma(shape + 1.0) * std::pow(uniform(), 1.0 / shape);
    const double d = shape - 1.0 / 3.0, c = 1.0 / std::sqrt(9.0 * d);
    for (;;) {
      double x, v;
      do {
        x = normal();
        v = 1.0 + c * x;
      } while (v <= 0.0);
      v = v * v * v;
      const double u = uniform();
      if (u < 1.0 - 0.0331 * x * x * x * x) return d * v;
      if (std::log(u) < 0.5 * x * x + d * (1.0 - v + std::log(v))) return d * v;
    }
  }

 private:
  r123::Philox4x32 gen_;
  r123::Philox4x32::key_type key_{};
  r123::Philox4x32::ctr_type ctr_{};
  r123::Philox4x32::ctr_type out_{};
  int pos_ = 4;
  bool have_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace drill
