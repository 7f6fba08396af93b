// The names of an enum's values in the configuration, listed once per enum: a list of
// {value, "name"} pairs from which the name of a value, the value of a name (with the error that
// lists the accepted names) and the JSON Schema's choices (config.hpp) are all taken.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace drill {

template <class E>
struct Named {
  E value;
  const char* name;
};

/// The names, in the list's order.
template <class E, std::size_t N>
std::vector<std::string> names_of(const Named<E> (&list)[N]) {
  std::vector<std::string> out;
  for (const Named<E>& n : list) out.push_back(n.name);
  return out;
}

/// The name of a value.
template <class E, std::size_t N>
std::string name_of(const Named<E> (&list)[N], E value) {
  for (const Named<E>& n : list)
    if (n.value == value) return n.name;
  throw std::logic_error("a value without a name");
}

/// The value of a name; otherwise std::invalid_argument("<field> = \"<s>\": unknown <what> (use a, b or c)").
template <class E, std::size_t N>
E parse_name(const Named<E> (&list)[N], const std::string& s, const std::string& field, const std::string& what) {
  std::string use;
  for (std::size_t k = 0; k < N; ++k) {
    if (s == list[k].name) return list[k].value;
    use += (k == 0 ? "" : k + 1 == N ? " or " : ", ") + std::string(list[k].name);
  }
  throw std::invalid_argument(field + " = \"" + s + "\": unknown " + what + " (use " + use + ")");
}

}  // namespace drill
