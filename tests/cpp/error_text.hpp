// Test helper: the message of the std::invalid_argument thrown by f(), or "no error".
#pragma once

#include <stdexcept>
#include <string>

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}
