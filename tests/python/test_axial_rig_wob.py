"""The coupled axial-torsional rig model (axial.type = rgd with the rig's motor and law) against sample
175's WOB swing at the stick-slip cycle (benchmarks/axial_rig_wob.py, docs/axial.md "Sample 175's WOB").

The bit's parameters come from the rig's description and RGD's published set, not from the WOB channel:
the test asserts the sign of the swing (the WOB rises while the bit slows, as in the record), its order
of magnitude, and that it grows with the cutting share (the depth of cut's delay is its source)."""
import pytest

import drillpy
from axial_rig_wob import model_swing, record_swing
from drillpy.records import rigsim

# the law of the whole-rig model drillpy analyze calibrates on 0-20 s (rounded): the rgd-rig preset's
LAW = drillpy.load_config(preset="rgd-rig")["law"]


@pytest.fixture(scope="module")
def swings(testrig_record):
    rec = record_swing(testrig_record, 0.0, 20.0)
    m = rigsim.RigModel(LAW, 0.0303, "rig", 0.25, 0.0186, command_rad_s=17.27, jack_gain_n_rad=181.8,
                        jack_relaxation_s=0.0987, platform_damping=0.75, gj_factor=1.0475,
                        bit_inertia_factor=1.07, coupling_stiffness_nm_rad=41.0)
    cfg = m.config(17.27, wob=rec["wob_mean"])
    models = {eps: model_swing(cfg, eps, rec["wob_mean"], 15.0, 5.0) for eps in (30e6, 60e6)}
    models["jack"] = model_swing(cfg, 30e6, rec["wob_mean"], 15.0, 5.0, jack_relaxation=0.0987)
    return rec, models


def test_the_coupled_rig_swings_its_wob_against_the_bit_speed_as_the_record_does(swings):
    rec, models = swings
    assert rec["corr"] < -0.3 and rec["h_deg"] < -90.0  # the record: WOB up while the bit slows
    for m in (models[30e6], models[60e6]):
        assert m["steady_wob"] == pytest.approx(rec["wob_mean"], rel=1e-3)  # the jack's operating point
        assert m["severity"] > 0.5  # it sticks and slips under the motor
        assert m["corr"] < -0.5 and m["h_deg"] < -90.0  # the same sign
        assert 0.1 < m["swing"] / rec["swing"] < 1.0  # the same order of magnitude (below it: the note)


def test_the_swing_grows_with_the_cutting_share(swings):
    _, models = swings
    a, b = models[30e6], models[60e6]
    assert b["cutting_wob"] == pytest.approx(2.0 * a["cutting_wob"], rel=0.02)
    assert 1.5 < b["swing"] / a["swing"] < 3.0


def _rig_coupled(tmp_path):
    """The coupled rig model of benchmarks/axial_rig_wob.py (eps 30 MPa, the wear flat it finds for
    sample 175's 565 N: 2.30 mm) as a configuration file, and its motor's command."""
    import json
    from axial_rig_wob import coupled_config
    m = rigsim.RigModel(LAW, 0.0303, "rig", 0.25, 0.0186, command_rad_s=17.27, jack_gain_n_rad=181.8,
                        jack_relaxation_s=0.0987, platform_damping=0.75, gj_factor=1.0475,
                        bit_inertia_factor=1.07, coupling_stiffness_nm_rad=41.0)
    cfg = coupled_config(m.config(17.27, wob=564.6), 30e6, 2.30e-3, 8.0, 4.0)
    cfg["simulation"]["output_stride"] = 10
    path = tmp_path / "rig_coupled.json"
    path.write_text(json.dumps(cfg))
    return path


def test_the_coupled_rig_runs_from_the_cli_and_a_sweep_across_its_stall_answers_every_point(tmp_path):
    """The motor's droop in simulate's text (the rig's WOB in N), and a sweep whose slowest command cannot
    carry the feed's steady drilling (the motor stalls there) gives SS at every speed, not an error."""
    import json
    from conftest import run_cli
    cfg = _rig_coupled(tmp_path)
    r = run_cli("simulate", "--config", str(cfg), "--no-progress")
    assert r.returncode == 0, r.stderr
    assert " N (steady 56" in r.stdout and "kN" not in r.stdout  # 565 N, not "0.6 kN"
    assert "steady drilling under the top drive at " in r.stdout
    r = run_cli("simulate", "--config", str(cfg), "--no-progress", "--json")
    s = json.loads(r.stdout)
    assert 8.0 < s["steady_speed_rad_s"] < 10.0  # the motor's droop from its 17.27 rad/s command
    r = run_cli("sweep", "--config", str(cfg), "--speeds", "8,17.27", "--no-progress", "--json",
                "--out", str(tmp_path / "sweep"))
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    ss = out["severity"] if "severity" in out else out["ss"]
    assert len(ss) == 2 and all(x is not None for x in ss)
    r = run_cli("simulate", "--config", str(cfg), "--no-progress", "--top-speed", "8")
    assert r.returncode == 0, r.stderr
    assert "no steady drilling under the top drive: it stalls" in r.stdout


def test_the_jack_top_holds_the_mean_wob_and_keeps_the_sign(swings):
    """axial.top = jack (the same 2 mm/s free feed relaxing the WOB to the record's mean in the rig model's
    0.099 s): the mean WOB within 2 % of the set force, the same sign of the swing, smaller than the feed's
    (the relaxation takes part of the 3 Hz swing: 2 pi f tau = 1.9)."""
    rec, models = swings
    j, f = models["jack"], models[30e6]
    assert j["wob_mean"] == pytest.approx(rec["wob_mean"], rel=0.02)
    assert j["corr"] < -0.5 and j["h_deg"] < -90.0
    assert 0.3 < j["swing"] / f["swing"] < 0.9


def test_the_rgd_rig_preset_sticks_slips_and_swings_its_wob_against_the_bit_speed():
    """drillpy's coupled rig (preset rgd-rig, docs/presets.md): under the rated motor and the jack it
    drills below the command (the motor's droop), sticks and slips at 2-4 Hz, holds the mean WOB near the
    565 N set force and swings it against the bit speed; 20 s of it from the CLI's JSON and the series."""
    import json
    import numpy as np
    from conftest import run_cli
    from drillpy.model.simulation import simulate
    from drillpy.records.signals import rig_lowpass
    from axial_rig_wob import swing
    r = run_cli("simulate", "--preset", "rgd-rig", "--duration", "20", "--json", "--no-progress")
    assert r.returncode == 0, r.stderr
    s = json.loads(r.stdout)
    assert 5.0 < s["steady_speed_rad_s"] < 17.27  # the motor's droop from its command
    assert s["severity"] > 0.5 and s["stick_fraction"] > 0.05
    assert s["mean_wob_n"] == pytest.approx(565.0, rel=0.02)
    assert s["wob_std_n"] > 1.0
    cfg = drillpy.load_config(preset="rgd-rig")
    cfg["simulation"].update(duration_s=20.0, output_stride=1)
    res = simulate(cfg)
    keep = res.t >= cfg["simulation"]["transient_s"]
    fs = 1.0 / float(res.t[1] - res.t[0])
    m = swing(res.t[keep], rig_lowpass(res.bit_speed, fs)[keep], rig_lowpass(res.axial.wob, fs)[keep])
    assert 2.0 < m["fc"] < 4.0
    assert m["corr"] < -0.5 and m["h_deg"] < -90.0
    assert np.isfinite(m["swing"]) and m["swing"] > 1.0
