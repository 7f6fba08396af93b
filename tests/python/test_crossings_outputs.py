"""Issue 13 item 5: SS crossings in either direction, CSV precision, analyze's output folder, progress bars."""
import json

import numpy as np
import pytest

from conftest import run_cli


def test_crossings_of_a_curve_rising_with_speed():
    from drillpy.model.simulation import severity_crossings, severity_threshold
    sp = np.linspace(2.0, 12.0, 11)
    ss = np.clip(0.1 * (sp - 1.8), 0.0, None)  # 0.5 at 6.8 rad/s, rising
    c = severity_crossings(sp, ss)
    assert len(c) == 1 and c[0]["direction"] == "rising"
    assert c[0]["speed_rad_s"] == pytest.approx(6.8)
    assert severity_threshold(sp, ss) is None   # the falling threshold keeps its meaning
    assert severity_crossings(sp[::-1], ss[::-1]) == c  # order of the grid does not matter


def test_crossings_of_a_falling_and_a_two_sided_curve():
    from drillpy.model.simulation import severity_crossings, severity_threshold
    sp = np.arange(6.0, 27.0)
    fall = np.where(sp < 16.0, 1.2, 0.1)
    c = severity_crossings(sp, fall)
    assert [x["direction"] for x in c] == ["falling"]
    assert c[0]["speed_rad_s"] == pytest.approx(severity_threshold(sp, fall))
    band = np.where((sp > 10.0) & (sp < 20.0), 0.9, 0.2)  # stick-slip in a band
    c = severity_crossings(sp, band)
    assert [x["direction"] for x in c] == ["rising", "falling"]
    assert c[1]["speed_rad_s"] == pytest.approx(severity_threshold(sp, band))
    assert severity_crossings(sp, np.zeros(sp.size)) == [] and severity_crossings(sp, np.ones(sp.size)) == []
    with pytest.raises(ValueError, match="one per speed"):
        severity_crossings(sp, band[:-1])


def test_sweep_reports_a_rising_crossing(monkeypatch, capsys, tmp_path):
    import drillpy.model.simulation as sim
    from drillpy.cli import main
    monkeypatch.setattr(sim, "sweep_severity", lambda cfg, speeds, **kw: np.clip(0.1 * (np.asarray(speeds) - 1.8), 0, None))
    assert main(["sweep", "--preset", "thesis-field", "--speeds", "2:12:11", "--no-progress", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["threshold_rad_s"] is None
    assert len(d["crossings"]) == 1 and d["crossings"][0]["direction"] == "rising"
    assert d["crossings"][0]["speed_rad_s"] == pytest.approx(6.8)
    assert main(["sweep", "--preset", "thesis-field", "--speeds", "2:12:11", "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "rising at 6.80 rad/s: stick-slip above it" in out and "no crossing" not in out


def test_sweep_json_crossings_on_the_preset():
    r = run_cli("sweep", "--preset", "thesis-field", "--law", "hysteretic", "--beta1", "0.14",
                "--speeds", "6:27:22", "--json", "--no-progress")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    falling = [c for c in d["crossings"] if c["direction"] == "falling"]
    # the threshold is the bisection's, inside the grid cell of the last falling crossing (issue 31)
    lo, hi = d["threshold_bracket_rad_s"]
    cell = np.floor(falling[-1]["speed_rad_s"])
    assert d["threshold_method"] == "bisection" and cell <= lo < d["threshold_rad_s"] < hi <= cell + 1.0
    assert hi - lo <= 2 * 0.02 and d["threshold_rpm"] == pytest.approx(d["threshold_rad_s"] * 30 / np.pi)


def test_time_format_follows_the_step():
    from drillpy.reports.simulation import time_format as _time_format
    assert _time_format(np.arange(0, 1, 1e-3)) == "%.3f"
    assert _time_format(np.arange(0, 1, 2.5e-4)) == "%.5f"
    assert _time_format(np.arange(0, 10, 0.5)) == "%.1f"
    assert _time_format([0.0]) == "%.9f"


def test_simulate_writes_series_csv_at_the_data_precision(tmp_path):
    r = run_cli("simulate", "--preset", "thesis-rig", "--out", str(tmp_path / "run"), "--no-progress")
    assert r.returncode == 0, r.stderr
    lines = [ln for ln in (tmp_path / "run" / "series.csv").read_text().splitlines() if not ln.startswith("#")]
    assert lines[0].startswith("time_s,bit_speed_rad_s")
    rows = [ln.split(",") for ln in lines[1:]]
    assert all(len(x.split(".")[1]) == 3 for x in (row[0] for row in rows[:50]))   # 1 ms step
    digits = max(len(v.lstrip("-").split("e")[0].replace(".", "").lstrip("0")) for row in rows for v in row[1:])
    assert digits <= 7
    data = np.genfromtxt(lines, delimiter=",", names=True)
    assert data["time_s"][-1] == pytest.approx(40.0) and np.all(np.isfinite(data["bit_speed_rad_s"]))


def test_failed_analyze_leaves_no_new_folder(tmp_path):
    r = run_cli("analyze", str(tmp_path / "nope.mat"), "--out", str(tmp_path / "out"), "--no-progress")
    assert r.returncode == 2 and "nope.mat" in r.stderr
    r = run_cli("analyze", str(tmp_path / "nope.mat"), "--out", str(tmp_path / "out2"), "--folds", "x")
    assert r.returncode == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def _failing_analysis(out_dir, *args, **kw):
    from pathlib import Path
    Path(out_dir, "figs").mkdir(parents=True, exist_ok=True)
    (Path(out_dir) / "figs" / "half.png").write_text("")
    raise ValueError("failed after the folder was made")


def test_analyze_removes_the_folder_it_made_when_it_fails(tmp_path, monkeypatch, capsys):
    import drillpy.reports.analysis as analysis
    from drillpy.cli import main
    rec = tmp_path / "r.csv"
    rec.write_text("")
    monkeypatch.setattr(analysis, "analyze_record", lambda record, out_dir, *a, **k: _failing_analysis(out_dir))
    assert main(["analyze", str(rec), "--out", str(tmp_path / "new" / "deeper"), "--no-progress"]) == 2
    assert "failed after the folder was made" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.csv"]       # new/ and new/deeper/ removed
    (tmp_path / "old").mkdir()
    (tmp_path / "old" / "keep.txt").write_text("mine")
    assert main(["analyze", str(rec), "--out", str(tmp_path / "old"), "--no-progress"]) == 2
    assert (tmp_path / "old" / "keep.txt").read_text() == "mine"          # a folder that existed stays
    assert main(["analyze", str(rec), "--out", str(tmp_path / "old" / "sub"), "--no-progress"]) == 2
    assert sorted(p.name for p in (tmp_path / "old").iterdir()) == ["figs", "keep.txt"]


def test_log_progress_echoes_lines_and_moves_through_the_stages(capsys):
    from drillpy.progress import log_progress
    with log_progress((("record:", "cycles"), ("cycles:", "fits")), "analyze", total=2) as log:
        log("record: 10 samples")
        log("  artifacts: none")
        log("cycles: 3 valid")
    assert capsys.readouterr().out == "record: 10 samples\n  artifacts: none\ncycles: 3 valid\n"
    with log_progress((("  candidate ", "candidates"),), "loop", enabled=False, echo=None, count=True) as log:
        log("  candidate friction")
    assert capsys.readouterr().out == ""


def test_analyze_and_loop_have_a_no_progress_flag():
    from drillpy.cli import build_parser
    p = build_parser()
    assert p.parse_args(["analyze", "r.mat", "--out", "o", "--no-progress"]).no_progress
    assert p.parse_args(["loop", "r.mat", "--preset", "thesis-rig", "--out", "o", "--no-progress"]).no_progress
    assert not p.parse_args(["analyze", "r.mat", "--out", "o"]).no_progress
