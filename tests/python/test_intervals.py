"""Issue 31 item 6: binomial intervals for probabilities, and a warning when the grid limits a precision."""
import numpy as np
import pytest
from scipy.stats import norm

from drillpy.uncertainty.robust_speed import grid_limit, robust_speed_summary
from drillpy.uncertainty.binomial import wilson_interval


def test_no_event_in_n_runs_bounds_p_by_z2_over_n_plus_z2():
    z = norm.ppf(0.95)
    for n in (9, 18, 500):
        lo, hi = wilson_interval(0.0, n)
        assert lo == 0.0 and hi == pytest.approx(z * z / (n + z * z))  # the closed form at p = 0
    lo, hi = wilson_interval([0.2, 0.8], 50)
    assert lo[0] == pytest.approx(1 - hi[1]) and hi[0] == pytest.approx(1 - lo[1])  # symmetric in p <-> 1 - p
    with pytest.raises(ValueError, match="p = "):
        wilson_interval(1.5, 10)


def _switching(speeds, at, samples=40, seed=0):
    """SS of samples that all leave stick-slip between two speeds: above 0.5 below ``at``, below above it."""
    rng = np.random.default_rng(seed)
    cut = at + rng.uniform(-0.3, 0.3, samples)
    return np.where(np.asarray(speeds)[None, :] < cut[:, None], 1.2, 0.1)


def test_a_bootstrap_inside_one_grid_cell_is_flagged_as_grid_limited():
    coarse = np.arange(10.0, 31.0, 2.0)  # every sample switches inside the cell 20-22
    s = robust_speed_summary(_switching(coarse, 21.0), coarse, None, 1, None)
    b = s["p05_speed_bootstrap"]
    assert b["high"] - b["low"] < 2.0 and "grid spacing there (2 rad/s)" in s["p05_speed_precision_warning"]
    fine = np.arange(19.0, 23.0, 0.005)  # the samples' own spread sets the interval: many cells wide, no warning
    s = robust_speed_summary(_switching(fine, 21.0), fine, None, 1, None)
    assert s["p05_speed_bootstrap"]["high"] - s["p05_speed_bootstrap"]["low"] > 0.005
    assert "p05_speed_precision_warning" not in s
    assert grid_limit({"low": float("nan"), "high": float("nan")}, fine) is None


def test_mc_rows_carry_the_wilson_interval_of_their_samples(capsys):
    import json

    from drillpy.cli import main
    assert main(["mc", "--preset", "thesis-rig", "--duration", "4", "--transient", "2", "--samples", "6",
                 "--warmup", "0", "--speeds", "4,8", "--no-figures", "--json", "--no-progress"]) == 0
    for r in json.loads(capsys.readouterr().out)["speeds"]:
        lo, hi = r["p_ss_gt_0_5_wilson90"]
        assert (lo, hi) == pytest.approx(tuple(wilson_interval(r["p_ss_gt_0_5"], 6)))
        assert lo <= r["p_ss_gt_0_5"] <= hi and hi - lo > 0.1  # 6 samples: never a point
