"""The random torque fluctuation eta(t) of the stochastic bit-rock law (thesis section 4.1).

PSD convention (everywhere in drillpy): ``S(f)`` is **one-sided, per hertz**,
``Var[eta] = integral_0^inf S(f) df`` with ``f`` in Hz. A two-sided density ``S2`` converts as
``S = 2 S2``; a one-sided density per rad/s ``G(omega)`` as ``S(f) = 2 pi G(2 pi f)``.

* :class:`PsdModel` -- the model of Eq. (4.4) with the natural logarithm; :data:`THESIS_PSD`
  holds the thesis's calibration f0 = 0.27 Hz, A0 = -7.6, a = -3.13, b = -11.67.
* :class:`PsdTable` -- a tabulated PSD; any callable ``S(f)`` (numpy in, numpy out) also works.
* :func:`generate` -- realizations by the spectral representation with an FFT (C++ engine);
  realization ``i`` with seed ``s`` is exactly the eta of Monte Carlo sample ``i``.
* :func:`periodogram` (Schuster's raw periodogram) and :func:`welch` (scipy.signal), and
  :func:`fit_psd_model` / :func:`fit_eta`, which fit Eq. (4.4) continuous at f0 (free: f0,
  a, b; A0 = a ln f0 + b) to a PSD estimate, with intervals.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Union

import numpy as np
from scipy import signal as _signal
from scipy.optimize import brentq
from scipy.special import digamma, polygamma

from drillpy import _core, validate


@dataclass(frozen=True)
class PsdModel:
    """Eq. (4.4): ln S = A0 for f < f0, ln S = a ln f + b for f >= f0 (S one-sided, 1/Hz)."""
    f0: float = 0.27
    A0: float = -7.6
    a: float = -3.13
    b: float = -11.67

    def __call__(self, f) -> np.ndarray:
        f = np.ascontiguousarray(np.atleast_1d(np.asarray(f, dtype=float)))
        return _core.psd_model_values(f, self.f0, self.A0, self.a, self.b)

    def integral(self, fmax: float = math.inf) -> float:
        """integral_0^fmax S df: the variance of eta for fmax = inf (needs a < -1)."""
        return _core.psd_model_integral(self.f0, self.A0, self.a, self.b, float(fmax))

    @classmethod
    def continuous(cls, f0: float, a: float, b: float) -> "PsdModel":
        """The model continuous at f0: A0 = a ln f0 + b."""
        f0 = validate.positive("f0_hz", f0)
        return cls(f0=f0, A0=a * math.log(f0) + b, a=a, b=b)

    @property
    def continuity_jump(self) -> float:
        """S(f0+) / S(f0-) = exp(a ln f0 + b - A0): 1 for a model continuous at f0 (the thesis's
        set gives 1.03)."""
        return math.exp(self.a * math.log(self.f0) + self.b - self.A0)

    def as_dict(self) -> dict:
        return {"type": "model_4_4", "f0_hz": self.f0, "A0": self.A0, "a": self.a, "b": self.b}


THESIS_PSD = PsdModel()

#: Conventions in which PSD model parameters may be given, with the factor that converts such a
#: density, evaluated at f in Hz, to drillpy's one-sided density per Hz.
PSD_CONVENTIONS = {"one-sided-hz": 1.0, "two-sided-hz": 2.0, "one-sided-rad-s": 2.0 * math.pi,
                   "two-sided-rad-s": 4.0 * math.pi}


def convert_psd_model(model: PsdModel, convention: str) -> PsdModel:
    """Read the parameters of ``model`` in another ``convention`` (see :data:`PSD_CONVENTIONS`)
    and return the equivalent drillpy model (one-sided per Hz): S -> c S, i.e. A0 and b grow by
    ln c. "two-sided-rad-s" (a density over omega in (-inf, inf), as in Soize's texts) gives
    c = 4 pi, so the thesis parameters would mean a standard deviation of 0.050 instead of 0.014.
    """
    if convention not in PSD_CONVENTIONS:
        raise ValueError(f"psd convention = {convention!r}: use one of {sorted(PSD_CONVENTIONS)}")
    k = math.log(PSD_CONVENTIONS[convention])
    return PsdModel(f0=model.f0, A0=model.A0 + k, a=model.a, b=model.b + k)


def scaled_to_std(model: PsdModel, std: float) -> PsdModel:
    """The shape of ``model`` scaled so that eta has standard deviation ``std`` (A0 and b shifted
    by the same ln c): e.g. the +-20 % the thesis reads in the field torque (section 4.0) taken as
    a two-sigma range gives std = 0.10 with the shape of Eq. (4.4)."""
    validate.positive("std", std)
    k = math.log(std ** 2 / model.integral())
    return PsdModel(f0=model.f0, A0=model.A0 + k, a=model.a, b=model.b + k)


@dataclass(frozen=True)
class PsdTable:
    """A tabulated one-sided PSD [1/Hz] at increasing frequencies [Hz]: linear between points,
    held at the first value below the first frequency, zero above the last one."""
    f_hz: tuple
    S: tuple

    def __init__(self, f_hz, S):
        object.__setattr__(self, "f_hz", tuple(np.asarray(f_hz, dtype=float).ravel()))
        object.__setattr__(self, "S", tuple(np.asarray(S, dtype=float).ravel()))
        self(np.zeros(1))  # validate now (the engine names the bad entry)

    def __call__(self, f) -> np.ndarray:
        f = np.ascontiguousarray(np.atleast_1d(np.asarray(f, dtype=float)))
        return _core.psd_table_values(np.asarray(self.f_hz), np.asarray(self.S), f)

    def as_dict(self) -> dict:
        return {"type": "table", "f_hz": list(self.f_hz), "S": list(self.S)}


Psd = Union[PsdModel, PsdTable, Callable[[np.ndarray], np.ndarray]]


def psd_on_grid(psd: Psd, dt: float, duration: float) -> tuple[np.ndarray, np.ndarray]:
    """The generator's frequency grid [Hz] for (dt, duration) and the PSD values on it.

    A user callable is called once with the whole grid; its values are checked by the engine
    (negative or non-finite values raise ValueError naming the frequency).
    """
    f = np.asarray(_core.process_grid(validate.positive("eta_dt_s", dt), validate.positive("duration_s", duration)))
    if not callable(psd):
        raise ValueError(f"psd = {psd!r}: must be a PsdModel, a PsdTable or a callable S(f)")
    S = np.ascontiguousarray(np.broadcast_to(np.asarray(psd(f), dtype=float), f.shape))
    _core.process_variance(S, dt, duration)  # validation only
    return f, S


def process_variance(psd: Psd = THESIS_PSD, dt: float = 0.05, duration: float = 100.0) -> float:
    """Exact variance of the generated process: the trapezoidal sum of S over [0, 1/(2 dt)]."""
    _, S = psd_on_grid(psd, dt, duration)
    return _core.process_variance(S, dt, duration)


def generate(psd: Psd = THESIS_PSD, *, dt: float = 0.05, duration: float = 100.0, samples: int = 1,
             seed: int = 0, first_sample: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Realizations of the centred stationary Gaussian process with one-sided PSD ``psd``.

    Returns ``(t, eta)`` with ``t = j dt`` over one period of the FFT grid (at least ``duration``
    seconds) and ``eta`` of shape (samples, len(t)). Row r is sample ``first_sample + r`` of
    ``seed``, identical to the eta of that Monte Carlo sample.
    """
    validate.seed(seed)
    n = validate.integer("samples", samples, 1, 100000)
    first = validate.integer("first_sample", first_sample, 0, 2**62)
    _, S = psd_on_grid(psd, dt, duration)
    eta = _core.generate_process(S, dt, duration, int(seed), first, n)
    return np.arange(eta.shape[1]) * dt, eta


def periodogram(x, dt: float, detrend: str | bool = "constant") -> tuple[np.ndarray, np.ndarray]:
    """Schuster's raw periodogram (no window, no averaging), one-sided density per Hz:
    ``S_k = 2 dt / N |sum_j x_j exp(-2 pi i j k / N)|^2`` (DC and Nyquist not doubled)."""
    x = _series(x, "x")
    return _signal.periodogram(x, fs=1.0 / validate.positive("dt", dt), window="boxcar", detrend=detrend,
                               return_onesided=True, scaling="density")


def welch(x, dt: float, segment: int | None = None,
          detrend: str | bool = "constant") -> tuple[np.ndarray, np.ndarray]:
    """Welch's averaged periodogram (Hann window, 50 % overlap), one-sided density per Hz.
    ``segment`` is the number of points per segment (default: N // 8)."""
    x = _series(x, "x")
    nper = max(16, x.size // 8) if segment is None else validate.integer("segment", segment, 8, x.size)
    return _signal.welch(x, fs=1.0 / validate.positive("dt", dt), window="hann", nperseg=nper,
                         noverlap=nper // 2, detrend=detrend, return_onesided=True, scaling="density")


@dataclass(frozen=True)
class PsdFit:
    """A fit of Eq. (4.4) continuous at f0 (:func:`fit_psd_model`) with its uncertainty.

    ``ci95`` holds 95 % intervals (as ``(low, high)``) of f0 [Hz], A0, a and b: f0 by the profile
    likelihood, the others by the Jacobian (Wald); ``se`` the standard errors from the Jacobian
    (for f0 by the delta method, f0 se(ln f0)). ``log_variance`` is the variance of one ln S
    ordinate used for both: the chi-square value psi'(K) (pi^2/6 for the raw periodogram) or the
    residual variance if that is larger (``log_variance_source``). ``f0_search_hz`` is the range
    f0 was searched in; ``f0_ci_at_search_edge`` says the f0 interval reaches an end of it (f0 is
    then not determined by the data on that side). ``continuity_jump`` = S(f0+)/S(f0-) is 1.0.
    """
    model: PsdModel
    rms_log_residual: float  #: rms of ln(S_estimate) + bias - ln(S_model) over the fitted points
    points: int
    se: dict = None
    ci95: dict = None
    log_variance: float = math.nan
    log_variance_source: str = ""
    f0_search_hz: tuple = (math.nan, math.nan)
    f0_ci_at_search_edge: bool = False
    f0_ci_connected: bool = True  #: False: the 95 % profile set of f0 has gaps (ci95 is its hull)

    @property
    def continuity_jump(self) -> float:
        return self.model.continuity_jump

    def as_dict(self) -> dict:
        return {**self.model.as_dict(), "constrained": "continuous at f0 (A0 = a ln f0 + b)",
                "continuity_jump": self.continuity_jump, "rms_log": self.rms_log_residual,
                "points": self.points, "se": dict(self.se or {}),
                "ci95": {k: [float(v[0]), float(v[1])] for k, v in (self.ci95 or {}).items()},
                "ci_method": {"f0_hz": "profile likelihood (chi^2_1)", "A0": "Jacobian (Wald)",
                              "a": "Jacobian (Wald)", "b": "Jacobian (Wald)"},
                "log_variance": self.log_variance, "log_variance_source": self.log_variance_source,
                "f0_search_hz": [float(v) for v in self.f0_search_hz],
                "f0_ci_at_search_edge": self.f0_ci_at_search_edge, "f0_ci_connected": self.f0_ci_connected}


_CHI2_1_95 = 3.841458820694124  # 95 % quantile of chi^2 with 1 degree of freedom
_Z_975 = 1.959963984540054


def fit_psd_model(f, S, *, averages: float = 1.0, fmin: float | None = None,
                  fmax: float | None = None) -> PsdFit:
    """Least-squares fit of Eq. (4.4), continuous at f0, to a PSD estimate in ln S versus ln f.

    Model: ln S = A0 for f < f0 and a ln f + b for f >= f0 with A0 = a ln f0 + b (the thesis's own
    set is continuous: -3.13 ln 0.27 - 11.67 = -7.57 ~ -7.6), i.e. a hinge in x = ln f:
    ln S = A0 + a max(x - ln f0, 0). Free parameters: f0, A0 and a (b follows).

    Periodogram ordinates are S chi^2_{2K} / (2K) with K ``averages`` (1 for the raw periodogram),
    so ln S is biased by psi(K) - ln K (-0.5772 for K = 1); the bias is removed before fitting.
    Points at f <= 0 or S = 0 are ignored.

    Global and stable: for a fixed f0 the problem is linear, so the residual sum of squares
    profiled over f0, SSE(f0), is computed in closed form (prefix sums). Between two consecutive
    frequencies of the estimate SSE(f0) has no interior minimum other than where the free
    (discontinuous) split fit of that partition happens to be continuous, so the minimum over the
    ordinates' frequencies and those points is the exact global least-squares solution; no start
    value or local minimum is involved. f0 is searched between the 3rd and the 3rd-last fitted
    frequency (at least 3 points on each side).

    Uncertainty (ordinates taken as independent with variance sigma^2 in ln S): sigma^2 is
    psi'(K) (pi^2/6 for the raw periodogram), replaced by the residual variance SSE/(n - 3) when
    that is larger (model misfit, e.g. spectral peaks). f0: profile-likelihood interval
    {f0 : SSE(f0) - SSE_min <= 3.84 sigma^2} (on a 4000-point log grid plus the ordinates, edges
    refined; its hull if it has gaps). A0, a, b: Wald intervals +-1.96 se from
    sigma^2 (J^T J)^-1 with J the Jacobian in (ln f0, A0, a), b = A0 - a ln f0 by the delta method.
    """
    f = np.asarray(f, dtype=float).ravel()
    S = np.asarray(S, dtype=float).ravel()
    if f.shape != S.shape:
        raise ValueError(f"S has {S.size} values: must match f ({f.size})")
    if not (np.all(np.isfinite(f)) and np.all(np.isfinite(S))):
        raise ValueError("f and S must be finite")
    if np.any(S < 0):
        raise ValueError(f"S = {S[S < 0][0]!r}: a PSD estimate must not be negative")
    if not averages >= 1:
        raise ValueError(f"averages = {averages!r}: must be >= 1")
    keep = (f > 0) & (S > 0)
    if fmin is not None:
        keep &= f >= fmin
    if fmax is not None:
        keep &= f <= fmax
    x, y = np.log(f[keep]), np.log(S[keep]) - (digamma(averages) - math.log(averages))
    order = np.argsort(x, kind="stable")
    x, y = x[order], y[order]
    n = x.size
    if n < 8:
        raise ValueError(f"only {n} positive frequencies to fit: need at least 8")
    xm, ym = float(np.mean(x)), float(np.mean(y))  # centred sums: no cancellation
    xc, yc = x - xm, y - ym
    c1, cx, cy = (np.concatenate([[0.0], np.cumsum(v)]) for v in (np.ones(n), xc, yc))
    cxx, cxy = (np.concatenate([[0.0], np.cumsum(v)]) for v in (xc * xc, xc * yc))
    syy = float(np.sum(yc * yc))
    lo, hi = float(x[2]), float(x[n - 3])

    def profile(x0):
        """(SSE, A0, a) of the hinge fit with its knot at each x0 (array)."""
        x0 = np.atleast_1d(np.asarray(x0, dtype=float))
        u = x0 - xm
        m = np.searchsorted(x, x0, side="right")  # points at or below the knot: z = 0
        k = n - m
        hx, hy = cx[n] - cx[m], cy[n] - cy[m]
        sz = hx - k * u
        szz = (cxx[n] - cxx[m]) - 2 * u * hx + k * u * u
        szy = (cxy[n] - cxy[m]) - u * hy
        vzz = szz - sz * sz / n
        vzy = szy  # sum y = 0 (centred)
        with np.errstate(divide="ignore", invalid="ignore"):
            a = np.where(vzz > 0, vzy / vzz, 0.0)
        sse = np.maximum(syy - a * vzy, 0.0)
        A0 = ym - a * sz / n
        return sse, A0, a

    # candidates: every ordinate's frequency and, per partition, the knot of the free split fit
    m = np.arange(3, n - 2)  # flat part = points [0, m)
    kk = n - m
    sx, sy = cx[n] - cx[m], cy[n] - cy[m]
    vxx = (cxx[n] - cxx[m]) - sx * sx / kk
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = np.where(vxx > 0, ((cxy[n] - cxy[m]) - sx * sy / kk) / vxx, 0.0)
        flat = cy[m] / m
        inter = sy / kk - slope * sx / kk  # line: yc = inter + slope xc
        knot = np.where(slope != 0, (flat - inter) / slope, np.nan) + xm
    inside = np.isfinite(knot) & (knot >= x[m - 1]) & (knot <= x[m])
    grid = np.unique(np.concatenate([x[2:n - 2], knot[inside], np.linspace(lo, hi, 4000)]))
    grid = grid[(grid >= lo) & (grid <= hi)]
    sse, A0s, as_ = profile(grid)
    ib = int(np.argmin(sse))
    x0, A0, a = float(grid[ib]), float(A0s[ib]), float(as_[ib])
    sse_min = float(sse[ib])
    resid = y - (A0 + a * np.maximum(x - x0, 0.0))
    sse_fit = float(resid @ resid)  # direct (the profile's closed form loses ~1e-13 of syy)

    sigma2_chi = float(polygamma(1, averages))
    sigma2_res = sse_fit / (n - 3)
    sigma2 = max(sigma2_chi, sigma2_res)
    source = (f"chi-square: psi'({averages:g}) = {sigma2_chi:.4g}" if sigma2 == sigma2_chi
              else f"residuals: SSE/(n-3) = {sigma2_res:.4g} > psi'({averages:g}) = {sigma2_chi:.4g}")

    # profile-likelihood interval of ln f0
    cut = sse_min + _CHI2_1_95 * sigma2
    acc = sse <= cut
    ia = np.flatnonzero(acc)
    connected = bool(ia[-1] - ia[0] + 1 == ia.size)

    def edge(i_in, i_out):
        g = lambda t: float(profile(t)[0][0]) - cut  # noqa: E731
        return float(brentq(g, grid[i_out], grid[i_in])) if g(grid[i_out]) > 0 else float(grid[i_out])

    x_lo = float(grid[0]) if ia[0] == 0 else edge(ia[0], ia[0] - 1)
    x_hi = float(grid[-1]) if ia[-1] == grid.size - 1 else edge(ia[-1], ia[-1] + 1)
    at_edge = bool(ia[0] == 0 or ia[-1] == grid.size - 1)

    # Jacobian in (ln f0, A0, a) at the optimum
    z = np.maximum(x - x0, 0.0)
    J = np.column_stack([-a * (x > x0), np.ones(n), z])
    try:
        cov = sigma2 * np.linalg.inv(J.T @ J)
    except np.linalg.LinAlgError:
        cov = np.full((3, 3), np.inf)
    gb = np.array([-a, 1.0, -x0])  # b = A0 - a ln f0
    se_x0, se_A0, se_a = (float(math.sqrt(v)) if v >= 0 else math.inf for v in np.diag(cov))
    vb = float(gb @ cov @ gb)
    se_b = math.sqrt(vb) if vb >= 0 else math.inf

    f0 = float(math.exp(x0))
    b = A0 - a * x0
    A0 = a * math.log(f0) + b  # the same expression as PsdModel.continuity_jump: jump exactly 1
    model = PsdModel(f0=f0, A0=A0, a=a, b=b)
    se = {"f0_hz": f0 * se_x0, "ln_f0": se_x0, "A0": se_A0, "a": se_a, "b": se_b}
    ci = {"f0_hz": (math.exp(x_lo), math.exp(x_hi)),
          "A0": (A0 - _Z_975 * se_A0, A0 + _Z_975 * se_A0),
          "a": (a - _Z_975 * se_a, a + _Z_975 * se_a),
          "b": (b - _Z_975 * se_b, b + _Z_975 * se_b)}
    return PsdFit(model=model, rms_log_residual=math.sqrt(sse_fit / n), points=n, se=se, ci95=ci,
                  log_variance=sigma2, log_variance_source=source,
                  f0_search_hz=(math.exp(lo), math.exp(hi)), f0_ci_at_search_edge=at_edge,
                  f0_ci_connected=connected)


def fit_eta(eta, dt: float, *, method: str = "schuster", segment: int | None = None,
            fmax: float | None = None) -> tuple[PsdFit, np.ndarray, np.ndarray]:
    """Estimate the PSD of an eta series (``method`` = "schuster" or "welch") and fit Eq. (4.4).

    Returns (fit, f, S_estimate). For Welch the number of averages is the number of segments
    (the overlap is ignored, a slight underestimate of the bias correction's K)."""
    x = _series(eta, "eta")
    if method == "schuster":
        f, S = periodogram(x, dt)
        k = 1.0
    elif method == "welch":
        f, S = welch(x, dt, segment)
        nper = max(16, x.size // 8) if segment is None else int(segment)
        k = float(max(1, (x.size - nper // 2) // (nper - nper // 2)))
    else:
        raise ValueError(f"method = {method!r}: use 'schuster' or 'welch'")
    return fit_psd_model(f, S, averages=k, fmax=fmax), f, S



def _series(x, name: str) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.ndim != 1 or a.size < 8:
        raise ValueError(f"{name}: must be a 1-D series of at least 8 values (got shape {a.shape})")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name}: must be finite (found NaN or inf)")
    return a
