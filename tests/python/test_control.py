"""The controlled top drive from the command line (issue 15): --controller on sweep, map and mc."""
import json

import pytest

from drillpy.cli import main

SWEEP = ["sweep", "--preset", "thesis-field", "--speeds", "10,14,16", "--duration", "100", "--transient", "50",
         "--json", "--no-progress"]


def _severity(capsys, *extra):
    assert main([*SWEEP, *extra]) == 0
    return json.loads(capsys.readouterr().out)["severity"]


def test_stiff_drive_reproduces_the_ideal_drive_and_z_torque_removes_the_stick_slip(capsys):
    """stiff: SS per speed within 1 % of the constant top speed; z_torque (impedance matching) takes
    every speed of the grid out of stick-slip where the ideal drive sticks (SS > 1.2)."""
    ideal = _severity(capsys)
    stiff = _severity(capsys, "--controller", "stiff", "--drive-inertia", "2000")
    z = _severity(capsys, "--controller", "z_torque", "--drive-inertia", "2000")
    assert min(ideal) > 1.2
    for a, b in zip(ideal, stiff):
        assert b == pytest.approx(a, rel=0.01)
    assert max(z) < 0.1


def test_mc_runs_with_a_controller(capsys):
    args = ["mc", "--preset", "thesis-field", "--modes", "8", "--speeds", "10,16", "--samples", "3", "--warmup",
            "20", "--duration", "30", "--transient", "10", "--json", "--no-progress"]
    assert main(args) == 0
    ideal = [r["mean_ss"] for r in json.loads(capsys.readouterr().out)["speeds"]]
    assert main([*args, "--controller", "z_torque", "--drive-inertia", "2000"]) == 0
    z = [r["mean_ss"] for r in json.loads(capsys.readouterr().out)["speeds"]]
    assert all(b < a for a, b in zip(ideal, z))


@pytest.mark.parametrize("args, message", [
    (["--kp", "3"], "--kp = 3.0: needs --controller"),
    (["--controller", "stiff"], "--controller = stiff: give --drive-inertia"),
    (["--controller", "stiff", "--drive-inertia", "-5"], "top_drive.inertia_kg_m2 = -5"),
])
def test_controller_options_are_checked(args, message, capsys):
    assert main([*SWEEP, *args]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err


def test_structural_studies_refuse_a_controller(capsys):
    assert main(["robust-ss", "--preset", "thesis-ch6", "--controller", "stiff", "--drive-inertia", "100"]) == 2
    assert "ideal top drive only" in capsys.readouterr().err
