"""The drillpy and drillsim commands: outputs, exit codes and one-line errors."""
import json
import time

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
    (["--preset", "thesis-field", "--out", "/etc/hostname"], "--out: /etc/hostname is a file, not a folder"),
])
def test_drillsim_errors(drillsim, args, needle, tmp_path):
    out = [] if "--out" in args else ["--out", str(tmp_path / "out")]
    r = subprocess.run([drillsim, *args, *out], capture_output=True, text=True)
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


def test_drillsim_refuses_a_deeply_nested_config_at_once_in_one_short_line(drillsim, tmp_path):
    deep = tmp_path / "deep.json"
    deep.write_text("[" * 200_000 + "]" * 200_000)  # issue 31: 67 s and a 400 KB line before
    t0 = time.perf_counter()
    r = subprocess.run([drillsim, "--config", str(deep), "--out", str(tmp_path / "o")], capture_output=True, text=True)
    assert time.perf_counter() - t0 < 5.0
    assert r.returncode == 2 and r.stderr == (f"drillsim: error: --config {deep}: JSON nested too deep: more than 64 "
                                              "levels of arrays and objects (a configuration has 4)\n")
    assert not (tmp_path / "o").exists()


def test_drillsim_too_many_steps_names_the_time_step_and_the_duration(drillsim, tmp_path):
    import drillpy
    cfg = drillpy.load_config(preset="thesis-rig")
    cfg["simulation"]["dt_s"] = 1e-12
    (tmp_path / "c.json").write_text(json.dumps(cfg))
    r = subprocess.run([drillsim, "--config", str(tmp_path / "c.json"), "--out", str(tmp_path / "o")],
                       capture_output=True, text=True)
    assert r.returncode == 2 and r.stderr.count("\n") == 1
    assert r.stderr.startswith("drillsim: error: simulation.dt_s = 1e-12 with simulation.duration_s = "), r.stderr
    assert "a time step below 1 us" in r.stderr


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
    assert set(d) == {"short_horizon_error", "long_run", "record"} and 0 < d["short_horizon_error"] < 3
    assert d["record"]["window_s"] == pytest.approx([30.0, 36.0], abs=2e-3) and "top_speed" in d["record"]["artifacts"]  # its encoder spikes
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


def _one_error_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("drillpy: error: "), err
    return err[0]


def test_usage_errors_are_one_line_and_negative_numbers_are_values(capsys):
    """Found by test_fuzz.py: argparse dumped its usage; '--speeds -10,-5' read as an option."""
    from drillpy.cli import main
    with pytest.raises(SystemExit) as e:
        main(["modes", "--preset", "thesis-rig", "--elements", "x"])
    assert e.value.code == 2
    assert _one_error_line(capsys) == ("drillpy: error: argument --elements: invalid int value: 'x' "
                                       "(see drillpy modes --help)")
    assert main(["sweep", "--preset", "thesis-rig", "--speeds", "-10,-5", "--no-progress"]) == 2
    assert "sweep.top_speeds_rad_s[0] = -10: must be positive" in _one_error_line(capsys)


@pytest.mark.parametrize("args, needle", [
    (["modes", "--preset", "thesis-rig", "-n", "0"], "-n = 0: must be an integer between 1 and 20"),
    (["modes", "--preset", "thesis-rig", "-n", "9999999999999999999"], "-n = 9999999999999999999"),
    (["modes", "--preset", "thesis-rig", "--threads", str(10**30)], f"threads = '{10**30}'"),
    (["sweep", "--preset", "thesis-rig", "--speeds", "6:27:10000000000000"], "at most 100000 points"),
    (["sweep", "--preset", "thesis-rig", "--speeds", "inf,8"], "--speeds = 'inf,8': the values must be finite"),
    (["frf", "--preset", "thesis-ch6", "--case", str(10**25)], f"case = {10**25}: must be an integer between 1 and 7"),
    (["robust-ss", "--preset", "thesis-ch6", "--samples", str(2**63)], f"samples = {2**63}"),
    (["robust-ss", "--preset", "thesis-ch6", "--eta-npy", "/nonexistent.npy"], "--eta-npy = '/nonexistent.npy': no such"),
])
def test_out_of_range_options_name_the_option(capsys, args, needle):
    """Found by test_fuzz.py: pybind11 cast errors, a misleading field, a grid of 10^13 points."""
    from drillpy.cli import main
    assert main(args) == 2
    assert needle in _one_error_line(capsys)


def test_files_given_to_options_are_checked_before_work(tmp_path, capsys):
    """Found by test_fuzz.py: '[Errno 17] File exists' after the run, numpy's pickle text, a warning."""
    from drillpy.cli import main
    f = tmp_path / "file.txt"
    f.write_text("not a folder")
    assert main(["simulate", "--preset", "thesis-rig", "--out", str(f)]) == 2
    assert f"--out = '{f}': is a file, not a folder" in _one_error_line(capsys)
    assert main(["simulate", "--preset", "thesis-rig", "--out", str(f / "sub")]) == 2
    assert f"'{f}' on its path is a file" in _one_error_line(capsys)
    assert main(["robust-ss", "--preset", "thesis-ch6", "--eta-npy", str(f)]) == 2
    assert "not a NumPy .npy array file" in _one_error_line(capsys)
    (tmp_path / "empty.csv").write_text("")
    assert main(["mc", "--preset", "thesis-rig", "--psd-table", str(tmp_path / "empty.csv")]) == 2
    assert "empty.csv': no data" in _one_error_line(capsys)


def test_analyze_options_are_checked_before_work(tmp_path, capsys):
    """Found by test_fuzz.py: '--folds -2' gave numpy's 'number sections must be larger than 0.',
    '--psd-fmax 0' a fit error, '--calibrate 1:0' a tuple of np.float64."""
    from drillpy.cli import main
    p = tmp_path / "r.csv"
    p.write_text("time_s,bit_speed_rad_s\n" + "\n".join(f"{k / 1000},{5 + np.sin(k / 50)}" for k in range(500)))
    for args, needle in ((["--folds", "-2"], "--folds = -2: must be an integer >= 0"),
                         (["--psd-fmax", "0"], "--psd-fmax = 0.0: must be a positive number [Hz]"),
                         (["--calibrate", "1:0"], "--calibrate = '1:0': needs finite T0 < T1 [s]"),
                         (["--calibrate", "0:x"], "--calibrate = '0:x': use T0:T1 [s]"),
                         (["--rig-fix", "bogus=1"], "--rig-fix = 'bogus=1': 'bogus' is not a parameter of the rig model"),
                         (["--rig-fix", "static_torque_factor=5"],
                          "--rig-fix = 'static_torque_factor=5': static_torque_factor must be a number within its "
                          "physical range [1, 1.2]"),
                         (["--rig-fix", "gj_factor=nan"], "gj_factor must be a number within its physical range"),
                         (["--rig-fix", "gj_factor"], "--rig-fix = 'gj_factor': give NAME=VALUE or NAME=free"),
                         (["--horizon-weight", "-1"], "--horizon-weight = -1.0: must be a non-negative number"),
                         (["--rig-search", "4"], "--rig-search = '4': use STARTS,EVALUATIONS, two integers"),
                         (["--rig-search", "0,200"], "--rig-search = '0,200': the starts and the evaluations must each "
                                                     "be at least 1")):
        assert main(["analyze", str(p), "--out", str(tmp_path / "out"), "--no-progress", *args]) == 2
        assert needle in _one_error_line(capsys)
        assert not (tmp_path / "out").exists()


def test_json_outputs_hold_null_not_nan(tmp_path, capsys):
    """Found by test_fuzz.py: robust-ss printed and wrote NaN (a bootstrap interval of two samples)."""
    from drillpy.cli import main
    args = ["robust-ss", "--preset", "thesis-ch6", "--samples", "2", "--speeds", "8", "--duration", "0.1",
            "--transient", "0", "--no-progress", "--json", "--out", str(tmp_path / "rs")]
    assert main(args) == 0

    def refuse(token):
        raise AssertionError(token)
    d = json.loads(capsys.readouterr().out, parse_constant=refuse)
    json.loads((tmp_path / "rs" / "robust_ss.json").read_text(), parse_constant=refuse)
    assert any(v is None for st in d.values() if isinstance(st, dict) for v in st.get("p05_speed_bootstrap", {}).values())


def test_a_failed_command_removes_the_output_folder_it_created(tmp_path, capsys):
    """Found by test_fuzz.py: drillpy report left its folder when the run failed (dt above the stability bound)."""
    from drillpy.cli import main
    assert main(["report", "--preset", "thesis-rig", "--dt", "1", "--no-progress", "--out", str(tmp_path / "a" / "b")]) == 2
    assert "stability bound" in _one_error_line(capsys)
    assert not (tmp_path / "a").exists()


def test_eta_std_too_large_is_an_error_not_an_overflow(capsys):
    """Found by test_fuzz.py (long run): --eta-std 1e180 raised OverflowError (34, 'Numerical result out of range')."""
    from drillpy.cli import main
    assert main(["mc", "--preset", "thesis-rig", "--eta-std", "1e180", "--no-progress"]) == 2
    assert "--eta-std = 1e+180: too large" in _one_error_line(capsys)


@pytest.mark.parametrize("args, needle", [
    (["convergence", "--preset", "thesis-rig", "--dt", "1"], "--dt = 1.0: convergence runs its own ladder"),
    (["frf", "--preset", "thesis-rig", "--samples", "3"], "--cb-modes: the configuration 'thesis-rig' sets no "
                                                          "craig_bampton.modes"),
])
def test_options_a_command_cannot_honour_are_refused(args, needle, capsys):
    """Reported by test_fuzz.py: convergence ignored --dt silently; frf on a string without Craig-Bampton
    modes blamed craig_bampton.modes = 0, a field the user never wrote."""
    from drillpy.cli import main
    assert main([*args, "--no-progress"]) == 2
    assert needle in _one_error_line(capsys)


def test_too_few_bit_speed_samples_name_the_channel():
    from drillpy.records.signals import segment_cycles
    with pytest.raises(ValueError, match=r"^bit_speed: 2 valid samples of 4: too few"):
        segment_cycles(np.array([1.0, np.nan, 2.0, np.nan]), 0.01, 0.1)
