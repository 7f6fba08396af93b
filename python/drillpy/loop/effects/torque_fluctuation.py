"""``torque_fluctuation``: a slowly varying bit-rock contact, T = T_law (1 + eta(t)) (Eq. 4.1)."""
from __future__ import annotations

import math

import numpy as np
from scipy import signal as sps

from .base import Effect, Param


class TorqueFluctuation(Effect):
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

    def count(self, p):
        return 2

    def starts(self, model, data):
        return [{"tau_s": tau, "memory_s": mem} for tau in (0.1, 1.0, 10.0) for mem in (0.03, 0.3)]

    def eta(self, p, model, data, chs, idx, leads):
        level, slope = estimate(p, model, data, chs)
        return forecast(p, level[idx], slope[idx], leads)

    def inject(self, truth, p):
        from drillpy.uncertainty.process import PsdModel
        f0 = p["f0_hz"]
        psd = PsdModel(f0=f0, A0=0.0, a=-3.13, b=3.13 * math.log(f0))  # Eq. (4.4) shape, continuous at f0
        truth.eta = p["std"] * truth.process(psd, "eta")


def estimate(p: dict, model, data, chs: dict) -> tuple:
    """Per sample, the state (eta, eta') of the fluctuation estimated from the record's past: the
    straight line fitted by least squares to eta_obs = T / T_law - 1 over the slip samples up to and
    including that sample, with weights exp(-age / m) (m: ``memory_s``). The weighted sums are
    recursive: filters with the kernels lambda^n, n lambda^n, n^2 lambda^n (lambda = exp(-dt / m))."""
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
    free response is exp(-s/tau) [eta (1 + s/tau) + s eta']."""
    tau = p["tau_s"]
    s = np.asarray(lead)[None, :]
    return np.exp(-s / tau) * (level[:, None] * (1.0 + s / tau) + s * slope[:, None])


EFFECT = TorqueFluctuation()
