// Input validation helpers: every refusal names the field and the offending value.
#pragma once

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace drill {

/// Format a value for an error message (full precision for doubles).
template <class T>
std::string show(const T& value) {
  std::ostringstream os;
  os.precision(10);
  os << value;
  return os.str();
}

/// Throw std::invalid_argument("<field> = <value>: <why>") unless `ok`.
template <class T>
void require(bool ok, const std::string& field, const T& value, const std::string& why) {
  if (!ok) throw std::invalid_argument(field + " = " + show(value) + ": " + why);
}

/// A finite, strictly positive number.
inline void require_positive(double value, const std::string& field) {
  require(std::isfinite(value), field, value, "must be a finite number");
  require(value > 0.0, field, value, "must be positive");
}

/// A finite number (any sign).
inline void require_finite(double value, const std::string& field) {
  require(std::isfinite(value), field, value, "must be a finite number");
}

/// A finite, non-negative number.
inline void require_non_negative(double value, const std::string& field) {
  require(std::isfinite(value), field, value, "must be a finite number");
  require(value >= 0.0, field, value, "must not be negative");
}

}  // namespace drill
