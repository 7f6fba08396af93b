"""The controlled top drive from the command line (issue 15): --controller on sweep, map, mc and robust-ss."""
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


def test_frequency_domain_studies_refuse_a_controller(capsys):
    for cmd in ("frf", "frf-report"):
        assert main([cmd, "--preset", "thesis-ch6", "--controller", "stiff", "--drive-inertia", "100"]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "--controller = stiff: the frequency-domain studies" in err


ROBUST = ["robust-ss", "--preset", "thesis-ch6", "--cb-modes", "6,3", "--dt", "1e-3", "--duration", "30",
          "--transient", "15", "--samples", "4", "--speeds", "10,12", "--seed", "3", "--json", "--no-progress"]


def test_robust_ss_with_z_torque_lowers_the_stick_slip_of_the_random_strings(capsys, tmp_path):
    """robust-ss --controller: every SM_CB2 realization runs with the controlled drive (tuned on the
    nominal string); z_torque lowers the mean SS and P(SS > 0.5) of the random strings against the ideal
    drive, and the saved configuration holds the drive."""
    assert main(ROBUST) == 0
    ideal = json.loads(capsys.readouterr().out)
    assert main([*ROBUST, "--controller", "z_torque", "--drive-inertia", "2000", "--out", str(tmp_path)]) == 0
    z = json.loads(capsys.readouterr().out)
    for label in ("deterministic", "structure (SM_CB2)"):
        assert max(ideal[label]["mean_ss"]) > 0.5, label  # the ideal drive sticks at these speeds
        for a, b in zip(ideal[label]["mean_ss"], z[label]["mean_ss"]):
            assert b < 0.5 * a, label
    assert ideal["structure (SM_CB2)"]["p_ss_above_0_5"][0] == 1.0
    assert max(z["structure (SM_CB2)"]["p_ss_above_0_5"]) == 0.0
    saved = json.loads((tmp_path / "robust_ss.json").read_text())["config"]["top_drive"]
    assert saved["type"] == "controlled" and saved["controller"]["type"] == "z_torque"
    assert saved["inertia_kg_m2"] == 2000
