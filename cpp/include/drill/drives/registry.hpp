// The top drives of the engine, how the top of the string is turned, listed once (DRILL_TOP_DRIVES
// below). TopDrive's Kind and its table of names (top_drive.type), its parameters, validate(),
// steady_speed() and the other hooks (topdrive.hpp), the variants of the configuration's
// "top_drive" block and so its JSON Schema (config.hpp), and the per-step update of the top speed
// in Integrator::run_euler (one instantiation per drive) are derived from the list.
//
//   ideal       drives/ideal.hpp       the thesis: the top turns at the command (Eqs. 2.1-2.6)
//   motor       drives/motor.hpp       the rig's open-loop motor: J_m Omega' = min(c_m (Omega_c - Omega), T_max) - T_top
//                                      (thesis sections 5.3.2, 5.1)
//   controlled  drives/controlled.hpp  J Omega' = u - T_top, u from a speed controller (controller.hpp)
//
// Adding a top drive (drives/motor.hpp is an example to copy):
//  1. A header drives/<name>.hpp with, in namespace drill::drives, a struct <Drive> with
//       Params                        its parameters (members of TopDrive, so they must not clash
//                                     with another drive's; `using Params = ...` shares another's);
//                                     the top's inertia J is TopDrive::inertia, shared
//       has_inertia                   whether the top is a free inertia (its speed a state of the
//                                     simulation, under the stability bound Integrator::stability_bound(td),
//                                     modified Euler only); false: it turns at the command signal
//       has_controller                whether it is driven by top_drive.controller (a Controller:
//                                     read, written, tuned from the string and checked with it)
//       accel_from_torque             whether top_accel(d, command, omega, dt, t0, dT) gives the top's
//                                     acceleration from the string's top torque t0 + dT domega
//                                     (Integrator::state_from_bit of a measured state)
//       keys<D>()                     the config keys of its variant of "top_drive", in schema order
//       validate(d)                   the checks of its parameters ("top_drive.<key>" in the messages)
//       steady_speed(d, command, T)   its speed under a steady torque T at the command
//       droops(d)                     whether that speed differs from the command (Simulation::
//                                     steady_speed then solves for it)
//       Run<D>                        its top speed in Integrator::run_euler, one step at a time:
//                                     speed(t, om_state), next(t, om, T_top), accel(t, om, om_next),
//                                     torque() (reported, NaN: none) and finish(state); built as
//                                     Run<D>(d, command signal, dt, start state, top_torque0)
//     where D is TopDrive.
//  2. Its #include and one line X(<name>, <Drive>) in the list below.
//  3. Its test (tests/cpp/test_topdrive.cpp; test_drive_registry.cpp checks every drive of the list).
#pragma once

#include "drill/drives/controlled.hpp"
#include "drill/drives/ideal.hpp"
#include "drill/drives/motor.hpp"

/// X(name, Drive) for every top drive, in the order of top_drive.type's choices: its name (and the
/// enumerator TopDrive::Kind::name) and its struct in drill::drives. The first is the default.
#define DRILL_TOP_DRIVES(X)   \
  X(ideal, Ideal)             \
  X(motor, Motor)             \
  X(controlled, Controlled)   \
  /* end of the list */
