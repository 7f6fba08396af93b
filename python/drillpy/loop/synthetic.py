"""Synthetic records of the test rig with chosen effects switched on, from a *truth* that differs
from the declared model.

:func:`declared_config` is the model a loop declares: the ``thesis-rig`` preset (Table 5.1, one mode
at 2.89 Hz) with a reversible law (beta1 = 0), modal damping 0.05, an ideal top drive and ideal
sensors. :func:`truth_config` draws, from the seed, a truth away from it (``nuisance=True``, the
default): modal damping ratio in [0.03, 0.08], GJ within +-1.5 %, the law's slip branch scaled by
+-8 % with its slope changed by +-10 %, 40 elements with 3 modes instead of 20 elements with one,
and a time step four times finer. :func:`synthetic_record` simulates the truth with any subset of
the effects of the loop's catalogue (:mod:`drillpy.loop.effects`; each effect's ``inject``) and of
:data:`EXTRA` (effects outside the catalogue), then adds measurement noise.

The recorded WOB always fluctuates (``wob_std`` relative: 0.14 by default, the rig's 0.137 on sample
175; band-limited to ``wob_band_hz``), with or
without the coupling, so that a loop must tell whether the torque follows it. All random numbers
(the truth's draws, WOB, eta, noise) come from the seed (the engine's counter-based generator,
:func:`drillpy.uncertainty.process.generate`, for the series): the same seed gives the same record anywhere.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from drillpy.model.config import normalize
from drillpy.model.configuration import Configuration
from drillpy.loop.effects import CATALOGUE
from drillpy.loop.view import view
from drillpy.uncertainty.process import PsdTable, generate, process_variance
from drillpy.records.io import Record
from drillpy.model.simulation import simulate
from drillpy import validate

#: Effects outside the loop's catalogue the generator can inject, with their default parameters:
#: ``top_speed_ramp``: the ideal drive's speed ramps linearly by ``ramp_fraction`` of its mean over the
#: record (a driller changing the set point).
EXTRA = {"top_speed_ramp": {"ramp_fraction": 0.15}}
EFFECTS = tuple(CATALOGUE) + tuple(EXTRA)
#: Parameters of each effect when switched on without values.
DEFAULTS = {**{n: dict(e.defaults) for n, e in CATALOGUE.items()}, **EXTRA}
#: Standard deviations of the white measurement noise (scaled by ``noise``).
NOISE = {"bit_speed": 0.05, "top_speed": 0.05, "torque_on_bit": 0.02, "wob": 2.0}
#: Streams of the generator (sample indices of drillpy.uncertainty.process.generate).
_STREAMS = {"wob": 0, "eta": 1, "bit_speed": 2, "top_speed": 3, "torque_on_bit": 4, "wob_noise": 5}
#: Modal damping ratio of the declared model (the preset's 0.25 is an effective value lumping the
#: dissipation the loop is meant to find, at the stability edge).
DAMPING_RATIO = 0.05


def declared_config(preset: str = "thesis-rig", damping_ratio: float = DAMPING_RATIO) -> dict:
    """The declared model of the synthetic records: the preset with a reversible law (beta1 = 0),
    modal damping ``damping_ratio``, an ideal top drive, ideal sensors and no extra damping.

    Parameters
    ----------
    preset : str
        Engine preset (``thesis-rig``: Table 5.1, one mode at 2.89 Hz).
    damping_ratio : float
        Modal damping ratio of the first mode [-] (:data:`DAMPING_RATIO`, 0.05, by default).

    Returns
    -------
    dict
        Normalized engine configuration: the preset's law with ``beta1 = 0`` (if it has one), no
        bit viscous torque (``bit_viscous_nms = 0``), no ``top_drive`` and no ``sensors`` section.
    """
    cfg = Configuration.load(preset=preset)
    changes = {"operation.bit_viscous_nms": 0.0, **({"law.beta1": 0.0} if "beta1" in cfg.law else {})}
    return normalize(cfg.replace(changes, damping={"type": "modal", "ratios": [float(damping_ratio)]},
                                 top_drive=None, sensors=None))


def truth_config(seed: int, *, modes: int = 3, elements: int = 40, dt_factor: int = 4) -> tuple:
    """A truth away from :func:`declared_config`, drawn from ``seed``: (config, the draws).

    Drawn uniformly: the modal damping ratio in [0.03, 0.08] (every mode), Young's modulus (so
    GJ) times a factor in [0.985, 1.015], the slip branch a4..a7 of the Eq. (5.1) law times a
    factor in [0.92, 1.08] and a5 (the slope) times a further factor in [0.9, 1.1]. The same seed
    gives the same truth.

    Parameters
    ----------
    seed : int
        Seed of the draws.
    modes : int
        Modes of the reduced-order model (the declared model has 1).
    elements : int
        Finite elements per string section.
    dt_factor : int
        The engine time step is the declared one divided by this.

    Returns
    -------
    config : dict
        Normalized engine configuration of the truth.
    draws : dict
        ``damping_ratio``, ``gj_factor``, ``law_scale``, ``law_slope_factor``, ``modes``,
        ``elements`` and ``dt_s`` [s].
    """
    rng = np.random.default_rng([seed, 7919])
    cfg = view(declared_config())
    z = float(rng.uniform(0.03, 0.08))
    gj = float(rng.uniform(0.985, 1.015))
    scale, slope = float(rng.uniform(0.92, 1.08)), float(rng.uniform(0.9, 1.1))
    sections = [{**s.to_dict(), "youngs_modulus_pa": s.youngs_modulus_pa * gj, "elements": elements}
                for s in cfg.string.sections]
    law = {f"law.{k}": getattr(cfg.law, k) * scale for k in ("a4", "a5", "a6", "a7")}
    law["law.a5"] *= slope
    dt = cfg.simulation.dt_s / dt_factor
    cfg = cfg.replace({"string.sections": sections, "rom.modes": modes, **law, "simulation.dt_s": dt},
                      damping={"type": "modal", "ratios": [z] * modes})
    draws = {"damping_ratio": z, "gj_factor": gj, "law_scale": scale, "law_slope_factor": slope, "modes": modes,
             "elements": elements, "dt_s": dt}
    return normalize(cfg), draws


@dataclass
class Truth:
    """What the effects' ``inject`` change: the truth's configuration, its input series on the grid
    ``sdt`` (the recorded WOB ``wob``, the law's WOB ``wob_law``, the relative torque fluctuation
    ``eta``, the top-speed series ``top``) and functions applied to the recorded channels (``post``).

    Attributes
    ----------
    cfg : dict
        Engine configuration of the truth (effects may edit it).
    wob : ndarray
        Recorded WOB [N] on the grid ``sdt``, from the start of the simulation (settling
        included) to one second past its end.
    sdt : float
        Step of the input series [s] (1 ms).
    seed : int
        Seed of every random series.
    wob_law : ndarray or None
        WOB the law sees [N] (the ``wob_coupling`` effect); None: the configured constant WOB.
    eta : ndarray or None
        Relative torque fluctuation eta(t) [-] of Eq. (4.1), T = T_law (1 + eta) (the
        ``torque_fluctuation`` effect); None: none.
    top : ndarray or None
        Top-speed series [rad/s] imposed on the top drive (e.g. ``top_speed_ramp``); None: the
        configured top drive.
    post : list of callable
        ``f(chans, fs_hz) -> chans`` applied in order to the recorded channels (dict of SI
        arrays) before the noise is added, e.g. the low-pass acquisition filter of ``sensor_lag``.
    """
    cfg: dict
    wob: np.ndarray
    sdt: float
    seed: int
    wob_law: np.ndarray | None = None
    eta: np.ndarray | None = None
    top: np.ndarray | None = None
    post: list = field(default_factory=list)

    def process(self, psd, stream: str) -> np.ndarray:
        """A realization of unit variance of a Gaussian process with one-sided PSD ``psd``.

        Parameters
        ----------
        psd : PsdModel, PsdTable or callable
            One-sided PSD S(f) [1/Hz] (:mod:`drillpy.uncertainty.process`); only its shape
            matters, the realization is scaled to unit variance.
        stream : str
            Which of the seed's independent streams to use: ``"wob"``, ``"eta"``,
            ``"bit_speed"``, ``"top_speed"``, ``"torque_on_bit"`` or ``"wob_noise"`` (an effect
            uses the one named after what it drives).

        Returns
        -------
        ndarray
            One value per sample of :attr:`wob`, on the grid ``sdt``.
        """
        return _unit_process(psd, self.sdt, self.wob.size * self.sdt, self.seed, _STREAMS[stream])[: self.wob.size]


def _check_effects(effects) -> dict:
    if isinstance(effects, str):
        effects = [effects]
    out = {}
    items = effects.items() if isinstance(effects, dict) else ((e, None) for e in effects)
    for name, par in items:
        if name not in EFFECTS:
            raise ValueError(f"effect = {name!r}: unknown (known: {', '.join(EFFECTS)})")
        p = dict(DEFAULTS[name])
        unknown = set(par or {}) - set(p)
        if unknown:
            raise ValueError(f"effects[{name!r}]: unknown parameter(s) {sorted(unknown)} (known: {sorted(p)})")
        p.update(par or {})
        for k, v in p.items():
            validate.non_negative(f"effects[{name!r}][{k!r}]", v)
        out[name] = p
    return out


def _unit_process(psd, dt: float, duration: float, seed: int, stream: int) -> np.ndarray:
    """A realization of unit variance of a Gaussian process with one-sided PSD ``psd``."""
    _, x = generate(psd, dt=dt, duration=duration, samples=1, seed=seed, first_sample=stream)
    return x[0] / math.sqrt(process_variance(psd, dt, duration))


def synthetic_record(effects=(), *, duration_s: float = 12.0, seed: int = 0, fs_hz: float = 500.0,
                     noise: float = 1.0, settle_s: float = 6.0, wob_std: float = 0.14, wob_band_hz: float = 4.0,
                     nuisance: bool = True, config: dict | None = None) -> Record:
    """A record of the rig with ``effects`` switched on, plus white measurement noise.

    Parameters
    ----------
    effects : iterable of names or dict name -> parameters
        Effects of :data:`EFFECTS` (parameters default to :data:`DEFAULTS`).
    duration_s : float
        Length of the record [s] (after ``settle_s`` of simulation are dropped).
    seed : int
        Seed of the truth's draws and of the WOB, eta and noise realizations.
    fs_hz : float
        Sampling rate of the record [Hz] (the engine's step must divide 1 / fs_hz).
    noise : float
        Multiplier of the noise standard deviations :data:`NOISE` (0: noise free).
    settle_s : float
        Simulated time dropped at the start [s]: the truth starts at rest and settles into its
        stick-slip before the record begins (the record's time starts at 0).
    wob_std, wob_band_hz : float
        Relative standard deviation of the recorded WOB and its band [Hz].
    nuisance : bool
        Simulate a truth away from the declared model (:func:`truth_config`); False: the declared
        model itself (only to check that a model predicts its own records).
    config : dict, optional
        The truth's configuration (overrides ``nuisance``).

    Returns
    -------
    Record
        SI channels; ``provenance["synthetic"]`` holds the effects, their parameters, the truth's
        draws and the seed.
    """
    eff = _check_effects(effects)
    validate.non_negative("noise", noise)
    for name, val in (("duration_s", duration_s), ("fs_hz", fs_hz), ("wob_band_hz", wob_band_hz)):
        validate.positive(name, val)
    draws = {}
    if config is not None:
        cfg = Configuration.of(config)
    elif nuisance:
        cfg, draws = truth_config(seed)
        cfg = view(cfg)
    else:
        cfg = view(declared_config())
    dt_out, dt = 1.0 / fs_hz, cfg.simulation.dt_s
    stride = int(round(dt_out / dt))
    if stride < 1 or abs(stride * dt - dt_out) > 1e-9 * dt_out:
        raise ValueError(f"fs_hz = {fs_hz}: 1/fs must be a multiple of simulation.dt_s = {dt}")
    total = settle_s + duration_s
    cfg = cfg.replace({"simulation.duration_s": total, "simulation.transient_s": min(settle_s, 0.5 * total),
                       "simulation.output_stride": stride})
    w0 = float(cfg.operation.wob_n)
    sdt = 1e-3  # random inputs on the engine's series grid
    n_series = int(round((total + 1.0) / sdt))
    wob_psd = PsdTable([0.0, wob_band_hz, wob_band_hz * 1.01], [1.0, 1.0, 0.0])
    wob = w0 * (1.0 + wob_std * _unit_process(wob_psd, sdt, n_series * sdt, seed, _STREAMS["wob"])[:n_series])
    truth = Truth(cfg.to_dict(), wob, sdt, int(seed))  # a dict: the effects' inject edit it in place
    # the configuration changes first (a motor's command depends on the law and the extra torques)
    order = sorted(eff, key=lambda n: n in CATALOGUE and CATALOGUE[n].inject_last)
    for name in order:
        if name in CATALOGUE:
            CATALOGUE[name].inject(truth, eff[name])
        elif name == "top_speed_ramp":
            om = float(view(truth.cfg).operation.top_speed_rad_s)
            t = np.arange(n_series) * sdt
            truth.top = om * (1.0 + eff[name]["ramp_fraction"] * (t / total - 0.5))
    cfg = Configuration.from_dict(truth.cfg)
    res = simulate(cfg, wob_series=truth.wob_law, eta_series=truth.eta, top_speed_series=truth.top,
                   series_dt=sdt, start="rest")
    keep = res.t >= settle_s - 1e-12
    t = res.t[keep] - settle_s
    vb = res.bit_speed[keep]
    c_v = cfg.operation.get("bit_viscous_nms", 0.0)
    tq = res.torque_on_bit[keep] - c_v * vb  # the load cell sees the contact torque
    w = np.interp(res.t[keep], np.arange(wob.size) * sdt, wob)
    axial = cfg.get("axial")
    if axial is not None and axial.get("type") == "jack":  # the load cells read the jack's WOB state
        w = res.wob[keep]
    chans = {"bit_speed": vb, "top_speed": res.top_speed[keep], "torque_on_bit": tq, "wob": w}
    for f in truth.post:
        chans = f(chans, fs_hz)
    if noise > 0:
        n = t.size
        for k, sd in NOISE.items():
            white = PsdTable([0.0, 0.5 * fs_hz], [1.0, 1.0])
            stream = _STREAMS["wob_noise" if k == "wob" else k]
            chans[k] = chans[k] + noise * sd * _unit_process(white, dt_out, n * dt_out, seed, stream)[:n]
    info = {"effects": eff, "seed": int(seed), "noise": float(noise), "fs_hz": float(fs_hz),
            "duration_s": float(duration_s), "wob_std": float(wob_std), "truth": draws, "config": cfg.to_dict()}
    return Record(time_s=t, **chans, units={"time": "s", "bit_speed": "rad_s", "top_speed": "rad_s",
                                            "torque_on_bit": "Nm", "wob": "N"},
                  provenance={"source": f"synthetic (seed {seed}; effects: {', '.join(eff) or 'none'})",
                              "format": "drillpy.records.synthetic", "synthetic": info})
