"""The coupled model's exact modal scheme (axial.type = rgd, simulation.scheme = exact_modal,
drill/axial_torsional.hpp) from Python: Monte Carlo samples are the same bits on any thread count and
any chunking of a stored study, and a step beyond the scheme's bound is one error naming
simulation.dt_s (tests/cpp/test_axial_exact.cpp has the convergence against the modified Euler)."""
import numpy as np
import pytest

from drillpy.model.config import load_config
from drillpy.model.simulation import simulate


def _exact(duration=6.0, dt=5e-3):
    cfg = load_config(preset="rgd-field")
    cfg["simulation"].update(scheme="exact_modal", dt_s=dt, duration_s=duration, transient_s=duration / 2)
    return cfg


def test_monte_carlo_on_the_exact_scheme_is_the_same_bits_for_any_threads_and_chunks(tmp_path):
    from drillpy.study import compute_study, mc_study
    from drillpy.uncertainty.montecarlo import stochastic_study
    from drillpy.uncertainty.process import PsdModel
    for law in (False, True):
        cfg = _exact()
        if law:
            cfg["axial"]["torque"] = "law"
            cfg["law"] = load_config(preset="thesis-field")["law"]
            cfg["simulation"]["dt_s"] = 2e-3
        psd = PsdModel(2.0, -3.22, -3.0, -1.14)
        kw = dict(psd=psd, duration=6.0, transient=3.0)
        speeds = [3.0, 9.0]
        ref = stochastic_study(cfg, speeds, 5, 11, threads=1, progress=False, **kw).severity
        assert np.all(np.isfinite(ref))
        assert np.array_equal(stochastic_study(cfg, speeds, 5, 11, threads=2, progress=False, **kw).severity, ref)
        for chunk in (1, 3):
            data = compute_study(mc_study(cfg, speeds, 5, 11, **kw), tmp_path / f"{law}-{chunk}", chunk=chunk,
                                 threads=2, progress=False)
            assert np.array_equal(data["severity"], ref)
            assert data["done"].all()


def test_a_step_beyond_the_exact_bound_is_refused_naming_simulation_dt_s():
    cfg = _exact(dt=0.03)
    with pytest.raises(ValueError, match=r"^simulation\.dt_s = 0\.03: exceeds the exact-modal bound") as e:
        simulate(cfg)
    assert str(e.value).count("simulation.dt_s") == 1
    r = simulate(_exact(duration=2.0, dt=0.02))  # within it, 3.3 x the modified Euler's bound (6.1 ms)
    assert np.isfinite(r.severity) and r.axial.present
