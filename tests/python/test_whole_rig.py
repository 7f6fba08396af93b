"""The whole-rig truth (benchmarks/whole_rig.py): an independent simulator of the chapter-5 test rig with
its sensors. It must share no code with drillpy, and its records must carry the physical facts the
measured sample 175 shows: the open-loop motor's droop, the WOB rising while the bit sticks, the
platform's 20 Hz resonance under the 10 Hz acquisition filter, and stalls at a high WOB.
Physical facts with tolerances, never exact floats."""
from __future__ import annotations

import ast
import json
import math

import numpy as np
import pytest
import scipy.io
import scipy.signal

from conftest import REPO

rig = pytest.importorskip("whole_rig")

QUIET = set(rig.ELEMENTS) - {"noise", "artifacts"}   # every physical element, no sensor noise or glitches


@pytest.fixture(scope="module")
def quiet():
    return rig.simulate({}, QUIET, duration=10.0, seed=3)


def _band(x, lo, hi):
    f, p = scipy.signal.welch(x - x.mean(), rig.FS, nperseg=2048)
    b = (f >= lo) & (f <= hi)
    return p[b].sum()


def test_it_imports_no_drillpy_code():
    tree = ast.parse((REPO / "benchmarks" / "whole_rig.py").read_text())
    names = {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    names |= {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module}
    assert not any(x.split(".")[0] == "drillpy" for x in names)
    assert {x.split(".")[0] for x in names} <= {"__future__", "argparse", "json", "math", "sys", "time",
                                                "pathlib", "numpy", "scipy"}


def test_default_rig_stick_slips_like_the_test_rig(quiet):
    c = quiet["clean"]
    assert quiet["f1_clamped_hz"] == pytest.approx(math.sqrt(3.08 / 9.33e-3) / (2 * math.pi), rel=0.01)
    s = rig.record_stats(quiet["time"], quiet["top_speed"], quiet["bit_speed"], quiet["torque"], quiet["wob"])
    assert 6.5 < s["bit_mean"] < 11 and 4 < s["bit_sd"] < 8
    assert 2.4 < s["peak_hz"] < 3.2
    assert 0.01 < c["stuck"].mean() < 0.3 and c["held"].mean() < 0.02   # sticks, but no stall
    assert 1.6 < s["torque_mean"] < 2.6 and 480 < s["wob_mean"] < 640


def test_open_loop_motor_droops(quiet):
    p, c = quiet["params"], quiet["clean"]
    # the motor law itself: Omega + (J_m / c_m) Omega' = Omega_c - T_top / c_m (the rotor's inertia corrected)
    om, T = c["om0"], c["T_top"]
    y = om + p["J_m"] / p["c_m"] * np.gradient(om) * rig.FS
    slope = np.polyfit(T[5:-5], y[5:-5], 1)[0]
    assert slope == pytest.approx(-1 / p["c_m"], rel=0.05)
    # what an analyst sees on the record: the top speed regressed on the measured torque
    s = rig.record_stats(quiet["time"], quiet["top_speed"], quiet["bit_speed"], quiet["torque"], quiet["wob"])
    assert s["droop_slope"] == pytest.approx(-1 / p["c_m"], rel=0.25)
    assert s["droop_r"] < -0.8
    assert s["droop_intercept"] == pytest.approx(p["omega_c"], rel=0.15)


def test_wob_rises_while_the_bit_sticks_and_falls_while_it_slips(quiet):
    c = quiet["clean"]
    dW = np.gradient(c["W"]) * rig.FS
    fast = c["omN"] > c["omN"].mean()
    assert dW[c["stuck"]].mean() > 200.0        # N/s: the jack keeps feeding, the bit does not cut
    assert dW[fast].mean() < -50.0              # the bit cuts faster than the jack feeds
    s = rig.record_stats(quiet["time"], quiet["top_speed"], quiet["bit_speed"], quiet["torque"], quiet["wob"])
    assert s["wob_deficit_r"] > 0.5 and s["wob_deficit_slope"] > 0
    assert 0.0 < s["wob_lead_s"] < 0.1          # the WOB leads the angle deficit (the jack's droop)


def test_platform_resonance_is_under_the_10_hz_filter(quiet):
    c = quiet["clean"]
    contact, cell, rec = c["T_c"], c["load_cell"], quiet["torque"]
    assert cell.mean() == pytest.approx(contact.mean(), rel=0.02)      # statically the cell reads the contact
    assert _band(cell, 1, 4) == pytest.approx(_band(contact, 1, 4), rel=0.2)
    # the 20 Hz platform rings: near its resonance the cell reads far more than the contact torque has
    assert _band(cell, 14, 24) > 5 * _band(contact, 14, 24)
    # the 10 Hz second-order IIR: |H|^2 is 0.06..0.2 in 14-24 Hz, about 1 below 4 Hz
    b, a = scipy.signal.butter(2, 10.0, fs=rig.FS)
    h2 = np.abs(scipy.signal.freqz(b, a, [14.0, 24.0], fs=rig.FS)[1]) ** 2
    ratio = _band(rec, 14, 24) / _band(cell, 14, 24)
    assert h2.min() * 0.5 < ratio < h2.max() * 2.0
    assert _band(rec, 1, 4) == pytest.approx(_band(cell, 1, 4), rel=0.15)
    # one-directional load cell
    assert cell.min() >= 0.0


def test_a_high_wob_stalls_the_top_drive():
    p = rig.DEFAULTS
    res = rig.simulate({"jack_voltage": 1.2}, QUIET, duration=8.0, seed=1)
    c = res["clean"]
    stalled = c["stuck"] & (c["om0"] < p["stall_speed"])
    assert stalled.mean() > 0.2
    stall_torque = p["c_m"] * p["omega_c"]
    # stalled, the string holds at least the motor's stall torque (more when the rotor overshot and the
    # one-way hold keeps the twist), while the bit's static capacity exceeds it
    assert stall_torque * 0.95 < np.median(c["T_c"][stalled]) < stall_torque + p["T_hold"]
    assert np.median(p["mu_static"] * p["r_b"] * c["W"][stalled]) > stall_torque
    assert c["relief"].any()                    # the operator relieves the WOB
    # without the operator, the stall lasts
    res = rig.simulate({"jack_voltage": 1.2}, QUIET - {"operator"}, duration=6.0, seed=1)
    c = res["clean"]
    assert (c["stuck"] & (c["om0"] < p["stall_speed"]))[-2000:].all()


def test_record_format_and_artifacts(tmp_path):
    res = rig.simulate({"spike_rate": 2.0}, duration=6.0, seed=2, noise=1.0)
    out = tmp_path / "rec.mat"
    rig.write_mat(res, str(out))
    d = scipy.io.loadmat(out)
    names = {k for k in d if not k.startswith("__")}
    assert names == {f"{v}_Sample_175_complete" for v in ("Time", "Bit_Speed", "Top_Speed", "Bit_Torque", "WOB")}
    assert all(d[n].shape == (6000, 1) for n in names)
    t = d["Time_Sample_175_complete"].ravel()
    assert t[0] == 0.0 and np.diff(t) == pytest.approx(1e-3)
    assert 50 < d["Bit_Speed_Sample_175_complete"].mean() < 120          # RPM
    meta = json.loads(out.with_suffix(".json").read_text())
    assert meta["params"]["c_m"] == rig.DEFAULTS["c_m"] and "artifacts" in meta["elements"]
    # isolated encoder spikes reach about -200 RPM on the top channel only
    top = d["Top_Speed_Sample_175_complete"].ravel()
    assert top.min() < -90 and d["Bit_Speed_Sample_175_complete"].min() > -20
    # an explicit artifact stretch oscillates between about -200 and +50 RPM
    res = rig.simulate({"stretch": [[2.0, 4.0]]}, duration=6.0, seed=2)
    seg = res["top_speed"][2100:3900] / rig.RPM
    assert seg.min() < -100 and 20 < np.median(seg) < 60


def test_step_size_is_converged():
    """The exact (zero-order-hold) integrator: halving the nonlinear inputs' hold step changes little."""
    el = QUIET - {"eta"}
    a = rig.simulate({"dt": 1e-4}, el, duration=6.0, seed=4)["clean"]
    b = rig.simulate({"dt": 5e-5}, el, duration=6.0, seed=4)["clean"]
    assert a["omN"].mean() == pytest.approx(b["omN"].mean(), rel=0.02)
    assert a["T_c"].mean() == pytest.approx(b["T_c"].mean(), rel=0.02)
    assert abs(a["stuck"].mean() - b["stuck"].mean()) < 0.01


#: Thesis laws in rad/s at a reference WOB of 557.1 N (``law`` option): Tucker-Wang Eq. (3.1) peaking
#: near 0.5 rad/s, and Eq. (5.1) with a static torque of 3 N m above its slip branch (its a2 = 1.976 / 1.36 N m).
TW_LAW = {"type": "tucker_wang", "speed_unit": "rad_s", "wob_ref_n": 557.1, "c0": 1.3, "alpha0": 10.0,
          "alpha1": 4.0, "alpha2": 4.0}
POLY_LAW = {"type": "polynomial", "speed_unit": "rpm", "wob_ref_n": 557.1, "gain": 1.36, "ref_speed": 90.36,
            "a0": 3.0 / 1.36, "a1": (1.976 - 3.0 / 1.36) / 0.9036, "a2": 1.976, "a3": 0.0, "a4": 1.983,
            "a5": -0.001315, "a6": -4.823e-05, "a7": 1.047e-07}


def test_a_thesis_law_is_its_equation_odd_in_the_speed():
    # Eq. (3.1): c0 [tanh(a0 v) + a1 v / (1 + a2 v^2)], its hump's peak c0 h = c0 a1 / (2 sqrt(a2)) at 1 / sqrt(a2)
    v = 0.5
    assert rig.law_torque(v, 0.0, TW_LAW) == pytest.approx(1.3 * (math.tanh(5.0) + 1.0), rel=1e-12)
    assert rig.law_torque(-v, 0.0, TW_LAW) == pytest.approx(-rig.law_torque(v, 0.0, TW_LAW), rel=1e-12)
    # Eq. (5.1): the static torque gain a0 at rest, the cubic branch above 5 % of the reference speed
    assert rig.law_static(POLY_LAW) == pytest.approx(3.0)
    assert rig.law_static(TW_LAW) == 0.0
    u = 20.0 * 30.0 / math.pi
    assert rig.law_torque(20.0, 0.0, POLY_LAW) == pytest.approx(
        1.36 * (1.983 - 0.001315 * u - 4.823e-05 * u ** 2 + 1.047e-07 * u ** 3), rel=1e-12)
    # Eq. (3.3)'s hysteresis: an accelerating bit carries more torque than a decelerating one
    hy = {"type": "hysteretic", "speed_unit": "rad_s", "wob_ref_n": 557.1, "b0": 0.9, "b1": 10.0, "b2": 5.0,
          "b3": 4.0, "b4": 0.78, "b5": 1.1, "beta1": 0.1, "beta2": 1.0}
    assert rig.law_torque(2.0, 50.0, hy) > rig.law_torque(2.0, 0.0, hy) > rig.law_torque(2.0, -50.0, hy)
    with pytest.raises(ValueError, match="law.type = 'coulomb'"):
        rig.simulate({"law": {"type": "coulomb"}}, QUIET, duration=0.1, seed=1)


def test_a_law_with_a_static_torque_sticks_and_a_regularized_one_never_enters_the_stuck_mode():
    el = QUIET - {"jack_switch", "rock"}
    stuck = rig.simulate({"law": POLY_LAW, "jack_steps": [], "c_m": 0.22, "omega_c": 15.0}, el, duration=4.0,
                         seed=2)["clean"]
    smooth = rig.simulate({"law": TW_LAW, "jack_steps": []}, el, duration=4.0, seed=2)["clean"]
    assert stuck["stuck"].mean() > 0.02
    assert not smooth["stuck"].any()
    # slipping, the contact torque is the law at the WOB over its reference (to the torque fluctuation's 3 %)
    slip = ~smooth["stuck"] & (smooth["omN"] - smooth["omp"] > 1.0)
    law = np.array([rig.law_torque(v, 0.0, TW_LAW) for v in (smooth["omN"] - smooth["omp"])[slip]])
    ratio = smooth["T_c"][slip] / (smooth["W"][slip] / 557.1 * law)
    assert abs(np.median(ratio) - 1.0) < 0.02
