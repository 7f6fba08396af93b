// A parameter set: one struct deriving once from each of several parameter structs. The laws
// (laws/registry.hpp) and the top drives (drives/registry.hpp) each list their parameter structs,
// and entries of a list may share one (Eqs. 5.1 and 5.3 share the polynomial's): the configured law
// and the configured top drive derive from the set of their list, each struct once.
#pragma once

#include <type_traits>

namespace drill {

/// A struct deriving from each of the parameter structs P.
template <class... P>
struct Parameters : P... {
  bool operator==(const Parameters& o) const {
    return (... && (static_cast<const P&>(*this) == static_cast<const P&>(o)));
  }
};

/// UniqueParameters<Parameters<>, P...>::type: Parameters of the structs P..., each once, in order.
template <class Acc, class... P>
struct UniqueParameters {
  using type = Acc;
};
template <class... Acc, class P, class... Rest>
struct UniqueParameters<Parameters<Acc...>, P, Rest...>
    : UniqueParameters<std::conditional_t<(... || std::is_same_v<P, Acc>), Parameters<Acc...>, Parameters<Acc..., P>>,
                       Rest...> {};

}  // namespace drill
