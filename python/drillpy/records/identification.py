"""Least-squares identification of the bit-rock laws from (bit speed, acceleration, torque) data.

Laws (thesis equation numbers), all evaluated by the engine (``_core.law_torque``), never
re-implemented here:

=========================== ========= ======================================================
name                        equation  free parameters (speed unit RPM by default)
=========================== ========= ======================================================
``tucker_wang``             (3.1)     c0, alpha1, alpha2          (alpha0 fixed)
``hysteretic_reversible``   (3.2)     b0, b0*b2, v_knee, b4, b5   (b1 fixed, H = 0: model 1)
``hysteretic``              (3.2-3.3) b0, b0*b2, v_knee, b4, b5, beta1, beta2   (b1 fixed)
``polynomial``              (5.1)     a0 (stick phases), a4..a7   (gain 1.36, ref = mean speed; a1..a3 tied)
``polynomial_hysteretic``   (5.3)     a0 (stick phases), a4..a7, beta1, beta2
=========================== ========= ======================================================

Fixed parameters and why: alpha0 (3.1) and b1 (3.2) only set how fast the tanh term saturates
near zero speed; on slip samples (bit speed above the stick threshold) tanh is saturated and they
are not identifiable, so they are fixed (default 10 per RPM: tanh > 0.9999 above 0.5 RPM). Eq. (3.2) is fitted in the
parameters b0, b0*b2 (the amplitude of the fraction) and the knee speed v_knee = b3^(-1/b5)
(where the denominator reaches 2): the thesis's b0..b5 make the problem ill-conditioned (b0 and
b2 trade off when the Coulomb term is small, b3 and b5 scale together); b2 and b3 follow and are
written in the engine law.

Eq. (5.1) is the *non-regularized* law: its a0 is the static (break-away) torque, 1.36 a0 at rest
and W = W_ref, and the engine keeps the bit stuck while the string torque is below it. a0 is
identified from the stick phases, not from the slip samples: the torque at which the bit breaks
away is the largest measured torque of each stick phase (up to ``lag_s`` into the slip that
follows, which the rig's 10 Hz filter delays), one value per cycle (:func:`breakaway_torques`);
1.36 a0 is their mean, with a Student-t interval over the cycles. The slip branch a4..a7 (and
beta1, beta2 of Eq. 5.3) is then fitted on the slip samples with a0 held at that value. The two
low-speed pieces (below 1 % and 5 % of the mean bit speed) lie below the stick threshold and
carry no slip data: a1, a2, a3 are tied (reported as such): the law falls linearly from the
static torque at rest to the cubic's value at 5 % of the mean speed, reached at 1 %, and is flat
in between (continuous on v > 0).

The fit is :func:`scipy.optimize.least_squares` on the torque residuals. Parameter uncertainty:
residuals of a 1 kHz record are strongly correlated within a stick-slip cycle, so the covariance
is the cluster-robust sandwich with the cycles as clusters, (J'J)^-1 (sum_c J_c' r_c r_c' J_c)
(J'J)^-1 G / (G - 1), and the 95 % intervals use Student's t with G - 1 degrees of freedom (G
cycles). AIC and BIC use the Gaussian likelihood with the effective number of independent
residuals n_eff = n / tau (tau: integrated autocorrelation time of the residuals, the largest over
the compared laws, so that all laws are compared on the same n_eff). The out-of-sample RMSE comes
from K-fold cross-validation over contiguous blocks of cycles.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize, stats

from drillpy import _core
from drillpy.records.io import RPM
from drillpy.records.signals import MeanCycle, platform_response, var_mse

METHOD_NOTE = (
    "Least squares through the engine's law evaluation on the slip samples of valid cycles. alpha0 (3.1) "
    "and b1 (3.2) only set how fast tanh saturates near zero speed and are fixed (10 per RPM); Eq. (3.2) is "
    "fitted as b0, b0*b2 and the knee speed v_knee = b3^(-1/b5) (better conditioned; b2 and b3 follow); the "
    "low-speed pieces of Eq. (5.1) are tied to the cubic (continuous, zero at rest). Intervals: cluster-robust "
    "sandwich covariance with the cycles as clusters and Student's t (G - 1 dof). AIC/BIC: Gaussian "
    "likelihood with n_eff = n / tau independent residuals (tau: integrated autocorrelation time of the "
    "residuals, the largest over the laws). CV RMSE: 5-fold cross-validation over contiguous blocks of cycles.")

LAWS = ("tucker_wang", "hysteretic_reversible", "hysteretic", "polynomial", "polynomial_hysteretic")
EQUATIONS = {"tucker_wang": "3.1", "hysteretic_reversible": "3.2 (H = 0)", "hysteretic": "3.2-3.3",
             "polynomial": "5.1", "polynomial_hysteretic": "5.3"}


def law_eval(law: dict, speed, accel, wob) -> tuple:
    """Torque [N m] and its derivatives dT/dv [N m s/rad], dT/da [N m s^2/rad] from the engine.

    The law is evaluated by ``_core.law_torque`` (the C++ ``BitRockLaw``), the same code the
    simulations use; nothing is re-implemented in Python.

    Parameters
    ----------
    law : dict
        Engine law (``type``, ``speed_unit``, ``wob_ref_n`` and the parameters of Eqs. 3.1, 3.2-3.3,
        5.1 or 5.3), e.g. :attr:`LawFit.law`. Validated by the engine.
    speed : array_like
        Bit speed [rad/s] (SI, whatever the law's ``speed_unit``).
    accel : float or array_like
        Bit acceleration [rad/s^2], broadcast to the shape of ``speed`` (only the hysteretic laws
        use it).
    wob : float or array_like
        Weight on bit [N], broadcast to the shape of ``speed``; the torque scales with
        W / ``wob_ref_n``.

    Returns
    -------
    tuple of ndarray
        ``(T, dT_dv, dT_da)``, each of the length of ``speed``.
    """
    v = np.ascontiguousarray(speed, dtype=float)
    a = np.ascontiguousarray(np.broadcast_to(np.asarray(accel, float), v.shape))
    w = np.ascontiguousarray(np.broadcast_to(np.asarray(wob, float), v.shape))
    return _core.law_torque(json.dumps(law), v, a, w)


@dataclass
class FitData:
    """Samples for identification (SI).

    Attributes
    ----------
    speed, accel, torque : ndarray
        Bit speed [rad/s], bit acceleration [rad/s^2], torque on bit [N m].
    wob : ndarray
        WOB at which the law is evaluated [N]: the constant ``wob_ref`` (default) or the measured
        WOB (then T scales with W / W_ref, section 3.3).
    group : ndarray of int
        Stick-slip cycle of each sample (clusters of the covariance and cross-validation folds).
    wob_ref : float
        Reference WOB of the fitted laws [N] (the mean measured WOB).
    speed_ref : float
        Mean bit speed [rad/s] (the reference speed of Eq. 5.1).
    breakaway : ndarray, optional
        Break-away torque of each stick phase, scaled to ``wob_ref`` [N m]
        (:func:`breakaway_torques`): identifies the static torque a0 of Eqs. (5.1), (5.3).
    """
    speed: np.ndarray
    accel: np.ndarray
    torque: np.ndarray
    wob: np.ndarray
    group: np.ndarray
    wob_ref: float
    speed_ref: float
    breakaway: np.ndarray | None = None

    def __post_init__(self):
        n = np.asarray(self.speed).size
        for k in ("speed", "accel", "torque", "wob", "group"):
            x = np.asarray(getattr(self, k))
            if x.shape != (n,):
                raise ValueError(f"FitData.{k}: has shape {x.shape}, expected ({n},)")
            if k != "group" and not np.all(np.isfinite(x)):
                raise ValueError(f"FitData.{k}: has non-finite values")
        if n < 20:
            raise ValueError(f"FitData: only {n} samples (need at least 20)")

    def __len__(self) -> int:
        return self.speed.size

    def subset(self, mask) -> "FitData":
        """The samples selected by ``mask`` (references and break-away torques unchanged).

        Parameters
        ----------
        mask : array_like of bool
            One entry per sample; used for the cross-validation folds.

        Returns
        -------
        FitData

        Raises
        ------
        ValueError
            If fewer than 20 samples are selected.
        """
        m = np.asarray(mask, bool)
        return FitData(self.speed[m], self.accel[m], self.torque[m], self.wob[m], self.group[m],
                       self.wob_ref, self.speed_ref, self.breakaway)

    @classmethod
    def from_arrays(cls, speed, accel, torque, labels, cycle_id, wob=None, use_wob: bool = False,
                    wob_ref: float | None = None, every: int = 1, cycles=None,
                    platform: tuple | None = None) -> "FitData":
        """Slip samples (``labels != 0``) of valid cycles (``cycle_id >= 0``), every ``every``-th.

        Parameters
        ----------
        speed : array_like
            Bit speed of every sample of the record [rad/s].
        accel : array_like
            Bit acceleration [rad/s^2] (:func:`drillpy.records.signals.derivative`).
        torque : array_like
            Measured torque on bit [N m].
        labels : array_like of int
            Branch of each sample (:meth:`drillpy.records.signals.Cycles.branch_labels`): +1 upper,
            -1 lower, 0 stuck or outside a valid cycle.
        cycle_id : array_like of int
            Valid cycle of each sample, -1 outside (:meth:`drillpy.records.signals.Cycles.cycle_id`);
            the clusters of the covariance.
        wob : array_like, optional
            Measured WOB [N]; its mean over the kept samples is the reference WOB. None: no WOB
            channel, reference 1 N (or ``wob_ref``) and no scaling.
        use_wob : bool
            Evaluate the law at the measured WOB (T scales with W / W_ref); False (default): at
            the reference WOB.
        wob_ref : float, optional
            Reference WOB [N] instead of the mean measured WOB.
        every : int
            Keep one sample in ``every`` (the rig's channels are low-passed at 10 Hz, so 100 Hz of
            a 1 kHz record carries the same information at a tenth of the cost; the intervals are
            cluster-robust and do not depend on the sampling rate).
        cycles : Cycles, optional
            The :class:`drillpy.records.signals.Cycles` the labels came from; their stick phases
            give the break-away torques (static torque of Eq. 5.1), kept when there are at least 2.
        platform : (float, float, float), optional
            ``(fs_hz, natural_hz, damping)``: bring the speed, the acceleration and the WOB through
            the torque-on-bit platform (:func:`through_platform`) before they are compared with the
            torque, which passed through it on its way to the load cell (the law is then fitted on
            the two sides after the same chain; the break-away torques are unchanged). None
            (default): the speed and the WOB as measured.

        Returns
        -------
        FitData
            ``speed_ref`` is the mean bit speed of the kept samples.

        Raises
        ------
        ValueError
            If ``every`` is not a positive integer, or fewer than 20 samples are kept.
        """
        if int(every) != every or every < 1:
            raise ValueError(f"every = {every!r}: must be a positive integer")
        m = (np.asarray(labels) != 0) & (np.asarray(cycle_id) >= 0)
        wob_raw = wob
        if platform is not None:
            # the platform's overshoot takes the filtered speed below zero where a slip ends in a stick: the
            # bit does not turn backwards there, and the law (odd in the speed) would flip its sign
            sp = through_platform(speed, *platform)
            speed = np.where(np.asarray(speed, float) >= 0, np.maximum(sp, 0.0), sp)
            accel = through_platform(accel, *platform)
            wob = None if wob is None else through_platform(wob, *platform)
        sub = np.zeros(m.size, bool)
        sub[::int(every)] = True
        m &= sub
        v = np.asarray(speed, float)[m]
        if wob is not None:
            w_all = np.asarray(wob, float)[m]
            ref = float(np.mean(w_all)) if wob_ref is None else float(wob_ref)
        else:
            w_all, ref = None, (1.0 if wob_ref is None else float(wob_ref))
        w = w_all if (use_wob and w_all is not None) else np.full(v.size, ref)
        brk = None
        if cycles is not None:
            brk = breakaway_torques(cycles, torque, wob_raw if use_wob else None, ref)
            brk = brk if brk.size >= 2 else None
        return cls(v, np.asarray(accel, float)[m], np.asarray(torque, float)[m], w,
                   np.asarray(cycle_id)[m], ref, float(np.mean(v)), brk)


def through_platform(x, fs_hz: float, natural_hz: float, damping: float) -> np.ndarray:
    """A measured channel brought through the torque-on-bit platform the torque went through.

    The rig's torque reaches the acquisition through the platform's second-order mode and then the
    10 Hz filter; the encoders and the WOB through the filter only
    (:func:`drillpy.records.signals.platform_response`, the rig model's record chain). Fitting the
    measured torque against the measured speed then compares a torque delayed (about
    2 zeta / w_n, 12 ms at 20 Hz and zeta 0.75) and smoothed by the platform with a speed that was
    not, which flattens the law's falling branch. Passing the speed (and the WOB, which scales the
    law) through the same platform puts both sides of the fit behind the same chain; for a law
    linear in the speed over the slip range the two orders of law and filter agree.
    :meth:`FitData.from_arrays` holds the filtered speed at zero or above where the measured one is
    (the platform's overshoot at the end of a slip is no backward rotation).

    Non-finite samples (excluded stretches) are bridged linearly before filtering so that they do
    not ring the filter; they stay excluded from the fit by their labels.

    Parameters
    ----------
    x : array_like
        A uniformly sampled channel (any unit).
    fs_hz, natural_hz, damping : float
        Sampling rate [Hz], the platform's natural frequency [Hz] and damping ratio [-].

    Returns
    -------
    ndarray
        The channel as the platform's load cell would read it, same length.
    """
    x = np.asarray(x, float)
    ok = np.isfinite(x)
    if not ok.any():
        return x.copy()
    if not ok.all():
        i = np.arange(x.size)
        x = np.interp(i, i[ok], x[ok])
    return platform_response(x, fs_hz, natural_hz, damping)


def breakaway_torques(cycles, torque, wob=None, wob_ref: float = 1.0, *, min_stick_s: float = 0.01,
                      lag_s: float = 0.03) -> np.ndarray:
    """Break-away torque of every stick phase of the valid cycles [N m].

    The bit of a valid cycle sticks from ``cycles.stick[j]`` to ``cycles.end[j]``; while stuck the
    torque on it is the string's, rising until it reaches the static torque and the bit breaks
    away (points 1-2 of the cycle of Fig. 5.6). The break-away torque is the largest torque from
    the start of the stick phase to ``lag_s`` after its end (the rig's 10 Hz filter delays the
    peak by a few 10 ms). Stick phases shorter than ``min_stick_s`` are skipped (the bit barely
    stopped), and so are those with a non-finite torque. With ``wob`` the value is scaled to
    ``wob_ref`` by W_ref / W at the break-away instant (the law scales with W / W_ref).

    The filter also flattens the peak: on a simulated truth the filtered break-away torques
    understate the static torque by about 9 % (docs/records.md, section 1).

    Parameters
    ----------
    cycles : Cycles
        Cycles of the record (:func:`drillpy.records.signals.segment_cycles`).
    torque : array_like
        Measured torque on bit of the record [N m].
    wob : array_like, optional
        Measured WOB [N]; None: no scaling.
    wob_ref : float
        Reference WOB the values are scaled to [N] (used with ``wob`` only).
    min_stick_s : float
        Shortest stick phase used [s].
    lag_s : float
        How far past the end of the stick phase the peak is searched [s].

    Returns
    -------
    ndarray
        One break-away torque per stick phase used [N m], in cycle order (possibly empty).
    """
    tq = np.asarray(torque, float)
    lag = int(round(lag_s / cycles.dt))
    out = []
    for j in np.flatnonzero(cycles.valid):
        a, b = int(cycles.stick[j]), int(cycles.end[j])
        if (b - a) * cycles.dt < min_stick_s:
            continue
        seg = tq[a:min(b + lag, tq.size)]
        if not np.all(np.isfinite(seg)):
            continue
        k = a + int(np.argmax(seg))
        val = float(tq[k])
        if wob is not None:
            val *= wob_ref / float(np.asarray(wob, float)[k])
        out.append(val)
    return np.asarray(out)


# ----------------------------------------------------------------------------- law families
@dataclass
class _Family:
    names: tuple
    lower: tuple
    upper: tuple
    build: object  # (params, data, speed_unit, fixed) -> law dict


def _tw(p, d, unit, fx):
    return {"type": "tucker_wang", "speed_unit": unit, "wob_ref_n": d.wob_ref, "c0": p[0],
            "alpha0": fx["alpha0"], "alpha1": p[1], "alpha2": p[2]}


def _hys(p, d, unit, fx, hyst=True):
    # free parameters: b0 and the product b0 b2 (the fraction's amplitude), which keeps the fit
    # well conditioned when the data want a small Coulomb term b0
    law = {"type": "hysteretic", "speed_unit": unit, "wob_ref_n": d.wob_ref, "b0": p[0], "b1": fx["b1"],
           "b2": p[1] / p[0], "b3": p[2] ** -p[4], "b4": p[3], "b5": p[4], "beta1": 0.0, "beta2": 0.0}
    if hyst:
        law["beta1"], law["beta2"] = p[5], p[6]
    return law


def _poly(p, d, unit, fx, hyst=False):
    ref = d.speed_ref * (RPM if unit == "rpm" else 1.0)
    a4, a5, a6, a7 = p[:4]
    a0 = float(fx.get("a0", 0.0))  # static torque / gain (identified from the stick phases)
    v5 = 0.05 * ref
    t5 = a4 + v5 * (a5 + v5 * (a6 + v5 * a7))  # cubic at 5 % of the reference speed
    law = {"type": "polynomial_hysteretic" if hyst else "polynomial", "speed_unit": unit,
           "wob_ref_n": d.wob_ref, "a0": a0, "a1": (t5 - a0) / (0.01 * ref), "a2": t5, "a3": 0.0,
           "a4": a4, "a5": a5, "a6": a6, "a7": a7, "ref_speed": ref, "gain": fx["gain"]}
    if hyst:
        law["beta1"], law["beta2"] = p[4], p[5]
    return law


_INF = np.inf
FAMILIES = {
    "tucker_wang": _Family(("c0", "alpha1", "alpha2"), (1e-9, -_INF, 0.0), (_INF, _INF, _INF), _tw),
    "hysteretic_reversible": _Family(("b0", "b0*b2", "v_knee", "b4", "b5"), (1e-6, -_INF, 1e-6, 1e-3, 1e-3),
                                     (_INF, _INF, _INF, 10.0, 10.0),
                                     lambda p, d, u, fx: _hys(p, d, u, fx, hyst=False)),
    "hysteretic": _Family(("b0", "b0*b2", "v_knee", "b4", "b5", "beta1", "beta2"),
                          (1e-6, -_INF, 1e-6, 1e-3, 1e-3, 0.0, 0.0), (_INF, _INF, _INF, 10.0, 10.0, 0.99, _INF),
                          _hys),
    "polynomial": _Family(("a4", "a5", "a6", "a7"), (-_INF,) * 4, (_INF,) * 4, _poly),
    "polynomial_hysteretic": _Family(("a4", "a5", "a6", "a7", "beta1", "beta2"),
                                     (-_INF,) * 4 + (0.0, 0.0), (_INF,) * 4 + (0.99, _INF),
                                     lambda p, d, u, fx: _poly(p, d, u, fx, hyst=True)),
}
PARAM_UNITS = {  # for reports; speed unit RPM
    "c0": "N m", "alpha0": "1/RPM", "alpha1": "1/RPM", "alpha2": "1/RPM^2", "b0": "N m", "b1": "1/RPM",
    "b0*b2": "N m RPM^-b4", "v_knee": "RPM", "b3": "RPM^-b5", "b4": "-", "b5": "-", "beta1": "-", "beta2": "s/RPM",
    "a0": "ft lbf", "a4": "ft lbf", "a5": "ft lbf/RPM", "a6": "ft lbf/RPM^2", "a7": "ft lbf/RPM^3",
}


@dataclass
class LawFit:
    """A fitted law with its uncertainty and goodness of fit (made by :func:`fit_law`).

    ``law`` is the engine's JSON law (dict) ready for a configuration; ``values``/``stderr``/
    ``ci_low``/``ci_high`` follow ``names``; ``fixed`` lists the parameters held fixed.
    RMSE [N m] and R^2 are on the fitted samples; ``cv_rmse`` is out of sample; ``var_mse``
    is Eq. (5.2) on the mean cycle [(N m)^4].

    Attributes
    ----------
    name : str
        Law name, one of :data:`LAWS` (equation number in :data:`EQUATIONS`).
    law : dict
        The fitted engine law, ready for the ``law`` block of a configuration or :func:`law_eval`.
    names : tuple of str
        Names of the identified parameters (``a0`` first when identified from the stick phases).
    values, stderr : ndarray
        Estimates and cluster-robust standard errors, in the units of :data:`PARAM_UNITS` for the
        speed unit of the fit.
    ci_low, ci_high : ndarray
        Bounds of the confidence interval (Student's t over the cycles); NaN for a parameter at a
        bound.
    fixed : dict
        Parameters held fixed or tied, with their values (alpha0, b1, gain 1.36, a1..a3, ...).
    n : int
        Number of fitted (slip) samples.
    n_clusters : int
        Number of stick-slip cycles among them (G of the covariance).
    rss : float
        Residual sum of squares [(N m)^2].
    rmse : float
        Root-mean-square residual on the fitted samples [N m].
    r2 : float
        Coefficient of determination on the fitted samples [-].
    tau : float
        Integrated autocorrelation time of the residuals [samples] (:func:`autocorrelation_time`).
    cv_rmse : float
        Cross-validated RMSE [N m] (:func:`cross_validated_rmse`); NaN until :func:`fit_laws`
        sets it.
    var_mse : float
        Var[MSE] of Eq. (5.2) on the mean cycle [(N m)^4]; NaN until set.
    aic, bic : float
        Information criteria with n_eff independent residuals (set by :func:`fit_laws`; lower is
        better).
    n_eff : float
        Effective number of independent residuals, n / tau (tau the largest over the compared
        laws).
    at_bound : tuple of str
        Parameters that ended on a bound of the fit (flagged, no interval).
    message : str
        Termination message of :func:`scipy.optimize.least_squares`.
    residual : ndarray
        Torque residuals, model minus measured [N m], one per fitted sample.
    static_cycles : int
        Number of stick phases a0 was identified from (Eqs. 5.1, 5.3; 0: not identified).
    """
    name: str
    law: dict
    names: tuple
    values: np.ndarray
    stderr: np.ndarray
    ci_low: np.ndarray
    ci_high: np.ndarray
    fixed: dict
    n: int
    n_clusters: int
    rss: float
    rmse: float
    r2: float
    tau: float
    cv_rmse: float = float("nan")
    var_mse: float = float("nan")
    aic: float = float("nan")
    bic: float = float("nan")
    n_eff: float = float("nan")
    at_bound: tuple = ()
    message: str = ""
    residual: np.ndarray = field(default=None, repr=False)
    static_cycles: int = 0  #: stick phases a0 was identified from (Eqs. 5.1, 5.3; 0: not identified)

    @property
    def slip_values(self) -> np.ndarray:
        """The parameters fitted to the slip samples (``values`` without a0 from the stick phases)."""
        return self.values[1:] if self.static_cycles else self.values

    @property
    def static_torque_nm(self) -> float:
        """Break-away torque at rest and W_ref [N m] (non-regularized laws; 0 for the others)."""
        return float(self.law.get("gain", 0.0) * self.law.get("a0", 0.0))

    @property
    def k(self) -> int:
        """Number of parameters fitted to the slip samples (a0, identified from the stick phases,
        is not one of them)."""
        return len(self.names) - (1 if self.static_cycles else 0)

    def predict(self, speed, accel=0.0, wob=None) -> np.ndarray:
        """Torque [N m] of the fitted law (engine) at SI speed and acceleration.

        Parameters
        ----------
        speed : array_like
            Bit speed [rad/s].
        accel : float or array_like
            Bit acceleration [rad/s^2] (used by the hysteretic laws; 0: the reversible curve).
        wob : float or array_like, optional
            Weight on bit [N]; default the law's reference WOB ``wob_ref_n``.

        Returns
        -------
        ndarray
            Torque on bit [N m], one value per speed.
        """
        w = self.law["wob_ref_n"] if wob is None else wob
        return law_eval(self.law, speed, accel, w)[0]

    def as_dict(self) -> dict:
        """The fit as a JSON-ready dict (the ``fits`` of ``summary.json``).

        Returns
        -------
        dict
            ``law``, ``equation``, ``engine_law``, ``parameters`` (per name: ``value``,
            ``stderr`` (None at a bound), ``ci95`` (None without an interval), ``unit``,
            ``at_bound``, ``source``: stick phases or slip samples), ``fixed``, ``fixed_rule``,
            ``static_torque_nm``, ``static_torque_cycles``, ``k``, ``n``, ``n_clusters``,
            ``n_eff``, ``rmse_nm``, ``r2``, ``cv_rmse_nm``, ``var_mse``, ``aic``, ``bic``,
            ``residual_autocorrelation_time_samples``, ``at_bound`` and ``message``.
        """
        def ci(lo, hi):
            return None if not (np.isfinite(lo) and np.isfinite(hi)) else [float(lo), float(hi)]
        return {"law": self.name, "equation": EQUATIONS[self.name], "engine_law": self.law,
                "parameters": {nm: {"value": float(v), "stderr": None if nm in self.at_bound else float(s),
                                    "ci95": ci(lo, hi), "unit": PARAM_UNITS.get(nm, ""),
                                    "at_bound": nm in self.at_bound,
                                    "source": "stick phases" if (nm == "a0" and self.static_cycles) else "slip samples"}
                               for nm, v, s, lo, hi in zip(self.names, self.values, self.stderr,
                                                           self.ci_low, self.ci_high)},
                "fixed": self.fixed, "fixed_rule": _fixed_rule(self.name),
                "static_torque_nm": self.static_torque_nm, "static_torque_cycles": self.static_cycles, "k": self.k, "n": self.n, "n_clusters": self.n_clusters,
                "n_eff": self.n_eff, "rmse_nm": self.rmse, "r2": self.r2, "cv_rmse_nm": self.cv_rmse,
                "var_mse": self.var_mse, "aic": self.aic, "bic": self.bic,
                "residual_autocorrelation_time_samples": self.tau, "at_bound": list(self.at_bound),
                "message": self.message}


def _fixed_rule(name: str) -> str:
    if name == "tucker_wang":
        return "alpha0 fixed: it only sets how fast tanh saturates near rest, not identifiable from slip samples"
    if name.startswith("hyst"):
        return "b1 fixed: it only sets how fast tanh saturates near rest, not identifiable from slip samples"
    return ("gain fixed at 1.36 (Eq. 5.1); a1, a2, a3 tied: the law falls linearly from the static torque "
            "1.36 a0 at rest to the cubic's value at 5 % of the reference speed, reached at 1 %, flat in between "
            "(no slip samples below the stick threshold)")


def _start(name: str, d: FitData, unit: str, fx: dict, prior: dict) -> np.ndarray:
    s = RPM if unit == "rpm" else 1.0
    v = d.speed * s
    scale = d.wob / d.wob_ref
    if name.startswith("polynomial"):
        c = np.polyfit(v, d.torque / scale / fx["gain"], 3)[::-1]
        return np.r_[c, 0.1, 0.01] if name.endswith("hysteretic") else c
    if name == "tucker_wang":
        lo, hi = np.percentile(d.torque, [5, 95])
        vpk = max(np.percentile(v, 5), 1e-3)
        return np.array([lo, 2.0 * (hi / lo - 1.0) / vpk, 1.0 / vpk ** 2])
    tw = prior.get("tucker_wang")  # Eq. (3.2) with b4 = 1, b5 = 2 is Eq. (3.1)
    base = (np.array([tw[0], tw[0] * tw[1], tw[2] ** -0.5, 1.0, 2.0]) if tw is not None
            else np.array([np.percentile(d.torque, 5), 1.0, 1.0, 1.0, 2.0]))
    if name == "hysteretic":
        rev = prior.get("hysteretic_reversible")
        base = rev if rev is not None else base
        return np.r_[base, 0.1, 0.01]
    return base


def _cluster_cov(J: np.ndarray, r: np.ndarray, groups: np.ndarray) -> np.ndarray:
    _, g = np.unique(groups, return_inverse=True)
    G = g.max() + 1
    bread = np.linalg.pinv(J.T @ J)
    S = np.zeros((G, J.shape[1]))
    np.add.at(S, g, J * r[:, None])
    meat = S.T @ S
    return bread @ meat @ bread * (G / max(G - 1, 1))


def autocorrelation_time(r: np.ndarray) -> float:
    """Integrated autocorrelation time tau = 1 + 2 sum rho_k [samples], summed over the initial
    positive sequence of the autocorrelation (Geyer).

    n / tau is the number of effectively independent residuals used by the AIC and BIC.

    Parameters
    ----------
    r : ndarray
        A series, e.g. the torque residuals of a fit in sample order (its mean is removed).

    Returns
    -------
    float
        tau [samples]; 1 for white noise.
    """
    x = np.asarray(r, float) - np.mean(r)
    n = x.size
    f = np.fft.rfft(x, 2 * n)
    acf = np.fft.irfft(f * np.conj(f))[:n]
    acf /= acf[0]
    neg = np.flatnonzero(acf[1:] <= 0)
    m = neg[0] + 1 if neg.size else n
    return float(1.0 + 2.0 * np.sum(acf[1:m]))


def fit_law(name: str, data: FitData, *, speed_unit: str = "rpm", fixed: dict | None = None,
            start=None, prior: dict | None = None, confidence: float = 0.95) -> LawFit:
    """Fit one law to ``data`` by nonlinear least squares through the engine.

    Parameters
    ----------
    name : str
        One of :data:`LAWS`.
    data : FitData
        The slip samples to fit (:meth:`FitData.from_arrays`); its break-away torques, when
        present, give a0 of Eqs. (5.1) and (5.3).
    speed_unit : {"rpm", "rad_s"}
        Unit the law's parameters refer to (the bit speed and acceleration enter the formulas in it).
    fixed : dict, optional
        Values of the fixed parameters (``alpha0``, ``b1`` [1/speed unit], ``gain``).
    start : array, optional
        Starting values of the free parameters.
    prior : dict, optional
        Fitted values of other laws used to start this one (``{"tucker_wang": values, ...}``).
    confidence : float
        Level of the intervals.

    Returns
    -------
    LawFit
        With ``cv_rmse``, ``var_mse``, ``aic``, ``bic`` and ``n_eff`` still NaN (set by
        :func:`fit_laws`).

    Raises
    ------
    ValueError
        For an unknown law or speed unit.
    """
    if name not in FAMILIES:
        raise ValueError(f"law = {name!r}: unknown (use {', '.join(LAWS)})")
    if speed_unit not in ("rpm", "rad_s"):
        raise ValueError(f"speed_unit = {speed_unit!r}: use 'rpm' or 'rad_s'")
    fam = FAMILIES[name]
    fx = {"alpha0": 10.0 if speed_unit == "rpm" else 10.0 * RPM, "gain": 1.36}
    fx["b1"] = fx["alpha0"]
    fx.update(fixed or {})
    used_fixed = {k: fx[k] for k in (("alpha0",) if name == "tucker_wang" else ("b1",) if name.startswith("hyst")
                                     else ("gain",))}
    static = None  # (a0, stderr, ci_low, ci_high, cycles) of Eq. (5.1) from the stick phases
    if name.startswith("polynomial"):
        if "a0" in (fixed or {}):
            used_fixed["a0"] = fx["a0"]
        elif data.breakaway is not None:
            b = np.asarray(data.breakaway, float) / fx["gain"]
            G = b.size
            se0 = float(np.std(b, ddof=1) / math.sqrt(G))
            q0 = stats.t.ppf(0.5 + confidence / 2, G - 1)
            fx["a0"] = float(np.mean(b))
            static = (fx["a0"], se0, fx["a0"] - q0 * se0, fx["a0"] + q0 * se0, G)
        else:
            fx["a0"] = 0.0
            used_fixed["a0"] = 0.0  # no stick phase: the law is zero at rest
    x0 = np.asarray(start if start is not None else _start(name, data, speed_unit, fx, prior or {}), float)
    lb, ub = np.array(fam.lower, float), np.array(fam.upper, float)
    with np.errstate(invalid="ignore"):
        inner_lo = np.where(np.isfinite(lb), lb + 1e-6 * (np.abs(lb) + 1), -np.inf)
        inner_hi = np.where(np.isfinite(ub), ub - 1e-6 * (np.abs(ub) + 1), np.inf)
    x0 = np.clip(x0, inner_lo, inner_hi)

    def resid(p):
        T = law_eval(fam.build(p, data, speed_unit, fx), data.speed, data.accel, data.wob)[0]
        return T - data.torque

    res = optimize.least_squares(resid, x0, bounds=(lb, ub), x_scale="jac", method="trf",
                                 max_nfev=100 * len(x0), xtol=1e-9, ftol=1e-9, gtol=1e-9)
    p = res.x
    r = res.fun
    J = _jac(resid, p, lb, ub)
    cov = _cluster_cov(J, r, data.group)
    se = np.sqrt(np.clip(np.diag(cov), 0, None))
    G = np.unique(data.group).size
    q = stats.t.ppf(0.5 + confidence / 2, max(G - 1, 1))
    rss = float(r @ r)
    n = r.size
    tss = float(np.sum((data.torque - data.torque.mean()) ** 2))
    at_bound = tuple(nm for nm, v, lo, hi in zip(fam.names, p, lb, ub)
                     if (np.isfinite(lo) and abs(v - lo) <= 1e-6 * (1 + abs(lo)))
                     or (np.isfinite(hi) and abs(v - hi) <= 1e-6 * (1 + abs(hi))))
    lo_ci, hi_ci = p - q * se, p + q * se
    for j, nm in enumerate(fam.names):  # a parameter at a bound gets a flag, not an interval
        if nm in at_bound:
            lo_ci[j] = hi_ci[j] = np.nan
    law = fam.build(p, data, speed_unit, fx)
    names = fam.names
    if static is not None:
        names = ("a0",) + names
        p, se = np.r_[static[0], p], np.r_[static[1], se]
        lo_ci, hi_ci = np.r_[static[2], lo_ci], np.r_[static[3], hi_ci]
    if name.startswith("polynomial"):
        used_fixed.update({k: law[k] for k in ("a1", "a2", "a3")})
    return LawFit(name, law, names, p, se, lo_ci, hi_ci,
                  used_fixed, n, G, rss, math.sqrt(rss / n), 1.0 - rss / tss, autocorrelation_time(r),
                  at_bound=at_bound, message=str(res.message), residual=r,
                  static_cycles=0 if static is None else static[4])


def _jac(fun, p, lb, ub) -> np.ndarray:
    """Central-difference Jacobian of the residuals (one-sided at a bound)."""
    f0 = fun(p)
    J = np.empty((f0.size, p.size))
    for j in range(p.size):
        h = 1e-6 * max(abs(p[j]), 1e-3)
        up, dn = p.copy(), p.copy()
        up[j] = min(p[j] + h, ub[j])
        dn[j] = max(p[j] - h, lb[j])
        J[:, j] = (fun(up) - fun(dn)) / (up[j] - dn[j])
    return J


def cross_validated_rmse(name: str, data: FitData, folds: int = 5, start=None, **kw) -> float:
    """Out-of-sample RMSE [N m]: fit on all but one block of contiguous cycles, predict it.

    Parameters
    ----------
    name : str
        Law, one of :data:`LAWS`.
    data : FitData
        The samples; the cycles (``data.group``) are split into ``folds`` contiguous blocks.
    folds : int
        Number of blocks (K of K-fold cross-validation).
    start : array_like, optional
        Starting values of the free parameters for every fold (e.g. the full fit's).
    **kw
        Passed to :func:`fit_law` (``speed_unit``, ``fixed``, ``prior``, ``confidence``).

    Returns
    -------
    float
        sqrt(sum of squared prediction errors / number of samples) over all folds [N m]; NaN when
        there are fewer cycles than folds.
    """
    g = np.unique(data.group)
    if g.size < folds:
        return float("nan")
    blocks = np.array_split(g, folds)
    sse, n = 0.0, 0
    for b in blocks:
        test = np.isin(data.group, b)
        f = fit_law(name, data.subset(~test), start=start, **kw)
        d = data.subset(test)
        r = f.predict(d.speed, d.accel, d.wob) - d.torque
        sse += float(r @ r)
        n += r.size
    return math.sqrt(sse / n)


def mean_cycle_var_mse(fit: LawFit, mc: MeanCycle, stick_threshold: float | None = None) -> float:
    """Var[MSE] (Eq. 5.2) between the mean cycle's branch curves and the law evaluated at the
    same speeds with each branch's mean acceleration, at the reference WOB.

    Bins at or below ``stick_threshold`` [rad/s] are excluded: there the bit is stuck or
    breaking away, the measured torque is the string's (anything up to the static torque), and a
    regularized law is zero by construction, so that one bin would dominate Eq. (5.2) for every
    law alike and the statistic could not rank them.

    Parameters
    ----------
    fit : LawFit
        The fitted law.
    mc : MeanCycle
        Mean cycle of the record (:func:`drillpy.records.signals.mean_cycle`); its upper and
        lower curves together are the windowed experimental torque of Eq. (4.3).
    stick_threshold : float, optional
        Bins at or below this speed are left out [rad/s]; None keeps every bin.

    Returns
    -------
    float
        Var[MSE] [(N m)^4].
    """
    ref, mod = [], []
    keep = np.ones(mc.speed.size, bool) if stick_threshold is None else mc.speed > stick_threshold
    for curve, acc in ((mc.upper, mc.accel_upper), (mc.lower, mc.accel_lower)):
        ok = np.isfinite(curve) & np.isfinite(acc) & keep
        ref.append(curve[ok])
        mod.append(fit.predict(mc.speed[ok], acc[ok]))
    return var_mse(np.concatenate(ref), np.concatenate(mod))


def fit_laws(data: FitData, names=LAWS, *, mc: MeanCycle | None = None, folds: int = 5,
             speed_unit: str = "rpm", stick_threshold: float | None = None) -> list:
    """Fit several laws, with cross-validated RMSE, Var[MSE] on the mean cycle (bins above
    ``stick_threshold`` [rad/s], :func:`mean_cycle_var_mse`) and AIC/BIC on a common effective
    sample size (see the module docstring).

    The laws are fitted in the order given, and a law fitted earlier gives the starting values of
    a later one: Eq. (3.2) starts from Eq. (3.1) (b4 = 1, b5 = 2), Eq. (3.2-3.3) from Eq. (3.2)
    with H = 0 (the order of :data:`LAWS`).

    Parameters
    ----------
    data : FitData
        The slip samples (:meth:`FitData.from_arrays`).
    names : iterable of str
        Laws to fit, from :data:`LAWS` (default: all five).
    mc : MeanCycle, optional
        Mean cycle of the same record; None: no Var[MSE].
    folds : int
        Cross-validation folds over cycles; 0: no cross-validation (``cv_rmse`` stays NaN).
    speed_unit : {"rpm", "rad_s"}
        Unit the law parameters refer to.
    stick_threshold : float, optional
        Mean-cycle bins at or below this bit speed are left out of Var[MSE] [rad/s].

    Returns
    -------
    list of LawFit
        In the order of ``names``, with ``cv_rmse``, ``var_mse``, ``n_eff``, ``aic`` and ``bic``
        set.
    """
    fits, prior = [], {}
    for nm in names:
        f = fit_law(nm, data, speed_unit=speed_unit, prior=prior)
        prior[nm] = f.slip_values
        if folds:
            f.cv_rmse = cross_validated_rmse(nm, data, folds, start=f.slip_values, speed_unit=speed_unit)
        if mc is not None:
            f.var_mse = mean_cycle_var_mse(f, mc, stick_threshold)
        fits.append(f)
    tau = max(f.tau for f in fits)
    for f in fits:
        f.n_eff = f.n / tau
        ll = f.n_eff * math.log(f.rss / f.n)
        f.aic = ll + 2 * f.k
        f.bic = ll + f.k * math.log(f.n_eff)
    return fits


def evidence_label(delta_bic: float) -> str:
    """Kass and Raftery (1995) scale for a BIC difference.

    Parameters
    ----------
    delta_bic : float
        BIC of the competing law minus that of the preferred law (>= 0).

    Returns
    -------
    str
        ``"very strong"`` (> 10), ``"strong"`` (> 6), ``"positive"`` (> 2) or
        ``"not worth more than a bare mention"``.
    """
    if delta_bic > 10:
        return "very strong"
    if delta_bic > 6:
        return "strong"
    if delta_bic > 2:
        return "positive"
    return "not worth more than a bare mention"


def compare_laws(fits: list) -> dict:
    """Comparison table (rows sorted by BIC) and which law the data prefer, how strongly.

    Parameters
    ----------
    fits : list of LawFit
        Output of :func:`fit_laws` (AIC and BIC set); at least one.

    Returns
    -------
    dict
        ``table`` (per law, best BIC first: ``law``, ``equation``, ``k``, ``rmse_nm``,
        ``cv_rmse_nm``, ``r2``, ``var_mse``, ``aic``, ``bic``, ``delta_bic``, ``akaike_weight``),
        ``preferred`` (lowest BIC) and ``n_eff``; with two laws or more also ``runner_up``,
        ``delta_bic``, ``evidence`` (:func:`evidence_label`) and a one-sentence ``statement``,
        plus ``best_cv`` (lowest cross-validated RMSE) when cross-validation was run.
    """
    rows = sorted(fits, key=lambda f: f.bic)
    best = rows[0]
    table = [{"law": f.name, "equation": EQUATIONS[f.name], "k": f.k, "rmse_nm": f.rmse,
              "cv_rmse_nm": f.cv_rmse, "r2": f.r2, "var_mse": f.var_mse, "aic": f.aic, "bic": f.bic,
              "delta_bic": f.bic - best.bic, "akaike_weight": 0.0} for f in rows]
    aic = np.array([f.aic for f in rows])
    w = np.exp(-0.5 * (aic - aic.min()))
    for row, wi in zip(table, w / w.sum()):
        row["akaike_weight"] = float(wi)
    second = rows[1] if len(rows) > 1 else None
    out = {"table": table, "preferred": best.name, "n_eff": best.n_eff}
    if second is not None:
        d = second.bic - best.bic
        out["runner_up"] = second.name
        out["delta_bic"] = d
        out["evidence"] = evidence_label(d)
        out["statement"] = (
            f"The data prefer the {best.name} law (Eq. {EQUATIONS[best.name]}): BIC lower by {d:.1f} than "
            f"the next, {second.name} ({evidence_label(d)} evidence on the Kass-Raftery scale, with "
            f"n_eff = {best.n_eff:.0f} independent residuals); Akaike weight {table[0]['akaike_weight']:.2f}.")
        cv = [f for f in fits if np.isfinite(f.cv_rmse)]
        if cv:
            cv_best = min(cv, key=lambda f: f.cv_rmse)
            out["best_cv"] = cv_best.name
            out["statement"] += (
                f" Out of sample (cross-validation over cycles) the lowest RMSE is {cv_best.name} "
                + (f"({cv_best.cv_rmse:.4f} N m vs {best.cv_rmse:.4f} N m for {best.name})."
                   if cv_best is not best else f"too ({best.cv_rmse:.4f} N m)."))
    return out
