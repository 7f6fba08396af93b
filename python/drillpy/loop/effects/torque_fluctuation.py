"""``torque_fluctuation``: a slowly varying bit-rock contact, T = T_law (1 + eta(t)) (Eq. 4.1)."""
from __future__ import annotations

import math

import numpy as np
from scipy import signal as sps

from .base import Effect, Param


class TorqueFluctuation(Effect):
    """A slowly varying bit-rock contact, T = T_law (1 + eta(t)) (Eq. 4.1), eta a coloured process
    whose state is estimated from the record's past (:func:`estimate`) and whose conditional mean
    is forecast over each horizon (:func:`forecast`).

    Parameters ``tau_s`` tau [s] (correlation time of eta, 0.01-1000 s), ``memory_s`` m [s] (memory
    of the estimate, 0.002-100 s), both fitted in ln, and ``std`` [-] (standard deviation of
    eta = T / T_law - 1 on the calibration part's slip samples; reported, not fitted).
    """
    name = "torque_fluctuation"
    params = (Param("tau_s", "s", "correlation time of eta", 0.01, 1e3, "log"),
              Param("memory_s", "s", "memory of the estimate of eta from the past", 0.002, 100.0, "log"),
              Param("std", "-", "standard deviation of eta (estimated, reported)", fitted=False))
    change = ("T = T_law (1 + eta(t)) (Eq. 4.1), eta white noise through a critically damped second-order low-pass "
              "(time constant tau): at a restart (eta, eta') from the past of T/T_law - 1, then the conditional mean "
              "exp(-s/tau) [eta (1 + s/tau) + s eta'] over the horizon")
    signature = ("a law residual, relative to T_law, that its own recent past predicts (correlated over longer than "
                 "the horizon)")
    reading = ("slow changes of the bit-rock contact that no input explains: rock heterogeneity, cuttings, wear, the "
               "lateral friction of the bit in its hole (section 5.3.2); the fluctuation process of chapter 4")
    defaults = {"std": 0.15, "f0_hz": 0.25}

    def estimate(self, p, slip):
        """``std``: the standard deviation of eta = T / T_law - 1 (Eq. 4.1) over the calibration
        part's slip samples, leaving out those where |T_law| is below 10 % of its median; see
        :meth:`Effect.estimate`.

        Parameters
        ----------
        p : dict
            The effect's values (not read).
        slip : callable
            ``slip()`` -> (T, T_law) [N m] on the calibration part's slip samples.
        """
        T, Tl = slip()
        ok = np.abs(Tl) > 0.1 * np.median(np.abs(Tl))
        return {"std": float(np.std(T[ok] / Tl[ok] - 1.0, ddof=1))}

    def describe(self, p):
        """The fluctuation's standard deviation and memory tau (Eq. 4.1); see :meth:`Effect.describe`.

        Parameters
        ----------
        p : dict
            The effect's values (``std`` when estimated, ``tau_s``).
        """
        return (f"a torque fluctuation of standard deviation {p.get('std', float('nan')):.3g} that persists over "
                f"tau = {p['tau_s']:.3g} s")

    def count(self, p):
        """Two: tau and the memory (``std`` is not fitted); see :meth:`Effect.count`.

        Parameters
        ----------
        p : dict
            ``{"tau_s", "memory_s", "std"}`` (not read).
        """
        return 2

    def flags(self, p, data, model=None):
        """Flag an eta the forecast forgets within the first half of a horizon: the effect stands
        for a contact that changes slowly, correlated over longer than a horizon (its signature),
        and its conditional mean keeps (1 + s/tau) exp(-s/tau) of the restart's eta after s; below
        1/e at the horizon's middle (tau < 0.058 s for 0.25 s horizons) the fit is correcting the
        first samples after each restart, the model's own error there, not forecasting a bit-rock
        fluctuation (validation case 26, a viscous bit torque: tau 0.025 s, std 0.043, gain 6.2 %;
        the injected fluctuation, case 15: tau 0.24 s, 90 % kept at the middle). See
        :meth:`Effect.flags`.

        Parameters
        ----------
        p : dict
            ``{"tau_s": tau [s], ...}``.
        data : LoopData
            The record (its sampling interval ``dt`` [s] and horizon length ``L`` [samples]).
        model : LoopModel, optional
            Not used.
        """
        half = 0.5 * data.L * data.dt
        x = half / p["tau_s"]
        kept = (1.0 + x) * math.exp(-x)
        if kept < math.exp(-1.0):
            return [f"eta's forecast keeps {100 * kept:.2g} % of its restart value half-way through the {2 * half:g} s "
                    f"horizon (tau {p['tau_s']:.3g} s): a fluctuation forgotten that fast is the model's own error "
                    f"after each restart, not a slow change of the bit-rock contact"]
        return []

    def starts(self, model, data):
        """tau 0.1, 1 and 10 s by memory 0.03 and 0.3 s; see :meth:`Effect.starts`.

        Parameters
        ----------
        model : LoopModel
            Not used.
        data : LoopData
            Not used.
        """
        return [{"tau_s": tau, "memory_s": mem} for tau in (0.1, 1.0, 10.0) for mem in (0.03, 0.3)]

    def eta(self, p, model, data, chs, idx, leads):
        """The conditional mean of eta over each horizon (:func:`forecast`) from its state at the
        restart estimated from the record's past (:func:`estimate`); see :meth:`Effect.eta`.

        Parameters
        ----------
        p : dict
            ``{"tau_s": tau [s], "memory_s": m [s], ...}``.
        model : LoopModel
            The model (its law T_law).
        data : LoopData
            The record on the analysis grid.
        chs : dict
            State channels (``v`` [rad/s], ``T`` [N m], ...).
        idx : array_like of int
            Restart sample indices.
        leads : numpy.ndarray
            Times after the restart [s].
        """
        level, slope = estimate(p, model, data, chs)
        return forecast(p, level[idx], slope[idx], leads)

    def inject(self, truth, p):
        """Set the truth's eta to a Gaussian process of standard deviation ``std`` whose PSD has the
        shape of Eq. (4.4) (flat below f0, falling as f^-3.13 above, continuous at f0); see
        :meth:`Effect.inject`.

        Parameters
        ----------
        truth : drillpy.loop.synthetic.Truth
            The synthetic truth (its ``eta`` series).
        p : dict
            ``{"std": [-], "f0_hz": f0 [Hz]}`` (defaults 0.15 and 0.25 Hz).
        """
        from drillpy.uncertainty.process import PsdModel
        f0 = p["f0_hz"]
        psd = PsdModel(f0=f0, A0=0.0, a=-3.13, b=3.13 * math.log(f0))  # Eq. (4.4) shape, continuous at f0
        truth.eta = p["std"] * truth.process(psd, "eta")


def estimate(p: dict, model, data, chs: dict) -> tuple:
    """Per sample, the state (eta, eta') of the fluctuation estimated from the record's past: the
    straight line fitted by least squares to eta_obs = T / T_law - 1 over the slip samples up to and
    including that sample, with weights exp(-age / m) (m: ``memory_s``). The weighted sums are
    recursive: filters with the kernels lambda^n, n lambda^n, n^2 lambda^n (lambda = exp(-dt / m)).

    Samples where the law's torque is below 10 % of its median magnitude over the slip samples
    (T / T_law is ill-conditioned there) do not enter the fit.

    Parameters
    ----------
    p : dict
        The effect's values; ``p["memory_s"]`` m [s] is read.
    model : LoopModel
        The model (its law T_law(v, a, W_eff)).
    data : LoopData
        The record on the analysis grid (``dt`` [s], ``valid``, ``stick_threshold`` [rad/s]).
    chs : dict
        State channels (:func:`drillpy.loop.model.state_channels`).

    Returns
    -------
    tuple of numpy.ndarray
        (eta [-], eta' [1/s]) per sample of the analysis grid: the fitted line's value and slope at
        that sample (where the line is not determined: eta' 0 and eta the weighted mean, or 0
        before the first usable sample).
    """
    from ..model import law_torque
    Tl = law_torque(model, chs)
    slip = data.valid & (chs["v"] > data.stick_threshold)
    floor = 0.1 * float(np.median(np.abs(Tl[slip]))) if slip.any() else 0.0
    m = (slip & (np.abs(Tl) > floor)).astype(float)
    y = np.where(m > 0, chs["T"] / np.where(m > 0, Tl, 1.0) - 1.0, 0.0)
    lam = math.exp(-data.dt / p["memory_s"])
    kernels = (([1.0], [1.0, -lam]), ([0.0, lam], [1.0, -2 * lam, lam ** 2]),
               ([0.0, lam, lam ** 2], [1.0, -3 * lam, 3 * lam ** 2, -lam ** 3]))
    S = [sps.lfilter(b, a, m) for b, a in kernels]          # sum w age^k  (age in samples)
    Y = [sps.lfilter(b, a, m * y) for b, a in kernels[:2]]  # sum w y age^k
    det = S[0] * S[2] - S[1] ** 2
    ok = (S[0] > 1e-6) & (det > 1e-9 * np.maximum(S[0] * S[2], 1e-300))
    level = np.where(S[0] > 1e-6, Y[0] / np.maximum(S[0], 1e-300), 0.0)
    # y = level - slope * age dt: least squares with the weights
    a0 = np.where(ok, (S[2] * Y[0] - S[1] * Y[1]) / np.where(ok, det, 1.0), level)
    a1 = np.where(ok, (S[1] * Y[0] - S[0] * Y[1]) / np.where(ok, det, 1.0), 0.0) / data.dt
    return a0, a1


def forecast(p: dict, level: np.ndarray, slope: np.ndarray, lead: np.ndarray) -> np.ndarray:
    """Conditional mean of eta at the leads [s] (columns) from (eta, eta') at the restarts (rows):
    eta is modelled as white noise through a critically damped second-order low-pass of time
    constant tau (PSD falling as f^-4 above 1/(2 pi tau), the steep coloured shape of Eq. 4.4), whose
    free response is exp(-s/tau) [eta (1 + s/tau) + s eta'].

    Parameters
    ----------
    p : dict
        The effect's values; ``p["tau_s"]`` tau [s] is read.
    level : numpy.ndarray
        eta [-] at each restart.
    slope : numpy.ndarray
        eta' [1/s] at each restart.
    lead : numpy.ndarray
        Times after the restart s [s].

    Returns
    -------
    numpy.ndarray
        eta [-], shape (restarts, leads).
    """
    tau = p["tau_s"]
    s = np.asarray(lead)[None, :]
    return np.exp(-s / tau) * (level[:, None] * (1.0 + s / tau) + s * slope[:, None])


EFFECT = TorqueFluctuation()
