"""The eta process (thesis section 4.1): PSD model (4.4), convention, generator (checked against
scipy's periodogram as an independent oracle), Welch, the fit of Eq. (4.4) continuous at f0
(f0, a, b free) with its intervals, bad input."""
import math

import numpy as np
import pytest
from scipy import signal

from drillpy.uncertainty.process import (PSD_CONVENTIONS, THESIS_PSD, PsdModel, PsdTable, convert_psd_model,
                             fit_eta, fit_psd_model, generate, periodogram, process_variance, welch)


def test_thesis_model_values_and_variance():
    m = THESIS_PSD
    assert (m.f0, m.A0, m.a, m.b) == (0.27, -7.6, -3.13, -11.67)
    f = np.array([0.0, 0.1, 0.2699, 0.27, 1.0, 5.0])
    expect = np.where(f < 0.27, np.exp(-7.6), np.exp(-3.13 * np.log(np.maximum(f, 0.27)) - 11.67))
    np.testing.assert_allclose(m(f), expect, rtol=1e-14)
    var = math.exp(-7.6) * 0.27 + math.exp(-11.67) * 0.27 ** -2.13 / 2.13
    assert m.integral() == pytest.approx(var, rel=1e-13)
    assert math.sqrt(m.integral()) == pytest.approx(0.01416, abs=1e-5)


def test_conventions_scale_the_density():
    # a two-sided density per rad/s S2(omega) has one-sided per-Hz density 4 pi S2
    m = convert_psd_model(THESIS_PSD, "two-sided-rad-s")
    assert m.integral() == pytest.approx(4 * math.pi * THESIS_PSD.integral(), rel=1e-12)
    assert math.sqrt(m.integral()) == pytest.approx(0.0502, abs=1e-4)
    assert convert_psd_model(THESIS_PSD, "two-sided-hz").integral() == pytest.approx(
        2 * THESIS_PSD.integral(), rel=1e-12)
    assert set(PSD_CONVENTIONS) == {"one-sided-hz", "two-sided-hz", "one-sided-rad-s",
                                    "two-sided-rad-s"}
    with pytest.raises(ValueError, match="psd convention = 'per-hz'"):
        convert_psd_model(THESIS_PSD, "per-hz")


def test_mean_periodogram_of_realizations_matches_the_target_psd():
    """Convention check with scipy.signal.periodogram (one-sided, density) as the oracle:
    the mean over M = 200 realizations is S chi^2_{2M}/(2M) per bin (sd 7 %, upper tail longer
    than a normal one). Stated tolerances: mean ratio over all bins within 1.5 %, 32-bin bands
    within 6 %, every one of the 1023 bins within 40 %, and the bin-to-bin scatter 7 % +- 1 %."""
    dt = 0.05
    t, eta = generate(THESIS_PSD, dt=dt, duration=100.0, samples=200, seed=42)
    assert eta.shape == (200, 2048)
    f, P = signal.periodogram(eta, fs=1 / dt, window="boxcar", detrend=False,
                              return_onesided=True, scaling="density", axis=-1)
    ratio = P.mean(axis=0)[1:-1] / THESIS_PSD(f[1:-1])
    assert ratio.mean() == pytest.approx(1.0, abs=0.015)
    bands = ratio[: ratio.size // 32 * 32].reshape(-1, 32).mean(axis=1)
    assert np.max(np.abs(bands - 1)) < 0.06
    assert np.max(np.abs(ratio - 1)) < 0.40
    assert ratio.std() == pytest.approx(1 / math.sqrt(200), abs=0.01)


def test_sample_variance_equals_the_psd_integral():
    """Ensemble mean of the time-averaged eta^2 = integral_0^inf S df = 2.004e-4 (the generator's
    exact variance is the trapezoidal sum on [0, 10 Hz], 0.03 % below it); 300 realizations:
    sd of the estimate about 1 %, tolerance 3 %."""
    t, eta = generate(THESIS_PSD, dt=0.05, duration=100.0, samples=300, seed=7)
    assert process_variance(THESIS_PSD, 0.05, 100.0) == pytest.approx(THESIS_PSD.integral(),
                                                                       rel=0.005)
    assert np.mean(eta ** 2) == pytest.approx(THESIS_PSD.integral(), rel=0.03)
    assert abs(np.mean(eta)) < 3 * math.sqrt(THESIS_PSD.integral() / 300 / 20)
    # Gaussian marginal: kurtosis 3 within sampling error
    z = eta.ravel() / eta.std()
    assert np.mean(z ** 4) == pytest.approx(3.0, abs=0.15)


def test_welch_estimate_of_a_long_realization_follows_the_model():
    dt = 0.05
    _, eta = generate(THESIS_PSD, dt=dt, duration=6000.0, samples=1, seed=3)
    f, S = welch(eta[0], dt, segment=4096)
    for lo, hi in ((0.02, 0.2), (0.4, 1.0), (1.0, 3.0)):
        sel = (f >= lo) & (f < hi)
        assert np.mean(S[sel] / THESIS_PSD(f[sel])) == pytest.approx(1.0, abs=0.08), (lo, hi)


def test_periodogram_convention_one_sided_per_hz():
    # white noise of variance s2 sampled at dt has one-sided density 2 s2 dt
    rng = np.random.default_rng(0)
    x = rng.normal(0, 0.3, 2 ** 16)
    f, P = periodogram(x, 0.01)
    assert f[-1] == pytest.approx(50.0)
    assert np.mean(P[1:-1]) == pytest.approx(2 * 0.09 * 0.01, rel=0.02)
    assert np.sum(P) * (f[1] - f[0]) == pytest.approx(np.var(x), rel=0.01)  # Parseval


@pytest.mark.parametrize("seed", [0, 1])
def test_fit_recovers_the_thesis_parameters(seed):
    """Fit of Eq. (4.4) to the raw periodogram of a generated 6554-s record. The log of a raw
    periodogram ordinate scatters with sd pi/sqrt(6) = 1.28 around ln S - 0.577 (removed)."""
    _, eta = generate(THESIS_PSD, dt=0.05, duration=4000.0, samples=1, seed=seed)
    fit, f, S = fit_eta(eta[0], 0.05)
    m = fit.model
    assert m.f0 == pytest.approx(0.27, abs=0.04)
    assert m.A0 == pytest.approx(-7.6, abs=0.06)
    assert m.a == pytest.approx(-3.13, abs=0.03)
    assert m.b == pytest.approx(-11.67, abs=0.03)
    assert fit.rms_log_residual == pytest.approx(math.pi / math.sqrt(6), abs=0.03)
    fw, _, _ = fit_eta(eta[0], 0.05, method="welch", segment=4096)
    assert fw.model.a == pytest.approx(-3.13, abs=0.05)
    assert fw.model.A0 == pytest.approx(-7.6, abs=0.1)


def test_fit_of_an_exact_model_is_exact():
    """A noise-free continuous model with f0 between two grid frequencies is recovered exactly
    (the knot of the profile is solved in closed form, not picked from the grid)."""
    f = np.linspace(0.01, 5.0, 500)
    m = PsdModel.continuous(f0=0.5037, a=-2.0, b=-6.0)
    fit = fit_psd_model(f, m(f) * math.exp(-0.5772156649015329))  # raw-periodogram bias
    assert fit.model.a == pytest.approx(-2.0, abs=1e-9)
    assert fit.model.b == pytest.approx(-6.0, abs=1e-9)
    assert fit.model.A0 == pytest.approx(-2.0 * math.log(0.5037) - 6.0, abs=1e-9)
    assert fit.model.f0 == pytest.approx(0.5037, rel=1e-9)
    assert fit.rms_log_residual < 1e-9


def test_fitted_model_is_continuous_at_f0():
    """Eq. (4.4) fitted with A0 = a ln f0 + b: no jump at f0 (the thesis's own set jumps by 3 %
    only; the free 4-parameter fit used to jump x10-x21 on the test-rig record)."""
    assert THESIS_PSD.continuity_jump == pytest.approx(math.exp(-3.13 * math.log(0.27) - 11.67 + 7.6))
    assert abs(THESIS_PSD.continuity_jump - 1) < 0.04
    _, eta = generate(PsdModel.continuous(f0=1.5, a=-2.5, b=-5.0), dt=0.01, duration=100.0, seed=3)
    fit, _, _ = fit_eta(eta[0], 0.01)
    m = fit.model
    assert fit.continuity_jump == 1.0
    assert fit.as_dict()["continuity_jump"] == 1.0
    assert m.A0 == pytest.approx(m.a * math.log(m.f0) + m.b, abs=1e-12)
    below, above = m([m.f0 * (1 - 1e-9), m.f0 * (1 + 1e-9)])
    assert above / below == pytest.approx(1.0, abs=1e-7)


def _brute_force_hinge(f, S, knots):
    x, y = np.log(f), np.log(S) + 0.5772156649015329
    best = (math.inf, None)
    for x0 in knots:
        A = np.column_stack([np.ones_like(x), np.maximum(x - x0, 0.0)])
        c = np.linalg.lstsq(A, y, rcond=None)[0]
        best = min(best, (float(np.sum((A @ c - y) ** 2)), x0))
    return best


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_fit_is_the_global_least_squares_minimum(seed):
    """No start value or local minimum decides: the profiled fit is at least as good as a brute
    force over 5000 knots, and lands next to its best knot."""
    m = PsdModel.continuous(f0=0.8, a=-2.0, b=-6.0)
    _, eta = generate(m, dt=0.05, duration=20.0, seed=seed)
    f, S = periodogram(eta[0], 0.05)
    fit = fit_psd_model(f, S)
    k = f > 0
    x = np.log(f[k])
    sse_bf, x0_bf = _brute_force_hinge(f[k], S[k], np.linspace(x[2], x[-3], 5000))
    assert fit.rms_log_residual ** 2 * fit.points <= sse_bf + 1e-9
    assert math.log(fit.model.f0) == pytest.approx(x0_bf, abs=2 * (x[-3] - x[2]) / 5000 + 0.02)


def test_fit_recovers_a_non_thesis_psd_within_its_intervals():
    """Synthetic eta from a continuous Eq. (4.4) unlike the thesis's (f0 0.8 Hz, a -2, A0 -6,
    b = A0 - a ln f0 = -6.446), dt 0.02 s, 327.7-s records (8192 ordinates), 40 realizations:
    every parameter's 95 % interval holds the true value in at least 34 of 40 fits (a false
    alarm probability of 1.4 % per parameter at exact 95 % coverage), the reported standard
    errors match the scatter of the estimates, and the intervals are narrow."""
    A0, a, f0 = -6.0, -2.0, 0.8
    b = A0 - a * math.log(f0)
    true = {"f0_hz": f0, "A0": A0, "a": a, "b": b}
    _, eta = generate(PsdModel(f0=f0, A0=A0, a=a, b=b), dt=0.02, duration=300.0, samples=40, seed=11)
    fits = [fit_eta(e, 0.02)[0] for e in eta]
    first = fits[0]
    for k, v in true.items():
        lo, hi = first.ci95[k]
        assert lo <= v <= hi, (k, v, lo, hi)
    assert not first.f0_ci_at_search_edge and first.f0_ci_connected
    max_width = {"f0_hz": 0.25, "A0": 0.45, "a": 0.1, "b": 0.25}
    for k, v in true.items():
        ci = np.array([fi.ci95[k] for fi in fits])
        assert np.sum((ci[:, 0] <= v) & (v <= ci[:, 1])) >= 34, k
        assert np.all(ci[:, 1] - ci[:, 0] < max_width[k]), k
    for k, attr in (("A0", "A0"), ("a", "a"), ("b", "b"), ("f0_hz", "f0")):
        est = np.array([getattr(fi.model, attr) for fi in fits])
        se = np.median([fi.se[k] for fi in fits])
        assert abs(est.mean() - true[k]) < 3 * est.std(ddof=1) / math.sqrt(40), k
        assert 0.7 < est.std(ddof=1) / se < 1.4, k


def _eta_exp_window(path, t0, t1):
    """eta_exp of a window of the record exactly as drillpy.reports.analysis.analyze_record computes it
    (default AnalysisOptions: stick threshold 5 % of the median top speed, mean-of-all-cycles
    reference) and the fit of Eq. (4.4) to its raw periodogram up to 10 Hz."""
    from drillpy.records import signals as sig
    from drillpy.records.cleaning import CleaningOptions, clean
    from drillpy.records.io import read_record
    raw = read_record(path).select(t0, t1)
    rec, _ = clean(raw, CleaningOptions())
    thr = 0.05 * abs(float(np.nanmedian(rec.top_speed[rec.valid("top_speed")])))
    v, tq = rec.bit_speed, rec.torque_on_bit
    cyc = sig.segment_cycles(v, rec.dt, thr, valid=rec.valid("bit_speed", "torque_on_bit"))
    acc = sig.derivative(np.where(np.isfinite(v), v, 0.0), rec.dt)
    lab = cyc.branch_labels(len(rec))
    mc = sig.mean_cycle(v, tq, acc, lab)
    eta = sig.eta_exp(rec.time_s, v, tq, lab, mc, reference="mean")
    f, p = periodogram(eta.eta, 1.0 / eta.fs_hz)
    return fit_psd_model(f, p, averages=1.0, fmax=10.0)


def test_psd_fit_is_stable_between_two_windows_of_sample_175():
    """0-20 s and 20-40 s of the rig record: both fits continuous at f0 and the 95 % intervals
    of every parameter overlap (the free fit gave f0 = 3.23 and 0.53 Hz here, jumps x0.24, x0.10)."""
    from _testrig import sample175_path
    path = sample175_path()
    w1, w2 = _eta_exp_window(path, 0.0, 20.0), _eta_exp_window(path, 20.0, 40.0)
    for fit in (w1, w2):
        assert fit.continuity_jump == 1.0
        assert fit.ci95["f0_hz"][0] <= fit.model.f0 <= fit.ci95["f0_hz"][1]
        assert fit.f0_search_hz[0] <= fit.ci95["f0_hz"][0] <= fit.ci95["f0_hz"][1] <= fit.f0_search_hz[1]
    for k in ("f0_hz", "A0", "a", "b"):
        (lo1, hi1), (lo2, hi2) = w1.ci95[k], w2.ci95[k]
        assert max(lo1, lo2) <= min(hi1, hi2), (k, w1.ci95[k], w2.ci95[k])


def test_user_psd_as_table_and_as_function():
    # band-limited white: S = 2 on [0, 1] Hz -> variance 2
    table = PsdTable([0.0, 1.0], [2.0, 2.0])
    assert process_variance(table, 0.1, 50.0) == pytest.approx(2.0, abs=2 / 51.2)
    fn = lambda f: np.where(f <= 1.0, 2.0, 0.0)  # noqa: E731
    assert process_variance(fn, 0.1, 50.0) == pytest.approx(process_variance(table, 0.1, 50.0))
    _, a = generate(table, dt=0.1, duration=50.0, samples=3, seed=1)
    _, b = generate(fn, dt=0.1, duration=50.0, samples=3, seed=1)
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(table([0.0, 0.5, 2.0]), [2.0, 2.0, 0.0])


def test_realizations_depend_only_on_seed_and_sample_index():
    _, a = generate(THESIS_PSD, dt=0.05, duration=60.0, samples=5, seed=9)
    _, b = generate(THESIS_PSD, dt=0.05, duration=60.0, samples=2, seed=9, first_sample=3)
    np.testing.assert_array_equal(a[3:], b)
    _, c = generate(THESIS_PSD, dt=0.05, duration=60.0, samples=1, seed=10)
    assert not np.array_equal(a[0], c[0])


@pytest.mark.parametrize("psd, match", [
    (lambda f: -np.ones_like(f), r"psd\(f = 0 Hz\) = -1: must not be negative"),
    (lambda f: np.where(f > 1, np.nan, 1.0), r"psd\(f = .* Hz\) = nan: must be a finite number"),
    (lambda f: np.where(f > 1, np.inf, 1.0), r"must be a finite number"),
])
def test_negative_or_non_finite_psd_is_refused(psd, match):
    with pytest.raises(ValueError, match=match):
        generate(psd, dt=0.05, duration=10.0)


def test_bad_tables_and_models_are_refused():
    with pytest.raises(ValueError, match=r"psd.table.S\[1\] = -3"):
        PsdTable([0.0, 1.0, 2.0], [1.0, -3.0, 1.0])
    with pytest.raises(ValueError, match=r"psd.table.S\[0\] = nan"):
        PsdTable([0.0, 1.0], [np.nan, 1.0])
    with pytest.raises(ValueError, match="increase strictly"):
        PsdTable([1.0, 0.5], [1.0, 1.0])
    with pytest.raises(ValueError, match="psd.f0_hz = -0.2"):
        PsdModel(f0=-0.2)(1.0)
    with pytest.raises(ValueError, match="psd.a = -0.5"):
        PsdModel(a=-0.5).integral()


@pytest.mark.parametrize("kwargs, match", [
    ({"dt": 0.0}, "eta_dt_s = 0.0: must be a positive number"),
    ({"dt": -0.1}, "eta_dt_s = -0.1"),
    ({"dt": float("nan")}, "eta_dt_s = nan"),
    ({"dt": 1e-9, "duration": 1000.0}, r"more than 2\^26 points"),
    ({"duration": 0.0}, "duration_s = 0.0"),
    ({"samples": 0}, "samples = 0: must be an integer between 1 and 100000"),
    ({"samples": 2.5}, "samples = 2.5"),
    ({"samples": 100001}, "samples = 100001"),
    ({"seed": -1}, "seed = -1: must be an integer"),
    ({"seed": 1.5}, "seed = 1.5: must be an integer"),
    ({"seed": "7"}, "seed = '7': must be an integer"),
    ({"seed": True}, "seed = True"),
    ({"first_sample": -2}, "first_sample = -2"),
])
def test_bad_generator_arguments_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        generate(THESIS_PSD, **kwargs)


def test_bad_series_for_estimators():
    with pytest.raises(ValueError, match="must be finite"):
        periodogram(np.array([1.0] * 10 + [np.nan]), 0.1)
    with pytest.raises(ValueError, match="at least 8 values"):
        welch(np.ones(4), 0.1)
    with pytest.raises(ValueError, match="dt = 0"):
        periodogram(np.ones(64), 0)
    with pytest.raises(ValueError, match="method = 'burg'"):
        fit_eta(np.ones(64), 0.1, method="burg")


def test_scaled_to_std_keeps_the_shape_and_sets_the_variance():
    from drillpy.uncertainty.process import THESIS_PSD, scaled_to_std
    m = scaled_to_std(THESIS_PSD, 0.2 / 3)
    assert m.integral() == pytest.approx((0.2 / 3) ** 2, rel=1e-9)
    f = np.array([0.1, 0.27, 1.0, 5.0])
    ratio = m(f) / THESIS_PSD(f)
    np.testing.assert_allclose(ratio, ratio[0], rtol=1e-12)  # one factor at every frequency
    with pytest.raises(ValueError, match="std"):
        scaled_to_std(THESIS_PSD, -0.1)
