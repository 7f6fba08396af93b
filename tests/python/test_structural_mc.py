"""drillpy.uncertainty.structural: SS under SM_CB2 structural uncertainty in the time domain, the eta hook,
and the `robust-ss` command."""
import json

import numpy as np
import pytest

import drillpy as d
from drillpy.uncertainty import frf as F
from drillpy.cli import main
from drillpy.uncertainty.process import THESIS_PSD, generate
from drillpy.uncertainty.structural import severity_sources, severity_study

CFG = F.with_cb_modes(d.with_overrides(d.load_config(preset="thesis-ch6"), dt=1e-3, duration=30.0,
                                       transient=15.0), [6, 3])
SPEEDS = [8.0, 20.0]


def eta_rows(samples):
    return 0.3 * np.sin(0.37 * np.arange(400)[None, :] + np.arange(samples)[:, None])  # every 0.1 s


def test_sources_statistics_and_thread_invariance():
    s = severity_sources(CFG, SPEEDS, 4, delta=0.1, eta_psd=THESIS_PSD, progress=False, threads=1)
    assert list(s) == ["deterministic", "structure (SM_CB2)", "bit-rock (eta)", "structure + bit-rock"]
    det = s["deterministic"].ss
    assert det.shape == (1, 2) and det[0, 0] > 0.5  # stick-slip at low top speed (Eq. 3.4)
    st = s["structure (SM_CB2)"]
    assert st.ss.shape == (4, 2) and np.ptp(st.ss[:, 0]) > 0
    assert np.all(st.q05 <= st.mean + 1e-12) and np.all(st.mean <= st.q95 + 1e-12)
    assert st.p_stick_slip[0] == pytest.approx(np.mean(st.ss[:, 0] > 0.5))
    again = severity_study(CFG, SPEEDS, 4, delta=0.1, progress=False, threads=2)
    np.testing.assert_array_equal(st.ss, again.ss)
    eta_only = s["bit-rock (eta)"].ss
    assert np.ptp(eta_only[:, 1]) > 0 and not np.allclose(eta_only[:, 1], det[0, 1])


def test_psd_eta_is_the_chapter_4_generator_realization():
    _, eta = generate(THESIS_PSD, dt=0.05, duration=30.0, samples=3, seed=7)
    a = severity_study(CFG, [20.0], 3, delta=0.1, eta_psd=THESIS_PSD, eta_dt=0.05, seed=7, progress=False)
    b = severity_study(CFG, [20.0], 3, delta=0.1, eta=eta, eta_dt=0.05, seed=7, progress=False)
    np.testing.assert_array_equal(a.ss, b.ss)


def test_bad_eta_is_refused():
    with pytest.raises(ValueError, match="eta"):
        severity_study(CFG, SPEEDS, 3, eta=np.zeros((2, 100)), progress=False)
    with pytest.raises(ValueError, match="either eta or eta_psd"):
        severity_study(CFG, SPEEDS, 2, eta=np.zeros((2, 10)), eta_psd=THESIS_PSD, progress=False)
    with pytest.raises(ValueError, match="must not be negative"):
        severity_study(CFG, SPEEDS, 2, eta_psd=lambda f: -np.ones_like(f), progress=False)
    with pytest.raises(ValueError, match="speeds"):
        severity_study(CFG, [], 2, progress=False)


def test_cli_robust_ss(capsys, tmp_path):
    np.save(tmp_path / "eta.npy", eta_rows(3))
    rc = main(["robust-ss", "--preset", "thesis-ch6", "--cb-modes", "6,3", "--dt", "1e-3", "--duration", "30",
               "--transient", "15", "--samples", "3", "--speeds", "8,20", "--eta-npy", str(tmp_path / "eta.npy"),
               "--eta-dt", "0.1", "--out", str(tmp_path), "--json", "--no-progress"])
    assert rc == 0
    res = json.loads(capsys.readouterr().out)
    assert set(res) == {"deterministic", "structure (SM_CB2)", "bit-rock (eta)", "structure + bit-rock"}
    assert res["structure (SM_CB2)"]["samples"] == 3 and len(res["structure + bit-rock"]["q95_ss"]) == 2
    assert (tmp_path / "severity_bands.png").stat().st_size > 10000


@pytest.mark.parametrize("source", [dict(), dict(eta_psd=THESIS_PSD)], ids=["structural", "eta_psd"])
def test_chunks_of_samples_stack_to_the_whole_run(source):
    kw = dict(delta=0.1, seed=4, progress=False, **source)
    whole = severity_study(CFG, SPEEDS, 7, **kw).ss
    head = severity_study(CFG, SPEEDS, 3, first_sample=0, **kw)
    tail = severity_study(CFG, SPEEDS, 4, first_sample=3, **kw)
    assert tail.first_sample == 3
    np.testing.assert_array_equal(np.vstack([head.ss, tail.ss]), whole)


def test_eta_rows_of_a_chunk_belong_to_its_samples():
    eta = eta_rows(5)
    whole = severity_study(CFG, [20.0], 5, eta=eta, eta_dt=0.1, progress=False).ss
    tail = severity_study(CFG, [20.0], 2, eta=eta[3:], eta_dt=0.1, first_sample=3, progress=False).ss
    np.testing.assert_array_equal(tail, whole[3:])
    with pytest.raises(ValueError, match="first_sample = -1"):
        severity_study(CFG, SPEEDS, 2, first_sample=-1, progress=False)
