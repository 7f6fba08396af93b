"""The main job on a coarse grid: files, numbers and the quantified map conclusions."""
import json

import numpy as np
import pytest

import drillpy
from drillpy.reports.preset import field_report, map_conclusions


def test_field_report_writes_figures_and_summary(tmp_path):
    cfg = drillpy.load_config(preset="thesis-field")
    s = field_report(cfg, tmp_path, speeds=[8.0, 14.0, 20.0, 26.0], map_speeds_rpm=[60, 110, 160],
                     map_wobs_kn=[50, 150, 250], progress=False)
    for f in ("severity_vs_top_speed.png", "time_series.png", "stability_maps.png", "summary.json"):
        assert (tmp_path / f).stat().st_size > 1000, f
    back = json.loads((tmp_path / "summary.json").read_text())
    np.testing.assert_allclose(back["frequencies_hz"], [0.13, 0.42, 0.74, 1.07, 1.41], atol=0.005)
    assert 14.0 < back["sweep"]["threshold_rad_s"] < 26.0
    assert s["sweep"]["threshold_rad_s"] == back["sweep"]["threshold_rad_s"]  # the return is what was written
    # one answer: the bisection's, with its precision and RPM; the thesis's 16 rad/s belongs to thesis-ch4,
    # its 3-cycle regime of section 4.2.1 to this preset
    sw = back["sweep"]
    assert sw["threshold_method"] == "bisection" and sw["threshold_precision_rad_s"] <= 0.02
    assert sw["threshold_rpm"] == pytest.approx(sw["threshold_rad_s"] * 30 / np.pi) and sw["thesis_threshold_rad_s"] is None
    assert back["reference_run"]["thesis_periodic_regime"].startswith("3-cycle")
    m = back["stability_maps"]["severity"]
    assert len(m) == 3 and np.array(m["model 1 (reversible, beta1 = 0)"]).shape == (3, 3)


def test_map_conclusions_on_synthetic_maps():
    sp, w = np.array([50., 100., 150.]), np.array([50., 150., 250.])
    base = np.array([[0.2, 0.1, 0.0], [1.0, 0.6, 0.4], [1.2, 1.0, 0.9]])
    hyst = base.copy()
    hyst[0, 1:] = 0.0
    hyst[1, 1] = 0.3   # more stable at high speed / low WOB
    hyst[2, 0] = 1.6   # more severe at low speed / high WOB
    c = map_conclusions(sp, w, {"m1": base, "m3": hyst})
    assert c["hysteresis_enlarges_stable_region"] and c["hysteresis_raises_ss_low_speed_high_wob"]
    c = map_conclusions(sp, w, {"m1": hyst, "m3": base})
    assert not c["hysteresis_enlarges_stable_region"] and not c["hysteresis_raises_ss_low_speed_high_wob"]
