"""Plain NumPy version of the engine's reduced-order time loop (modified Euler, appendix A).

Used as the baseline of benchmarks/bench_engine.py and as a test oracle
(tests/python/test_simulation.py). It takes the reduced matrices from the engine
(Eqs. 2.8-2.10), brings them to M = I, K = diag(omega^2) like the engine, and steps
Eqs. (A.5)-(A.6) with the hysteretic law (3.2)-(3.3) and the bit acceleration of (A.1)
evaluated in Python.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.linalg

import drillpy
from drillpy.model.config import engine_config


def hysteretic_parts(law: dict, v: float, wob: float):
    """Eqs. (3.2)-(3.3) at SI bit speed v as T(a) = base + frac (1 + c tanh(k a))."""
    s = 30.0 / math.pi if law["speed_unit"] == "rpm" else 1.0
    vu = v * s
    sg = (vu > 0) - (vu < 0)
    w = wob / law["wob_ref_n"] * law["b0"]
    av = abs(vu)
    frac = law["b2"] * av ** law["b4"] * sg / (1.0 + law["b3"] * av ** law["b5"])
    return w * math.tanh(law["b1"] * vu), w * frac, law["beta1"] * sg, law["beta2"] * s


def bit_acceleration(alpha: float, g: float, base: float, frac: float, c: float, k: float) -> float:
    """Root of a + g (base + frac (1 + c tanh(k a))) = alpha (Eq. A.1 with the torque of Eq. 3.3)."""
    up = alpha - g * (base + frac * (1 + c))
    dn = alpha - g * (base + frac * (1 - c))
    if frac * c == 0.0:
        return alpha - g * (base + frac)
    if k * up > 19.0:
        return up
    if k * dn < -19.0:
        return dn
    lo, hi = min(up, dn), max(up, dn)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid + g * (base + frac * (1 + c * math.tanh(k * mid))) - alpha > 0:
            hi = mid
        else:
            lo = mid
        if hi - lo < 1e-13 * (1 + abs(alpha)):
            break
    return 0.5 * (lo + hi)


def run_modified_euler(cfg: dict, top_speed: float, duration: float | None = None):
    """Bit speed at every step of a constant-top-speed run from Eq. (2.10)."""
    if cfg["law"]["type"] != "hysteretic":
        raise ValueError("the NumPy reference implements the hysteretic law only")
    sim = drillpy._core.Simulation(engine_config(cfg))
    r = sim.reduced_matrices()
    w2, V = scipy.linalg.eigh(r["K"], r["M"])
    d = np.diag(V.T @ r["D"] @ V).copy()
    bit = r["bit"] @ V
    Vinv = V.T @ r["M"]
    p = Vinv @ (-top_speed * r["init_velocity"])
    z = np.zeros_like(p)
    dt = cfg["simulation"]["dt_s"]
    n = int(round((duration or cfg["simulation"]["duration_s"]) / dt))
    law, wob = cfg["law"], cfg["operation"]["wob_n"]
    out = np.empty(n + 1)
    g = float(bit @ bit)
    for i in range(n + 1):
        v = top_speed + float(bit @ p)
        out[i] = v
        if i == n:
            break
        f = -d * p - w2 * z
        base, frac, c, k = hysteretic_parts(law, v, wob)
        a = bit_acceleration(float(bit @ f), g, base, frac, c, k)
        T = base + frac * (1 + c * math.tanh(k * a))
        p = p + dt * (f - bit * T)   # Eq. (A.5)
        z = z + dt * p               # Eq. (A.6)
    return out
