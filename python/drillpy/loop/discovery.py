"""What the catalogue cannot name: sparse regression of a residual on a library of candidate terms.

The loop's catalogue (:mod:`drillpy.loop.effects`) only tries effects it knows by name. This module is
the step after it: the residual r [N m] left by the declared model (one value per sample, NaN where
undefined) is regressed on a library of candidate terms built from the measured channels
(:func:`library`), the few terms that explain it are kept (:func:`discover`) and each is reported
with its coefficient in physical units and a physical reading; :func:`residual_structure` describes
what is left (RMS, spectral peaks, correlation with the channels).

**Estimator.** Orthogonal matching pursuit (:func:`sklearn.linear_model.orthogonal_mp`, its path)
along its path of 0..``max_terms`` terms, the number of terms chosen by BIC computed with the
effective sample size n_eff = n / tau. OMP refits the selected terms by unpenalized least squares
(no Lasso shrinkage, so the coefficients are read directly in physical units) and caps the model at
a handful of terms, and its one-term-at-a-time path makes an information criterion at n_eff
(which :class:`~sklearn.linear_model.LassoLarsIC` cannot take: it uses the raw n) and a blocked
bootstrap cheap and exact.

**Autocorrelation.** Samples of a 500 Hz-1 kHz record are far from independent. tau is the
integrated autocorrelation time of the residual (:func:`drillpy.records.identification.autocorrelation_time`,
Geyer's initial positive sequence), the larger of the residual's own and of what a first OMP/BIC
fit on all samples leaves of it (the noise, whose correlation is what matters, may be slower than
the residual as a whole), and n_eff = n / tau replaces n in the BIC and in the tests.
**Stability:** the selection is repeated on ``B = 50`` circular moving-block bootstrap resamples
(blocks of round(tau) samples, :class:`numpy.random.Generator` seeded with ``seed``); a term is kept
only if it is selected in at least 80 % of them; kept terms are then removed one at a time (the
weakest first) while the partial F test at n_eff, F = n_eff (RSS_without - RSS) / RSS on
(1, n_eff - p) degrees of freedom, has a p-value above ``alpha``. Coefficient intervals are the
2.5-97.5 % percentiles of the least-squares refits of the kept terms on the same resamples.
**Aliases:** terms correlated beyond |r| = 0.95 on the samples used (e.g. v and top - v when the
top speed is nearly constant, twist and a when one mode dominates) cannot be told apart by any
regression; their selections are pooled, the one selected most often is reported and lists the
others as ``aliases`` with their readings.

**Conventions.** Every term but ``constant`` enters the regression centred (its mean goes into the
constant), so the coefficient of ``constant`` is the mean level of the residual the other terms do
not account for. Explained fractions are fractions of the residual's mean square sum r^2 (the
offset counts as something to explain): joint, 1 - RSS(kept)/sum r^2; partial, the increase of RSS
when the term is removed from the joint fit, over sum r^2.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy import signal as sps
from scipy import stats

from drillpy.records.identification import autocorrelation_time
from drillpy import validate

#: Number of block-bootstrap resamples of the stability check.
N_BOOTSTRAP = 50
#: A term is kept only if selected in at least this fraction of the resamples.
MIN_SELECTION_FREQUENCY = 0.8
#: Smooth sign s(x) = x / sqrt(x^2 + eps^2), eps this fraction of mean |x|.
SIGN_EPS_FRACTION = 0.05
#: Terms correlated beyond this (in absolute value) on the samples used are aliases: the data cannot
#: tell them apart; their selections are pooled and the kept one lists the others.
ALIAS_CORRELATION = 0.95
#: Fewest finite samples accepted.
MIN_SAMPLES = 50
REQUIRED_CHANNELS = ("v", "a", "T", "twist")
OPTIONAL_CHANNELS = ("top", "dtop", "W")


@dataclass(frozen=True, eq=False)  # holds an array: identity equality
class Term:
    """One candidate term of the library.

    Attributes
    ----------
    name : str
        Short name (the key in the library).
    values : numpy.ndarray
        The term, one value per sample, in the unit of the channels it is built from.
    unit : str
        Unit of its coefficient when the residual is a torque [N m] (N m per unit of the term).
    reading : str
        Physical reading of a non-zero coefficient.
    """

    name: str
    values: np.ndarray = field(repr=False)
    unit: str
    reading: str


class Library(dict):
    """``dict[str, Term]`` returned by :func:`library`, with the terms it left out in ``skipped``
    (``{name: reason}``)."""

    def __init__(self, *args, skipped: dict | None = None, **kwargs):
        super().__init__(*args, **kwargs)
        self.skipped = dict(skipped or {})


# ------------------------------------------------------------------------------------ helpers
def _array(name: str, x, n: int | None = None) -> np.ndarray:
    try:
        a = np.asarray(x, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} = {x!r:.60}: not a numeric array ({exc})") from None
    if a.ndim != 1:
        raise ValueError(f"{name}: a 1-D array is needed, got shape {a.shape}")
    if n is not None and a.size != n:
        raise ValueError(f"{name}: length {a.size} does not match the other arrays' length {n}")
    return a


def _check_finite_count(name: str, x: np.ndarray) -> np.ndarray:
    ok = np.isfinite(x)
    if not ok.any():
        raise ValueError(f"{name}: non-finite everywhere ({x.size} samples)")
    if ok.sum() < MIN_SAMPLES:
        raise ValueError(f"{name}: {int(ok.sum())} finite samples, at least {MIN_SAMPLES} needed")
    return ok


def smooth_sign(x: np.ndarray, eps: float | None = None) -> np.ndarray:
    """Smooth sign x / sqrt(x^2 + eps^2); ``eps`` defaults to 5 % of the mean |x| (NaN ignored).

    Parameters
    ----------
    x : numpy.ndarray
        Values (e.g. bit speed [rad/s]).
    eps : float, optional
        Regularization, in the unit of ``x`` (default :data:`SIGN_EPS_FRACTION` x mean |x|); when
        it is not positive the plain sign is returned.

    Returns
    -------
    numpy.ndarray
        Values in (-1, 1), same shape as ``x``.
    """
    x = np.asarray(x, float)
    if eps is None:
        eps = SIGN_EPS_FRACTION * float(np.nanmean(np.abs(x)))
    if not (eps > 0.0):
        return np.sign(x)
    return x / np.sqrt(x * x + eps * eps)


def _fill_nan(x: np.ndarray) -> np.ndarray:
    """Linear interpolation over non-finite samples (constant beyond the ends)."""
    ok = np.isfinite(x)
    if ok.all():
        return x
    i = np.arange(x.size)
    return np.interp(i, i[ok], x[ok])


def _tau(x: np.ndarray) -> float:
    """Integrated autocorrelation time [samples] of the finite samples of ``x``, at least 1."""
    x = x[np.isfinite(x)]
    if x.size < 3 or np.ptp(x) == 0.0:
        return 1.0
    t = autocorrelation_time(x)
    return float(min(max(t, 1.0), x.size)) if math.isfinite(t) else 1.0


# ------------------------------------------------------------------------------------ library
def library(channels: dict, wob_ref: float | None = None, *, dt: float | None = None) -> Library:
    """Candidate terms built from the measured channels.

    Parameters
    ----------
    channels : dict
        1-D arrays of equal length sampled every ``dt``: ``v`` bit speed [rad/s], ``a`` bit
        acceleration [rad/s^2], ``T`` torque on bit [N m], ``twist`` top angle minus bit angle [rad]
        (known up to a constant); optional ``top`` top speed [rad/s], ``dtop`` its rate [rad/s^2],
        ``W`` weight on bit [N], ``t`` time stamps [s] (used for the bit angle when ``dt`` is not
        given).
    wob_ref : float, optional
        Reference weight on bit [N] of the WOB terms; default the mean of ``W``.
    dt : float, optional
        Sampling interval [s], needed for the bit angle (cumulative integral of ``v``) of the
        once-per-revolution terms; without it (and without ``channels['t']``) they are skipped.

    Returns
    -------
    Library
        ``{name: Term}`` (a ``dict``); ``.skipped`` maps the terms left out to the reason (input
        not given, values constant or NaN everywhere).

    Notes
    -----
    Terms (coefficient unit for a residual in N m): ``constant`` [N m]; ``twist`` (centred) [N m/rad]
    stiffness mismatch; ``top_minus_v`` [N m s/rad] string damping mismatch; ``v`` [N m s/rad]
    viscous torque at the bit; ``sign_v`` = v / sqrt(v^2 + eps^2), eps 5 % of mean |v| [N m]
    Coulomb friction; ``v_abs_v`` = v|v| [N m s^2/rad^2] quadratic drag; ``a`` [kg m^2] bit
    inertia mismatch; ``T`` [-] torque gain / law scale; ``T_sign_a`` = T s(a) (smooth sign, eps
    5 % of mean |a|) [-] hysteresis of the bit-rock law; ``W`` = W - W_ref [m] WOB coupling;
    ``T_W`` = T (W / W_ref - 1) [-] WOB-proportional torque; ``dtop`` [kg m^2] top-drive inertia
    coupling; ``sin_theta``, ``cos_theta`` of the bit angle theta = int v dt [N m] a
    once-per-revolution effect.
    """
    if not isinstance(channels, dict):
        raise ValueError(f"channels = {type(channels).__name__}: a dict of 1-D arrays is needed")
    for key in REQUIRED_CHANNELS:
        if key not in channels or channels[key] is None:
            raise ValueError(f"channels[{key!r}]: missing (needed: {', '.join(REQUIRED_CHANNELS)})")
    v = _array("channels['v']", channels["v"])
    n = v.size
    ch = {"v": v}
    for key in REQUIRED_CHANNELS[1:] + OPTIONAL_CHANNELS + ("t",):
        if channels.get(key) is not None:
            ch[key] = _array(f"channels[{key!r}]", channels[key], n)
    for key in REQUIRED_CHANNELS:
        _check_finite_count(f"channels[{key!r}]", ch[key])
    if dt is not None:
        dt = validate.positive("dt", dt, "s")

    skipped: dict[str, str] = {}
    terms: list[Term] = []

    def add(name, values, unit, reading):
        terms.append(Term(name, np.asarray(values, float), unit, reading))

    v, a, T = ch["v"], ch["a"], ch["T"]
    sv = smooth_sign(v)
    add("constant", np.ones(n), "N m",
        "constant torque offset: a torque-sensor zero offset or a speed-independent friction torque")
    add("twist", ch["twist"] - np.nanmean(ch["twist"]), "N m/rad",
        "string stiffness mismatch: GJ/L of the model off by this much (torque per radian of twist)")
    if "top" in ch:
        add("top_minus_v", ch["top"] - v, "N m s/rad",
            "string (structural) damping mismatch: torque per rad/s of top-bit speed difference")
    else:
        skipped["top_minus_v"] = "channels['top'] not given"
    add("v", v, "N m s/rad", "viscous torque at the bit (mud / contact damping proportional to bit speed)")
    add("sign_v", sv, "N m",
        "Coulomb friction at the bit or along the string (a torque of constant magnitude opposing rotation)")
    add("v_abs_v", v * np.abs(v), "N m s^2/rad^2", "quadratic (turbulent-like) drag on the bit speed")
    add("a", a, "kg m^2", "bit-side inertia mismatch (torque proportional to the bit acceleration)")
    add("T", T, "1", "torque-sensor gain or bit-rock law scale off by this fraction")
    add("T_sign_a", T * smooth_sign(a), "1",
        "hysteresis of the bit-rock law: torque differs between accelerating and decelerating bit")
    if "W" in ch:
        W = ch["W"]
        if wob_ref is None:
            wref = float(np.nanmean(W))
        else:
            wref = validate.positive("wob_ref", wob_ref, "N")
        add("W", W - wref, "m", "WOB coupling: torque per newton of weight-on-bit variation (an effective radius)")
        if wref != 0.0 and math.isfinite(wref):
            add("T_W", T * (W / wref - 1.0), "1",
                "WOB-proportional torque: the bit-rock torque scales with the weight on bit")
        else:
            skipped["T_W"] = f"reference WOB {wref!r} N is zero or not finite"
    else:
        skipped["W"] = skipped["T_W"] = "channels['W'] not given"
    if "dtop" in ch:
        add("dtop", ch["dtop"], "kg m^2",
            "top-drive inertia coupling: torque proportional to the top-drive acceleration")
    else:
        skipped["dtop"] = "channels['dtop'] not given"

    theta = None
    vf = _fill_nan(v)
    if dt is not None:
        theta = np.concatenate(([0.0], np.cumsum(0.5 * (vf[1:] + vf[:-1]) * dt)))
    elif "t" in ch and np.all(np.isfinite(ch["t"])) and np.all(np.diff(ch["t"]) > 0):
        tt = ch["t"]
        theta = np.concatenate(([0.0], np.cumsum(0.5 * (vf[1:] + vf[:-1]) * np.diff(tt))))
    if theta is not None:
        add("sin_theta", np.sin(theta), "N m",
            "once-per-revolution torque (sine of the bit angle): misalignment, eccentricity, a bent joint")
        add("cos_theta", np.cos(theta), "N m",
            "once-per-revolution torque (cosine of the bit angle): misalignment, eccentricity, a bent joint")
    else:
        skipped["sin_theta"] = skipped["cos_theta"] = "bit angle needs dt (or channels['t'])"

    out = Library()
    for term in terms:
        x = term.values
        ok = np.isfinite(x)
        if not ok.any():
            skipped[term.name] = "NaN everywhere"
        elif term.name != "constant" and np.ptp(x[ok]) == 0.0:
            skipped[term.name] = "constant values (no information)"
        else:
            out[term.name] = term
    out.skipped = skipped
    return out


# ------------------------------------------------------------------------------------ regression
def _omp_bic(X: np.ndarray, y: np.ndarray, n_eff: float, max_terms: int) -> np.ndarray:
    """Indices of the columns OMP selects at the BIC-optimal number of terms (BIC at n_eff), from
    one OMP path (:func:`sklearn.linear_model.orthogonal_mp`, ``return_path``: the coefficients
    after each added term)."""
    from sklearn.linear_model import orthogonal_mp

    n = y.size
    best = (n_eff * math.log(max(float(y @ y), 1e-300) / n), np.zeros(0, int))
    kmax = min(max_terms, X.shape[1], max(int(n_eff) - 2, 0))
    if kmax < 1:
        return best[1]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "ended prematurely due to linear dependence": the path stops there
        path = orthogonal_mp(X, y, n_nonzero_coefs=kmax, precompute=X.shape[0] > X.shape[1], return_path=True)
    path = path.reshape(X.shape[1], -1)
    for coef in path.T:
        sel = np.flatnonzero(coef)
        rss = float(np.sum((y - X @ coef) ** 2))
        bic = n_eff * math.log(max(rss, 1e-300) / n) + sel.size * math.log(n_eff)
        if bic < best[0]:
            best = (bic, sel)
    return best[1]


def _ols(X: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, float]:
    if X.shape[1] == 0:
        return np.zeros(0), float(y @ y)
    coef = np.linalg.lstsq(X, y, rcond=None)[0]
    r = y - X @ coef
    return coef, float(r @ r)


def _block_indices(rng: np.random.Generator, n: int, block: int) -> np.ndarray:
    nb = -(-n // block)
    starts = rng.integers(0, n, size=nb)
    return ((starts[:, None] + np.arange(block)[None, :]) % n).ravel()[:n]


def discover(residual: np.ndarray, terms: dict, *, dt: float, max_terms: int = 4,
             alpha: float = 0.01, seed: int = 0) -> dict:
    """Find the library terms that explain a residual, by sparse regression.

    Parameters
    ----------
    residual : numpy.ndarray
        Residual [N m], one value per sample. NaN samples (of the residual or of a term) are
        excluded and the rest concatenated; a term NaN on more than 5 % of the finite-residual
        samples is skipped instead.
    terms : dict
        ``{name: Term}``, typically :func:`library`'s result (its ``skipped`` is carried over).
    dt : float
        Sampling interval [s] (reports tau in seconds).
    max_terms : int
        Most terms selected in one fit.
    alpha : float
        Level of the partial F test at n_eff that every kept term must pass.
    seed : int
        Seed of the block bootstrap's :class:`numpy.random.Generator`.

    Returns
    -------
    dict
        ``terms``: list of ``{name, coefficient, unit, ci95, selection_frequency,
        explained_fraction, reading}`` (coefficient in ``unit``, ci95 the 95 % block-bootstrap
        interval, explained_fraction the partial fraction of the residual's mean square);
        ``explained_fraction`` (R^2 of the kept terms jointly), ``unexplained_fraction``, ``n``
        (samples used), ``n_eff``, ``tau`` [samples], ``tau_s`` [s], ``block_length`` [samples],
        ``skipped`` ({name: reason}), ``selection_frequency`` (every candidate), ``method``.

    Raises
    ------
    ValueError
        Length mismatch, ``dt <= 0``, fewer than 50 finite samples, no term, bad ``max_terms`` or
        ``alpha``.
    """
    dt = validate.positive("dt", dt, "s")
    r = _array("residual", residual)
    if not isinstance(terms, dict) or not terms:
        raise ValueError(f"terms = {terms!r:.60}: a non-empty dict of Term is needed")
    if isinstance(max_terms, bool) or not isinstance(max_terms, (int, np.integer)) or max_terms < 1:
        raise ValueError(f"max_terms = {max_terms!r}: must be a positive integer")
    if not (isinstance(alpha, (int, float)) and 0.0 < alpha < 1.0):
        raise ValueError(f"alpha = {alpha!r}: must lie in (0, 1)")
    ok = _check_finite_count("residual", r)
    n_all = r.size

    skipped = dict(getattr(terms, "skipped", {}) or {})
    cols: dict[str, np.ndarray] = {}
    meta: dict[str, Term] = {}
    for name, term in terms.items():
        if not isinstance(term, Term):
            raise ValueError(f"terms[{name!r}]: a Term is needed, got {type(term).__name__}")
        x = _array(f"terms[{name!r}].values", term.values, n_all)
        good = np.isfinite(x[ok])
        if not good.any():
            skipped[name] = "NaN on every finite-residual sample"
        elif good.mean() < 0.95:
            skipped[name] = f"NaN on {100 * (1 - good.mean()):.0f} % of the finite-residual samples"
        else:
            cols[name], meta[name] = x, term
    if not cols:
        raise ValueError("terms: no usable term (all NaN)")
    use = ok.copy()
    for x in cols.values():
        use &= np.isfinite(x)
    if use.sum() < MIN_SAMPLES:
        raise ValueError(f"residual: {int(use.sum())} samples finite in the residual and every term, "
                         f"at least {MIN_SAMPLES} needed")
    y = r[use]
    n = y.size
    names, Xs, scale = [], [], []
    for name, x in cols.items():
        xu = x[use]
        if name == "constant":
            names.append(name)
            Xs.append(np.ones(n))
            scale.append(1.0)
            continue
        s = float(np.std(xu))
        if not (s > 1e-12 * max(1.0, float(np.max(np.abs(xu))))):
            skipped[name] = "constant values on the samples used (no information)"
            continue
        names.append(name)
        Xs.append((xu - xu.mean()) / s)
        scale.append(s)
    X = np.column_stack(Xs) if Xs else np.zeros((n, 0))
    scale = np.asarray(scale)

    # tau: the larger of the residual's and of what a first OMP/BIC fit on all samples leaves
    tau = _tau(y)
    if X.shape[1]:
        sel0 = _omp_bic(X, y, n / tau, max_terms)
        c0, _ = _ols(X[:, sel0], y)
        tau = max(tau, _tau(y - X[:, sel0] @ c0))
    n_eff = n / tau
    block = max(1, int(round(tau)))
    method = (f"sklearn.linear_model.orthogonal_mp path (<= {max_terms} terms, "
              f"standardized), number of terms by BIC at n_eff = n/tau; kept if selected in >= "
              f"{MIN_SELECTION_FREQUENCY:.0%} of {N_BOOTSTRAP} moving-block bootstrap refits "
              f"(block {block} samples) and partial F test at n_eff p < {alpha:g}")
    tss = float(y @ y)
    base = {"n": int(n), "n_eff": float(n_eff), "tau": float(tau), "tau_s": float(tau * dt),
            "block_length": block, "skipped": skipped, "method": method}
    if X.shape[1] == 0 or tss == 0.0:
        return {"terms": [], "explained_fraction": 0.0, "unexplained_fraction": 1.0,
                "selection_frequency": {}, **base}

    # aliases: terms the data cannot tell apart (|correlation| above ALIAS_CORRELATION, transitively)
    p_all = X.shape[1]
    group = list(range(p_all))

    def root(j):
        while group[j] != j:
            j = group[j]
        return j

    C = X.T @ X / n  # correlations: the non-constant columns are centred and of unit variance
    for i in range(p_all):
        for j in range(i + 1, p_all):
            if names[i] != "constant" and names[j] != "constant" and abs(C[i, j]) > ALIAS_CORRELATION:
                group[root(j)] = root(i)
    groups = np.array([root(j) for j in range(p_all)])

    rng = np.random.default_rng(seed)
    resamples = [_block_indices(rng, n, block) for _ in range(N_BOOTSTRAP)]
    counts = np.zeros(p_all)
    gcounts = np.zeros(p_all)
    for idx in resamples:
        sel = _omp_bic(X[idx], y[idx], n_eff, max_terms)
        counts[sel] += 1
        gcounts[np.unique(groups[sel])] += 1
    freq = counts / N_BOOTSTRAP
    gfreq = gcounts / N_BOOTSTRAP
    kept = []
    for g in np.flatnonzero(gfreq >= MIN_SELECTION_FREQUENCY):
        members = np.flatnonzero(groups == g)
        strong = [j for j in members if freq[j] >= MIN_SELECTION_FREQUENCY]
        kept += strong or [int(members[np.argmax(freq[members])])]
    kept = sorted(kept, key=lambda j: (-gfreq[groups[j]], -freq[j], j))

    # partial F test at n_eff: drop the weakest term while it is not significant
    while kept:
        _, rss = _ols(X[:, kept], y)
        p = len(kept)
        dof = max(n_eff - p, 1.0)
        pvals = []
        for i in range(p):
            _, rss_i = _ols(X[:, [k for m, k in enumerate(kept) if m != i]], y)
            F = n_eff * (rss_i - rss) / max(rss, 1e-300)
            pvals.append(float(stats.f.sf(F, 1, dof)))
        worst = int(np.argmax(pvals))
        if pvals[worst] <= alpha:
            break
        kept.pop(worst)

    if not kept:
        return {"terms": [], "explained_fraction": 0.0, "unexplained_fraction": 1.0,
                "selection_frequency": dict(zip(names, map(float, freq))), **base}

    coef, rss = _ols(X[:, kept], y)
    boot = np.array([_ols(X[idx][:, kept], y[idx])[0] for idx in resamples])
    phys = coef / scale[kept]
    lo, hi = np.percentile(boot / scale[kept], [2.5, 97.5], axis=0)
    out_terms = []
    for i, j in enumerate(kept):
        _, rss_i = _ols(X[:, [k for m, k in enumerate(kept) if m != i]], y)
        t = meta[names[j]]
        aliases = [{"name": names[k], "correlation": float(C[j, k]), "reading": meta[names[k]].reading}
                   for k in np.flatnonzero(groups == groups[j]) if k != j and k not in kept]
        out_terms.append({"name": names[j], "coefficient": float(phys[i]), "unit": t.unit,
                          "ci95": (float(lo[i]), float(hi[i])),
                          "selection_frequency": float(gfreq[groups[j]]),
                          "explained_fraction": float((rss_i - rss) / tss), "reading": t.reading,
                          "aliases": aliases})
    explained = float(min(max(1.0 - rss / tss, 0.0), 1.0))
    return {"terms": out_terms, "explained_fraction": explained, "unexplained_fraction": 1.0 - explained,
            "selection_frequency": dict(zip(names, map(float, freq))), **base}


# ------------------------------------------------------------------------------------ structure
def _acf(x: np.ndarray) -> np.ndarray:
    x = x - x.mean()
    n = x.size
    f = np.fft.rfft(x, 2 * n)
    acf = np.fft.irfft(f * np.conj(f))[:n]
    return acf / acf[0] if acf[0] > 0 else np.zeros(n)


def _first_nonpositive(acf: np.ndarray) -> int:
    neg = np.flatnonzero(acf[1:] <= 0)
    return int(neg[0] + 1) if neg.size else acf.size


def residual_structure(residual: np.ndarray, channels: dict, dt: float) -> dict:
    """RMS, spectral peaks and channel correlations of a residual.

    Parameters
    ----------
    residual : numpy.ndarray
        Residual [N m], one value per sample (NaN samples excluded from the RMS and correlations,
        linearly interpolated over for the spectrum).
    channels : dict
        1-D arrays of the residual's length; those present of ``twist`` [rad], ``v`` [rad/s],
        ``top`` [rad/s], ``W`` [N] are correlated with it, and ``sign(v)`` (smooth sign, eps 5 % of
        mean |v|) when ``v`` is present.
    dt : float
        Sampling interval [s].

    Returns
    -------
    dict
        ``rms`` [N m]; ``peaks``: the three highest local maxima of the Welch PSD (Hann window,
        segments of about 4 s, half overlap), each ``{frequency_hz, psd}`` (psd in (N m)^2/Hz,
        frequency refined by a parabola through the log-PSD); ``resolution_hz``;
        ``correlations``: ``{channel: {r, p_value, n_eff}}``, Pearson r with its two-sided p-value
        from Student's t on n_eff - 2 degrees of freedom, n_eff = n / (1 + 2 sum_k rho_r(k)
        rho_x(k)) (Bartlett), the sum over the lags where either autocorrelation is still in its
        initial positive run; ``n``.
    """
    dt = validate.positive("dt", dt, "s")
    r = _array("residual", residual)
    if not isinstance(channels, dict):
        raise ValueError(f"channels = {type(channels).__name__}: a dict of 1-D arrays is needed")
    ok = _check_finite_count("residual", r)
    n_all = r.size
    rf = r[ok]
    rms = float(np.sqrt(np.mean(rf * rf)))

    x = _fill_nan(r)
    fs = 1.0 / dt
    nper = int(2 ** math.ceil(math.log2(max(4.0 / dt, 16.0))))
    if n_all < 2 * nper:
        nper = max(16, n_all // 2)
    f, P = sps.welch(x, fs=fs, nperseg=min(nper, n_all), detrend="constant")
    pk, _ = sps.find_peaks(P)
    pk = pk[np.argsort(-P[pk], kind="stable")][:3]
    peaks = []
    for i in pk:
        fi = float(f[i])
        if 0 < i < f.size - 1 and np.all(P[i - 1:i + 2] > 0):
            l0, l1, l2 = np.log(P[i - 1:i + 2])
            den = l0 - 2 * l1 + l2
            if den < 0:
                fi += float(0.5 * (l0 - l2) / den) * float(f[1] - f[0])
        peaks.append({"frequency_hz": fi, "psd": float(P[i])})

    cand = {}
    for key in ("twist", "v", "top", "W"):
        if channels.get(key) is not None:
            cand[key] = _array(f"channels[{key!r}]", channels[key], n_all)
    if "v" in cand:
        cand["sign_v"] = smooth_sign(cand["v"])
    corr = {}
    for key, c in cand.items():
        m = ok & np.isfinite(c)
        if m.sum() < MIN_SAMPLES or np.ptp(c[m]) == 0.0 or np.ptp(r[m]) == 0.0:
            corr[key] = {"r": float("nan"), "p_value": float("nan"), "n_eff": float("nan")}
            continue
        a, b = r[m], c[m]
        rho = float(np.corrcoef(a, b)[0, 1])
        ra, rb = _acf(a), _acf(b)
        lag = max(_first_nonpositive(ra), _first_nonpositive(rb))
        tau = 1.0 + 2.0 * float(np.sum(ra[1:lag] * rb[1:lag]))
        neff = float(min(max(a.size / max(tau, 1.0), 3.0), a.size))
        if abs(rho) >= 1.0:
            p = 0.0
        else:
            tstat = rho * math.sqrt((neff - 2.0) / (1.0 - rho * rho))
            p = float(2.0 * stats.t.sf(abs(tstat), neff - 2.0))
        corr[key] = {"r": rho, "p_value": p, "n_eff": neff}
    return {"rms": rms, "peaks": peaks, "resolution_hz": float(f[1] - f[0]) if f.size > 1 else float("nan"),
            "correlations": corr, "n": int(ok.sum())}
