"""The calibration's finite-difference Jacobian in one engine call (issue 33, item 2): scipy's
'2-point' steps, the batched engine call (``_core.predict_horizons_many``) bit for bit the models'
single calls whatever the batch, the Jacobian bit for bit scipy's own, and the loop's decisions the
same with either (``LoopOptions.batched_jacobian``)."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.optimize._numdiff import approx_derivative

from drillpy import loop as L
from drillpy.loop import fitting as F
from drillpy.loop import model as M
from drillpy.loop.run import analysis_config
from drillpy.model.config import normalize
from drillpy.loop.synthetic import declared_config, synthetic_record

RATE_HZ, DT_S = 500.0, 2e-4


def _points(x0, lo, hi, rel):
    """The points scipy's '2-point' differences evaluate (its map, spied)."""
    seen = []

    def spy(fun, xs):
        out = []
        for x in xs:
            seen.append(np.copy(x))
            out.append(fun(x))
        return out

    approx_derivative(lambda x: np.array([x.sum()]), x0, method="2-point", rel_step=rel, f0=np.array([x0.sum()]),
                      bounds=(lo, hi), workers=spy)
    return seen


def test_steps_are_scipys_2_point_steps():
    """Interior points, zeros (sign +1 and the sqrt(eps) fallback), points next to a bound (the step
    reversed) and a bound closer than the step both ways (up to the farther bound): the perturbed
    points equal scipy's bit for bit."""
    lo = np.array([-np.inf, 0.0, -1.0, 0.0, -5.0, np.log(1e-3), 0.97, 0.0])
    hi = np.array([np.inf, 1.0, 1.0, 1e-4, 5.0, 0.0, 1.03, 1.0])
    x0 = np.array([3.7, 0.9995, -0.99995, 5e-5, 0.0, -1e-6, 1.0299999, 0.0])
    for rel in (1e-3, 1e-2):
        h = F.fd_steps(x0, lo, hi, rel)
        mine = []
        for i in range(x0.size):
            x = np.copy(x0)
            x[i] = x0[i] + h[i]
            mine.append(x)
        theirs = _points(x0, lo, hi, rel)
        assert len(theirs) == len(mine)
        for a, b in zip(mine, theirs):
            np.testing.assert_array_equal(a, b)


def test_fd_jacobian_is_scipys_bit_for_bit():
    """The same columns from one batch call as scipy's from one call each, and the same layout."""
    rng = np.random.default_rng(3)
    A = rng.normal(size=(40, 5))

    def f(x):
        return np.tanh(A @ x) + x[0] * x[1]

    lo, hi = -np.ones(5), np.ones(5)
    x0 = np.array([0.3, -0.2, 0.99999, 0.0, -0.5])
    f0 = f(x0)
    ref = approx_derivative(f, x0, method="2-point", rel_step=1e-3, f0=f0, bounds=(lo, hi))
    calls = []

    def batch(points):
        calls.append(len(points))
        return [f(x) for x in points]

    J = F.fd_jacobian(batch, x0, f0, F.fd_steps(x0, lo, hi, 1e-3))
    assert calls == [5]
    np.testing.assert_array_equal(J, ref)
    assert J.flags.f_contiguous == ref.flags.f_contiguous


@pytest.fixture(scope="module")
def calibrated():
    rec = synthetic_record({"sensor_lag": {}}, duration_s=10.0, seed=5, fs_hz=RATE_HZ)
    opt = L.LoopOptions(rate_hz=RATE_HZ, dt_s=DT_S, nfev_per_parameter=8)
    cfg = normalize(declared_config())
    data = L.prepare(rec, cfg, opt)
    cfg = analysis_config(cfg, data.dt, opt.dt_s)
    m, _ = F.calibrate(cfg, data, opt)
    return m, data, opt


def _perturbed(m, data):
    """The model with every calibrated parameter perturbed alone (a Jacobian's models), and a sensor lag."""
    names = [F.LAW, F.DAMPING, F.GJ] + list(m.effects)
    x0, lo, hi, where = F._pack(m, data, names)
    x0 = np.clip(x0, F._inside(lo, +1), F._inside(hi, -1))
    h = F.fd_steps(x0, lo, hi, F.DIFF_STEP)
    models = [F._unpack(m, x0, where, data.law_knot, trial=True)]
    for i in range(x0.size):
        x = np.copy(x0)
        x[i] += h[i]
        models.append(F._unpack(m, x, where, data.law_knot, trial=True))
    lag = m.copy()
    lag.effects["sensor_lag"] = {"lowpass_hz": 20.0}  # a restart lead D > 0: longer horizons in the same call
    return models + [lag], x0, lo, hi, where


@pytest.mark.parametrize("batched", [True, False])
def test_many_models_in_one_call_are_their_single_calls_bit_for_bit(calibrated, batched):
    """predict_many (one engine call) equals predict per model, on the SIMD and the scalar path,
    whatever the models sharing the call (all, reversed, one at a time, and an invalid one among them)."""
    m, data, opt = calibrated
    data = dataclasses.replace(data, batched=batched)
    models, *_ = _perturbed(m, data)
    single = [M.predict(x, data, threads=2, top=True) for x in models]
    bad = m.copy()
    bad.cfg = {**bad.cfg, "damping": {**bad.cfg["damping"], "ratios": [-1.0]}}  # refused by the engine
    for group in (models, models[::-1], models[:1], [models[0], bad, models[-1]]):
        got = M.predict_many(group, data, threads=2, top=True)
        assert len(got) == len(group)
        for x, g in zip(group, got):
            if x is bad:
                assert isinstance(g, ValueError)
                continue
            ref = single[next(i for i, y in enumerate(models) if y is x)]
            for a, b in zip(g, ref):
                np.testing.assert_array_equal(a, b)


def test_batched_jacobian_equals_the_per_perturbation_jacobian(calibrated):
    """The Jacobian from one engine call (fd_jacobian over residual_vectors) equals scipy's '2-point'
    Jacobian with one residual_vector call per perturbation, bit for bit."""
    m, data, opt = calibrated
    _, x0, lo, hi, where = _perturbed(m, data)

    def res(x):
        return M.residual_vector(F._unpack(m, x, where, data.law_knot, trial=True), data, 0)

    def batch(points):
        return M.residual_vectors([F._unpack(m, x, where, data.law_knot, trial=True) for x in points], data, 0)

    f0 = res(x0)
    ref = approx_derivative(res, x0, method="2-point", rel_step=F.DIFF_STEP, f0=f0, bounds=(lo, hi))
    J = F.fd_jacobian(batch, x0, f0, F.fd_steps(x0, lo, hi, F.DIFF_STEP))
    assert np.abs(J).max() > 0
    np.testing.assert_array_equal(J, ref)


def test_calibration_is_the_same_with_either_jacobian(calibrated):
    """fit_dynamic with the batched Jacobian and with scipy's per-perturbation one: the same
    parameters and intervals, bit for bit (the same Jacobian, the same optimizer path)."""
    m, data, opt = calibrated
    names = [F.LAW, F.DAMPING, F.GJ] + list(m.effects)
    a, ca = F.fit_dynamic(m, data, names, opt)
    opt_b = dataclasses.replace(opt, batched_jacobian=False)
    b, cb = F.fit_dynamic(m, data, names, opt_b)
    assert a.law == b.law and a.effects == b.effects and a.damping_ratios == b.damping_ratios
    assert a.gj_factor == b.gj_factor and ca == cb


def test_loop_decisions_are_the_same_with_either_jacobian():
    """A short synthetic record with one effect: the loop run with the batched Jacobian and with
    scipy's takes the same steps (actions, effects, order) with the same errors."""
    rec = synthetic_record({"sensor_lag": {}}, duration_s=8.0, seed=6, fs_hz=RATE_HZ)
    runs = []
    for bj in (True, False):
        opt = L.LoopOptions(rate_hz=RATE_HZ, dt_s=DT_S, nfev_per_parameter=6, max_steps=2, long_run=False,
                            discovery=False, effects=("sensor_lag", "viscous_damping"), batched_jacobian=bj)
        runs.append(L.run_loop(rec, declared_config(), opt, log=lambda *a: None))
    a, b = runs
    assert [(s.action, s.effect) for s in a.steps] == [(s.action, s.effect) for s in b.steps]
    assert [s.error_after for s in a.steps] == [s.error_after for s in b.steps]
    assert a.baseline.E_test == b.baseline.E_test
    assert a.final.E_test == b.final.E_test
