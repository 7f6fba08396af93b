"""Calibration of a loop model: the law on the law residual, then the law, the modal damping ratios,
the string's GJ within the declared geometry's tolerance and every effect's free parameters jointly
on the calibration horizons (least squares on the normalized short-horizon residuals, restarted to
convergence), with 95 % intervals of the effects' parameters.

The same procedure and budget (``LoopOptions.nfev_per_parameter`` evaluations per parameter, from
the current model's values) calibrate the declared model, the null candidate (no effect added) and
every candidate, so that a candidate gains only through its own parameters.
"""
from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np
from scipy import optimize

from drillpy.records import bit_balance
from drillpy.records import identification as ident
from drillpy.records import rig_fluctuation
from drillpy.records.io import RPM
from .data import LoopData
from .effects import CATALOGUE, declared_effects, stripped
from .model import STIFFNESS, LoopModel, law_channels, law_torque, residual_vector, residual_vectors
from .options import LoopOptions
from .side_by_side import task_map
from .view import view

LAW = "law"          #: pseudo-effect: the law's free parameters (and the WOB coupling gain)
DAMPING = "damping"  #: pseudo-effect: the modal damping ratios
GJ = "gj"            #: pseudo-effect: the GJ within the declared geometry's tolerance
#: Bounds of a modal damping ratio (fitted in ln).
DAMPING_BOUNDS = (1e-3, 1.0)
#: tanh(beta2 a) may saturate at no less than 1/100 of the acceleration spread (else it is a sign switch).
BETA2_SPREAD = 100.0
#: A restart of the short-horizon least squares is repeated while it lowers the cost by this share,
#: at most RESTARTS times (within the same evaluation budget).
RESTART_GAIN = 0.01
RESTARTS = 20
#: Relative step of the calibration's finite-difference Jacobian (scipy's ``diff_step``).
DIFF_STEP = 1e-3
#: A least-squares run whose cost fell by less than STALL_GAIN of itself over its last STALL_WINDOW
#: iterations has stalled and stops there (docs/loop.md, "Calibration"): such a run crawls along a
#: flat valley, each step just above scipy's ftol, to its budget (sample 175's torque_fluctuation on
#: the exact modal scheme: 545 evaluations for the last 0.09 % of its cost).
STALL_WINDOW = 40
STALL_GAIN = 2e-4


class _FamilyData:
    """What identification.FAMILIES' builders read: the reference WOB and speed [rad/s]."""
    def __init__(self, wob_ref: float, speed_ref: float):
        self.wob_ref, self.speed_ref = wob_ref, speed_ref


#: Bounds of the polynomial law's knot v_k [RPM] where its low-speed piece meets the cubic
#: (``LoopOptions.law_knot``): from below the rig's stick threshold to the upper half of the slip speeds.
KNOT_BOUNDS_RPM = (4.0, 60.0)


def _poly_knot(p, d, unit, fx, hyst=False):
    """Eq. (5.1)/(5.3) with its low-speed shape calibrated: the cubic a4..a7 above the knot v_k, a
    straight line below it from r t_k at v_k / 5 to the cubic's value t_k at v_k, and from a0 at rest
    to r t_k below v_k / 5 (the engine's pieces at 1 % and 5 % of ``ref_speed`` = 20 v_k).
    Parameters a4..a7 (beta1, beta2), r in [0, 1], v_k; speeds in the law's unit.

    r <= 1: the piece rises (or is flat) towards the knot. A torque that *falls* from a peak just off
    rest is a break-away, ``static_friction``, which the catalogue names with evidence; the law's own
    shape must not absorb it (validation case 18 lost its static friction to a free peak)."""
    a4, a5, a6, a7 = p[:4]
    r, v_k = p[-2], p[-1]
    ref, v1 = v_k / 0.05, v_k / 5.0
    a0 = float(fx.get("a0", 0.0))
    t_k = a4 + v_k * (a5 + v_k * (a6 + v_k * a7))
    t_low = r * t_k
    a3 = (t_k - t_low) / (v_k - v1)
    law = {"type": "polynomial_hysteretic" if hyst else "polynomial", "speed_unit": unit,
           "wob_ref_n": d.wob_ref, "a0": a0, "a1": (t_low - a0) / v1, "a2": t_low - a3 * v1, "a3": a3,
           "a4": a4, "a5": a5, "a6": a6, "a7": a7, "ref_speed": ref, "gain": fx["gain"]}
    if hyst:
        law["beta1"], law["beta2"] = p[4], p[5]
    return law


#: Weight [N m] of the prior row w (1 - r) the law residual's fit adds for the knot's low_ratio r:
#: where the slip samples do not reach below the knot (a knot near the stick threshold) r is not
#: identified and starts the short-horizon fits at 1, the thesis's flat piece; where they do, one
#: row of 0.05 N m against hundreds of slip samples barely moves it.
KNOT_PRIOR_NM = 0.05

_FAMILIES = dict(ident.FAMILIES)
for _n in ("polynomial", "polynomial_hysteretic"):
    _f = ident.FAMILIES[_n]
    _h = _n.endswith("hysteretic")
    _FAMILIES[_n + "_knot"] = ident._Family(_f.names + ("low_ratio", "v_knot"), _f.lower + (0.0, -np.inf),
                                            _f.upper + (1.0, np.inf),
                                            lambda p, d, u, fx, h=_h: _poly_knot(p, d, u, fx, h))


def _law_family(law: dict, hysteresis: bool, a_scale: float, knot: bool = False) -> tuple:
    """(family name, starting parameters, fixed parameters, _FamilyData) of a law; ``knot``: a
    polynomial law's low-speed knot and low_ratio are fitted (:func:`_poly_knot`,
    ``LoopOptions.law_knot``), else the thesis's tie."""
    t, unit = law["type"], law["speed_unit"]
    s = RPM if unit == "rpm" else 1.0
    hyst0 = [float(law.get("beta1", 0.0)) or 0.1, float(law.get("beta2", 0.0)) or 1.0 / (a_scale * s)]
    if t in ("polynomial", "polynomial_hysteretic"):
        p = [law["a4"], law["a5"], law["a6"], law["a7"]]
        fd = _FamilyData(law["wob_ref_n"], law["ref_speed"] / s)
        name = "polynomial_hysteretic" if hysteresis else "polynomial"
        p += hyst0 if hysteresis else []
        if knot:
            v1 = 0.01 * float(law["ref_speed"])
            t_k = float(law["a2"]) + float(law["a3"]) * 5.0 * v1
            r = min(max((float(law["a2"]) + float(law["a3"]) * v1) / t_k if t_k > 0 else 1.0, 0.0), 1.0)
            k_lo, k_hi = _knot_bounds(unit)
            v_k = min(max(5.0 * v1, k_lo), k_hi)
            return name + "_knot", p + [r, v_k], {"gain": law["gain"]}, fd
        return name, p, {"gain": law["gain"]}, fd
    fd = _FamilyData(law["wob_ref_n"], 1.0)
    if t == "hysteretic":
        knee = law["b3"] ** (-1.0 / law["b5"]) if law["b3"] > 0 else 1e6
        p = [law["b0"], law["b0"] * law["b2"], knee, law["b4"], law["b5"]]
        return ("hysteretic" if hysteresis else "hysteretic_reversible"), p + (hyst0 if hysteresis else []), \
            {"b1": law["b1"]}, fd
    if t == "tucker_wang":
        if hysteresis:  # Eq. (3.2) with b4 = 1, b5 = 2 is Eq. (3.1); H acts on the fraction
            knee = law["alpha2"] ** -0.5 if law["alpha2"] > 0 else 1e6
            return "hysteretic", [law["c0"], law["c0"] * law["alpha1"], knee, 1.0, 2.0] + hyst0, \
                {"b1": law["alpha0"]}, fd
        return "tucker_wang", [law["c0"], law["alpha1"], law["alpha2"]], {"alpha0": law["alpha0"]}, fd
    raise ValueError(f"law.type = {t!r}: not supported by drillpy loop")


def law_fit_residual(model: LoopModel, data: LoopData) -> np.ndarray:
    """The law residual [N m] on the calibration part's slip samples after :func:`fit_law`.

    Parameters
    ----------
    model : LoopModel
        The current model.
    data : LoopData
        The record on the analysis grid.

    Returns
    -------
    numpy.ndarray
        T - T_law(v, a, W_eff) [N m] at ``data.law_train`` (channels with the model's measurement
        chain undone, :func:`drillpy.loop.model.law_channels`).
    """
    m = fit_law(model, data)
    chs = law_channels(m, data)
    idx = data.law_train
    return chs["T"][idx] - law_torque(m, chs, idx)


def _knot_bounds(unit: str) -> tuple:
    """:data:`KNOT_BOUNDS_RPM` in the law's speed unit."""
    f = 1.0 if unit == "rpm" else 1.0 / RPM
    return KNOT_BOUNDS_RPM[0] * f, KNOT_BOUNDS_RPM[1] * f


def _a_scale(data: LoopData) -> float:
    return float(np.std(data.ch["v1"][data.law_train])) or 1.0


def _law_bounds(model: LoopModel, data: LoopData, fam) -> tuple:
    lo, hi = np.array(fam.lower, float), np.array(fam.upper, float)
    if "v_knot" in fam.names:
        lo[-1], hi[-1] = _knot_bounds(model.law["speed_unit"])
    if "beta2" in fam.names:
        s = RPM if model.law["speed_unit"] == "rpm" else 1.0
        hi[fam.names.index("beta2")] = BETA2_SPREAD / (_a_scale(data) * s)
    return lo, hi


def _inside(bound: np.ndarray, sign: int) -> np.ndarray:
    """Bounds moved inside by a relative 1e-9 (infinite ones unchanged)."""
    b = np.asarray(bound, float).copy()
    f = np.isfinite(b)
    b[f] += sign * 1e-9 * (1.0 + np.abs(b[f]))
    return b


def _law_owned(model: LoopModel) -> dict:
    """Law key -> the model's effect that stands for it (:attr:`Effect.law_keys
    <drillpy.loop.effects.base.Effect.law_keys>`: the hysteresis term's beta1, beta2)."""
    return {k: n for n in model.effects for k in CATALOGUE[n].law_keys}


def _law_joint(model: LoopModel) -> list:
    """(effect name, Param) of the parameters fitted with the law's own
    (:meth:`Effect.law_params <drillpy.loop.effects.base.Effect.law_params>`), in the model's order."""
    return [(n, q) for n, p in model.effects.items() for q in CATALOGUE[n].law_params(p)]


def fit_law(model: LoopModel, data: LoopData) -> LoopModel:
    """Least squares on the law residual of the calibration part's slip samples: the law's free
    parameters, with the law's optional term when an effect stands for it (``bit_hysteresis``'s
    Eq. 3.3, :attr:`Effect.law_keys <drillpy.loop.effects.base.Effect.law_keys>`) and the
    parameters effects fit with the law (``wob_coupling``'s gain k, :meth:`Effect.law_params
    <drillpy.loop.effects.base.Effect.law_params>`, which set the law's WOB input through
    :meth:`Effect.wob_input <drillpy.loop.effects.base.Effect.wob_input>`).

    The law family follows the declared law (polynomial Eq. 5.1/5.3, hysteretic Eq. 3.2, or
    Tucker-Wang Eq. 3.1), its bounds those of :data:`drillpy.records.identification.FAMILIES`
    (beta2 at most :data:`BETA2_SPREAD` / sd(a)); trust-region least squares, tolerances 1e-10.

    Parameters
    ----------
    model : LoopModel
        The current model.
    data : LoopData
        The record on the analysis grid.

    Returns
    -------
    LoopModel
        A copy with the fitted law, ``n_law`` and the parameters of the effects fitted with the law
        updated.
    """
    m = model.copy()
    chs = law_channels(m, data)
    idx = data.law_train
    v, a, T = chs["v"][idx], chs["a"][idx], chs["T"][idx]
    owned = _law_owned(m)
    joint = _law_joint(m)
    W = chs["W"][idx] if joint and "W" in chs else np.full(idx.size, m.wob)
    name, p0, fx, fd = _law_family(m.law, bool(owned), _a_scale(data), data.law_knot)
    fam = _FAMILIES[name]
    unit = m.law["speed_unit"]
    x0 = list(p0) + [float(m.effects[n].get(q.name, CATALOGUE[n].defaults[q.name])) for n, q in joint]
    lo, hi = _law_bounds(m, data, fam)
    jb = [CATALOGUE[n].bounds(q, m) for n, q in joint]
    lo, hi = np.r_[lo, [b[0] for b in jb]], np.r_[hi, [b[1] for b in jb]]
    x0 = np.clip(np.array(x0, float), _inside(lo, +1), _inside(hi, -1))
    npar = len(fam.names)

    knot = "low_ratio" in fam.names
    r_at = fam.names.index("low_ratio") if knot else 0

    def joint_values(x) -> dict:
        out = {}
        for (n, q), val in zip(joint, x[npar:]):
            out.setdefault(n, {})[q.name] = float(val)
        return out

    def law_wob(x):
        w = W
        for n, p in joint_values(x).items():
            w_n = CATALOGUE[n].wob_input(p, m, W)
            w = w if w_n is None else w_n
        return w

    def resid(x):
        law = fam.build(x[:npar], fd, unit, fx)
        r = ident.law_eval(law, v, a, law_wob(x))[0] - T
        return np.append(r, KNOT_PRIOR_NM * (1.0 - x[r_at])) if knot else r

    res = optimize.least_squares(resid, x0, bounds=(lo, hi), x_scale="jac", method="trf", max_nfev=200 * len(x0),
                                 xtol=1e-10, ftol=1e-10)
    law = fam.build(res.x[:npar], fd, unit, fx)
    m.law = law
    m.n_law = npar - len(owned)
    for n in dict.fromkeys(owned.values()):
        m.effects[n] = CATALOGUE[n].from_law(law)
    m.effects.update(joint_values(res.x))
    return m


def _law_vector(model: LoopModel, knot: bool) -> tuple:
    name, p0, fx, fd = _law_family(model.law, bool(_law_owned(model)), 1.0, knot)
    return _FAMILIES[name], np.array(p0, float), fx, fd


def _pack(model: LoopModel, data: LoopData, names) -> tuple:
    """(x, lower, upper, where) of the parameters ``names`` (LAW, DAMPING or effect names)."""
    x, lo, hi, where = [], [], [], []

    def add(val, a, b, scale, w):
        if scale == "log":
            x.append(math.log(min(max(val, a * 1.0001), b / 1.0001)))
            lo.append(math.log(a))
            hi.append(math.log(b))
        else:
            x.append(val)
            lo.append(a)
            hi.append(b)
        where.append(w + (scale,))

    for name in names:
        if name == LAW:
            fam, p0, _, _ = _law_vector(model, data.law_knot)
            flo, fhi = _law_bounds(model, data, fam)
            for i in range(p0.size):
                add(float(p0[i]), flo[i], fhi[i], "lin", (LAW, fam.names[i]))
            for n, q in _law_joint(model):
                add(float(model.effects[n][q.name]), *CATALOGUE[n].bounds(q, model), q.scale, (n, q.name))
        elif name == DAMPING:
            for i, z in enumerate(model.damping_ratios or ()):
                add(float(z), *DAMPING_BOUNDS, "log", (DAMPING, i))
        elif name == GJ:
            add(model.gj_factor, 1.0 - model.gj_tolerance, 1.0 + model.gj_tolerance, "log", (GJ, 0))
        else:
            eff = CATALOGUE[name]
            p = model.effects[name]
            for q in eff.free(p):
                a, b = eff.bounds(q, model)
                add(float(p[q.name]), a, b, q.scale, (name, q.name))
    return np.array(x, float), np.array(lo, float), np.array(hi, float), where


def _unpack(model: LoopModel, x, where, knot: bool, trial: bool = False) -> LoopModel:
    """The model with the parameters ``x`` (:func:`_pack`'s ``where``). A copy of the model
    (configuration, law and effects); with ``trial`` (an optimizer's evaluation, read only) a copy of
    what the parameters change alone (the law, the effects' parameter dicts and, when fitted, the
    damping section), the rest of the configuration shared with ``model``: dicts edited in place, the
    copy-on-write a :meth:`Configuration.replace <drillpy.model.configuration.Configuration.replace>`
    of the whole configuration would cost on every trial avoided."""
    if trial:
        damping = any(w[0] == DAMPING for w in where)
        cfg = {**model.cfg, "damping": {**model.cfg["damping"], "ratios": list(model.cfg["damping"]["ratios"])}} \
            if damping else model.cfg
        m = dataclasses.replace(model, cfg=cfg, law=dict(model.law), effects={n: dict(p) for n, p in model.effects.items()})
    else:
        m = model.copy()
    law_p = [xi for xi, w in zip(x, where) if w[0] == LAW]
    if law_p:
        fam, _, fx, fd = _law_vector(model, knot)
        m.law = fam.build(np.array(law_p), fd, model.law["speed_unit"], fx)
        for n in dict.fromkeys(_law_owned(m).values()):
            m.effects[n] = CATALOGUE[n].from_law(m.law)
    for xi, (name, key, scale) in zip(x, where):
        val = float(math.exp(xi) if scale == "log" else xi)
        if name == DAMPING:
            m.cfg["damping"]["ratios"][key] = val
        elif name == GJ:
            m.gj_factor = val
        elif name != LAW:
            m.effects[name][key] = val
    return m


def fd_steps(x0: np.ndarray, lo: np.ndarray, hi: np.ndarray, rel_step: float) -> np.ndarray:
    """The steps h of scipy's '2-point' finite differences (``scipy.optimize.least_squares`` with
    ``diff_step=rel_step`` and bounds): h = rel_step sign(x) |x| (sign(0) = +1; where that step
    vanishes, sqrt(eps) sign(x) max(1, |x|)), reversed where x + h leaves the bounds and fits
    the other way, else up to the farther bound (``scipy.optimize._numdiff``; the column i of the
    Jacobian is (f(x + h_i e_i) - f(x)) / ((x_i + h_i) - x_i)). ``tests/python/test_loop_jacobian.py``
    checks them against scipy's own.

    Parameters
    ----------
    x0 : numpy.ndarray
        The point (strictly inside the bounds).
    lo, hi : numpy.ndarray
        The bounds.
    rel_step : float
        The relative step.

    Returns
    -------
    numpy.ndarray
        The signed steps h.
    """
    sign = (x0 >= 0).astype(float) * 2 - 1
    h = rel_step * sign * np.abs(x0)
    dx = (x0 + h) - x0
    h = np.where(dx == 0, np.finfo(float).eps ** 0.5 * sign * np.maximum(1.0, np.abs(x0)), h)
    if np.all((lo == -np.inf) & (hi == np.inf)):
        return h
    lower, upper = x0 - lo, hi - x0
    adj = h.copy()
    x = x0 + h
    violated = (x < lo) | (x > hi)
    fitting = np.abs(h) <= np.maximum(lower, upper)
    adj[violated & fitting] *= -1
    forward = (upper >= lower) & ~fitting
    adj[forward] = upper[forward]
    backward = (upper < lower) & ~fitting
    adj[backward] = -lower[backward]
    return adj


def fd_jacobian(batch, x0: np.ndarray, f0: np.ndarray, h: np.ndarray) -> np.ndarray:
    """The '2-point' Jacobian of scipy's ``_dense_difference`` with the residuals of every perturbed
    point from one call ``batch(points)`` (a list of arrays, one per point, in order): column i is
    (f(x + h_i e_i) - f0) / ((x_i + h_i) - x_i), the same operations as scipy's, and the same
    (Fortran) layout.

    Parameters
    ----------
    batch : callable
        list of points -> list of residual vectors.
    x0 : numpy.ndarray
        The point.
    f0 : numpy.ndarray
        The residuals at ``x0``.
    h : numpy.ndarray
        The steps (:func:`fd_steps`).

    Returns
    -------
    numpy.ndarray
        The Jacobian, residuals x parameters.
    """
    points = []
    for i in range(x0.size):
        x1 = np.copy(x0)
        x1[i] = x0[i] + h[i]
        points.append(x1)
    fs = batch(points)
    jt = np.empty((x0.size, f0.size))
    for i, f in enumerate(fs):
        jt[i] = (f - f0) / ((x0[i] + h[i]) - x0[i])
    return jt.T


def e_train(model: LoopModel, data: LoopData, threads: int) -> float:
    """E on the calibration horizons (inf when the engine refuses the model).

    Parameters
    ----------
    model : LoopModel
        The model to score.
    data : LoopData
        The record on the analysis grid.
    threads : int
        Engine threads (0: OpenMP default).

    Returns
    -------
    float
        E_train [-], or inf when the prediction fails or is not finite.
    """
    try:
        r = residual_vector(model, data, threads)
    except (ValueError, RuntimeError):
        return math.inf
    with np.errstate(over="ignore", invalid="ignore"):
        e = float(np.sqrt(r @ r))
    return e if math.isfinite(e) else math.inf


def fit_dynamic(model: LoopModel, data: LoopData, names, opt: LoopOptions) -> tuple:
    """Least squares on the calibration horizons' normalized residuals over the parameters of
    ``names`` (the others held), from the model's values, with ``opt.nfev_per_parameter``
    evaluations per parameter. Returns the model and the 95 % intervals of the effects' parameters
    ({effect: {parameter: {"value", "ci95", "at_bound"}}}; the intervals from the Jacobian at the
    optimum, the residual variance inflated by its autocorrelation time).

    Parameters ``"log"``-scaled (and the damping ratios, bounds :data:`DAMPING_BOUNDS`, and the
    GJ factor within its tolerance) are fitted in ln; a trial the engine refuses scores a residual
    of 10 everywhere. Trust region, relative step 1e-3, tolerances 1e-6; restarted from its result
    (at most :data:`RESTARTS` times, within the budget) while a restart lowers the cost by
    :data:`RESTART_GAIN` at least: the residual jumps where a predicted stop or break-away crosses
    a sample, the trust region shrinks on such a kink and the step tolerance then ends the search
    short of a stationary point (docs/loop.md, "Calibration"). A run that has stalled (its cost down
    by less than :data:`STALL_GAIN` of itself over :data:`STALL_WINDOW` iterations) stops there, with
    no restart.

    Parameters
    ----------
    model : LoopModel
        The current model.
    data : LoopData
        The record on the analysis grid.
    names : list of str
        What to fit: :data:`LAW` (the law's free parameters, with the ``wob_coupling`` gain),
        :data:`DAMPING` (the modal damping ratios), :data:`GJ` (the string's GJ factor within
        ``model.gj_tolerance``) and effect names (their
        :meth:`~drillpy.loop.effects.base.Effect.free` parameters).
    opt : LoopOptions
        ``nfev_per_parameter`` and ``threads`` are used.

    Returns
    -------
    tuple
        (fitted LoopModel, intervals dict); an unchanged copy and {} when nothing is free.
        ``ci95`` is None for a parameter at its bound (``at_bound`` True) or without a finite
        standard error.
    """
    x0, lo, hi, where = _pack(model, data, names)
    if x0.size == 0:
        return model.copy(), {}
    x0 = np.clip(x0, _inside(lo, +1), _inside(hi, -1))
    size = (3 if data.has_top else 2) * int((~data.is_test).sum()) * data.L

    def clean(r):  # an unstable or diverging trial: a large residual
        if isinstance(r, (ValueError, RuntimeError)):
            return np.full(size, 10.0)
        if isinstance(r, BaseException):
            raise r
        return r if np.isfinite(r).all() else np.where(np.isfinite(r), r, 10.0)

    # the last evaluation and the last Jacobian: the optimizer asks for J where it just evaluated,
    # and a restart starts with f and J at the point where the run before it ended
    last, last_jac = {}, {}

    def res(x):
        if "x" in last and np.array_equal(last["x"], x):
            return np.copy(last["f"])
        try:
            r = residual_vector(_unpack(model, x, where, data.law_knot, trial=True), data, opt.threads, check=False)
        except (ValueError, RuntimeError) as e:
            r = e
        last["x"], last["f"] = np.copy(x), clean(r)
        return last["f"]

    def batch(points):  # the perturbed models of one Jacobian: one engine call
        models = [_unpack(model, x, where, data.law_knot, trial=True) for x in points]
        return [clean(r) for r in residual_vectors(models, data, opt.threads, check=False)]

    def jac(x):
        if "x" in last_jac and np.array_equal(last_jac["x"], x):
            return np.copy(last_jac["J"])
        f0 = last["f"] if "x" in last and np.array_equal(last["x"], x) else res(x)
        last_jac["x"], last_jac["J"] = np.copy(x), fd_jacobian(batch, x, f0, fd_steps(x, lo, hi, DIFF_STEP))
        return last_jac["J"]  # (the trust region with the linear loss does not write into J)

    # one engine call per Jacobian (scipy's steps, the engine's lanes bit-identical to single runs:
    # the same Jacobian as scipy's '2-point', bit for bit), or scipy's differences, one call each
    kw = dict(bounds=(lo, hi), method="trf", jac=jac if opt.batched_jacobian else "2-point", diff_step=DIFF_STEP,
              x_scale="jac", xtol=1e-6, ftol=1e-6)
    budget = opt.nfev_per_parameter * x0.size
    r = optimize.least_squares(res, x0, max_nfev=budget, callback=_stall_check(), **kw)
    used = r.nfev
    # Restarts: the short horizons' residual jumps where a predicted stop or break-away crosses a
    # sample, so the trust region shrinks on a kink and the step test (xtol) stops the search far from
    # a stationary point; a restart from the result re-opens the region. Repeated, within the same
    # budget, while a restart lowers the cost by RESTART_GAIN at least (docs/loop.md, "Calibration").
    for _ in range(RESTARTS):
        if used >= budget or r.status not in (2, 3):
            break
        s = optimize.least_squares(res, r.x, max_nfev=budget - used, callback=_stall_check(), **kw)
        used += s.nfev
        gained = s.cost < (1.0 - RESTART_GAIN) * r.cost
        if s.cost < r.cost:
            r = s
        if not gained:
            break
    return _unpack(model, r.x, where, data.law_knot), _intervals(r, lo, hi, where, _law_owned(model))


def _stall_check():
    """A ``least_squares`` callback that stops a run whose cost fell by less than
    :data:`STALL_GAIN` of itself over its last :data:`STALL_WINDOW` iterations (status -2: no
    restart follows)."""
    costs = []

    def check(intermediate_result):
        costs.append(float(intermediate_result.cost))
        if len(costs) > STALL_WINDOW and costs[-1 - STALL_WINDOW] - costs[-1] < STALL_GAIN * costs[-1]:
            raise StopIteration
    return check


def _intervals(r, lo, hi, where, owned: dict) -> dict:
    J, f = r.jac, r.fun
    n, p = f.size, r.x.size
    tau = max(1.0, ident.autocorrelation_time(f)) if n > 3 and np.std(f) > 0 else 1.0
    s2 = float(f @ f) * n / max(n - p, 1) / n  # the residuals are normalized by sqrt(2 n): their mean square
    try:
        cov = np.linalg.pinv(J.T @ J) * s2 * tau
    except np.linalg.LinAlgError:
        cov = np.full((p, p), np.nan)
    out = {}
    for i, (name, key, scale) in enumerate(where):
        if name == LAW and key in owned:
            name = owned[key]  # the law's optional term is that effect's
        elif name in (LAW, DAMPING, GJ):
            continue
        se = math.sqrt(max(cov[i, i], 0.0)) if np.isfinite(cov[i, i]) else math.nan
        a, b = r.x[i] - 1.96 * se, r.x[i] + 1.96 * se
        tr = math.exp if scale == "log" else float
        span = hi[i] - lo[i] if np.isfinite(hi[i] - lo[i]) else max(abs(r.x[i]), 1.0)
        edge = (np.isfinite(lo[i]) and r.x[i] - lo[i] <= 1e-3 * span) or (np.isfinite(hi[i]) and hi[i] - r.x[i] <= 1e-3 * span)
        out.setdefault(name, {})[key] = {"value": tr(r.x[i]), "ci95": None if edge or not math.isfinite(se) else
                                         [tr(a), tr(b)], "at_bound": bool(edge)}
    return out


def _calibrate(model: LoopModel, data: LoopData, opt: LoopOptions) -> tuple:
    """The law, the damping ratios, the GJ within its tolerance and every effect's free parameters
    jointly on the calibration horizons, from the model's values."""
    return fit_dynamic(model, data, [LAW] + ([] if model.damping_held else [DAMPING]) + ([GJ] if model.gj_free else [])
                       + list(model.effects), opt)


def _finish(model: LoopModel, data: LoopData) -> LoopModel:
    """The values the effects estimate outside the fits (:meth:`Effect.estimate
    <drillpy.loop.effects.base.Effect.estimate>`), from the calibrated model's slip samples."""
    @functools.cache
    def slip():
        chs = law_channels(model, data)
        idx = data.law_train
        return chs["T"][idx], law_torque(model, chs, idx)

    for n, p in model.effects.items():
        p.update(CATALOGUE[n].estimate(p, slip))
    return model


def refit(model: LoopModel, data: LoopData, opt: LoopOptions) -> tuple:
    """Calibrate every parameter of a model from a fresh law fit and from its own values; the
    calibration (never the validation) error decides. Returns (model, intervals).

    Parameters
    ----------
    model : LoopModel
        The current model.
    data : LoopData
        The record on the analysis grid.
    opt : LoopOptions
        The loop's options (the optimizer's budget, threads).

    Returns
    -------
    tuple
        (LoopModel, intervals as :func:`fit_dynamic`).
    """
    law = fit_law(model, data)
    own = model.copy()
    own.n_law = law.n_law  # one law family: its free parameters count alike from either start
    a, b = task_map(lambda m, o: _calibrate(m, data, o), [law, own], opt)  # the two starts side by side
    best = a if e_train(a[0], data, opt.threads) < e_train(b[0], data, opt.threads) else b
    m = _finish(best[0], data)
    m.intervals = best[1]
    return m, best[1]


def null_candidate(model: LoopModel, data: LoopData, opt: LoopOptions) -> tuple:
    """The control of a round: the current model recalibrated, no effect added, same procedure and
    budget as every candidate.

    Parameters
    ----------
    model : LoopModel
        The current model.
    data : LoopData
        The record on the analysis grid.
    opt : LoopOptions
        The loop's options (the optimizer's budget, threads).

    Returns
    -------
    tuple
        (LoopModel, intervals as :func:`fit_dynamic`).
    """
    m, ci = _calibrate(model, data, opt)
    return _finish(m, data), ci


def declared_model(cfg: dict, data: LoopData, opt: LoopOptions) -> LoopModel:
    """The declared model before its calibration: its catalogue effects taken out of the
    configuration into the model, the declared law, damping and GJ, and the operating point (top
    speed and WOB: the calibration part's means).

    Parameters
    ----------
    cfg : dict
        The declared engine configuration (normalized, at the loop's engine step).
    data : LoopData
        The record on the analysis grid.
    opt : LoopOptions
        The loop's options (the GJ tolerance).

    Returns
    -------
    LoopModel
    """
    tr = data.valid & (data.t < data.t_split)
    op = view(cfg).operation
    om = float(np.mean(data.ch["top"][tr])) if data.has_top else float(op.top_speed_rad_s)
    w0 = float(np.mean(data.ch["W"][tr])) if data.has_wob else float(op.wob_n)
    base = stripped(cfg)
    wr = data.wob_response
    fluct = None
    if opt.long_run_fluctuation == "record":  # Eq. (4.1)'s fluctuation the calibration part shows
        part = data.record.select(None, data.t_split)
        fluct = rig_fluctuation.of_record(part, data.stick_threshold)
    return LoopModel(base, view(base).law.to_dict(), om, w0, declared_effects(cfg), gj_tolerance=opt.gj_tolerance,
                     wob_input=wr["input"] if wr else "measured", wob_is_response=bool(wr and wr["response"]),
                     metric_scale=(data.sigma_v, data.sigma_T), fluctuation=fluct,
                     channel_timing=bit_balance.applied_timing(data.channel_timing))


def calibrate(cfg: dict, data: LoopData, opt: LoopOptions) -> tuple:
    """The declared model (:func:`declared_model`) calibrated on the calibration part: the law, the
    damping ratios, the string's GJ within ``opt.gj_tolerance`` of the declared and the effects'
    parameters. Returns (model, intervals).

    Parameters
    ----------
    cfg : dict
        The declared engine configuration (normalized, at the loop's engine step).
    data : LoopData
        The record on the analysis grid.
    opt : LoopOptions
        The loop's options (the optimizer's budget, threads).

    Returns
    -------
    tuple
        (LoopModel, intervals as :func:`fit_dynamic`).
    """
    return refit(declared_model(cfg, data, opt), data, opt)


def fit_candidate(model: LoopModel, data: LoopData, name: str, opt: LoopOptions) -> tuple:
    """The model with effect ``name`` added, started from the current values and the effect's best
    start (an effect that reshapes the law also from the law refitted on the law residual with it:
    the calibration error of the starts decides), calibrated like the null candidate. Returns
    (model, intervals).

    A law-level effect is started from its defaults and fitted with the law on the law residual
    first. An effect whose direct measurement is significant starts from the measured values only.
    ``string_stiffness`` carries the whole GJ factor: the factor calibrated within the declared
    tolerance is reset to 1 while it is an effect.

    Parameters
    ----------
    model : LoopModel
        The current model.
    data : LoopData
        The record on the analysis grid.
    name : str
        The catalogue name of the effect to add.
    opt : LoopOptions
        The loop's options (the optimizer's budget, threads).

    Returns
    -------
    tuple
        (LoopModel, intervals as :func:`fit_dynamic`).

    Raises
    ------
    ValueError
        No start the engine accepts.
    """
    eff = CATALOGUE[name]
    m = model.copy()
    if name == STIFFNESS:
        m.gj_factor = 1.0  # the effect carries the whole factor
    if eff.level == "law":
        m.effects[name] = dict(eff.defaults)  # the law's start (fit_law starts the hysteresis from the law)
        m, ci = _calibrate(fit_law(m, data), data, opt)  # the law's new term on the law residual first
        return _finish(m, data), ci
    best, err = None, math.inf
    d = eff.direct(m, data)
    for p in ([d["params"]] if d and d["significant"] else eff.starts(m, data)):
        c = m.copy()
        c.effects[name] = dict(p)
        for s in ([c, fit_law(c, data)] if eff.reshapes_law else [c]):
            e = e_train(s, data, opt.threads)
            if e < err:
                best, err = s, e
    if best is None:
        raise ValueError(f"{name}: no start the engine accepts")
    m, ci = _calibrate(best, data, opt)
    return _finish(m, data), ci


def fit_round(model: LoopModel, data: LoopData, names: list, opt: LoopOptions) -> tuple:
    """A round's fits side by side (:func:`drillpy.loop.side_by_side.task_map`): the null candidate
    (:func:`null_candidate`) and every candidate of ``names`` (:func:`fit_candidate`).

    Parameters
    ----------
    model : LoopModel
        The current model.
    data : LoopData
        The record on the analysis grid.
    names : list of str
        The candidates' catalogue names.
    opt : LoopOptions
        The loop's options (the optimizer's budget, threads).

    Returns
    -------
    tuple
        (the null candidate's model, {name: (model, intervals), or the ValueError or RuntimeError of
        a candidate the engine refuses: not evidence}).
    """
    def fit(name, o):
        if name is None:
            return null_candidate(model, data, o)[0]
        try:
            return fit_candidate(model, data, name, o)
        except (ValueError, RuntimeError) as err:
            return err
    null_m, *fits = task_map(fit, [None, *names], opt)
    return null_m, dict(zip(names, fits))


def parameter_evidence(model: LoopModel, name: str, ci: dict, data: LoopData) -> tuple:
    """(parameters with intervals, reasons against crediting the effect): each fitted parameter
    must be inside its bounds and its interval must exclude the no-effect value; the effect's own
    plausibility checks must pass.

    A parameter at a bound that is not ``binding`` (a shape parameter) is only flagged; the
    no-effect value is widened by the parameter's ``margin``. A directly measured parameter takes
    the direct measurement's interval (the effect's other parameters keep the fit's).

    Parameters
    ----------
    model : LoopModel
        The fitted candidate (with the effect).
    name : str
        The effect's catalogue name.
    ci : dict
        Intervals from :func:`fit_dynamic` ({effect: {parameter: {"value", "ci95", "at_bound"}}}).
    data : LoopData
        The record (for the effect's :meth:`~drillpy.loop.effects.base.Effect.flags`).

    Returns
    -------
    tuple
        ({parameter: {"value", "ci95", "at_bound", "unit", ...}}, list of str reasons; empty: the
        parameters are significant and physical).
    """
    eff = CATALOGUE[name]
    p = model.effects.get(name, {})
    rows, reasons = {}, []
    direct = eff.direct(model, data) if p.get("source") else None
    for q in eff.params:
        if q.name not in p:
            continue
        info = dict(ci.get(name, {}).get(q.name, {"value": p[q.name], "ci95": None, "at_bound": False}))
        if direct is not None and q.name in direct["ci95"]:
            info.update(ci95=direct["ci95"][q.name], source=p["source"])
        info["unit"] = q.unit
        rows[q.name] = info
        if not q.fitted:
            continue
        if info["at_bound"] and not q.binding:
            info["flag"] = "at its bound"
        elif info["at_bound"]:
            reasons.append(f"{q.name} = {p[q.name]:.4g} {q.unit} at its bound")
        elif q.null is not None and info.get("ci95") is not None:
            lo, hi = info["ci95"]
            if lo <= q.null + q.margin and hi >= q.null - q.margin:
                what = f"the no-effect value {q.null:g}" + (f" +- {q.margin:g} (the declared model's tolerance)"
                                                            if q.margin else "")
                reasons.append(f"{q.name}: 95 % interval [{lo:.4g}, {hi:.4g}] reaches {what}")
    reasons += eff.flags(p, data, model)
    return rows, reasons
