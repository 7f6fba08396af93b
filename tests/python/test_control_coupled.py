"""Controlled top drives on the axial-torsional model (axial.type = rgd, preset rgd-field; the drive's
step in drill/axial_torsional.hpp): the stiff drive tends to the ideal one, ZTorque takes the RGD string
below section 3.3's stick-slip level at 8 rad/s where the ideal drive is above it, with and without
the chapter-4 stochastic torque, the same numbers on any thread count, and ``drillpy control`` runs."""
import json

import numpy as np

from drillpy.cli import main
from drillpy.control.tuning import Window, controlled_drive, window_severity
from drillpy.model.config import load_config, with_overrides
from drillpy.model.simulation import simulate

J = 2000.0  # [kg m^2] an assumed field top drive (docs/control.md)


def test_z_torque_takes_the_rgd_string_below_the_stick_slip_level_at_8_rad_s():
    cfg = load_config(preset="rgd-field")  # 60 s, SS over the last 30 s
    ideal = simulate(cfg, 8.0)
    stiff = simulate(with_overrides(cfg, top_drive=controlled_drive("stiff", J)), 8.0)
    z = simulate(with_overrides(cfg, top_drive=controlled_drive("z_torque", J)), 8.0)
    assert ideal.severity > 0.55  # 0.653: the torsional oscillation of the coupled string (docs/axial.md)
    assert abs(stiff.severity - ideal.severity) < 0.1 * ideal.severity  # the stiff PI tends to the ideal drive
    assert z.severity < 0.3  # 0.144: the top absorbs the torsional waves
    assert abs(z.mean_top_speed - 8.0) < 0.01 * 8.0  # integral action: the top turns at the command


def test_the_stochastic_study_is_the_same_on_any_thread_count_and_z_torque_lowers_every_sample():
    cfg = load_config(preset="rgd-field")
    w = Window([8.0], [150e3], 4, 1, warmup=0.0, duration=30.0, transient=15.0)
    ideal = window_severity(cfg, None, w, threads=1)
    z1 = window_severity(cfg, controlled_drive("z_torque", J), w, threads=1)
    z2 = window_severity(cfg, controlled_drive("z_torque", J), w, threads=2)
    assert np.array_equal(z1, z2)
    assert np.all(ideal > 0.5) and np.all(z1 < 0.45)


def test_drillpy_control_runs_on_the_coupled_model(capsys, tmp_path):
    args = ["control", "--preset", "rgd-field", "--drive-inertia", "2000", "--samples", "2",
            "--validation-samples", "2", "--grid", "2", "--refine", "0", "--bootstrap", "20", "--duration", "20",
            "--transient", "10", "--speeds", "4,8", "--wob", "150kN", "--no-progress", "--json"]
    assert main([*args, "--threads", "1", "--out", str(tmp_path / "a")]) == 0
    one = json.loads(capsys.readouterr().out)
    assert main([*args, "--threads", "2", "--out", str(tmp_path / "b")]) == 0
    assert json.loads(capsys.readouterr().out) == one
    assert set(one["tunings"]) == {"soft_speed", "z_torque"}
    assert {"ideal", "stiff", "z_torque_tuned"} <= set(one["drives"])
    control = json.loads((tmp_path / "a" / "control.json").read_text())
    assert control["tuning_window"]["warmup_s"] == 0.0  # the coupled runs start in steady drilling


def test_a_constant_feed_is_refused_naming_axial_top(capsys, tmp_path):
    cfg = load_config(preset="rgd-field")
    cfg["axial"].update(top="feed", rop_m_s=0.01)
    del cfg["operation"]["wob_n"]
    path = tmp_path / "feed.json"
    path.write_text(json.dumps(cfg))
    assert main(["control", "--config", str(path), "--drive-inertia", "2000", "--out", str(tmp_path / "o")]) == 2
    assert "axial.top = 'feed'" in capsys.readouterr().err
