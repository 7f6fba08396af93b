"""One schema for a run's summary (drill/run_summary.hpp): drillsim and drillpy write the same."""
import json
import subprocess

from conftest import run_cli


def test_drillsim_and_drillpy_write_the_same_run_summary(drillsim, tmp_path):
    r = subprocess.run([drillsim, "--preset", "thesis-rig", "--out", str(tmp_path / "drillsim")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    r = run_cli("simulate", "--preset", "thesis-rig", "--out", str(tmp_path / "drillpy"), "--json")
    assert r.returncode == 0, r.stderr
    cpp = json.loads((tmp_path / "drillsim" / "summary.json").read_text())
    py = json.loads((tmp_path / "drillpy" / "summary.json").read_text())
    assert py.pop("provenance")["drillpy_version"]  # drillpy's own: version, command line, time
    assert cpp.pop("job") == "run"
    assert list(py) == ["severity", "mean_top_speed_rad_s", "stick_fraction", "stick_durations_s",
                        "slip_durations_s", "period_cycles", "period_stick_s", "period_slip_s", "config"]
    assert sorted(cpp) == sorted(py)
    assert cpp == py  # same numbers: both serialize the same RunReport through run_summary
    assert json.loads(r.stdout) == {k: v for k, v in py.items() if k != "config"}
