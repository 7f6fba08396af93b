"""drillpy.uncertainty.robust_speed: the 5 % speed located by bisection on the same samples, and its bootstrap
interval, on a study whose exact answer is known."""
import numpy as np
import pytest

from drillpy.uncertainty.robust_speed import bootstrap_interval, exceedance, p_speed, refine_p_speed


def _study(n, seed=3):
    """Sample i sticks (SS = 1.2) below its own speed u_i ~ U(14, 22) and drills smoothly (SS = 0.1)
    above it: P(SS > 0.5) at speed s is the fraction of u_i above s, and the 5 % speed is the
    95 % quantile of the u_i."""
    u = np.random.default_rng(seed).uniform(14.0, 22.0, n)

    def evaluate(sp):
        return np.where(u[:, None] > np.asarray(sp)[None, :], 1.2, 0.1)
    return u, evaluate


def test_refinement_brackets_the_exact_crossing_to_the_tolerance():
    u, ev = _study(400)
    grid = np.arange(10.0, 26.0)
    ss = ev(grid)
    exact = np.sort(u)[int(np.ceil(0.95 * u.size)) - 1]  # P(SS > 0.5) <= 5 % from the 380th-largest u on
    r = refine_p_speed(ss, grid, ev, tol=0.01)
    assert r.precision <= 0.01
    assert r.below <= exact <= r.above + 1e-12
    assert exceedance(ev([r.below]))[0] > 0.05 >= exceedance(ev([r.above]))[0]
    # the refined grid keeps the original speeds and the same samples
    assert set(grid) <= set(r.speeds) and r.severity.shape == (400, r.speeds.size)
    # the grid's linear interpolation is off by more than the refined bracket
    assert abs(p_speed(ss, grid) - exact) > r.precision


def test_no_crossing_gives_none():
    _, ev = _study(50)
    grid = np.array([23.0, 24.0, 25.0])  # smooth everywhere
    assert p_speed(ev(grid), grid) is None
    assert refine_p_speed(ev(grid), grid, ev, tol=0.1) is None


def test_bootstrap_interval_covers_the_truth_and_narrows_with_samples():
    widths = []
    for n in (100, 1600):
        u, ev = _study(n, seed=11)
        grid = np.linspace(14.0, 22.0, 81)
        b = bootstrap_interval(ev(grid), grid, seed=1)
        assert b["low"] <= 14.0 + 0.95 * 8.0 <= b["high"] + 0.1  # the population 95 % quantile: 21.6
        widths.append(b["high"] - b["low"])
    assert widths[1] < 0.5 * widths[0]  # 1/sqrt(n): 16 x the samples, a quarter of the width


def test_bad_inputs_are_refused_with_the_field_named():
    _, ev = _study(10)
    with pytest.raises(ValueError, match="tol"):
        refine_p_speed(ev([15.0, 16.0]), [15.0, 16.0], ev, tol=0)
    with pytest.raises(ValueError, match="severity"):
        p_speed(np.zeros((3, 2)), [1.0, 2.0, 3.0])
