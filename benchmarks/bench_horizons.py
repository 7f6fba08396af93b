"""Speed of the short-horizon predictions of ``drillpy loop``: the engine's batch runner
(``_core.predict_horizons``: restart states, inputs, sensors, all horizons in parallel) against the
same horizons run one by one through ``Simulation.run`` from Python (the baseline a loop without
the batch runner would use), measured in the same run.

    PYTHONPATH=python python3 benchmarks/bench_horizons.py

Prints the time per evaluation of 80 horizons of 0.25 s of the thesis-rig model (engine step
0.1 ms, outputs at 1 kHz: one evaluation of the calibration half of sample 175) and the ratios
(on one thread the runner costs what the engine's steps cost; its gain is the threads and the
restart states, sensors and inputs handled without Python).
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
    state = np.column_stack([ref.bit_speed[k], ref.bit_accel[k], ref.torque_on_bit[k],
                             np.full(n, cfg["operation"]["top_speed_rad_s"]), np.zeros(n)])
    sensor = np.column_stack([state[:, 0], state[:, 1], state[:, 2], np.zeros(n), state[:, 3], np.zeros(n)])
    batch = {}
    for threads in (1, 0):
        batch[threads] = []
        for _ in range(5):
            t = time.perf_counter()
            _core.predict_horizons(sim, idx.tolist(), state, sensor, dt, L, threads=threads)
            batch[threads].append(time.perf_counter() - t)
    short = drillpy.with_overrides(cfg, duration=L * dt, transient=0.5 * L * dt)
    one = _core.Simulation(engine_config(short))
    loop = []
    for _ in range(2):
        t = time.perf_counter()
        for h in range(n):
            q, qd = _core.state_from_bit(sim, *state[h])
            one.run(q0=q, qdot0=qd, record=True)
        loop.append(time.perf_counter() - t)
    b1, b, s = min(batch[1]), min(batch[0]), min(loop)
    print(f"{n} horizons of {L * dt:g} s ({n * L * stride} engine steps): one Simulation.run per horizon "
          f"{1e3 * s:.1f} ms; batch runner {1e3 * b1:.1f} ms on 1 thread (ratio {s / b1:.2f}), {1e3 * b:.1f} ms on "
          f"{_core.max_threads()} OpenMP threads (ratio {s / b:.2f}); {1e9 * b1 / (n * L * stride):.0f} ns per step")


if __name__ == "__main__":
    main()
