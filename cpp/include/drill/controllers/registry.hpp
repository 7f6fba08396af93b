// The speed controllers of a controlled top drive (controller.hpp), listed once
// (DRILL_CONTROLLERS below). Controller's Kind and its table of names (top_drive.controller.type),
// its validate(), tune() and torque_feedback(), and the variants of the configuration's
// "top_drive.controller" block and so its JSON Schema (config.hpp) are derived from the list. The
// controllers share Controller's fields and its loop (ControlLoop: a PI on the speed error, with the
// top torque's feedback where torque_feedback); each contributes its tuning.
//
//   stiff       controllers/stiff.hpp       high-gain PI
//   pi          controllers/pi.hpp          the user's gains
//   soft_speed  controllers/soft_speed.hpp  SoftSpeed: kp = Z, ki = J w_s^2
//   z_torque    controllers/z_torque.hpp    ZTorque: set point corrected by -(T_top - T_mean) / Z
//
// Adding a controller (controllers/stiff.hpp is an example to copy):
//  1. A header controllers/<name>.hpp with, in namespace drill::controllers, a struct <Ctl> with
//       torque_feedback              whether ControlLoop feeds the top torque back (z_torque)
//       keys<C>()                    the config keys of its variant of top_drive.controller, in schema
//                                    order (the shared ones from controllers/gain_keys.hpp)
//       validate(c)                  its checks of the configured fields (before Controller's own)
//       gains(c, J, w1, p, i)        its default gains p = kp, i = ki for the drive's inertia J and the
//                                    string's first natural frequency w1 (c.impedance resolved)
//       check_tuned(c)               its checks of the resolved values (after tuning)
//     where C is Controller. A new parameter is a member of Controller (with its check in
//     Controller::validate).
//  2. Its #include and one line X(<name>, <Ctl>) in the list below.
//  3. Its test (tests/cpp/test_controller.cpp, which also checks every controller of the list).
#pragma once

#include "drill/controllers/pi.hpp"
#include "drill/controllers/soft_speed.hpp"
#include "drill/controllers/stiff.hpp"
#include "drill/controllers/z_torque.hpp"

/// X(name, Ctl) for every controller, in the order of top_drive.controller.type's choices: its name
/// (and the enumerator Controller::Kind::name) and its struct in drill::controllers.
#define DRILL_CONTROLLERS(X) \
  X(stiff, Stiff)            \
  X(pi, Pi)                  \
  X(soft_speed, SoftSpeed)   \
  X(z_torque, ZTorque)       \
  /* end of the list */
