"""Top-drive control under uncertainty (issue 15; the thesis's future work 5, chapter 7).

* :mod:`drillpy.control.tuning` -- robust tuning: the gains of a controller that minimise the
  probability of stick-slip over an operating window (top speeds x WOBs) under the chapter-4
  stochastic bit-rock law, with common random numbers and the Monte Carlo error of the optimum.
* :mod:`drillpy.control.episode` -- one run with and without a controller: the motor torque the
  drive demands, against its limit.
* :mod:`drillpy.control.study` -- ``drillpy control``'s study: tuning, the drives compared on new
  samples, the episodes (:class:`~drillpy.control.study.ControlStudy`).

The controllers themselves are in the engine (``cpp/include/drill/controller.hpp``; docs/control.md).
"""
