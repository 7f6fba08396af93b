"""The start mode is part of the configuration (simulation.start), and what drillpy saves repeats
the run in drillsim; the C++ config parser's refusals reach Python and both CLIs (issue 13)."""
import json
import subprocess

import numpy as np
import pytest

from conftest import run_cli
from drillpy import _core
from drillpy.model.config import load_config, with_overrides
from drillpy.model.simulation import simulate, sweep_severity


def _short_rig(**kw) -> dict:
    cfg = load_config(preset="thesis-rig")
    cfg["simulation"]["duration_s"] = 6.0
    cfg["simulation"]["transient_s"] = 3.0
    return with_overrides(cfg, **kw)


def test_saved_simulate_config_repeats_the_run_in_drillsim(drillsim, tmp_path):
    out = tmp_path / "py"
    r = run_cli("simulate", "--preset", "thesis-rig", "--top-speed", "5", "--wob", "0.3kN", "--start", "steady",
                "--out", str(out), "--json")
    assert r.returncode == 0, r.stderr
    py = json.loads((out / "summary.json").read_text())
    cfg = py["config"]
    assert cfg["simulation"]["start"] == "steady"
    assert cfg["operation"]["top_speed_rad_s"] == 5.0
    assert cfg["operation"]["wob_n"] == pytest.approx(300.0)
    (tmp_path / "saved.json").write_text(json.dumps(cfg))
    r = subprocess.run([drillsim, "--config", str(tmp_path / "saved.json"), "--out", str(tmp_path / "cpp")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    cpp = json.loads((tmp_path / "cpp" / "summary.json").read_text())
    assert cpp["severity"] == py["severity"]
    assert cpp["stick_fraction"] == py["stick_fraction"]
    assert cpp["config"] == cfg


def test_start_defaults_to_the_configuration_and_an_explicit_one_wins():
    assert load_config(preset="thesis-rig")["simulation"]["start"] == "rest"
    steady = _short_rig(start="steady")
    assert steady["simulation"]["start"] == "steady" and _core.Config(json.dumps(steady)).start == "steady"
    rest = _short_rig()
    a = simulate(steady, record=False)
    b = simulate(rest, start="steady", record=False)
    assert (a.severity, a.stick_fraction) == (b.severity, b.stick_fraction)
    assert b.config["simulation"]["start"] == "steady"  # the effective configuration carries it
    c = simulate(steady, start="rest", record=False)
    d = simulate(rest, record=False)
    assert (c.severity, c.stick_fraction) == (d.severity, d.stick_fraction)
    assert c.config["simulation"]["start"] == "rest"
    sp = [4.0, 8.0]
    np.testing.assert_array_equal(sweep_severity(steady, sp, progress=False),
                                  sweep_severity(rest, sp, progress=False, start="steady"))
    np.testing.assert_array_equal(sweep_severity(steady, sp, progress=False, start="rest"),
                                  sweep_severity(rest, sp, progress=False))
    with pytest.raises(ValueError, match=r"simulation.start = \"spinning\""):
        _short_rig(start="spinning")
    with pytest.raises(ValueError, match="start = 'spinning'"):
        simulate(rest, start="spinning")


def test_cli_start_lands_in_the_saved_sweep_configuration(tmp_path):
    r = run_cli("sweep", "--preset", "thesis-rig", "--duration", "4", "--speeds", "4,8", "--start", "rigid",
                "--no-progress", "--out", str(tmp_path))
    assert r.returncode == 0, r.stderr
    assert json.loads((tmp_path / "sweep.json").read_text())["config"]["simulation"]["start"] == "rigid"


@pytest.mark.parametrize("field, text, message", [
    ("elements", '"elements": 4294967316', "elements = 4294967316"),
    ("modes", '"modes": 4294967297', "rom.modes = 4294967297"),
    ("modes", '"modes": 1e12', "rom.modes = 1000000000000"),
    ("modes", '"modes": 2.5', "rom.modes = 2.5: must be an integer"),
])
def test_integers_are_range_checked_not_wrapped(tmp_path, field, text, message):
    cfg = load_config(preset="thesis-rig")
    body = json.dumps(cfg)
    key = f'"{field}": '
    start = body.index(key)
    end = start + len(key)
    while body[end] not in ",}":
        end += 1
    (tmp_path / "c.json").write_text(body[:start] + text + body[end:])
    with pytest.raises(ValueError, match=message.replace(".", r"\.")):
        _core.Config((tmp_path / "c.json").read_text())
    r = run_cli("simulate", "--config", str(tmp_path / "c.json"))
    assert r.returncode == 2 and message in r.stderr, r.stderr


def test_duplicate_keys_and_bad_fractions_are_refused(drillsim, tmp_path):
    body = json.dumps(load_config(preset="thesis-rig"))
    dup = body.replace('"modes": 1', '"modes": 1, "modes": 2', 1)
    assert dup != body
    (tmp_path / "dup.json").write_text(dup)
    with pytest.raises(ValueError, match='rom.modes: duplicate key "modes"'):
        _core.Config(dup)
    r = run_cli("simulate", "--config", str(tmp_path / "dup.json"))
    assert r.returncode == 2 and "duplicate key 'modes'" in r.stderr, r.stderr
    r = subprocess.run([drillsim, "--config", str(tmp_path / "dup.json"), "--out", str(tmp_path / "o")],
                       capture_output=True, text=True)
    assert r.returncode == 2 and 'rom.modes: duplicate key "modes"' in r.stderr, r.stderr
    cfg = load_config(preset="thesis-rig")
    cfg["metrics"]["stick_threshold_fraction"] = 5
    with pytest.raises(ValueError, match="metrics.stick_threshold_fraction = 5: must be between 0 and 1"):
        load_config(config=cfg)


def test_negative_threads_are_refused_everywhere(drillsim, tmp_path):
    r = run_cli("sweep", "--preset", "thesis-rig", "--threads", "-4", "--speeds", "4,8")
    assert r.returncode == 2 and "threads = '-4'" in r.stderr, r.stderr
    r = subprocess.run([drillsim, "--preset", "thesis-rig", "--threads", "-4", "--out", str(tmp_path)],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "--threads = -4" in r.stderr, r.stderr
    with pytest.raises(ValueError, match="threads = -4"):
        sweep_severity(_short_rig(), [4.0], progress=False, threads=-4)


def test_drillsim_version(drillsim):
    from pathlib import Path
    r = subprocess.run([drillsim, "--version"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    cmake = (Path(__file__).resolve().parents[2] / "CMakeLists.txt").read_text()
    version = cmake.split("project(drillpy VERSION ", 1)[1].split()[0]
    assert r.stdout == f"drillsim {version}\n"


@pytest.mark.parametrize("kw, message", [
    ({"elements": 4294967316}, "elements = 4294967316"),
    ({"modes": 4294967297}, "modes = 4294967297"),
    ({"elements": 2.5}, "elements = 2.5"),
])
def test_count_overrides_are_range_checked(kw, message):
    with pytest.raises(ValueError, match=message):
        with_overrides(load_config(preset="thesis-rig"), **kw)
