"""Plausibility warnings (issue 13 item 3): sample 175 with the thesis-rig preset is plausible; the
same record with a unit error, or a declared string of another first mode, gets the warning that
names the channel and the value; ``drillpy analyze`` and ``drillpy loop`` print them on stderr and
write them into their JSON and report.md."""
import copy
import json

import numpy as np
import pytest

from _testrig import sample175_cleaned, sample175_raw
from conftest import run_cli
from drillpy.model.config import load_config
from drillpy.records import plausibility as pl
from drillpy.records.io import write_csv

F1_RIG_HZ = 2.89  # first natural frequency of the thesis-rig preset (Table 5.1)


@pytest.fixture(scope="module")
def rig():
    return load_config(preset="thesis-rig")


def _codes(ws):
    return [w.code for w in ws]


def _scaled(**factors):
    """Sample 175 as read, with channels (and ``time_s``) multiplied by the given factors."""
    rec = sample175_raw()
    for name, f in factors.items():
        setattr(rec, name, getattr(rec, name) * f)
    return rec


def test_sample175_with_the_rig_preset_is_plausible(rig):
    """The real record, as read (encoder spikes and all) and cleaned: no warning."""
    assert pl.check_record(sample175_raw(), rig) == []
    assert pl.check_record(sample175_cleaned()[0], rig) == []
    period = pl.cycle_period_s(sample175_cleaned()[0])
    assert 1.0 <= period * F1_RIG_HZ <= 1.1  # a cycle lasts about one first period (0.362 s)
    assert pl.torque_capacity_nm(rig) == pytest.approx(20.9, rel=0.01)  # 4 N m measured at most


def test_time_in_ms_labelled_s_gives_the_time_unit_warning(rig):
    """Time stamps 1000 times too large: 1 Hz on a 2.89 Hz string, and a 362 s stick-slip period."""
    ws = pl.check_record(_scaled(time_s=1000.0), rig)
    assert _codes(ws) == ["time_unit", "period"]
    w = ws[0]
    assert w.channel == "time" and w.unit == "Hz" and w.value == pytest.approx(1.0)
    assert w.plausible[0] == pytest.approx(2 * F1_RIG_HZ, rel=1e-3) and w.plausible[1] == pl.MAX_SAMPLE_RATE_HZ
    assert w.message.startswith("time: sampling rate 1 Hz") and "ms labelled s" in w.message
    p = ws[1]
    assert p.value == pytest.approx(362.0, rel=0.01) and p.value > p.plausible[1]
    assert "362" in p.message and "0.346 s" in p.message


def test_speeds_multiplied_by_60_give_the_speed_warnings(rig):
    """Both speeds 60 times too large: top speed ~930 rad/s, bit speed ~1200 rad/s."""
    ws = pl.check_record(_scaled(top_speed=60.0, bit_speed=60.0), rig)
    assert _codes(ws) == ["top_speed", "operating_point", "bit_speed"]
    top, op, bit = ws
    assert op.value == pytest.approx(60 * 8.47, rel=0.05) and op.plausible[1] == pytest.approx(4 * 8.47, rel=1e-3)
    assert top.channel == "top_speed" and top.value > pl.MAX_TOP_SPEED_RAD_S and top.unit == "rad/s"
    assert top.plausible == (0.0, pl.MAX_TOP_SPEED_RAD_S)
    assert top.message.startswith(f"top_speed: 99.5th percentile of |top speed| {top.value:.4g} rad/s")
    assert bit.channel == "bit_speed" and bit.value > pl.MAX_BIT_SPEED_RAD_S
    assert f"{bit.value:.4g} rad/s" in bit.message


def test_a_stick_slip_period_far_from_the_first_mode_gives_the_period_warning(rig):
    """The rig's record against a string whose bit inertia is 1000 times the rig's (first mode
    0.09 Hz): the 0.362 s cycles are 0.03 first periods; and the record 20 times too slow against the
    rig (7.2 s cycles, 21 first periods, at a plausible 50 Hz): the period warning alone."""
    heavy = copy.deepcopy(rig)
    heavy["string"]["lumped_inertias"][0]["inertia_kg_m2"] *= 1000.0
    ws = pl.check_record(sample175_raw(), heavy)
    assert _codes(ws) == ["period"]
    w = ws[0]
    assert w.channel == "bit_speed" and w.unit == "s" and w.value == pytest.approx(0.362, rel=0.01)
    assert w.value < w.plausible[0]
    assert w.message.startswith("bit_speed: the median stick-slip cycle period 0.362 s")
    slow = pl.check_record(_scaled(time_s=20.0), rig)
    assert _codes(slow) == ["period"] and slow[0].value / (1 / F1_RIG_HZ) == pytest.approx(20.9, rel=0.02)


@pytest.mark.parametrize("factors, codes", [
    ({"time_s": 1e-3}, ["time_unit", "duration"]),           # s labelled ms: 1 MHz, 40 ms
    ({"bit_speed": 30 / np.pi}, ["bit_speed"]),              # the bit speed alone in RPM: 22 x the top speed
    ({"torque_on_bit": 1e3}, ["torque"]),                    # kN m labelled N m: beyond the bar's yield
    ({"top_speed": 30 / np.pi, "bit_speed": 30 / np.pi}, ["operating_point"]),  # RPM labelled rad/s: 81 rad/s
], ids=["s-as-ms", "bit-rpm", "torque-kNm", "rpm-as-rad-s"])
def test_other_unit_errors(rig, factors, codes):
    ws = pl.check_record(_scaled(**factors), rig)
    assert _codes(ws) == codes
    for w in ws:
        assert w.message.startswith(w.channel + ":") and not w.plausible[0] <= w.value <= w.plausible[1]
        d = w.as_dict()
        assert json.loads(json.dumps(d, allow_nan=False)) == d


def test_markdown_section():
    w = pl.PlausibilityWarning("torque", "torque_on_bit", "torque_on_bit: too large", 5.0, (0.0, 1.0), "N m")
    assert pl.markdown([]) == ["## Warnings", "", "none", ""]
    assert pl.markdown([w]) == pl.markdown([w.as_dict()]) == ["## Warnings", "", "- torque_on_bit: too large", ""]


@pytest.fixture(scope="module")
def ms_csv(tmp_path_factory):
    """The first 10 s of sample 175 written with its time in ms under the column ``time_s``."""
    rec = sample175_raw().select(0.0, 10.0)
    rec.time_s = rec.time_s * 1000.0
    return write_csv(rec, tmp_path_factory.mktemp("ms") / "ms_as_s.csv")


def test_analyze_prints_and_writes_the_warnings(tmp_path, ms_csv):
    """drillpy analyze (no simulation, no folds: ~5 s): stderr, --json, summary.json and report.md."""
    out = tmp_path / "a"
    p = run_cli("analyze", str(ms_csv), "--out", str(out), "--no-sim", "--folds", "0", "--json", "--no-progress")
    assert p.returncode == 0, p.stderr
    lines = [ln for ln in p.stderr.splitlines() if ln.startswith("drillpy: warning: ")]
    assert len(lines) == 2 and lines[0].startswith("drillpy: warning: time: sampling rate 1 Hz")
    printed = json.loads(p.stdout)["warnings"]
    S = json.loads((out / "summary.json").read_text())
    assert printed == S["warnings"] and [w["code"] for w in printed] == ["time_unit", "period"]
    assert S["warnings"][0]["value"] == pytest.approx(1.0) and S["warnings"][0]["unit"] == "Hz"
    assert S["warnings"][1]["value"] == pytest.approx(S["cycles"]["period_s"]["median"])  # the period reported
    report = (out / "report.md").read_text()
    section = report.split("## Warnings\n\n")[1].split("\n\n")[0].splitlines()
    assert section == ["- " + w["message"] for w in printed]
    assert lines == ["drillpy: warning: " + w["message"] for w in printed]


def test_analyze_of_the_real_record_reports_none(tmp_path):
    out = tmp_path / "a"
    rec = sample175_raw().select(0.0, 10.0)
    p = run_cli("analyze", str(write_csv(rec, tmp_path / "s175.csv")), "--out", str(out), "--no-sim", "--folds", "0",
                "--no-progress")
    assert p.returncode == 0, p.stderr
    assert "drillpy: warning" not in p.stderr
    assert json.loads((out / "summary.json").read_text())["warnings"] == []
    assert "## Warnings\n\nnone\n" in (out / "report.md").read_text()


def test_analyze_with_simulations_refuses_a_record_slower_than_the_first_mode(tmp_path, ms_csv):
    """The rig calibration would simulate 10 000 s per run at 1 Hz: one error, after the warnings."""
    p = run_cli("analyze", str(ms_csv), "--out", str(tmp_path / "a"), "--folds", "0", "--no-progress")
    assert p.returncode == 2
    err = p.stderr.splitlines()
    assert err[0].startswith("drillpy: warning: time: sampling rate 1 Hz")
    assert err[-1].startswith("drillpy: error: time: sampling rate 1 Hz") and "--no-sim" in err[-1]
    assert not (tmp_path / "a").exists()


def test_loop_prints_the_warnings_before_it_refuses_the_record(tmp_path, ms_csv):
    """At 1 Hz the loop's 0.25 s horizons cannot be cut: the refusal stays, the warnings explain it."""
    p = run_cli("loop", str(ms_csv), "--preset", "thesis-rig", "--out", str(tmp_path / "l"), "--no-progress")
    assert p.returncode != 0
    err = p.stderr.splitlines()
    assert err[0].startswith("drillpy: warning: time: sampling rate 1 Hz") and "drillpy: error:" in err[-1]


def test_loop_writes_the_warnings(tmp_path, monkeypatch):
    """What the check returns reaches loop.json and report.md (a short loop on 12 s of sample 175)."""
    import drillpy.loop.run as run
    from drillpy.loop import LoopOptions
    from drillpy.reports.loop import loop_record
    w = pl.PlausibilityWarning("torque", "torque_on_bit", "torque_on_bit: a test warning", 5.0, (0.0, 1.0), "N m")
    monkeypatch.setattr(run, "check_record", lambda record, cfg: [w])
    monkeypatch.setattr(run, "emit", lambda ws: None)
    opt = LoopOptions(rate_hz=100.0, max_steps=0, long_run=False, discovery=False, backward=False)
    js = loop_record(sample175_raw().select(0.0, 12.0), tmp_path, preset="thesis-rig", options=opt,
                     log=lambda *a: None)
    assert js["warnings"] == [w.as_dict()]
    assert json.loads((tmp_path / "loop.json").read_text())["warnings"] == [w.as_dict()]
    assert "## Warnings\n\n- torque_on_bit: a test warning\n" in (tmp_path / "report.md").read_text()


def test_fitted_values_silence_only_the_configuration_check():
    """A calibration's trial configurations are judged by their bounds, not by the typed-input check:
    inside ``fitted_values`` a 45 rad/s motor command warns nothing, another warning still passes,
    and outside it the same configuration warns again."""
    import warnings

    from drillpy.model import plausibility as P
    cfg = load_config(preset="thesis-rig")
    cfg["operation"]["top_speed_rad_s"] = 45.0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with P.fitted_values():
            P.warn(P.check_config(cfg))
            warnings.warn("other", UserWarning)
        inside = [w.category for w in caught]
        P.warn(P.check_config(cfg))
    assert inside == [UserWarning]
    assert [w.category for w in caught][1:] and all(c is P.ImplausibleConfiguration for c in
                                                    [w.category for w in caught][1:])
