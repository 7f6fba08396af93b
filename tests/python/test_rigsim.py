"""The test rig in simulation: configuration, drives, comparison identities, damping estimate."""
import numpy as np
import pytest

from _testrig import sample175_cleaned
from drillpy import rigsim
from drillpy.cleaning import clean
from drillpy.config import load_config
from drillpy.records import RPM, Flag
from drillpy.simulation import natural_frequencies


@pytest.fixture(scope="module")
def window():
    rec, rep = sample175_cleaned()
    return rec.select(30.0, 40.0), rep.stick_threshold_rad_s


def test_rig_config_keeps_the_geometry():
    law = {"type": "tucker_wang", "speed_unit": "rpm", "wob_ref_n": 500.0, "c0": 1.0, "alpha0": 10.0,
           "alpha1": 0.2, "alpha2": 0.003}
    cfg = rigsim.rig_config(law, 0.1, duration_s=5.0)
    assert cfg["law"]["c0"] == 1.0 and cfg["damping"]["ratios"] == [0.1]
    assert cfg["operation"]["wob_n"] == 500.0  # the law is used at the WOB it was fitted at
    assert natural_frequencies(cfg, 1)[0] == pytest.approx(2.89, abs=0.01)  # Table 5.1 rig


def test_comparing_a_record_with_itself_is_exact(window):
    rec, thr = window
    cmp = rigsim.compare(rec, rec, thr)
    assert cmp.mismatch == 0.0 and cmp.loop_rms_nm == 0.0
    assert all(m == s for _, m, s in cmp.rows())


def test_preset_stick_slips_at_the_measured_mean_speed(window):
    rec, thr = window
    sim = rigsim.simulate_rig(rec, drive="constant")
    np.testing.assert_allclose(sim.time_s, rec.time_s, atol=1e-9)
    assert np.allclose(sim.top_speed, np.mean(rec.top_speed))
    cmp = rigsim.compare(rec, sim, thr)
    s = cmp.simulated
    assert s["ss"] > 0.5 and s["stick_fraction"] > 0.02  # self-excited stick-slip
    assert 2.0 < s["cycle_frequency_hz"] < 3.2  # near the 2.89 Hz first mode
    base = load_config(preset="thesis-rig")
    assert sim.provenance["config"]["law"] == base["law"]


def test_measured_drive_follows_the_top_speed(window):
    rec, thr = window
    sim = rigsim.simulate_rig(rec, drive="measured", filtered=False)
    np.testing.assert_allclose(sim.top_speed, rec.top_speed, rtol=1e-5)  # the drive is the measured signal


def test_damping_estimate_is_the_scan_minimum(window):
    rec, thr = window
    law = load_config(preset="thesis-rig")["law"]
    est = rigsim.estimate_damping(rec, law, thr, ratios=[0.02, 0.2, 0.6])
    assert [r for r, _ in est["scan"]] == [0.02, 0.2, 0.6]
    assert est["mismatch"] == min(m for _, m in est["scan"])
    assert est["ratio"] in (0.02, 0.2, 0.6)


def test_simulate_rig_refuses_incomplete_drives(window):
    rec, _ = window
    bad = rec.take(np.arange(len(rec)))
    bad.top_speed[100:400] = np.nan
    cleaned, _ = clean(bad)
    assert (cleaned.flags["top_speed"] & Flag.UNRELIABLE).any()
    with pytest.raises(ValueError, match="excluded samples"):
        rigsim.simulate_rig(cleaned)
    with pytest.raises(ValueError, match="drive = 'motor'"):
        rigsim.simulate_rig(rec, drive="motor")
    assert RPM > 0
