// Shared glue for the bindings: array conversions, JSON to Python, progress callbacks that check
// for Ctrl-C.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "drill/config.hpp"
#include "drill/parallel.hpp"

namespace drillpy_glue {

namespace py = pybind11;

/// A float64 array argument (C order; other dtypes and layouts are converted).
using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A new 1-D float64 array holding a copy of v.
inline py::array_t<double> as_array(const std::vector<double>& v) { return py::array_t<double>(v.size(), v.data()); }

/// The values of an array argument, flattened.
inline std::vector<double> to_vector(const Array& a) { return std::vector<double>(a.data(), a.data() + a.size()); }

/// A JSON value as Python objects (dict in the JSON's key order, list, int, float, str, bool, None).
template <class Json>
py::object to_python(const Json& j) {
  switch (j.type()) {
    case Json::value_t::object: {
      py::dict d;
      for (auto it = j.begin(); it != j.end(); ++it) d[py::str(it.key())] = to_python(it.value());
      return std::move(d);
    }
    case Json::value_t::array: {
      py::list l;
      for (const auto& x : j) l.append(to_python(x));
      return std::move(l);
    }
    case Json::value_t::string: return py::str(j.template get<std::string>());
    case Json::value_t::boolean: return py::bool_(j.template get<bool>());
    case Json::value_t::number_integer: return py::int_(j.template get<std::int64_t>());
    case Json::value_t::number_unsigned: return py::int_(j.template get<std::uint64_t>());
    case Json::value_t::number_float: return py::float_(j.template get<double>());
    default: return py::none();
  }
}

/// A JSON object as a Python dict (in the JSON's key order).
template <class Json>
py::dict to_python_dict(const Json& j) {
  return py::reinterpret_borrow<py::dict>(to_python(j));
}

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
