"""The configuration a sweep or a map saves repeats it in drillsim, controlled top drive included
(issue 13: every run reproducible from its outputs)."""
import json
import subprocess

import numpy as np

from conftest import run_cli


def _drillsim_sweep(drillsim, cfg, folder):
    folder.mkdir()
    (folder / "config.json").write_text(json.dumps(cfg))
    r = subprocess.run([drillsim, "--config", str(folder / "config.json"), "--job", "sweep", "--format", "npy",
                        "--out", str(folder / "out")], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return np.load(folder / "out" / "severity.npy")


def test_saved_sweep_and_map_configurations_repeat_in_drillsim(drillsim, tmp_path):
    run = ["--preset", "thesis-field", "--duration", "40", "--transient", "20", "--start", "rigid",
           "--controller", "z_torque", "--drive-inertia", "2000", "--no-progress"]
    r = run_cli("sweep", *run, "--speeds", "10,16", "--out", str(tmp_path / "sweep"))
    assert r.returncode == 0, r.stderr
    sweep = json.loads((tmp_path / "sweep" / "sweep.json").read_text())
    assert sweep["config"]["top_drive"]["controller"]["type"] == "z_torque"
    assert sweep["config"]["simulation"]["start"] == "rigid"
    ss = _drillsim_sweep(drillsim, sweep["config"], tmp_path / "d1")
    np.testing.assert_allclose(ss.ravel(), sweep["severity"], rtol=1e-12)
    r = run_cli("map", *run, "--speeds-rpm", "90,150", "--wobs-kn", "200,245", "--out", str(tmp_path / "map"))
    assert r.returncode == 0, r.stderr
    m = json.loads((tmp_path / "map" / "map.json").read_text())
    ss = _drillsim_sweep(drillsim, m["config"], tmp_path / "d2")
    np.testing.assert_allclose(ss, m["severity"], rtol=1e-12)
