// Shared glue for the bindings: progress callbacks that check for Ctrl-C, error translation.
#pragma once

#include <pybind11/pybind11.h>

#include "drill/parallel.hpp"

namespace drillpy_glue {

namespace py = pybind11;

/// A ProgressFn for long engine calls made with the GIL released: it takes the GIL, raises
/// KeyboardInterrupt on Ctrl-C and forwards (done, total) to an optional Python callable.
inline drill::ProgressFn progress_callback(const py::object& callback) {
  return [callback](std::size_t done, std::size_t total) {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (!callback.is_none()) callback(done, total);
    return true;
  };
}

}  // namespace drillpy_glue
