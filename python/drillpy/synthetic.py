"""Synthetic records of the test rig with chosen effects of the loop's catalogue switched on.

:func:`synthetic_record` simulates the ``thesis-rig`` model (Table 5.1, one mode at 2.89 Hz) with
the law of the preset made reversible (beta1 = 0: the *declared* model of :func:`declared_config`)
and switches on any subset of the effects of :mod:`drillpy.effects`, then adds measurement noise:

======================= =============================================================================
effect                  what the simulated "truth" has (parameters, defaults in :data:`DEFAULTS`)
======================= =============================================================================
``bit_hysteresis``      the law's acceleration term, Eq. (3.3): ``beta1`` [-], ``beta2`` [s/RPM]
``wob_coupling``        torque following the recorded WOB, T = T_law (1 + ``gain`` (W(t) / W_0 - 1))
``top_drive_dynamics``  an open-loop motor with droop: ``slope_nms_rad`` c_m, ``inertia_kg_m2`` J_m,
                        commanded so that its mean speed stays near the preset's 80.9 RPM
``sensor_lag``          every recorded channel through a second-order Butterworth at ``lowpass_hz``
``torque_fluctuation``  T = T_law (1 + eta(t)), eta Gaussian with the PSD shape of Eq. (4.4), flat up
                        to ``f0_hz`` and falling as f^-3.13 above, standard deviation ``std``
``viscous_damping``     a viscous torque ``bit_viscous_nms`` v on the bit that the torque sensor (under
                        the rock holder) does not see
======================= =============================================================================

The recorded WOB always fluctuates (``wob_std`` relative, band-limited to ``wob_band_hz``), with or
without the coupling, so that a loop must tell whether the torque follows it. All random numbers
(WOB, eta, noise) come from the engine's counter-based generator keyed by the seed
(:func:`drillpy.process.generate`): the same seed gives the same record on any machine.
"""
from __future__ import annotations

import copy
import math

import numpy as np

from .config import load_config, normalize
from .process import PsdModel, PsdTable, generate, process_variance
from .records import Record
from .signals import rig_lowpass
from .simulation import simulate

EFFECTS = ("bit_hysteresis", "wob_coupling", "top_drive_dynamics", "sensor_lag", "torque_fluctuation",
           "viscous_damping")

#: Parameters of each effect when switched on without values.
DEFAULTS = {
    "bit_hysteresis": {"beta1": 0.2, "beta2": 0.005},
    "wob_coupling": {"gain": 1.0},
    "top_drive_dynamics": {"slope_nms_rad": 0.25, "inertia_kg_m2": 0.02},
    "sensor_lag": {"lowpass_hz": 10.0},
    "torque_fluctuation": {"std": 0.15, "f0_hz": 0.25},
    "viscous_damping": {"bit_viscous_nms": 0.03},
}
#: Standard deviations of the white measurement noise (scaled by ``noise``).
NOISE = {"bit_speed": 0.05, "top_speed": 0.05, "torque_on_bit": 0.02, "wob": 2.0}
#: Streams of the generator (sample indices of drillpy.process.generate).
_STREAMS = {"wob": 0, "eta": 1, "bit_speed": 2, "top_speed": 3, "torque_on_bit": 4, "wob_noise": 5}


#: Modal damping ratio of the synthetic rig. The preset's 0.25 is an effective value that lumps the
#: dissipation the loop is meant to find (the motor's droop, water drag) and sits at the stability
#: edge: with a motor top drive it no longer stick-slips. At 0.05 the rig stick-slips with every
#: effect of the catalogue switched on.
DAMPING_RATIO = 0.05


def declared_config(preset: str = "thesis-rig", damping_ratio: float = DAMPING_RATIO) -> dict:
    """The declared model of the synthetic records: the preset with a reversible law (beta1 = 0),
    modal damping ``damping_ratio``, an ideal top drive, ideal sensors and no extra damping."""
    cfg = copy.deepcopy(load_config(preset=preset))
    cfg["damping"] = {"type": "modal", "ratios": [float(damping_ratio)]}
    if "beta1" in cfg["law"]:
        cfg["law"]["beta1"] = 0.0
    cfg["operation"]["bit_viscous_nms"] = 0.0
    cfg.pop("top_drive", None)
    cfg.pop("sensors", None)
    return normalize(cfg)


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
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
                raise ValueError(f"effects[{name!r}][{k!r}] = {v!r}: must be a finite non-negative number")
        out[name] = p
    return out


def _unit_process(psd, dt: float, duration: float, seed: int, stream: int) -> np.ndarray:
    """A realization of unit variance of a Gaussian process with one-sided PSD ``psd``."""
    _, x = generate(psd, dt=dt, duration=duration, samples=1, seed=seed, first_sample=stream)
    return x[0] / math.sqrt(process_variance(psd, dt, duration))


def synthetic_record(effects=(), *, duration_s: float = 12.0, seed: int = 0, fs_hz: float = 500.0,
                     noise: float = 1.0, settle_s: float = 3.0, wob_std: float = 0.1, wob_band_hz: float = 4.0,
                     config: dict | None = None) -> Record:
    """A record of the rig model with ``effects`` switched on, plus white measurement noise.

    Parameters
    ----------
    effects : iterable of names or dict name -> parameters
        Effects of :data:`EFFECTS` (parameters default to :data:`DEFAULTS`).
    duration_s : float
        Length of the record [s] (after ``settle_s`` of simulation are dropped).
    seed : int
        Seed of the WOB, eta and noise realizations.
    fs_hz : float
        Sampling rate of the record [Hz] (the engine's step must divide 1 / fs_hz).
    noise : float
        Multiplier of the noise standard deviations :data:`NOISE` (0: noise free).
    wob_std, wob_band_hz : float
        Relative standard deviation of the recorded WOB and its band [Hz].
    config : dict, optional
        Declared model to start from (default :func:`declared_config`).

    Returns
    -------
    Record
        SI channels; ``provenance["synthetic"]`` holds the effects, their parameters and the seed.
    """
    eff = _check_effects(effects)
    if not (isinstance(noise, (int, float)) and noise >= 0 and math.isfinite(noise)):
        raise ValueError(f"noise = {noise!r}: must be a finite non-negative number")
    for name, val in (("duration_s", duration_s), ("fs_hz", fs_hz), ("wob_band_hz", wob_band_hz)):
        if not (isinstance(val, (int, float)) and math.isfinite(val) and val > 0):
            raise ValueError(f"{name} = {val!r}: must be a positive number")
    cfg = copy.deepcopy(config if config is not None else declared_config())
    dt_out = 1.0 / fs_hz
    stride = int(round(dt_out / cfg["simulation"]["dt_s"]))
    if stride < 1 or abs(stride * cfg["simulation"]["dt_s"] - dt_out) > 1e-9 * dt_out:
        raise ValueError(f"fs_hz = {fs_hz}: 1/fs must be a multiple of simulation.dt_s = {cfg['simulation']['dt_s']}")
    total = settle_s + duration_s
    cfg["simulation"].update({"duration_s": total, "transient_s": min(settle_s, 0.5 * total), "output_stride": stride})
    w0 = float(cfg["operation"]["wob_n"])
    om0 = float(cfg["operation"]["top_speed_rad_s"])
    if "bit_hysteresis" in eff:
        if "beta1" not in cfg["law"]:
            raise ValueError(f"bit_hysteresis: the law {cfg['law']['type']!r} has no hysteresis term")
        cfg["law"]["beta1"] = eff["bit_hysteresis"]["beta1"]
        cfg["law"]["beta2"] = eff["bit_hysteresis"]["beta2"]
    c_v = eff.get("viscous_damping", {}).get("bit_viscous_nms", 0.0)
    cfg["operation"]["bit_viscous_nms"] = c_v
    if "top_drive_dynamics" in eff:
        p = eff["top_drive_dynamics"]
        cfg["top_drive"] = {"type": "motor", "slope_nms_rad": p["slope_nms_rad"], "inertia_kg_m2": p["inertia_kg_m2"]}
        from .simulation import law_torque
        t_mean = float(law_torque(cfg["law"], om0, 0.0, w0)[0]) + c_v * om0
        cfg["operation"]["top_speed_rad_s"] = om0 + t_mean / p["slope_nms_rad"]  # command above the mean by the droop
    cfg = normalize(cfg)
    # random inputs on the engine's series grid (1 ms)
    sdt = 1e-3
    wob_psd = PsdTable([0.0, wob_band_hz, wob_band_hz * 1.01], [1.0, 1.0, 0.0])
    wob = w0 * (1.0 + wob_std * _unit_process(wob_psd, sdt, total + 1.0, seed, _STREAMS["wob"]))
    eta = None
    if "torque_fluctuation" in eff:
        p = eff["torque_fluctuation"]
        f0 = p["f0_hz"]
        psd = PsdModel(f0=f0, A0=0.0, a=-3.13, b=3.13 * math.log(f0))  # Eq. (4.4) shape, continuous at f0
        eta = p["std"] * _unit_process(psd, sdt, total + 1.0, seed, _STREAMS["eta"])
    wob_law = None
    if "wob_coupling" in eff:  # the law's input: W_0 (1 + k (W / W_0 - 1)), proportional for k = 1
        wob_law = w0 * (1.0 + eff["wob_coupling"]["gain"] * (wob / w0 - 1.0))
    res = simulate(cfg, wob_series=wob_law, eta_series=eta, series_dt=sdt, start="steady")
    keep = res.t >= settle_s - 1e-12
    t = res.t[keep] - settle_s
    vb, top = res.bit_speed[keep], res.top_speed[keep]
    tq = res.torque_on_bit[keep] - c_v * res.bit_speed[keep]  # the load cell sees the contact torque
    w = np.interp(res.t[keep], np.arange(wob.size) * sdt, wob)
    chans = {"bit_speed": vb, "top_speed": top, "torque_on_bit": tq, "wob": w}
    if "sensor_lag" in eff:
        fc = eff["sensor_lag"]["lowpass_hz"]
        chans = {k: rig_lowpass(x, fs_hz, cutoff_hz=fc) for k, x in chans.items()}
    if noise > 0:
        n = t.size
        for k, sd in NOISE.items():
            white = PsdTable([0.0, 0.5 * fs_hz], [1.0, 1.0])
            stream = _STREAMS["wob_noise" if k == "wob" else k]
            chans[k] = chans[k] + noise * sd * _unit_process(white, dt_out, n * dt_out, seed, stream)[:n]
    truth = {"effects": eff, "seed": int(seed), "noise": float(noise), "fs_hz": float(fs_hz),
             "duration_s": float(duration_s), "wob_std": float(wob_std), "config": cfg}
    return Record(time_s=t, **chans, units={"time": "s", "bit_speed": "rad_s", "top_speed": "rad_s",
                                            "torque_on_bit": "Nm", "wob": "N"},
                  provenance={"source": f"synthetic (seed {seed}; effects: {', '.join(eff) or 'none'})",
                              "format": "drillpy.synthetic", "synthetic": truth})
