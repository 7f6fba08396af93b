// The hysteresis of the bit-rock laws, Eq. (3.3): H = beta1 tanh(beta2 a) sign(v), the factor
// (1 + H) of the fraction term of Eqs. (3.2) and (5.3). Every law carries beta1 and beta2 (zero:
// no hysteresis; the form of laws/at_speed.hpp takes k = beta2 s for every law); the hysteretic
// laws read them from their config keys (keys()).
#pragma once

#include <vector>

#include "drill/config_keys.hpp"
#include "drill/errors.hpp"

namespace drill::laws {

struct Hysteresis {
  double beta1 = 0.0, beta2 = 0.0;

  bool operator==(const Hysteresis& o) const { return beta1 == o.beta1 && beta2 == o.beta2; }

  /// beta1 in [0, 1) keeps 1 + H > 0.
  void validate() const {
    require_finite(beta1, "law.beta1");
    require(beta1 >= 0.0 && beta1 < 1.0, "law.beta1", beta1, "must lie in [0, 1) so that 1 + H > 0");
    require_non_negative(beta2, "law.beta2");
  }

  /// The config keys of a hysteretic law's variant (laws/registry.hpp): beta1, beta2.
  template <class L>
  static std::vector<Key<L>> keys() {
    return {{schema::number("beta1", "Eq. (3.3): H = beta1 tanh(beta2 a) sign(v), in [0, 1)").at_least(0.0).below(1.0).req(),
             &L::beta1},
            {schema::number("beta2", "Eq. (3.3) [1 / (speed_unit/s)]").non_negative().req(), &L::beta2}};
  }
};

}  // namespace drill::laws
