// Test helper: the test rig (Table 5.1, one mode) with a static torque (Eq. 5.1 with a0 > 0: the
// stick condition) and string friction, 4 s long (shared by the batched-integrator tests).
#pragma once

#include "drill/presets.hpp"

inline drill::Config rig_with_stick(drill::BitRockLaw::Kind kind) {
  drill::Config c = drill::preset("thesis-rig");
  c.law.kind = kind;
  c.law.a[0] = 1.0;
  c.string_friction = 0.3;
  c.sim.duration = 4.0;
  c.transient = 1.0;
  return c;
}
