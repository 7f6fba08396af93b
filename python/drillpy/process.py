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
  :func:`fit_psd_model` / :func:`fit_eta`, which fit (f0, A0, a, b) to a PSD estimate.
"""
from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import Callable, Union

import numpy as np
from scipy import signal as _signal
from scipy.special import digamma

from . import _core


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
    f = np.asarray(_core.process_grid(_positive(dt, "eta_dt_s"), _positive(duration, "duration_s")))
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
    check_seed(seed)
    n = check_count(samples, "samples", 100000)
    first = check_count(first_sample, "first_sample", 2**62, minimum=0)
    _, S = psd_on_grid(psd, dt, duration)
    eta = _core.generate_process(S, dt, duration, int(seed), first, n)
    return np.arange(eta.shape[1]) * dt, eta


def periodogram(x, dt: float, detrend: str | bool = "constant") -> tuple[np.ndarray, np.ndarray]:
    """Schuster's raw periodogram (no window, no averaging), one-sided density per Hz:
    ``S_k = 2 dt / N |sum_j x_j exp(-2 pi i j k / N)|^2`` (DC and Nyquist not doubled)."""
    x = _series(x, "x")
    return _signal.periodogram(x, fs=1.0 / _positive(dt, "dt"), window="boxcar", detrend=detrend,
                               return_onesided=True, scaling="density")


def welch(x, dt: float, segment: int | None = None,
          detrend: str | bool = "constant") -> tuple[np.ndarray, np.ndarray]:
    """Welch's averaged periodogram (Hann window, 50 % overlap), one-sided density per Hz.
    ``segment`` is the number of points per segment (default: N // 8)."""
    x = _series(x, "x")
    nper = max(16, x.size // 8) if segment is None else check_count(segment, "segment", x.size, minimum=8)
    return _signal.welch(x, fs=1.0 / _positive(dt, "dt"), window="hann", nperseg=nper,
                         noverlap=nper // 2, detrend=detrend, return_onesided=True, scaling="density")


@dataclass(frozen=True)
class PsdFit:
    model: PsdModel
    rms_log_residual: float  #: rms of ln(S_estimate) + bias - ln(S_model) over the fitted points
    points: int


def fit_psd_model(f, S, *, averages: float = 1.0, fmin: float | None = None,
                  fmax: float | None = None) -> PsdFit:
    """Least-squares fit of Eq. (4.4) to a PSD estimate, in ln S versus ln f.

    The four parameters are free (as in the thesis): for every split frequency f0 on the grid,
    A0 is the mean of ln S below f0 and (a, b) the straight line through ln S above it; the split
    with the smallest residual wins. Periodogram ordinates are S chi^2_{2K} / (2K) with K
    ``averages`` (1 for the raw periodogram), so ln S is biased by psi(K) - ln K (-0.5772 for
    K = 1); the bias is removed before fitting. Points at f <= 0 are ignored.
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
    order = np.argsort(x)
    x, y = x[order], y[order]
    n = x.size
    if n < 8:
        raise ValueError(f"only {n} positive frequencies to fit: need at least 8")
    # prefix sums: SSE of the flat part [0, m) and of the line [m, n) for every split m
    c1, cy, cyy = (np.concatenate([[0.0], np.cumsum(v)]) for v in (np.ones(n), y, y * y))
    cx, cxx, cxy = (np.concatenate([[0.0], np.cumsum(v)]) for v in (x, x * x, x * y))
    m = np.arange(3, n - 2)
    sse_flat = cyy[m] - cy[m] ** 2 / c1[m]
    k = n - m
    sx, sy = cx[-1] - cx[m], cy[-1] - cy[m]
    sxx, sxy, syy = cxx[-1] - cxx[m], cxy[-1] - cxy[m], cyy[-1] - cyy[m]
    vxx = sxx - sx * sx / k
    slope = (sxy - sx * sy / k) / vxx
    sse_line = (syy - sy * sy / k) - slope * (sxy - sx * sy / k)
    best = int(np.argmin(sse_flat + sse_line))
    mb = int(m[best])
    a = float(slope[best])
    b = float((sy[best] - a * sx[best]) / k[best])
    model = PsdModel(f0=float(np.exp(x[mb])), A0=float(cy[mb] / mb), a=a, b=b)
    rms = math.sqrt(float(sse_flat[best] + sse_line[best]) / n)
    return PsdFit(model=model, rms_log_residual=rms, points=n)


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


# ---- input checks shared with the Monte Carlo module -------------------------------------------

def check_seed(seed) -> int:
    """A seed is an integer in [0, 2^64)."""
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or not 0 <= int(seed) < 2**64:
        raise ValueError(f"seed = {seed!r}: must be an integer between 0 and 2^64 - 1")
    return int(seed)


def check_count(value, name: str, maximum: int, minimum: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) \
            or not minimum <= int(value) <= maximum:
        raise ValueError(f"{name} = {value!r}: must be an integer between {minimum} and {maximum}")
    return int(value)


def _positive(value, name: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} = {value!r}: must be a positive number") from None
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} = {value!r}: must be a positive finite number")
    return v


def _series(x, name: str) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.ndim != 1 or a.size < 8:
        raise ValueError(f"{name}: must be a 1-D series of at least 8 values (got shape {a.shape})")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name}: must be finite (found NaN or inf)")
    return a
