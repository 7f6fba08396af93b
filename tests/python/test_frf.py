"""drillpy.uncertainty.frf: Craig-Bampton frequencies, dispersions, FRF envelopes, Conv2 and the `frf` command."""
import dataclasses
import json

import numpy as np
import pytest
from scipy.integrate import trapezoid

import drillpy as d
from drillpy import _core
from drillpy.model.config import engine_config
from drillpy.uncertainty import frf as F
from drillpy.cli import main

CFG = d.load_config(preset="thesis-ch6")
SMALL = F.with_cb_modes(CFG, [10, 6])
FREQS = np.linspace(0.05, 10.0, 200)


def test_cb_frequencies_converge_to_the_full_fe_model():
    fe = d.natural_frequencies(CFG, 5)
    errs = [np.abs(F.cb_frequencies(CFG, 5, [m, m]) / fe - 1).max() for m in (3, 7, 25)]
    assert errs[0] > errs[1] > errs[2]
    assert errs[1] < 2e-4 and errs[2] < 5e-6  # converged after about 7 modes (appendix C)
    assert fe[0] == pytest.approx(0.313, abs=1e-3)


def test_dispersion_shapes_and_cases():
    assert F.dispersions(CFG, "SM_full", 0.1).shape == (1, 3, 2)
    d1 = F.dispersions(CFG, "SM_CB1", {"K": 0.2})
    assert d1[:, 2].tolist() == [[0.2, 0.2]] * 2 and d1[:, :2].sum() == 0
    d4 = F.dispersions(CFG, "SM_CB2", case=4)
    assert d4[0].min() == 0.1 and d4[1].max() == 0.0
    d7 = F.dispersions(CFG, "SM_CB2", case=7)
    assert d7[:, :, 0].max() == 0.0 and d7[:, :, 1].min() == 0.1
    with pytest.raises(ValueError, match="case"):
        F.dispersions(CFG, "SM_CB2", case=8)
    with pytest.raises(ValueError, match="SM_CB2"):
        F.dispersions(CFG, "SM_CB1", case=2)
    with pytest.raises(ValueError, match="shape"):
        F.dispersions(CFG, "SM_CB1", np.zeros((2, 3, 2)) + [0.1, 0.2])
    with pytest.raises(ValueError, match="unknown stochastic model"):
        F.dispersions(CFG, "SM_CB3")


def test_envelope_arrays_thread_invariance_and_the_first_resonance():
    kw = dict(samples=60, seed=3, freq_hz=FREQS, progress=False)
    a = F.frf_envelope(SMALL, "SM_CB2", case=4, threads=1, **kw)
    b = F.frf_envelope(SMALL, "SM_CB2", case=4, threads=2, **kw)
    assert a.lower_db.shape == (200, 3) and a.energy.shape == (60, 3)
    np.testing.assert_array_equal(a.lower_db, b.lower_db)
    np.testing.assert_array_equal(a.upper_db, b.upper_db)
    assert np.all(a.lower_db <= a.mean_db) and np.all(a.mean_db <= a.upper_db)
    assert a.nodes == [1, 100, 200]
    # The nominal FRF peaks at the first natural frequency of the clamped string (0.313 Hz).
    low = FREQS < 0.7
    assert FREQS[low][np.argmax(a.nominal_db[low, 2])] == pytest.approx(0.313, abs=FREQS[1] - FREQS[0])


def test_conv2_is_the_running_rms_of_the_band_energy():
    env = F.frf_envelope(SMALL, "SM_CB1", 0.0, samples=3, freq_hz=FREQS, progress=False)
    a2 = 10 ** (env.nominal_db / 10)  # |a|^2 of the mean model
    expected = np.sqrt(trapezoid(a2, 2 * np.pi * FREQS, axis=0))
    np.testing.assert_allclose(env.conv2()[-1], expected, rtol=1e-5)
    env = F.frf_envelope(SMALL, "SM_CB2", 0.1, samples=400, freq_hz=FREQS, progress=False)
    c = env.conv2()
    assert np.all(np.abs(c[-1] / c[199] - 1) < 0.05)  # converging with the number of samples


def test_random_matrix_keeps_the_null_space_of_a_floating_block():
    bha_k = _core.craig_bampton(engine_config(SMALL))["substructures"][1]["K"]
    s = _core.random_matrix(bha_k, 0.3, seed=2, sample=5)
    e = np.zeros(bha_k.shape[0])
    e[-1] = 1.0  # the interface rotation: rigid-body mode of the BHA
    assert np.linalg.norm(s @ e) < 1e-12 * np.linalg.norm(s)
    assert np.linalg.eigvalsh(s[:-1, :-1]).min() > 0
    with pytest.raises(ValueError, match=r"sqrt\(\(n\+1\)/\(n\+5\)\)"):
        _core.random_matrix(bha_k, 0.9)


def test_cli_json_has_grid_mean_and_bounds(capsys):
    rc = main(["frf", "--preset", "thesis-ch6", "--model", "SM_CB2", "--case", "4", "--samples", "40",
               "--freqs", "0.05:10:120", "--json", "--no-progress"])
    assert rc == 0
    res = json.loads(capsys.readouterr().out)
    assert len(res["freq_hz"]) == 120 and res["case"] == 4 and res["samples"] == 40
    assert [p["node"] for p in res["points"]] == [1, 100, 200]
    for p in res["points"]:
        lo, mean, hi = (np.array(p[k]) for k in ("lower_db", "mean_db", "upper_db"))
        assert lo.shape == (120,) and np.all(lo <= mean) and np.all(mean <= hi)


@pytest.mark.parametrize("args,message", [
    (["--delta", "0.95"], "delta_M,inner,DP = 0.95: must be below sqrt((n+1)/(n+5)) = 0.933"),
    (["--case", "9"], "case = 9"),
    (["--samples", "0"], "samples = 0"),
    (["--freqs", "0:10:50"], "freq_hz[0] = 0"),
])
def test_cli_bad_input_is_one_line_and_status_2(capsys, args, message):
    rc = main(["frf", "--preset", "thesis-ch6", "--no-progress", "--freqs", "0.1:10:20", *args])
    err = capsys.readouterr().err
    assert rc == 2
    assert err.startswith("drillpy: error:") and err.count("\n") == 1
    assert message in err


def test_envelope_from_chunks_of_samples_is_the_envelope_bit_for_bit():
    kw = dict(case=4, seed=5, freq_hz=FREQS, progress=False)
    whole = F.frf_envelope(SMALL, "SM_CB2", samples=11, probability=0.9, **kw)
    db_all, energy_all = F.frf_samples(SMALL, "SM_CB2", samples=11, **kw)
    chunks = [F.frf_samples(SMALL, "SM_CB2", samples=n, first_sample=first, threads=t, **kw)
              for first, n, t in ((0, 5, 1), (5, 6, 2))]
    db, energy = (np.concatenate(a) for a in zip(*chunks))
    assert db.dtype == np.float32 and db.shape == (11, 3, 200) and energy.shape == (11, 3)
    np.testing.assert_array_equal(chunks[1][0], db_all[5:])
    np.testing.assert_array_equal(chunks[1][1], energy_all[5:])
    # db[r, p, f]: sample first + r, point p, frequency f.
    one = _core.StochasticModel(engine_config(SMALL), "SM_CB2", F.dispersions(SMALL, case=4))
    np.testing.assert_allclose(db[7], one.frf_db(FREQS, [1, 100, 200], 7, 5).T, atol=1e-4)
    env = F.envelope_from_samples(SMALL, db, energy, "SM_CB2", probability=0.9, **kw)
    for f in dataclasses.fields(F.FRFEnvelope):
        np.testing.assert_array_equal(getattr(env, f.name), getattr(whole, f.name), err_msg=f.name)
    with pytest.raises(ValueError, match="db"):
        F.envelope_from_samples(SMALL, db[:, :2], energy, "SM_CB2", **kw)
    with pytest.raises(ValueError, match="energy"):
        F.envelope_from_samples(SMALL, db, energy[:10], "SM_CB2", **kw)
    with pytest.raises(ValueError, match="first_sample"):
        F.frf_samples(SMALL, "SM_CB2", samples=2, first_sample=-1, **kw)
