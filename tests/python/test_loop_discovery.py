"""drillpy.loop.discovery: sparse regression of a residual on a library of candidate terms.

The channels come from a one-DOF stick-slip oscillator of the rig's size (first mode 2.89 Hz, mean
bit speed 8 rad/s, torque on bit 2-4 N m) integrated in a few lines of NumPy; the residuals are
known combinations of library terms plus coloured (AR(1), tau ~ 100 samples) noise.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

from drillpy.loop.discovery import Term, discover, library, residual_structure

DT = 0.002  # [s], 500 Hz


def _simulate(duration: float = 20.0, dt: float = DT, sub: int = 10):
    """J v' = k twist + c (top - v) - T(v) W/W0, T(v) a regularized Stribeck law (stick-slip)."""
    J = 0.05                                  # [kg m^2]
    k = J * (2 * np.pi * 2.89) ** 2           # [N m/rad], first mode 2.89 Hz
    c = 0.01                                  # [N m s/rad]
    Tc, Ts, vs, ve = 2.0, 4.0, 5.0, 0.05      # [N m], [N m], [rad/s], [rad/s]
    n = int(round(duration / dt))
    t = np.arange(n) * dt
    top = 8.0 + 0.4 * np.sin(2 * np.pi * 0.21 * t)           # [rad/s]
    W = 1000.0 + 60.0 * np.sin(2 * np.pi * 0.37 * t + 1.0)   # [N]
    h = dt / sub
    th_t = th_b = v = 0.0
    V, TW, TQ = np.empty(n), np.empty(n), np.empty(n)
    for i in range(n):
        for _ in range(sub):
            Tb = (Tc + (Ts - Tc) * np.exp(-abs(v) / vs)) * np.tanh(v / ve) * W[i] / 1000.0
            v += h * (k * (th_t - th_b) + c * (top[i] - v) - Tb) / J
            th_b += h * v
            th_t += h * top[i]
        V[i], TW[i], TQ[i] = v, th_t - th_b, Tb
    return t, top, W, V, TW, TQ


def _ar1(seed: int, sd: float, n: int, phi: float = 0.98) -> np.ndarray:
    """Coloured noise: first-order autoregressive filter of white noise, scaled to std ``sd``."""
    x = lfilter([1.0], [1.0, -phi], np.random.default_rng(seed).standard_normal(n))
    return sd * x / x.std()


@pytest.fixture(scope="module")
def rig():
    t, top, W, V, TW, TQ = _simulate()
    rng = np.random.default_rng(1)
    v = V + 0.01 * rng.standard_normal(V.size)              # encoder noise
    channels = {"v": v, "a": np.gradient(v, DT), "T": TQ + 0.02 * rng.standard_normal(V.size),
                "twist": TW + 0.7,                          # known up to a constant
                "top": top, "dtop": np.gradient(top, DT), "W": W + 5.0 * rng.standard_normal(V.size)}
    return {"t": t, "channels": channels, "lib": library(channels, dt=DT)}


def test_simulated_rig_is_stick_slip(rig):
    v = rig["channels"]["v"]
    assert 7.0 < v.mean() < 9.0 and v.min() < 0.3 and np.mean(v < 0.3) > 0.05
    assert {"constant", "twist", "top_minus_v", "v", "sign_v", "v_abs_v", "a", "T", "T_sign_a",
            "W", "T_W", "dtop", "sin_theta", "cos_theta"} == set(rig["lib"])
    assert all(isinstance(t, Term) and t.unit and t.reading for t in rig["lib"].values())


def test_library_skips_missing_and_constant_terms(rig):
    ch = dict(rig["channels"])
    del ch["W"]
    ch["top"] = np.full(ch["v"].size, 8.0)
    ch["dtop"] = np.zeros(ch["v"].size)
    lib = library(ch)                                       # no dt: no bit angle
    assert "W" not in lib and "T_W" not in lib and "dtop" not in lib and "sin_theta" not in lib
    assert "constant" in lib.skipped["dtop"]
    assert "not given" in lib.skipped["W"] and "dt" in lib.skipped["sin_theta"]


def test_twist_term_alone(rig):
    """(a) residual = 0.3 N m/rad * twist + coloured noise: only twist, 0.3 inside its interval."""
    lib = rig["lib"]
    r = 0.3 * lib["twist"].values + _ar1(100, 0.05, lib["twist"].values.size)
    res = discover(r, lib, dt=DT)
    assert [t["name"] for t in res["terms"]] == ["twist"]
    tw = res["terms"][0]
    lo, hi = tw["ci95"]
    assert lo <= 0.3 <= hi and hi - lo < 0.05
    assert tw["unit"] == "N m/rad" and tw["selection_frequency"] >= 0.8
    assert res["explained_fraction"] > 0.6
    assert res["unexplained_fraction"] == pytest.approx(1 - res["explained_fraction"])
    assert 1 < res["n_eff"] < res["n"] / 20                  # strongly autocorrelated samples
    assert discover(r, lib, dt=DT) == res                    # deterministic for a given seed


def test_coulomb_and_viscous_terms(rig):
    """(b) residual = 0.2 N m sign(v) + 0.05 N m s/rad v + noise: finds both (and the offset)."""
    lib = rig["lib"]
    r = 0.2 * lib["sign_v"].values + 0.05 * lib["v"].values + _ar1(3, 0.05, lib["v"].values.size)
    res = discover(r, lib, dt=DT)
    found = {t["name"]: t for t in res["terms"]}
    assert {"sign_v", "v"} <= set(found) <= {"sign_v", "v", "constant"}
    for name, true in (("sign_v", 0.2), ("v", 0.05)):
        lo, hi = found[name]["ci95"]
        assert lo <= true <= hi, (name, found[name])
    # v and top - v are indistinguishable here (top speed nearly constant): reported as an alias
    assert "top_minus_v" in [a["name"] for a in found["v"]["aliases"]]


def test_pure_coloured_noise_finds_nothing(rig):
    """(c) pure coloured noise over 5 seeds: at most one false term in total."""
    lib = rig["lib"]
    n = lib["v"].values.size
    false = 0
    for seed in range(5):
        res = discover(_ar1(10 + seed, 0.05, n), lib, dt=DT, seed=seed)
        false += len(res["terms"])
        if not res["terms"]:
            assert res["explained_fraction"] == 0.0 and res["unexplained_fraction"] == 1.0
    assert false <= 1


def test_effect_outside_library(rig):
    """(d) a 7 Hz torque no term can represent: nothing kept, or most of it left unexplained."""
    lib, t = rig["lib"], rig["t"]
    r = 0.1 * np.sin(2 * np.pi * 7.0 * t) + _ar1(4, 0.02, t.size)
    res = discover(r, lib, dt=DT)
    assert res["terms"] == [] or res["unexplained_fraction"] > 0.8


def test_residual_structure_finds_7hz(rig):
    """(e) the Welch PSD's highest peak at 7 Hz (within 0.5 Hz); correlations with the channels."""
    t, ch = rig["t"], rig["channels"]
    r = 0.1 * np.sin(2 * np.pi * 7.0 * t) + _ar1(4, 0.02, t.size)
    r[100:130] = np.nan                                      # a gap
    s = residual_structure(r, ch, DT)
    assert abs(s["peaks"][0]["frequency_hz"] - 7.0) < 0.5 and len(s["peaks"]) == 3
    assert s["rms"] == pytest.approx(np.sqrt(np.nanmean(r ** 2)))
    assert set(s["correlations"]) == {"twist", "v", "sign_v", "top", "W"}
    assert all(c["p_value"] > 0.01 for c in s["correlations"].values())
    # a residual proportional to twist correlates with it, significantly at n_eff
    s2 = residual_structure(0.3 * ch["twist"] + _ar1(5, 0.05, t.size), ch, DT)
    c = s2["correlations"]["twist"]
    assert c["r"] > 0.8 and c["p_value"] < 1e-6 and c["n_eff"] < t.size


def test_bad_inputs_raise(rig):
    """(f) every bad input raises ValueError naming the argument."""
    lib, ch = rig["lib"], rig["channels"]
    n = ch["v"].size
    r = np.zeros(n)
    with pytest.raises(ValueError, match="dt"):
        discover(r, lib, dt=0.0)
    with pytest.raises(ValueError, match="dt"):
        residual_structure(r, ch, -1.0)
    with pytest.raises(ValueError, match=r"terms\['constant'\]"):
        discover(r[:-5], lib, dt=DT)                         # length mismatch
    with pytest.raises(ValueError, match="residual"):
        discover(np.full(n, np.nan), lib, dt=DT)             # non-finite everywhere
    few = np.full(n, np.nan)
    few[:40] = 1.0
    with pytest.raises(ValueError, match="residual.*40 finite"):
        discover(few, lib, dt=DT)
    with pytest.raises(ValueError, match="residual"):
        residual_structure(few, ch, DT)
    with pytest.raises(ValueError, match="max_terms"):
        discover(r, lib, dt=DT, max_terms=0)
    with pytest.raises(ValueError, match="alpha"):
        discover(r, lib, dt=DT, alpha=1.5)
    with pytest.raises(ValueError, match=r"channels\['T'\]"):
        library({**ch, "T": ch["T"][:-1]})
    with pytest.raises(ValueError, match=r"channels\['twist'\]"):
        library({k: x for k, x in ch.items() if k != "twist"})
    with pytest.raises(ValueError, match=r"channels\['a'\]"):
        library({**ch, "a": np.full(n, np.nan)})
    with pytest.raises(ValueError, match="wob_ref"):
        library(ch, wob_ref=-5.0)
    with pytest.raises(ValueError, match="dt"):
        library(ch, dt=float("nan"))
