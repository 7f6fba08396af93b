"""The rig model's stick-slip cycle against the WOB (drillpy.records.cycle_margin): the thesis's laws scale
with the WOB, so below some WOB the model stops sticking; a model that does so within 10 % of its part's
WOB is flagged, since the record's own 5 s blocks vary that much and keep sticking."""
import numpy as np
import pytest

import drillpy
from drillpy.records import rigsim
from drillpy.records.cleaning import clean
from drillpy.records.cycle_margin import FACTORS, cycle_margin
from drillpy.records.io import read_record

LAW = drillpy.load_config(preset="rgd-rig")["law"]


def _model(damping: float) -> rigsim.RigModel:
    # the whole-rig model of the 0-20 s part (tests/python/test_axial_rig_wob.py), its damping varied
    return rigsim.RigModel(LAW, damping, "rig", 0.25, 0.0186, command_rad_s=17.27, jack_gain_n_rad=181.8,
                           jack_relaxation_s=0.0987, platform_damping=0.75, gj_factor=1.0475,
                           bit_inertia_factor=1.07, coupling_stiffness_nm_rad=41.0)


@pytest.fixture(scope="module")
def margins(testrig_record):
    rec = clean(read_record(testrig_record).select(0.0, 20.0))[0]
    thr = rigsim.stick_threshold(rec)
    return {z: cycle_margin(_model(z), rec, thr) for z in (0.02, 0.036)}


def test_the_model_sticks_more_at_more_wob_and_less_damping(margins):
    stick = {z: np.array([r["stick_fraction"] for r in m["model"]]) for z, m in margins.items()}
    assert [r["wob_factor"] for r in margins[0.02]["model"]] == list(FACTORS)
    for s in stick.values():
        assert np.all(np.diff(s) >= -0.005)          # the law's torque, and its weakening, grow with the WOB
        assert s[-1] > s[0] + 0.05
    assert np.all(stick[0.02] >= stick[0.036] - 0.005)  # less damping, longer stick phases


def test_a_model_that_stops_sticking_at_ten_percent_less_wob_is_flagged(margins, testrig_record):
    blocks = margins[0.02]["record_blocks"]
    assert len(blocks) == 4 and all(b["stick_fraction"] > 0.02 for b in blocks)  # the record sticks in every block
    assert 480.0 < min(b["wob_n"] for b in blocks) < max(b["wob_n"] for b in blocks) < 620.0
    robust, marginal = margins[0.02], margins[0.036]
    assert robust["lost_below_factor"] is None and robust["flag"] is None
    assert marginal["lost_below_factor"] >= 0.9 and "marginal" in marginal["flag"]
    one = [r for r in marginal["model"] if r["wob_factor"] == 1.0][0]
    assert one["stick_fraction"] > 0.03               # it sticks at its part's own WOB


def test_predict_notes_a_window_below_the_wob_where_the_model_lost_its_cycle(margins, testrig_record):
    from drillpy.loop.prediction import predict_record
    from drillpy.records.cycle_margin import window_note
    marginal = margins[0.036]
    lost = marginal["lost_at_wob_n"]
    assert window_note(marginal, lost + 1.0) is None and window_note(None, 400.0) is None
    assert "model's edge" in window_note(marginal, lost - 1.0)
    m = _model(0.036)
    # model.json keeps the calibration's margin; 30-40 s of sample 175 has a mean WOB of 533 N
    m.calibration = {"cycle_margin": {"lost_below_factor": 0.95, "lost_at_wob_n": 560.0}}
    pred = predict_record(m, read_record(testrig_record), t0=30.0, t1=40.0, realizations=0, threads=1)
    assert pred.summary()["notes"] and "(533 N)" in pred.notes[0] and "(560 N" in pred.notes[0]
    m.calibration = {"cycle_margin": margins[0.02]}   # a model that sticks at every WOB tried: no note
    assert predict_record(m, read_record(testrig_record), t0=30.0, t1=40.0, realizations=0, threads=1).notes == []


def test_the_models_stick_fraction_follows_the_wob_inside_its_part_far_more_than_the_records(margins):
    from drillpy.records.cycle_margin import margin_lines, wob_slope
    # the slope is a least-squares slope per 100 N
    blocks = [{"wob_n": w, "stick_fraction": 0.01 + 0.002 * (w - 500.0)} for w in (500.0, 550.0, 620.0)]
    assert wob_slope(blocks) == pytest.approx(0.2, rel=1e-9)
    assert np.isnan(wob_slope(blocks[:2])) and np.isnan(wob_slope([dict(b, wob_n=500.0) for b in blocks]))
    for m in margins.values():
        s = m["wob_slope_per_100n"]
        one = [r for r in m["model"] if r["wob_factor"] == 1.0][0]
        assert len(one["blocks"]) == 4                           # the model's own blocks in its run at the part's WOB
        assert abs(s["record"]) < 0.03                           # sample 175's blocks: no trend in the WOB
        assert s["model"] > 0.05 and s["model"] > 3 * abs(s["record"])  # the law scales with the WOB
        assert "per 100 N" in margin_lines(m)[0]


def test_block_stick_min_is_the_smallest_stick_fraction_of_the_five_second_blocks():
    from drillpy.records.io import Record
    from drillpy.records.rig_comparison import block_stick_min
    dt, n = 0.01, 2000                                           # 20 s: four 5 s blocks
    t = np.arange(n) * dt
    v = np.full(n, 10.0)
    stuck = {0: 0.10, 1: 0.05, 2: 0.0, 3: 0.20}                  # each block's share of samples at rest
    for b, share in stuck.items():
        v[b * 500:b * 500 + int(share * 500)] = 0.0
    rec = Record(time_s=t, bit_speed=v, top_speed=np.full(n, 10.0), torque_on_bit=np.ones(n))
    sel = np.ones(n, bool)
    assert block_stick_min(rec, sel, 0.5) == pytest.approx(0.0)
    v[1000:1010] = 0.0                                          # the third block sticks too: 2 %
    assert block_stick_min(rec, sel, 0.5) == pytest.approx(0.02)
    sel[1000:1300] = False                                       # a block with under half its samples is left out
    assert block_stick_min(rec, sel, 0.5) == pytest.approx(0.05)
    assert np.isnan(block_stick_min(rec, np.zeros(n, bool), 0.5))


def test_the_cli_offers_every_extra_rig_metric():
    from drillpy.cli import build_parser
    from drillpy.records.rig_calibration import EXTRA_KEYS
    sub = [a for a in build_parser()._actions if a.dest == "command"][0].choices["analyze"]
    act = [a for a in sub._actions if a.dest == "rig_metric"][0]
    assert tuple(act.choices) == EXTRA_KEYS
