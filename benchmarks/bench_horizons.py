"""Speed of the short-horizon predictions of ``drillpy loop``: the engine's batch runner
(``_core.predict_horizons``: restart states, inputs, sensors, all horizons in parallel), its
horizons stepped one by one (``batched=False``, the scalar integrator) or in SIMD lockstep (the
default, issue 16), against the same horizons run one by one through ``Simulation.run`` from
Python (the baseline a loop without the batch runner would use), measured in the same run.

    PYTHONPATH=python python3 benchmarks/bench_horizons.py

Prints the time per evaluation of 80 horizons of 0.25 s of the thesis-rig model (engine step
0.1 ms, outputs at 1 kHz: one evaluation of the calibration half of sample 175), minima of 5; then
the same horizons turned by the rig's open-loop motor (section 5.3.2: droop, 8 N m limit) and loaded
by its jack, the loop's ``top_drive_dynamics`` and ``axial_jack`` candidates, scalar against batched
(both in SIMD lockstep since issue 33).
"""
from __future__ import annotations

import time

import numpy as np

import drillpy
from drillpy import _core
from drillpy.model.config import engine_config


def main() -> None:
    cfg = drillpy.load_config(preset="thesis-rig")
    sim = _core.Simulation(engine_config(cfg))
    n, L, dt = 80, 250, 1e-3
    ref = drillpy.simulate(drillpy.with_overrides(cfg, duration=25.0, transient=1.0))
    stride = int(round(dt / cfg["simulation"]["dt_s"]))
    idx = np.arange(n) * L + 2000
    k = idx * (stride // cfg["simulation"]["output_stride"])  # samples of the reference (every 1 ms)
    om = np.full(n, cfg["operation"]["top_speed_rad_s"])
    zero = np.zeros(n)
    v, a, T = ref.bit_speed[k], ref.bit_accel[k], ref.torque_on_bit[k]
    starts = _core.HorizonStart.from_arrays(
        index=idx.tolist(), bit_speed=v, bit_accel=a, torque=T, top_speed=om, top_accel=zero, y_bit_speed=v,
        dy_bit_speed=a, y_torque=T, dy_torque=zero, y_top_speed=om, dy_top_speed=zero)
    top = np.full(idx[-1] + L + 1, cfg["operation"]["top_speed_rad_s"])  # a sampled top speed, as the loop's

    def runner(threads: int, batched: bool) -> float:
        times = []
        for _ in range(5):
            t = time.perf_counter()
            _core.predict_horizons(sim, starts, dt, L, top_speed=top, threads=threads, batched=batched)
            times.append(time.perf_counter() - t)
        return min(times)

    scalar1, batched1, batched = runner(1, False), runner(1, True), runner(0, True)
    short = drillpy.with_overrides(cfg, duration=L * dt, transient=0.5 * L * dt)
    one = _core.Simulation(engine_config(short))
    loop = []
    for _ in range(2):
        t = time.perf_counter()
        for h in range(n):
            q, qd = _core.state_from_bit(sim, v[h], a[h], T[h], om[h], 0.0)
            one.run(q0=q, qdot0=qd, record=True)
        loop.append(time.perf_counter() - t)
    s = min(loop)
    steps = n * L * stride
    print(f"{n} horizons of {L * dt:g} s ({steps} engine steps):")
    print(f"  one Simulation.run per horizon      {1e3 * s:8.1f} ms")
    print(f"  runner, scalar, 1 thread            {1e3 * scalar1:8.1f} ms  {1e9 * scalar1 / steps:5.0f} ns per step")
    print(f"  runner, batched, 1 thread           {1e3 * batched1:8.1f} ms  {1e9 * batched1 / steps:5.0f} ns per step"
          f"  ({scalar1 / batched1:.2f} x scalar)")
    print(f"  runner, batched, {_core.max_threads()} threads           {1e3 * batched:8.1f} ms"
          f"  ({s / batched:.1f} x one run per horizon)")
    motor = {"type": "motor", "slope_nms_rad": 0.3, "inertia_kg_m2": 0.02, "max_torque_nm": 8.0}
    rig = drillpy.with_overrides(cfg, top_drive=motor)
    rig["axial"] = {"type": "jack", "gain_n_rad": 200.0, "relaxation_s": 0.1}
    sim = _core.Simulation(engine_config(rig))
    scalar1, batched1 = runner(1, False), runner(1, True)
    print("the same horizons with the rig's motor and jack (top speed and WOB states of the lanes):")
    print(f"  runner, scalar, 1 thread            {1e3 * scalar1:8.1f} ms  {1e9 * scalar1 / steps:5.0f} ns per step")
    print(f"  runner, batched, 1 thread           {1e3 * batched1:8.1f} ms  {1e9 * batched1 / steps:5.0f} ns per step"
          f"  ({scalar1 / batched1:.2f} x scalar)")


if __name__ == "__main__":
    main()
