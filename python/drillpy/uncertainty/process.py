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

# scipy.signal, scipy.optimize and scipy.special are imported where they are used: importing
# scipy.signal alone took 0.8 s of a 5 s `drillpy mc` run (issue 33), which uses none of them.
from drillpy import _core, validate


@dataclass(frozen=True)
class PsdModel:
    """The PSD model of Eq. (4.4) with the natural logarithm (S one-sided, per Hz).

    ``ln S(f) = A0`` for ``f < f0`` and ``ln S(f) = a ln f + b`` for ``f >= f0``. Calling the
    model, ``model(f)``, returns S [1/Hz] at the frequencies ``f`` [Hz] (a numpy array). The
    defaults are the thesis's calibration on field data (section 4.1, :data:`THESIS_PSD`), which
    in drillpy's convention integrates to Var[eta] = 2.0e-4 (standard deviation 0.014).

    Attributes
    ----------
    f0 : float
        Corner frequency [Hz] between the flat part and the power law (thesis: 0.27 Hz).
    A0 : float
        ln S [ln(1/Hz)] of the flat part below ``f0`` (thesis: -7.6).
    a : float
        Slope of ln S versus ln f above ``f0`` [-] (thesis: -3.13); the variance is finite only
        for ``a < -1``.
    b : float
        Intercept of the power law, ln S at f = 1 Hz [ln(1/Hz)] (thesis: -11.67).
    """
    f0: float = 0.27
    A0: float = -7.6
    a: float = -3.13
    b: float = -11.67

    def __call__(self, f) -> np.ndarray:
        f = np.ascontiguousarray(np.atleast_1d(np.asarray(f, dtype=float)))
        return _core.psd_model_values(f, self.f0, self.A0, self.a, self.b)

    def integral(self, fmax: float = math.inf) -> float:
        """Integral of S from 0 to ``fmax`` (closed form, in the engine).

        Parameters
        ----------
        fmax : float
            Upper frequency limit [Hz]; ``inf`` (default) integrates over the whole axis.

        Returns
        -------
        float
            integral_0^fmax S(f) df [-]: for ``fmax = inf`` the variance Var[eta] of the torque
            fluctuation (finite only for ``a < -1``).
        """
        return _core.psd_model_integral(self.f0, self.A0, self.a, self.b, float(fmax))

    @classmethod
    def continuous(cls, f0: float, a: float, b: float) -> "PsdModel":
        """The model of Eq. (4.4) continuous at f0, i.e. with A0 = a ln f0 + b.

        Parameters
        ----------
        f0 : float
            Corner frequency [Hz], > 0.
        a : float
            Slope of ln S versus ln f above ``f0`` [-].
        b : float
            Intercept of the power law, ln S at f = 1 Hz [ln(1/Hz)].

        Returns
        -------
        PsdModel
            The model with ``A0 = a ln f0 + b`` (``continuity_jump`` = 1).
        """
        f0 = validate.positive("f0_hz", f0)
        return cls(f0=f0, A0=a * math.log(f0) + b, a=a, b=b)

    @property
    def continuity_jump(self) -> float:
        """S(f0+) / S(f0-) = exp(a ln f0 + b - A0): 1 for a model continuous at f0 (the thesis's
        set gives 1.03)."""
        return math.exp(self.a * math.log(self.f0) + self.b - self.A0)

    def as_dict(self) -> dict:
        """JSON-ready description: ``{"type": "model_4_4", "f0_hz", "A0", "a", "b"}``."""
        return {"type": "model_4_4", "f0_hz": self.f0, "A0": self.A0, "a": self.a, "b": self.b}


THESIS_PSD = PsdModel()  #: the thesis's calibration of Eq. (4.4): f0 = 0.27 Hz, A0 = -7.6, a = -3.13, b = -11.67

#: Conventions in which PSD model parameters may be given, with the factor that converts such a
#: density, evaluated at f in Hz, to drillpy's one-sided density per Hz.
PSD_CONVENTIONS = {"one-sided-hz": 1.0, "two-sided-hz": 2.0, "one-sided-rad-s": 2.0 * math.pi,
                   "two-sided-rad-s": 4.0 * math.pi}


def convert_psd_model(model: PsdModel, convention: str) -> PsdModel:
    """Read the parameters of ``model`` in another ``convention`` (see :data:`PSD_CONVENTIONS`)
    and return the equivalent drillpy model (one-sided per Hz): S -> c S, i.e. A0 and b grow by
    ln c. "two-sided-rad-s" (a density over omega in (-inf, inf), as in Soize's texts) gives
    c = 4 pi, so the thesis parameters would mean a standard deviation of 0.050 instead of 0.014.

    Parameters
    ----------
    model : PsdModel
        Parameters f0 [Hz], A0, a, b of Eq. (4.4) as given in ``convention``.
    convention : str
        The convention the parameters were given in: "one-sided-hz" (drillpy's own, c = 1),
        "two-sided-hz" (c = 2), "one-sided-rad-s" (c = 2 pi) or "two-sided-rad-s" (c = 4 pi).

    Returns
    -------
    PsdModel
        The same density as a one-sided PSD per Hz (f0 and a unchanged).

    Raises
    ------
    ValueError
        For an unknown ``convention``.
    """
    if convention not in PSD_CONVENTIONS:
        raise ValueError(f"psd convention = {convention!r}: use one of {sorted(PSD_CONVENTIONS)}")
    k = math.log(PSD_CONVENTIONS[convention])
    return PsdModel(f0=model.f0, A0=model.A0 + k, a=model.a, b=model.b + k)


def scaled_to_std(model: PsdModel, std: float) -> PsdModel:
    """The shape of ``model`` scaled so that eta has standard deviation ``std`` (A0 and b shifted
    by the same ln c): e.g. the +-20 % the thesis reads in the field torque (section 4.0) taken as
    a two-sigma range gives std = 0.10 with the shape of Eq. (4.4).

    Parameters
    ----------
    model : PsdModel
        The PSD shape to keep (f0 and a unchanged); its variance must be finite (a < -1).
    std : float
        Target standard deviation of eta [-] (relative torque fluctuation, e.g. 0.0667), > 0.

    Returns
    -------
    PsdModel
        The model with ``integral() == std**2``.
    """
    validate.positive("std", std)
    k = math.log(std ** 2 / model.integral())
    return PsdModel(f0=model.f0, A0=model.A0 + k, a=model.a, b=model.b + k)


@dataclass(frozen=True)
class PsdTable:
    """A tabulated one-sided PSD [1/Hz] at increasing frequencies [Hz]: linear between points,
    held at the first value below the first frequency, zero above the last one.

    Calling the table, ``table(f)``, returns S [1/Hz] at the frequencies ``f`` [Hz]. The engine
    validates the table on construction and names the bad entry (ValueError).

    Parameters
    ----------
    f_hz : array_like
        Frequencies [Hz]: at least 2, finite, non-negative, strictly increasing.
    S : array_like
        One-sided PSD [1/Hz] at ``f_hz`` (same length): finite, non-negative.

    Attributes
    ----------
    f_hz : tuple of float
        The table's frequencies [Hz].
    S : tuple of float
        The table's PSD values [1/Hz].
    """
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
        """JSON-ready description: ``{"type": "table", "f_hz": [...], "S": [...]}``."""
        return {"type": "table", "f_hz": list(self.f_hz), "S": list(self.S)}


Psd = Union[PsdModel, PsdTable, Callable[[np.ndarray], np.ndarray]]


def psd_from_dict(d: dict) -> "PsdModel | PsdTable":
    """The PSD described by ``as_dict()`` of :class:`PsdModel` or :class:`PsdTable` (a stored study).

    Parameters
    ----------
    d : dict
        ``{"type": "model_4_4", "f0_hz", "A0", "a", "b"}`` or ``{"type": "table", "f_hz", "S"}``.

    Returns
    -------
    PsdModel or PsdTable
        The same PSD (the same values on any grid).

    Raises
    ------
    ValueError
        For any other description (a user callable cannot be stored).
    """
    kind = d.get("type") if isinstance(d, dict) else None
    if kind == "model_4_4":
        return PsdModel(d["f0_hz"], d["A0"], d["a"], d["b"])
    if kind == "table":
        return PsdTable(d["f_hz"], d["S"])
    raise ValueError(f"psd = {d!r}: not a stored PSD (a model_4_4 or a table; a Python callable cannot be stored)")


def psd_on_grid(psd: Psd, dt: float, duration: float) -> tuple[np.ndarray, np.ndarray]:
    """The generator's frequency grid [Hz] for (dt, duration) and the PSD values on it.

    A user callable is called once with the whole grid; its values are checked by the engine
    (negative or non-finite values raise ValueError naming the frequency).

    Parameters
    ----------
    psd : PsdModel, PsdTable or callable
        One-sided PSD of eta per Hz, ``S(f)`` [1/Hz] with ``f`` [Hz] (a callable takes and
        returns numpy arrays).
    dt : float
        Sampling step of eta [s] (> 0); the grid reaches the Nyquist frequency 1/(2 dt) [Hz].
    duration : float
        Time the process must cover [s] (> 0); the grid step is df = 1/(n dt) [Hz] with n the
        smallest power of two >= 4 such that n dt >= ``duration`` (at most 2^26 points).

    Returns
    -------
    f : numpy.ndarray
        Frequencies k df, k = 0 .. n/2 [Hz].
    S : numpy.ndarray
        The PSD on ``f`` [1/Hz].
    """
    f = np.asarray(_core.process_grid(validate.positive("eta_dt_s", dt), validate.positive("duration_s", duration)))
    if not callable(psd):
        raise ValueError(f"psd = {psd!r}: must be a PsdModel, a PsdTable or a callable S(f)")
    S = np.ascontiguousarray(np.broadcast_to(np.asarray(psd(f), dtype=float), f.shape))
    _core.process_variance(S, dt, duration)  # validation only
    return f, S


def process_variance(psd: Psd = THESIS_PSD, dt: float = 0.05, duration: float = 100.0) -> float:
    """Exact variance of the generated process: the trapezoidal sum of S over [0, 1/(2 dt)].

    This is Var[eta] of every realization of :func:`generate` with the same arguments (it
    differs from ``psd.integral()`` by the discretization and the part of S above the Nyquist
    frequency).

    Parameters
    ----------
    psd : PsdModel, PsdTable or callable
        One-sided PSD of eta per Hz [1/Hz] (default: the thesis's Eq. (4.4) calibration).
    dt : float
        Sampling step of eta [s].
    duration : float
        Time the process covers [s]; sets the frequency step (:func:`psd_on_grid`).

    Returns
    -------
    float
        Var[eta] [-].
    """
    _, S = psd_on_grid(psd, dt, duration)
    return _core.process_variance(S, dt, duration)


def generate(psd: Psd = THESIS_PSD, *, dt: float = 0.05, duration: float = 100.0, samples: int = 1,
             seed: int = 0, first_sample: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Realizations of the centred stationary Gaussian process with one-sided PSD ``psd``.

    Returns ``(t, eta)`` with ``t = j dt`` over one period of the FFT grid (at least ``duration``
    seconds) and ``eta`` of shape (samples, len(t)). Row r is sample ``first_sample + r`` of
    ``seed``, identical to the eta of that Monte Carlo sample.

    Spectral representation (docs/stochastic.md): on n = 2^k points, eta_j is a sum of cosines
    and sines at k df with Gaussian amplitudes of variance S(k df) df, evaluated by one inverse
    real FFT in the engine. The process is exactly Gaussian and circularly stationary; its
    variance is :func:`process_variance`.

    Parameters
    ----------
    psd : PsdModel, PsdTable or callable
        One-sided PSD of eta per Hz [1/Hz] (default: the thesis's Eq. (4.4) calibration).
    dt : float
        Sampling step [s] (default 0.05 s, the Monte Carlo's ``ETA_DT_S``).
    duration : float
        Minimum length of each realization [s].
    samples : int
        Number of realizations (rows), 1 to 100000.
    seed : int
        Random seed, an integer in [0, 2^64).
    first_sample : int
        Index of the first realization; row r is sample ``first_sample + r``.

    Returns
    -------
    t : numpy.ndarray
        Times j dt [s], shape (n,).
    eta : numpy.ndarray
        Realizations of eta [-], shape (samples, n).
    """
    validate.seed(seed)
    n = validate.integer("samples", samples, 1, 100000)
    first = validate.integer("first_sample", first_sample, 0, 2**62)
    _, S = psd_on_grid(psd, dt, duration)
    eta = _core.generate_process(S, dt, duration, int(seed), first, n)
    return np.arange(eta.shape[1]) * dt, eta


def periodogram(x, dt: float, detrend: str | bool = "constant") -> tuple[np.ndarray, np.ndarray]:
    """Schuster's raw periodogram (no window, no averaging), one-sided density per Hz:
    ``S_k = 2 dt / N |sum_j x_j exp(-2 pi i j k / N)|^2`` (DC and Nyquist not doubled).

    Computed by ``scipy.signal.periodogram`` (boxcar window). Its ordinates scatter as
    S chi^2_2 / 2 around the true PSD, which :func:`fit_psd_model` accounts for.

    Parameters
    ----------
    x : array_like
        The series, 1-D, at least 8 finite values (e.g. eta).
    dt : float
        Sampling step [s].
    detrend : str or bool
        Passed to scipy: "constant" (default) removes the mean, "linear" a straight line,
        False nothing.

    Returns
    -------
    f : numpy.ndarray
        Frequencies k / (N dt) [Hz], k = 0 .. N/2.
    S : numpy.ndarray
        One-sided PSD estimate [1/Hz for a dimensionless x].
    """
    from scipy import signal as _signal

    x = _series(x, "x")
    return _signal.periodogram(x, fs=1.0 / validate.positive("dt", dt), window="boxcar", detrend=detrend,
                               return_onesided=True, scaling="density")


def welch(x, dt: float, segment: int | None = None,
          detrend: str | bool = "constant") -> tuple[np.ndarray, np.ndarray]:
    """Welch's averaged periodogram (Hann window, 50 % overlap), one-sided density per Hz.
    ``segment`` is the number of points per segment (default: N // 8).

    Computed by ``scipy.signal.welch``. Averaging K segments narrows the scatter of the ordinates
    (about S chi^2_2K / 2K) at the cost of frequency resolution 1/(segment dt).

    Parameters
    ----------
    x : array_like
        The series, 1-D, at least 8 finite values (e.g. eta).
    dt : float
        Sampling step [s].
    segment : int, optional
        Points per segment, 8 to N (default: max(16, N // 8)).
    detrend : str or bool
        Passed to scipy: "constant" (default) removes each segment's mean, "linear" a straight
        line, False nothing.

    Returns
    -------
    f : numpy.ndarray
        Frequencies [Hz].
    S : numpy.ndarray
        One-sided PSD estimate [1/Hz for a dimensionless x].
    """
    from scipy import signal as _signal

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

    Attributes
    ----------
    model : PsdModel
        The fitted model (continuous at f0: A0 = a ln f0 + b).
    rms_log_residual : float
        Root mean square of ln(S_estimate) + bias correction - ln(S_model) over the fitted
        points; about pi/sqrt(6) = 1.28 for a raw periodogram of a process that follows the model.
    points : int
        Number of PSD ordinates fitted (f > 0, S > 0, within ``fmin``/``fmax``).
    se : dict
        Standard errors: "f0_hz" [Hz], "ln_f0", "A0", "a", "b".
    ci95 : dict
        95 % intervals ``(low, high)`` of "f0_hz" [Hz] (profile likelihood), "A0", "a" and "b"
        (Wald).
    log_variance : float
        Variance sigma^2 of one ln S ordinate used for ``se`` and ``ci95``.
    log_variance_source : str
        Where ``log_variance`` comes from: the chi-square value psi'(K) or the residuals.
    f0_search_hz : tuple of float
        (lowest, highest) f0 searched [Hz]: the 3rd and the 3rd-last fitted frequency.
    f0_ci_at_search_edge : bool
        True if the f0 interval reaches an end of ``f0_search_hz`` (f0 not bounded by the data on
        that side).
    f0_ci_connected : bool
        False if the 95 % profile set of f0 has gaps (``ci95["f0_hz"]`` is then its hull).
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
        """S(f0+) / S(f0-) of the fitted model: 1.0 (the fit is continuous at f0)."""
        return self.model.continuity_jump

    def as_dict(self) -> dict:
        """JSON-ready fit: the model's parameters, the constraint, ``continuity_jump``,
        ``rms_log``, ``points``, ``se``, ``ci95`` (lists), the interval method per parameter,
        ``log_variance`` and its source, and the f0 search range and flags."""
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

    Parameters
    ----------
    f : array_like
        Frequencies of the PSD estimate [Hz].
    S : array_like
        One-sided PSD estimate [1/Hz] at ``f`` (same length, finite, non-negative).
    averages : float
        Number K of averaged periodograms behind each ordinate, >= 1 (1 for the raw periodogram,
        the number of segments for Welch); sets the bias and the chi-square variance of ln S.
    fmin, fmax : float, optional
        Fit only the ordinates with ``fmin <= f <= fmax`` [Hz] (default: all).

    Returns
    -------
    PsdFit
        The fitted model with standard errors and 95 % intervals.

    Raises
    ------
    ValueError
        If ``f`` and ``S`` differ in length, are not finite, ``S`` is negative, ``averages < 1``,
        or fewer than 8 positive ordinates remain.
    """
    from scipy.optimize import brentq
    from scipy.special import digamma, polygamma

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

    For Welch the number of averages is the number of segments (the overlap is ignored, a slight
    underestimate of the bias correction's K).

    Parameters
    ----------
    eta : array_like
        The torque fluctuation series [-] (e.g. eta_exp of Eq. 4.2 or a generated realization),
        1-D, at least 8 finite values, sampled every ``dt``.
    dt : float
        Sampling step [s].
    method : str
        "schuster" (default): raw :func:`periodogram`; "welch": :func:`welch`.
    segment : int, optional
        Points per Welch segment (default: max(16, N // 8)); ignored by "schuster".
    fmax : float, optional
        Highest frequency fitted [Hz] (default: all up to the Nyquist frequency).

    Returns
    -------
    fit : PsdFit
        The fit of Eq. (4.4) continuous at f0 (:func:`fit_psd_model`).
    f : numpy.ndarray
        Frequencies of the estimate [Hz].
    S_estimate : numpy.ndarray
        The PSD estimate [1/Hz].
    """
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
