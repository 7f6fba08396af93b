"""Stick-slip severity under structural uncertainty in the time domain (thesis chapter 7, future
work item 1): random SM_CB2 (or SM_CB1 / SM_full) realizations of the string integrated with the
bit-rock law, optionally with the stochastic law T_sto = T_hys (1 + eta(t)) (Eq. 4.1).

The bit-rock uncertainty enters through ``eta``: an array with one eta(t) series per sample
(sampled every ``eta_dt`` seconds from t = 0), or an ``eta_generator(sample, n, dt) -> array``
callable, e.g. the PSD-based generator of Eq. (4.4). Sample i then carries realization i of the
random matrices and eta series i at every top speed (common random numbers).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .frf import stochastic_model
from .progress import progress_bar


@dataclass
class SeverityStudy:
    """SS (Eq. 3.4) for ``samples x speeds`` and its statistics per top speed."""
    speeds: np.ndarray
    ss: np.ndarray
    label: str = ""

    @property
    def mean(self) -> np.ndarray:
        return self.ss.mean(axis=0)

    @property
    def q05(self) -> np.ndarray:
        return np.quantile(self.ss, 0.05, axis=0)

    @property
    def q95(self) -> np.ndarray:
        return np.quantile(self.ss, 0.95, axis=0)

    @property
    def p_stick_slip(self) -> np.ndarray:
        """P(SS > 0.5) per speed."""
        return (self.ss > 0.5).mean(axis=0)

    @property
    def band_width(self) -> np.ndarray:
        """Width of the 90 % band (q95 - q05) per speed."""
        return self.q95 - self.q05

    def to_json(self) -> dict:
        return {"label": self.label, "top_speeds_rad_s": self.speeds.tolist(), "samples": int(self.ss.shape[0]),
                "mean_ss": self.mean.round(4).tolist(), "q05_ss": self.q05.round(4).tolist(),
                "q95_ss": self.q95.round(4).tolist(), "p_ss_above_0_5": self.p_stick_slip.round(4).tolist()}


def eta_array(eta_generator, samples: int, duration_s: float, dt: float) -> np.ndarray:
    """Stack ``eta_generator(i, n, dt)`` for i = 0..samples-1 into a (samples, n) array that covers
    ``duration_s``."""
    n = int(np.ceil(duration_s / dt)) + 2
    rows = [np.asarray(eta_generator(i, n, dt), dtype=float) for i in range(samples)]
    for i, r in enumerate(rows):
        if r.shape != (n,) or not np.all(np.isfinite(r)):
            raise ValueError(f"eta_generator({i}, {n}, {dt}) must return {n} finite values, got shape {r.shape}")
    return np.vstack(rows)


def severity_study(cfg: dict, speeds, samples: int, *, model: str = "SM_CB2", delta=0.1, case=None,
                   structural: bool = True, eta=None, eta_generator=None, eta_dt: float = 0.01,
                   seed: int = 1, label: str = "", progress: bool = True, threads: int = 0) -> SeverityStudy:
    """SS of ``samples`` realizations at each top speed [rad/s] (constant WOB of the configuration).

    ``structural=False`` keeps the mean structure (only eta is random). ``eta`` (array
    (samples, n) sampled every ``eta_dt`` s) or ``eta_generator`` adds the bit-rock uncertainty.
    """
    sp = np.atleast_1d(np.asarray(speeds, dtype=float))
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 1:
        raise ValueError(f"samples = {samples!r}: must be an integer >= 1")
    if eta is not None and eta_generator is not None:
        raise ValueError("give either eta or eta_generator, not both")
    if eta_generator is not None:
        eta = eta_array(eta_generator, samples, cfg["simulation"]["duration_s"], eta_dt)
    sm = stochastic_model(cfg, model, delta, case)
    eta_arg = None if eta is None else np.ascontiguousarray(eta, dtype=float)
    with progress_bar(samples * sp.size, label or "SS under structural uncertainty", progress) as cb:
        ss = sm.severity_samples(list(sp), int(samples), int(seed), bool(structural), eta_arg, float(eta_dt), cb,
                                 threads)
    return SeverityStudy(speeds=sp, ss=np.asarray(ss), label=label)


def severity_sources(cfg: dict, speeds, samples: int, *, delta=0.1, eta_generator=None, eta_dt: float = 0.01,
                     seed: int = 1, progress: bool = True, threads: int = 0) -> dict:
    """How much each source widens the SS band: the deterministic string, structural uncertainty
    (SM_CB2 with ``delta``), and, when ``eta_generator`` is given, bit-rock uncertainty alone and
    both together. Returns label -> SeverityStudy."""
    kw = dict(seed=seed, progress=progress, threads=threads)
    out = {"deterministic": severity_study(cfg, speeds, 1, delta=0.0, structural=False, label="deterministic", **kw),
           "structure (SM_CB2)": severity_study(cfg, speeds, samples, delta=delta, label="structure (SM_CB2)", **kw)}
    if eta_generator is not None:
        eta = eta_array(eta_generator, samples, cfg["simulation"]["duration_s"], eta_dt)
        out["bit-rock (eta)"] = severity_study(cfg, speeds, samples, delta=0.0, structural=False, eta=eta,
                                               eta_dt=eta_dt, label="bit-rock (eta)", **kw)
        out["structure + bit-rock"] = severity_study(cfg, speeds, samples, delta=delta, eta=eta, eta_dt=eta_dt,
                                                     label="structure + bit-rock", **kw)
    return out
