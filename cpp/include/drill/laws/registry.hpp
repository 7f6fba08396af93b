// The bit-rock laws of the engine, listed once (DRILL_BIT_ROCK_LAWS below). Everything that names
// the laws is derived from the list: BitRockLaw's Kind and its table of names (law.type), its
// parameters, validate(), at_speed() and static_torque() (bitrock.hpp), the variants of the
// configuration's "law" block and so its JSON Schema (config.hpp), and the dispatch of the two SIMD
// kernels (batched_kernel-inl.hpp).
//
//   tucker_wang            Eq. (3.1)       laws/tucker_wang.hpp
//   hysteretic             Eqs. (3.2-3.3)  laws/hysteretic.hpp
//   polynomial             Eq. (5.1)       laws/polynomial.hpp
//   polynomial_hysteretic  Eq. (5.3)       laws/polynomial.hpp
//
// Adding a law (laws/tucker_wang.hpp is the smallest example to copy):
//  1. A header laws/<name>.hpp. Under its include guard, in namespace drill::laws, a struct <Law> with
//       Params                 its parameters (members of BitRockLaw, so they must not clash with
//                              another law's), with operator==; or `using Params = ...` to share
//                              another law's (polynomial.hpp)
//       keys<L>()              the config keys of its variant of the "law" block, in schema order
//       validate(l)            the checks of its parameters ("law.<key>" in the messages)
//       at_speed(l, v, sg, r)  its formula at the bit speed v [speed_unit] (sg = sign(v)): r.base,
//                              r.frac, their derivatives and r.c of laws/at_speed.hpp (BitRockLaw
//                              applies the WOB and the unit)
//       static_torque(l, wob)  its break-away torque at rest [N m] (0: regularized, no stick)
//     where L is BitRockLaw. After the guard, under `#ifdef DRILL_LAW_LANES`, the same formula on
//     Highway vectors, between HWY_BEFORE_NAMESPACE() and HWY_AFTER_NAMESPACE(), in namespace
//     drill::HWY_NAMESPACE::batched_detail (whose D, V, M, TanhSat, Sign... it uses), as overloads
//     on the law's type:
//       LawAtSpeed(<Law>, d, law, v, sg, base, frac, c)   the modified Euler kernel: no FMA and the
//                                                         scalar expression order (bit-identical)
//       LawAtSpeedDv(<Law>, ..., dbase, dfrac)            the exact modal kernel, with FMA
//  2. Its #include and one line X(<name>, <Law>) in the list below.
//  3. Its test (tests/cpp/test_bitrock.cpp; test_law_registry.cpp checks every law of the list).
//
// The includes below have no guard: batched_kernel-inl.hpp, compiled once per Highway target
// (foreach_target.h re-includes it), includes this file each time with DRILL_LAW_LANES defined, so
// that each law's lanes part is compiled in every target's namespace (its scalar part, once).
#include "drill/laws/tucker_wang.hpp"
#include "drill/laws/hysteretic.hpp"
#include "drill/laws/polynomial.hpp"

#ifndef DRILL_LAWS_REGISTRY_HPP_
#define DRILL_LAWS_REGISTRY_HPP_

/// X(name, Law) for every law, in the order of law.type's choices: the law's name (law.type and the
/// enumerator BitRockLaw::Kind::name) and its struct in drill::laws.
#define DRILL_BIT_ROCK_LAWS(X)                   \
  X(tucker_wang, TuckerWang)                     \
  X(hysteretic, Hysteretic)                      \
  X(polynomial, Polynomial)                      \
  X(polynomial_hysteretic, PolynomialHysteretic) \
  /* end of the list */

#endif  // DRILL_LAWS_REGISTRY_HPP_
