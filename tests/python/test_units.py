"""Issue 31 item 2: every speed and WOB option takes a unit; the law's unit option cannot be mistaken."""
import json
import math

import numpy as np
import pytest

from drillpy.cli import main
from drillpy.units import parse_quantity


def test_the_table_converts_field_units_to_si():
    assert parse_quantity("120rpm", "speed", "x") == pytest.approx(4 * math.pi)
    assert parse_quantity("120 RPM", "speed", "x") == pytest.approx(4 * math.pi)
    assert parse_quantity("16", "speed", "x") == 16.0  # a plain number is SI, as before
    assert parse_quantity("45klbf", "force", "x") == pytest.approx(200.17e3, rel=1e-4)
    assert parse_quantity("200kN", "force", "x") == 200e3
    assert parse_quantity("1ft-lbf", "torque", "x") == pytest.approx(1.3558, rel=1e-4)
    assert parse_quantity("10ft", "length", "x") == pytest.approx(3.048)
    with pytest.raises(ValueError, match=r"--top-speed = '16furlong': unknown speed unit 'furlong'"):
        parse_quantity("16furlong", "speed", "--top-speed")
    with pytest.raises(ValueError, match=r"--wob = '45 kN N'"):
        parse_quantity("45 kN N", "force", "--wob")


def _json_run(capsys, *argv):
    assert main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


RIG = ["--preset", "thesis-rig", "--duration", "4", "--transient", "2", "--no-progress"]


def test_simulate_in_rpm_and_klbf_is_the_si_run(capsys):
    a = _json_run(capsys, "simulate", *RIG, "--top-speed", "90rpm", "--wob", "0.1124klbf")
    b = _json_run(capsys, "simulate", *RIG, "--top-speed", str(90 * math.pi / 30), "--wob", str(0.1124 * 4448.2216152605))
    assert a == b and a["severity"] > 0  # the same run, bit for bit


def test_sweep_and_mc_take_a_wob(capsys):
    lo = _json_run(capsys, "sweep", *RIG, "--speeds", "60,90rpm", "--wob", "200N")
    hi = _json_run(capsys, "sweep", *RIG, "--speeds", "60,90rpm", "--wob", "600N")
    assert lo["top_speeds_rad_s"] == pytest.approx([2 * math.pi, 3 * math.pi])
    assert not np.allclose(lo["severity"], hi["severity"])  # the WOB reached the runs
    mc = ["mc", *RIG, "--samples", "2", "--warmup", "0", "--speeds", "90rpm", "--no-figures"]
    lo, hi = _json_run(capsys, *mc, "--wob", "200N"), _json_run(capsys, *mc, "--wob", "600N")
    assert lo["speeds"][0]["top_speed_rad_s"] == pytest.approx(3 * math.pi)
    assert lo["speeds"][0]["mean_ss"] != hi["speeds"][0]["mean_ss"]


def test_the_map_keeps_its_axes_units_and_takes_others(capsys):
    a = _json_run(capsys, "map", *RIG, "--speeds-rpm", "90", "--wobs-kn", "0.4")
    b = _json_run(capsys, "map", *RIG, "--speeds-rpm", f"{3 * math.pi}rad/s", "--wobs-kn", "400N")
    assert a["top_speeds_rpm"] == [90.0] and b["top_speeds_rpm"] == pytest.approx([90.0])
    assert b["wobs_kn"] == pytest.approx([0.4]) and np.allclose(b["severity"], a["severity"], rtol=1e-9)


@pytest.mark.parametrize("argv, needle", [
    (["--speed-unit", "rpm"], "--speed-unit = rpm: renamed --law-speed-unit"),
    (["--wob-kn", "200"], "--wob-kn = 200: renamed --wob"),
    (["--top-speed", "16furlong"], "--top-speed = '16furlong': unknown speed unit"),
    (["--wob", "heavy"], "--wob = 'heavy': must be a number"),
])
def test_old_and_bad_unit_options_are_one_clear_error(capsys, argv, needle):
    assert main(["simulate", *RIG, *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("drillpy: error: ") and needle in err and err.count("\n") == 1
