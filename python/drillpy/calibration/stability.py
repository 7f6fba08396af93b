"""The posterior stability map: P(SS > 0.5) over the motor command x WOB (issue 35, item 3).

:func:`stability_map` combines the two sources of uncertainty in one Monte Carlo: what the record
leaves uncertain about the rig model (draws of a calibration's posterior, :mod:`drillpy.calibration.posterior`,
across the law families by their probabilities) and the random torque fluctuation of chapter 4
(T_sto = T (1 + eta(t)), Eq. 4.1, eta a stationary Gaussian process of the thesis's PSD, Eq. 4.4:
:mod:`drillpy.uncertainty.process`). Sample i is posterior draw i (systematic resampling of the
final population by weight) with eta realization i of the seed, run at every cell of the grid (the
same eta at every cell: common random numbers, so that the map's differences between cells are not
noise between samples); the runs are those of the calibration's simulator (the whole rig model,
the ``rig`` drive: motor with its torque limit, coupling, jack set to the cell's WOB), from rest.

SS (Eq. 3.4) is the engine's over the run after its transient. A run whose bit stays stuck (stick
fraction above :data:`STALL_FRACTION`: the motor at its torque limit cannot break the bit away) is
a stall: its SS, 0 or undefined with a bit at rest, says nothing of stability; a stall counts as
unstable in P (the bit does not drill) and its own probability is reported apart.

Sample i depends only on (seed, i): any thread count, and a Dask cluster of any size (the runs go
through :class:`drillpy.calibration.sampler.Sampler`, as the calibration's), give the same map. The map is stored in Zarr
(:meth:`StabilityMap.save`: an ``xarray.Dataset`` readable with ``xarray.open_zarr``), like the
Monte Carlo studies of chapter 4.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from drillpy.calibration.posterior import SIM_DT_S, posterior_particles, read_posterior, rig_model
from drillpy.calibration.sampler import Sampler
from drillpy.model.configuration import Configuration
from drillpy.model.simulation import simulate
from drillpy.uncertainty.binomial import wilson_interval
from drillpy.uncertainty.montecarlo import ETA_DT_S, SS_LEVEL
from drillpy.uncertainty.process import THESIS_PSD, generate

#: A run whose bit is stuck over more than this share of the measured window is a stall.
STALL_FRACTION = 0.95


@dataclass
class StabilityMap:
    """Result of :func:`stability_map`.

    Attributes
    ----------
    speeds, wobs : ndarray
        Motor commands Omega_c [rad/s] and WOB (the jack's set force) [N] of the grid.
    severity : ndarray
        SS of every sample at every cell, (samples, wobs, speeds); NaN where the run failed.
    stalled : ndarray
        True where the run stalled, same shape.
    families : list of str
        The law family of each sample.
    p_unstable : ndarray
        P(SS > 0.5 or a stall) per cell, (wobs, speeds).
    p_stall : ndarray
        P(stall) per cell.
    ci90 : ndarray
        Wilson 90 % interval of ``p_unstable`` over the samples, (2, wobs, speeds).
    settings : dict
        Seed, samples, duration, transient, time step, eta's PSD and sampling, the posterior's source.
    """
    speeds: np.ndarray
    wobs: np.ndarray
    severity: np.ndarray
    stalled: np.ndarray
    families: list
    p_unstable: np.ndarray
    p_stall: np.ndarray
    ci90: np.ndarray
    settings: dict = field(default_factory=dict)

    def to_dataset(self):
        """The map as an ``xarray.Dataset`` (dimensions ``sample``, ``wob``, ``speed``; ``family`` is
        the index of each sample's family in the attribute ``families``)."""
        import xarray as xr
        names = sorted(set(self.families))
        return xr.Dataset(
            {"severity": (("sample", "wob", "speed"), self.severity),
             "stalled": (("sample", "wob", "speed"), self.stalled),
             "family": (("sample",), np.array([names.index(f) for f in self.families], dtype=np.int16)),
             "p_unstable": (("wob", "speed"), self.p_unstable), "p_stall": (("wob", "speed"), self.p_stall),
             "p_unstable_lo": (("wob", "speed"), self.ci90[0]), "p_unstable_hi": (("wob", "speed"), self.ci90[1])},
            coords={"speed": self.speeds, "wob": self.wobs, "sample": np.arange(self.severity.shape[0])},
            attrs={"format": "drillpy.stability_map", "ss_level": SS_LEVEL, "stall_fraction": STALL_FRACTION,
                   "families": names,
                   **{k: (str(v) if isinstance(v, (dict, list)) else v) for k, v in self.settings.items()}})

    def save(self, path) -> Path:
        """Write the map to a Zarr store ``path`` (a folder, replaced).

        Parameters
        ----------
        path : str or Path

        Returns
        -------
        Path
        """
        p = Path(path)
        self.to_dataset().to_zarr(p, mode="w", consolidated=False)
        return p


def _grid(name: str, values, unit: str) -> np.ndarray:
    a = np.asarray(values, float).ravel()
    if a.size < 1 or not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise ValueError(f"{name} = {np.asarray(values).tolist()!r}: one or more positive values [{unit}]")
    return a


class _MapRuns:
    """The map's runs for a :class:`~drillpy.calibration.sampler.Sampler`: job (i, (iw, js)) is
    sample i (its posterior draw and eta realization) at WOB ``wobs[iw]`` and command
    ``speeds[js]``; every random draw is made before (picklable, sent once to each Dask worker)."""

    def __init__(self, base_law, fixed, draws, eta, eta_dt, speeds, wobs, duration_s, transient_s, dt_s):
        self.base_law, self.fixed, self.draws, self.eta, self.eta_dt = base_law, fixed, draws, eta, eta_dt
        self.speeds, self.wobs = speeds, wobs
        self.duration_s, self.transient_s, self.dt_s = duration_s, transient_s, dt_s

    def one(self, i, cell, record=None):
        """(SS, stalled) of sample ``i`` at ``cell`` = (iw, js); (NaN, False) where the engine refuses the run."""
        fam, values = self.draws[i]
        om, wob = float(self.speeds[cell[1]]), float(self.wobs[cell[0]])
        try:
            model = rig_model(self.base_law, fam, dict(values, command_rad_s=om), self.fixed)
            cfg = Configuration.of(model.config(om, wob, duration_s=self.duration_s)).replace(
                {"simulation.dt_s": self.dt_s, "simulation.transient_s": self.transient_s,
                 "simulation.output_stride": 1})
            r = simulate(cfg.engine(), om, eta_series=self.eta[i], series_dt=self.eta_dt, record=False)
            return float(r.severity), float(r.stick_fraction) > STALL_FRACTION
        except (ValueError, RuntimeError):
            return math.nan, False


def stability_map(posterior, speeds, wobs, *, samples: int = 40, seed: int = 0, duration_s: float = 30.0,
                  transient_s: float = 10.0, psd=THESIS_PSD, eta_dt: float = ETA_DT_S, dt_s: float = SIM_DT_S,
                  threads: int = 0, scheduler: str | None = None, chunk: int | None = None) -> StabilityMap:
    """P(SS > 0.5) of the calibrated rig over motor command x WOB (module docstring).

    Parameters
    ----------
    posterior : str or Path or dict
        A calibration's ``posterior.json`` (or its dict).
    speeds : array_like
        Motor commands Omega_c [rad/s].
    wobs : array_like
        WOB, the jack's set force [N].
    samples : int
        Monte Carlo samples (posterior draw and eta realization each).
    seed : int
        Seed of the draws and of eta.
    duration_s, transient_s : float
        Simulated time and the start-up left out of SS [s].
    psd : PsdModel, PsdTable or callable
        One-sided PSD of eta [1/Hz] (default the thesis's, Eq. 4.4).
    eta_dt : float
        Sampling step of eta [s].
    dt_s : float
        The engine's time step [s].
    threads : int
        Runs at once on the threads backend (0: one per core).
    scheduler : str, optional
        Where the runs go: ``local`` (or None: threads), ``local:N`` or ``tcp://HOST:PORT``
        (:mod:`drillpy.calibration.sampler`); the same map on any.
    chunk : int, optional
        Runs per Dask task.

    Returns
    -------
    StabilityMap

    Raises
    ------
    ValueError
        Naming the argument and the value.
    """
    s = read_posterior(posterior)
    speeds, wobs = _grid("speeds", speeds, "rad/s"), _grid("wobs", wobs, "N")
    if not isinstance(samples, (int, np.integer)) or samples < 2:
        raise ValueError(f"samples = {samples!r}: an integer of at least 2")
    if not (math.isfinite(duration_s) and math.isfinite(transient_s) and 0 <= transient_s < duration_s):
        raise ValueError(f"transient_s = {transient_s!r}, duration_s = {duration_s!r}: 0 <= transient < duration")
    spec, jobs, weight = posterior_particles(s)
    rng = np.random.default_rng([seed, 2 * 10 ** 6])
    cw = np.cumsum(weight)
    picks = np.minimum(np.searchsorted(cw, (rng.random() + np.arange(int(samples))) / int(samples)), len(jobs) - 1)
    _, eta = generate(psd, dt=eta_dt, duration=duration_s, samples=int(samples), seed=seed)
    runs = _MapRuns(s["record"]["base_law"], spec.fixed, [jobs[k] for k in picks], eta, eta_dt, speeds, wobs,
                    duration_s, transient_s, dt_s)
    tasks = [(i, (iw, js)) for i in range(int(samples)) for iw in range(wobs.size) for js in range(speeds.size)]
    with Sampler(threads, scheduler, chunk) as sampler:
        out = sampler.map(runs, tasks)
    shape = (int(samples), wobs.size, speeds.size)
    sev = out[:, 0].reshape(shape)
    stalled = out[:, 1].reshape(shape) > 0.5
    ok = np.isfinite(sev) | stalled
    unstable = stalled | (np.nan_to_num(sev, nan=0.0) > SS_LEVEL)
    n_ok = np.maximum(ok.sum(axis=0), 1)
    p = (unstable & ok).sum(axis=0) / n_ok
    lo, hi = wilson_interval(p, int(n_ok.min()))
    settings = {"seed": int(seed), "samples": int(samples), "duration_s": float(duration_s),
                "transient_s": float(transient_s), "dt_s": float(dt_s), "eta_dt_s": float(eta_dt),
                "psd": repr(psd), "posterior": str(posterior) if isinstance(posterior, (str, Path)) else
                s["record"].get("source"), "model_probability": s["model_probability"],
                "failed_runs": int((~ok).sum())}
    return StabilityMap(speeds, wobs, sev, stalled, [jobs[k][0] for k in picks], p,
                        (stalled & ok).sum(axis=0) / n_ok, np.array([lo, hi]), settings)
