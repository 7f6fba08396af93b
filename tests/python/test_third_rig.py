"""The third outside simulator of the loop's independent check (benchmarks/third_rig.py): it shares
no code with drillpy, its Ritz bar has the continuous bar's first natural frequency, the clean rig
stick-slips like the test rig, the load cell applies its gain and offset, and during a stick the
measured torque is the bar's twist times its stiffness (the torque balance of the held disk)."""
from __future__ import annotations

import ast
import math

import numpy as np
import pytest

from conftest import REPO

rig = pytest.importorskip("third_rig")

SHORT = {"duration_s": 3.0, "settle_s": 1.5}


@pytest.fixture(scope="module")
def clean():
    return rig.simulate({}, seed=1, **SHORT)


def test_it_imports_no_drillpy_code():
    tree = ast.parse((REPO / "benchmarks" / "third_rig.py").read_text())
    names = {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    names |= {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module}
    assert not any(x.split(".")[0] == "drillpy" for x in names)


def test_ritz_bar_has_the_continuous_bars_first_frequency():
    exact = rig.first_frequency_exact()                   # beta L tan(beta L) = J_bar / J_disk
    assert exact == pytest.approx(math.sqrt(3.08 / (rig.J_DISK + rig.J_BAR / 3)) / (2 * math.pi), rel=1e-4)
    assert rig.Rig({}).natural_frequencies_hz()[0] == pytest.approx(exact, rel=0.01)
    soft = rig.Rig({"gj_factor": 0.88}).natural_frequencies_hz()[0]
    assert soft == pytest.approx(rig.first_frequency_exact(0.88), rel=0.01)
    assert soft / exact == pytest.approx(math.sqrt(0.88), rel=1e-3)
    # the second mode of a bar whose end carries a much heavier disk: nearly clamped-clamped, pi c / L
    c = math.sqrt(rig.G_PA / rig.DENSITY)
    assert rig.Rig({}).natural_frequencies_hz()[1] == pytest.approx(c / (2 * rig.LENGTH_M), rel=0.01)


def test_clean_rig_stick_slips_at_the_nominal_point(clean):
    m = rig.true_metrics(clean)
    assert 0.9 < m["ss"] < 1.5
    assert 0.05 < m["stick_fraction"] < 0.3
    assert 2.0 < m["spectral_peak_hz"] < 3.3 and 2.0 < m["stick_onsets_per_s"] < 3.3
    assert clean["stick_events"] >= 6


def test_held_disk_balances_the_bar_twist(clean):
    """While the bit is held, the (quasi-static: the disk is at rest) contact torque is the bar's
    stiffness times its twist plus the Kelvin-Voigt part eta k (Omega - 0)."""
    s = clean["stuck"] & (clean["time_s"] > 0.5)
    twist = clean["theta"][0][s] - clean["theta"][1][s]
    rg = clean["rig"]
    expected = 3.08 * twist + rg.eta * 3.08 * rig.OMEGA0
    assert np.max(np.abs(clean["torque"][s] - expected)) < 1e-3 * np.max(np.abs(expected))


def test_load_cell_gain_and_offset_are_applied(clean):
    opts = {"torque_gain": 1.15, "torque_offset": 0.15}
    rec = rig.measure(clean, opts, seed=1, noise=0.0)
    keep = clean["time_s"] >= clean["settle_s"] - 1e-9
    assert rec["torque_on_bit"] == pytest.approx(1.15 * clean["torque"][keep] + 0.15, abs=1e-12)
    plain = rig.measure(clean, {}, seed=1, noise=0.0)
    assert plain["torque_on_bit"] == pytest.approx(clean["torque"][keep], abs=1e-12)


def test_encoder_speed_is_the_quantized_angle_differentiated(clean):
    rec = rig.measure(clean, {}, seed=1, noise=0.0)
    keep = clean["time_s"] >= clean["settle_s"] - 1e-9
    true = clean["omega"][1][keep]
    step = 2 * math.pi / rig.ENCODER_COUNTS * rig.FS_HZ
    # a backward difference lags by half a sample and is off by at most one count per sample
    mid = 0.5 * (true[1:] + true[:-1])
    assert np.max(np.abs(rec["bit_speed"][1:] - mid)) < step + 0.05
