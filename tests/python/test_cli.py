"""The drillpy and drillsim commands: outputs, exit codes and one-line errors."""
import json

import numpy as np
import pytest

from conftest import run_cli
import subprocess


def test_modes_json_gives_thesis_frequencies():
    r = run_cli("modes", "--preset", "thesis-field", "--elements", "100", "-n", "5", "--json")
    assert r.returncode == 0, r.stderr
    f = json.loads(r.stdout)["frequencies_hz"]
    np.testing.assert_allclose(f, [0.13, 0.42, 0.74, 1.07, 1.41], atol=0.005)


def test_sweep_json_reports_threshold():
    r = run_cli("sweep", "--preset", "thesis-field", "--law", "hysteretic", "--beta1", "0.14",
                "--speeds", "6:27:22", "--json", "--no-progress")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert len(d["severity"]) == 22 and 15.0 < d["threshold_rad_s"] < 21.0


@pytest.mark.parametrize("args, needle", [
    (["modes", "--preset", "nope"], 'preset = "nope"'),
    (["modes", "--preset", "thesis-field", "--elements", "0"], "elements = 0"),
    (["modes", "--preset", "thesis-field", "--modes", "500"], "rom.modes = 500"),
    (["simulate", "--preset", "thesis-field", "--dt", "0.05"], "stability bound"),
    (["sweep", "--preset", "thesis-field", "--speeds", "6:27"], "--speeds = '6:27'"),
    (["sweep", "--preset", "thesis-field", "--law", "tucker_wang", "--beta1", "0.1"], "has no hysteresis"),
])
def test_bad_input_gives_one_line_error(args, needle):
    r = run_cli(*args)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("drillpy: error:") and needle in lines[0], r.stderr


def test_config_file_errors(tmp_path):
    p = tmp_path / "c.json"
    p.write_text("{not json")
    r = run_cli("modes", "--config", str(p))
    assert r.returncode == 2 and "malformed JSON" in r.stderr


def test_drillsim_run_and_sweep(drillsim, tmp_path):
    r = subprocess.run([drillsim, "--preset", "thesis-rig", "--out", str(tmp_path / "run")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    s = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert s["severity"] > 0.5 and s["config"]["name"] == "thesis-rig"
    data = np.genfromtxt(tmp_path / "run" / "series.csv", delimiter=",", names=True)
    assert data["time_s"][-1] == pytest.approx(40.0) and np.all(np.isfinite(data["bit_speed_rad_s"]))

    cfg = json.loads(subprocess.run([drillsim, "--preset", "thesis-field", "--out", str(tmp_path / "x")],
                                    capture_output=True, text=True).returncode == 0 and
                     (tmp_path / "x" / "summary.json").read_text())["config"]
    cfg["sweep"] = {"top_speeds_rad_s": [8.0, 14.0, 20.0, 26.0], "wobs_n": []}
    (tmp_path / "c.json").write_text(json.dumps(cfg))
    r = subprocess.run([drillsim, "--config", str(tmp_path / "c.json"), "--job", "sweep", "--format", "npy",
                        "--out", str(tmp_path / "sw")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    ss = np.load(tmp_path / "sw" / "severity.npy")
    assert ss.shape == (1, 4) and ss[0, 0] > 1.0 and ss[0, 3] < 0.2
    assert 14.0 < json.loads((tmp_path / "sw" / "summary.json").read_text())["threshold_rad_s"] < 26.0


@pytest.mark.parametrize("args, needle", [
    (["--preset", "nope"], "--preset: nope not in {thesis-field,"),
    (["--preset", "thesis-field", "--format", "xls"], "--format: xls not in {csv,npy}"),
    (["--preset", "thesis-field", "--job", "xyz"], "--job: xyz not in {run,sweep}"),
    (["--preset", "thesis-field", "--threads", "abc"], "--threads = abc: must be an integer >= 0"),
    (["--preset", "thesis-field", "--threads", "-4"], "--threads = -4: must be an integer >= 0"),
    (["--preset", "thesis-field", "--threads", "1e12"], "--threads = 1e12: must be an integer >= 0"),
    (["--preset", "thesis-field", "--threads"], "--threads"),
    (["--config", "/nonexistent.json"], "--config: File does not exist: /nonexistent.json"),
    (["--job", "sweep"], "give --config FILE or --preset NAME"),
    (["--preset", "thesis-field", "--config", "/etc/hostname"], "--config excludes --preset"),
    (["--presett", "thesis-field"], "not expected: thesis-field --presett"),
    (["--preset", "thesis-field", "--bogus"], "not expected: --bogus"),
])
def test_drillsim_errors(drillsim, args, needle, tmp_path):
    r = subprocess.run([drillsim, *args, "--out", str(tmp_path / "out")], capture_output=True, text=True)
    assert r.returncode == 2
    assert r.stderr.count("\n") == 1 and r.stderr.startswith("drillsim: error:") and needle in r.stderr, r.stderr
    assert not (tmp_path / "out").exists()


def test_drillsim_help_version_and_config_errors(drillsim, tmp_path):
    r = subprocess.run([drillsim, "--help"], capture_output=True, text=True)
    assert r.returncode == 0 and r.stdout.startswith("drillsim: ") and "--threads N" in r.stdout and not r.stderr
    r = subprocess.run([drillsim, "--version"], capture_output=True, text=True)
    assert r.returncode == 0 and r.stdout.startswith("drillsim ")
    (tmp_path / "c.json").write_text('{"string": {}}')
    r = subprocess.run([drillsim, "--config", str(tmp_path / "c.json"), "--out", str(tmp_path / "o")],
                       capture_output=True, text=True)
    assert r.returncode == 2 and r.stderr == "drillsim: error: string.sections: missing or not an array\n"


def test_drillsim_progress_changes_no_number(drillsim, tmp_path):
    cfg = json.loads(subprocess.run([drillsim, "--preset", "thesis-rig", "--out", str(tmp_path / "a")],
                                    capture_output=True, text=True).returncode == 0 and
                     (tmp_path / "a" / "summary.json").read_text())["config"]
    cfg["sweep"] = {"top_speeds_rad_s": [4.0, 8.0, 12.0], "wobs_n": []}
    (tmp_path / "c.json").write_text(json.dumps(cfg))
    for job, needle in (("run", "run: 40.0/40.0 s simulated, "), ("sweep", "sweep: 3/3 points, ")):
        out = {}
        for flag in ("--progress", "--no-progress", "--quiet"):
            d = tmp_path / f"{job}{flag}"
            r = subprocess.run([drillsim, "--config", str(tmp_path / "c.json"), "--job", job, "--out", str(d), flag],
                               capture_output=True, text=True)
            assert r.returncode == 0, r.stderr
            assert (needle in r.stderr) == (flag == "--progress"), r.stderr
            out[flag] = json.loads((d / "summary.json").read_text())
        assert out["--progress"] == out["--no-progress"] == out["--quiet"]
    # not a terminal: no report by default
    r = subprocess.run([drillsim, "--config", str(tmp_path / "c.json"), "--out", str(tmp_path / "d")],
                       capture_output=True, text=True)
    assert r.returncode == 0 and r.stderr == ""


def test_predict_applies_a_model_file_without_refitting(tmp_path):
    from _testrig import sample175_path
    from drillpy.records import rigsim
    from drillpy.jsonio import jsonable
    from drillpy.model.config import load_config
    rec = str(sample175_path())
    model = rigsim.RigModel(load_config(preset="thesis-rig")["law"], 0.3, "constant")
    (tmp_path / "model.json").write_text(json.dumps(jsonable(model.to_dict(top_speed=8.0, wob=560.0))))
    r = run_cli("predict", str(tmp_path / "model.json"), rec, "--t0", "30", "--t1", "36", "--out",
                str(tmp_path / "p"), "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert set(d) == {"short_horizon_error", "long_run"} and 0 < d["short_horizon_error"] < 3
    lr = d["long_run"]
    for k in ("ss", "stick_fraction", "cycle_frequency_hz"):
        assert set(lr[k]) >= {"measured", "predicted"}
    assert lr["ss"]["measured"] > 0.5 and len(lr["torque_p05_p95_nm"]["predicted"]) == 2
    assert (tmp_path / "p" / "summary.json").is_file() and (tmp_path / "p" / "overlay.png").is_file()
    (tmp_path / "bad.json").write_text(json.dumps({"config": {}}))
    r = run_cli("predict", str(tmp_path / "bad.json"), rec, "--json")
    assert r.returncode == 2 and "drillpy rig model" in r.stderr and len(r.stderr.strip().splitlines()) == 1


def test_every_command_is_registered_in_order_with_its_handler():
    from drillpy.cli import COMMANDS, build_parser
    sub = next(a for a in build_parser()._actions if a.dest == "command")
    assert tuple(sub.choices) == COMMANDS
    for name, p in sub.choices.items():
        assert p.get_default("func").__name__ == "cmd_" + name.replace("-", "_")


def test_mc_counts_are_ints_and_a_bad_one_is_a_one_line_error(capsys):
    from drillpy.cli import build_parser, main
    a = build_parser().parse_args(["mc", "--preset", "thesis-field", "--samples", "12", "--seed", "3"])
    assert (a.samples, a.seed, a.first_sample) == (12, 3, 0)
    assert main(["mc", "--preset", "thesis-field", "--first-sample", "x", "--no-progress"]) == 2
    assert capsys.readouterr().err == "drillpy: error: first_sample = 'x': must be an integer\n"
