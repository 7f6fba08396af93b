"""The stochastic torque of Eq. (4.1) in the rig model: identified on a record, drawn, predictive intervals."""
import json

import numpy as np
import pytest

from _testrig import sample175_cleaned
from drillpy.jsonio import jsonable
from drillpy.records import rig_fluctuation as rf
from drillpy.records import rigsim
from drillpy.records import rig_comparison

#: The Eq. (4.4) fit of sample 175's eta_exp, 0-20 s (drillpy analyze's psd.fit), rounded: nearly flat above f0.
SHAPE = {"type": "model_4_4", "f0_hz": 0.159, "A0": -5.14, "a": -0.486, "b": -6.03}


def test_the_band_limited_psd_integrates_to_the_level_and_is_zero_above_the_band():
    fl = rf.identify(SHAPE, 0.065, 10.0)
    f, S = np.asarray(fl["psd"]["f_hz"]), np.asarray(fl["psd"]["S"])
    assert f[0] == 0.0 and f[-1] == 10.0 and np.all(S > 0)
    assert np.sum(0.5 * (S[1:] + S[:-1]) * np.diff(f)) == pytest.approx(0.065 ** 2, rel=1e-12)
    # the shape is kept: the ratio of two ordinates is the model's
    i, j = 10, 200
    a = SHAPE["a"]
    assert S[j] / S[i] == pytest.approx((f[j] / f[i]) ** a, rel=1e-9)
    with pytest.raises(ValueError, match="eta_std"):
        rf.identify(SHAPE, 0.0, 10.0)
    with pytest.raises(ValueError, match="fmax_hz"):
        rf.identify(SHAPE, 0.1, float("nan"))


def test_a_realization_has_the_identified_level_and_is_the_same_for_the_same_seed_and_sample():
    fl = rf.identify(SHAPE, 0.1, 10.0)
    x = rf.realization(fl, 1e-3, 400.0, seed=3, sample=0)
    assert abs(np.mean(x)) < 0.02 and np.std(x) == pytest.approx(0.1, rel=0.1)
    assert np.array_equal(x, rf.realization(fl, 1e-3, 400.0, seed=3, sample=0))
    assert not np.array_equal(x, rf.realization(fl, 1e-3, 400.0, seed=3, sample=1))
    # nothing above the band: the periodogram above 10 Hz is empty to rounding
    P = np.abs(np.fft.rfft(x)) ** 2
    fq = np.fft.rfftfreq(x.size, 1e-3)
    assert P[fq > 10.5].sum() < 1e-20 * P.sum()


def _model(win, thr, fluct):
    from test_rigsim import _identified_law
    law = _identified_law(win, thr)
    return rigsim.RigModel(law, 0.05, "rig", 0.2, 0.02, command_rad_s=19.0, jack_gain_n_rad=150.0,
                           jack_relaxation_s=0.15, platform_damping=0.6, gj_factor=1.0, bit_inertia_factor=1.05,
                           coupling_stiffness_nm_rad=30.0, torque_fluctuation=fluct)


def test_predictive_intervals_widen_with_the_fluctuation_and_collapse_without_it():
    rec, rep = sample175_cleaned()
    win, thr = rec.select(30.0, 38.0), rep.stick_threshold_rad_s
    loud = _model(win, thr, rf.identify(SHAPE, 0.15, 10.0))
    quiet = _model(win, thr, rf.identify(SHAPE, 1e-9, 10.0))
    det = rigsim.simulate_model(quiet, win)
    ss0 = rig_comparison.compare(win, det, thr).simulated["ss"]
    q = rf.predictive(quiet, win, thr, n=3)
    lo, hi = q["metrics"]["ss"]["interval"]
    assert lo == pytest.approx(ss0, abs=1e-4) and hi == pytest.approx(ss0, abs=1e-4)  # eta ~ 0: the deterministic run
    p = rf.predictive(loud, win, thr, n=6)
    lo, hi = p["metrics"]["ss"]["interval"]
    assert hi - lo > 0.01  # each realization of eta drives another long run
    assert p["realizations"] == 6 and p["of"] == len(rf.METRICS) and 0 <= p["inside"] <= p["of"]
    assert p == rf.predictive(loud, win, thr, n=6)  # same seed, same numbers
    m = p["metrics"]["stick_fraction"]
    assert m["inside"] == (m["interval"][0] <= m["measured"] <= m["interval"][1])
    # the model file carries it
    back = rigsim.RigModel.from_dict(json.loads(json.dumps(jsonable(loud.to_dict()))))
    assert back.torque_fluctuation["std"] == pytest.approx(0.15)
    with pytest.raises(ValueError, match="realizations"):
        rf.predictive(loud, win, thr, n=1)
    none = _model(win, thr, None)
    with pytest.raises(ValueError, match="torque_fluctuation"):
        rf.predictive(none, win, thr, n=3)
    assert "torque_fluctuation" not in none.to_dict()


def test_no_stochastic_part_when_the_deterministic_model_departs_from_its_mean_cycle_as_much_as_the_record():
    from drillpy.records.analysis import AnalysisOptions, _torque_fluctuation
    from drillpy.uncertainty import process
    rec, rep = sample175_cleaned()
    win, thr = rec.select(30.0, 38.0), rep.stick_threshold_rad_s
    m = _model(win, thr, None)
    sims = {"polynomial, the rig modelled whole (calibrated model)": (rigsim.simulate_model(m, win), None)}
    fit = process.fit_psd_model(*process.periodogram(np.random.default_rng(0).normal(size=4096) * 0.1, 1e-2))
    for record_std, expect in ((1e-3, None), (5.0, "some")):
        S = {"eta": {"std": record_std}, "rig": {}}
        fl = _torque_fluctuation(S, fit, sims, AnalysisOptions(), lambda *_: None)
        own = S["rig"]["eta_exp_std"]["model"]
        assert 0.01 < own < 1.0  # the deterministic model's cycles depart from their mean cycle too
        if expect is None:
            assert fl is None  # nothing left for Eq. (4.1)
        else:
            assert fl["std"] == pytest.approx(np.sqrt(record_std ** 2 - own ** 2))
