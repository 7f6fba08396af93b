"""The axial-torsional model's Monte Carlo through the batched path (AxialTorsional::run_lanes): the
samples of an ``rgd-field`` study step in lanes (``MonteCarlo.lockstep``) and give the same numbers
as one by one, on 1 and 2 threads, in any chunks of the sample range (so in any batch composition),
on both schemes; ``drillpy mc``'s API (``stochastic_study``) likewise on 1 and 2 threads."""
import numpy as np
import pytest

from drillpy.model.config import load_config
from drillpy.uncertainty.montecarlo import ETA_DT_S, stochastic_study, study_config, study_engine
from drillpy.uncertainty.process import PsdModel

PSD = PsdModel(2.0, -3.22, -3.0, -1.14)  # flat to 2 Hz, then f^-3: eta std about 0.35 (test_axial_torsional.py)


def _coupled(scheme: str) -> dict:
    cfg = load_config(preset="rgd-field")
    cfg["simulation"]["scheme"] = scheme
    return study_config(cfg, 4.0, 2.0)


@pytest.mark.parametrize("scheme", ["modified_euler", "exact_modal"])
def test_coupled_monte_carlo_is_the_same_in_lanes_threads_and_chunks(scheme):
    mc = study_engine(_coupled(scheme), PSD, ETA_DT_S, 2026, 0.0)
    assert mc.lockstep  # the coupled samples go through the batched path
    speeds = [3.0, 6.0]
    n = 9
    ref = mc.severity(speeds, 0, n, None, 2, False)  # one by one: the scalar path
    assert ref.shape == (n, 2) and np.all(np.isfinite(ref))
    assert len(np.unique(ref[:, 0])) == n  # the samples differ
    for threads in (1, 2):
        assert np.array_equal(mc.severity(speeds, 0, n, None, threads, True), ref), threads
    # chunks of 1, 3 and 5 samples: each sample in another lane, beside other samples
    for cuts in ((0, 1, 4, 9), (0, 5, 8, 9), (0, 3, 6, 9)):
        parts = [mc.severity(speeds, a, b - a, None, 2, True) for a, b in zip(cuts[:-1], cuts[1:])]
        assert np.array_equal(np.vstack(parts), ref), cuts


def test_coupled_stochastic_study_is_the_same_on_one_and_two_threads():
    cfg = load_config(preset="rgd-field")
    kw = dict(psd=PSD, duration=4.0, transient=2.0, progress=False, deterministic=False)
    a = stochastic_study(cfg, [3.0, 9.0], 6, 5, threads=1, **kw)
    b = stochastic_study(cfg, [3.0, 9.0], 6, 5, threads=2, **kw)
    c = stochastic_study(cfg, [3.0, 9.0], 3, 5, threads=2, first_sample=3, **kw)
    assert np.array_equal(a.severity, b.severity)
    assert np.array_equal(a.severity[3:], c.severity)
