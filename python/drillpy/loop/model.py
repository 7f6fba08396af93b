"""A calibrated loop model (:class:`LoopModel`) and its short-horizon predictions.

The model is the declared configuration with every catalogue effect stripped (``cfg``), its
calibrated law, modal damping ratios and operating point, and the effects it has (declared or
added) with their parameters. :func:`predict` restarts it every horizon from the state read off
the record (``Integrator::state_from_bit``, exact for the rig's one mode) and integrates the next
horizon with the engine (``drill/horizons.hpp``); :func:`evaluate` scores the predictions with the
metric E of docs/loop.md.
"""
from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field

import numpy as np

from drillpy import _core
from drillpy.records import identification as ident
from drillpy.records.bit_balance import string_of, timing_of
from drillpy.model.config import engine_config
from .data import LoopData, measured
from .effects import CATALOGUE
from .side_by_side import engine_threads
from .view import view

#: The catalogue's effect that carries a GJ beyond the declared geometry's tolerance.
STIFFNESS = "string_stiffness"


@dataclass
class LoopModel:
    """A calibrated model: the declared configuration without the catalogue's effects, its
    calibrated law, modal damping ratios and operating point, and its effects (SI parameters).

    Attributes
    ----------
    cfg : dict
        The declared engine configuration with every catalogue effect stripped
        (:func:`drillpy.loop.effects.stripped`): string geometry, reduced-order model, damping
        (the calibrated modal ratios in its ``damping.ratios``), law family, operation and
        simulation settings at the loop's engine step.
    law : dict
        The calibrated bit-rock law (engine ``law`` section: ``type``, ``speed_unit`` and its
        coefficients, in the law's own speed unit), with the hysteresis term when
        ``bit_hysteresis`` is an effect.
    top_speed : float
        Constant top speed of the ideal drive [rad/s]: the calibration part's mean recorded top
        speed (the declared one without a top-speed channel).
    wob : float
        WOB W_0 at which the law is evaluated [N]: the calibration part's mean recorded WOB (the
        declared one without a WOB channel).
    effects : dict
        Effect name -> parameter dict (name -> value in the parameter's unit), declared or added.
    n_law : int
        Free parameters of the law (the hysteresis term and the WOB gain counted with their
        effects).
    damping_held : bool
        True: the modal damping ratios are set by the limit cycle, not fitted
        (``damping_hold.hold_damping``); they then do not count in :attr:`k`.
    gj_tolerance : float
        Relative tolerance of the declared GJ (``LoopOptions.gj_tolerance``): the string's GJ is
        calibrated within 1 +- it while ``string_stiffness`` is not an effect; 0: held as declared.
    gj_factor : float
        The calibrated GJ over the declared GJ, within the tolerance (1 when held or when
        ``string_stiffness``, which then carries the whole factor, is an effect).
    intervals : dict
        The last calibration's 95 % intervals of the effects' parameters (effect -> parameter ->
        ``{"value", "ci95", "at_bound"}``; :func:`drillpy.loop.fitting.fit_dynamic`).
    wob_input : str
        The law's WOB channel: ``"measured"`` (the recorded WOB) or ``"trend"`` (its 0.5 Hz trend,
        where the record showed the WOB is a response of the rotation; ``LoopOptions.wob_input``).
    wob_is_response : bool
        The calibration record's WOB was a response of the rotation
        (:func:`drillpy.loop.data.wob_response`).
    metric_scale : tuple or None
        (sd_v [rad/s], sd_T [N m]) of the calibration part (``LoopData.sigma_v``, ``sigma_T``): the
        scale of the metric E, kept in ``model.json`` so that ``drillpy predict`` scores any record
        on it (None: a model file without it; the record's own spreads are taken).
    fluctuation : dict or None
        The bit-rock torque fluctuation of Eq. (4.1) its long runs carry, identified on the
        calibration part (:func:`drillpy.records.rig_fluctuation.of_record`; ``LoopOptions.long_run_fluctuation``),
        kept in ``model.json``; None: the long runs are the law's alone. The short-horizon
        predictions never take it.
    channel_timing : dict or None
        The channels' timing the calibration read its record at (``top_lead_s``, ``torque_lag_s`` [s]
        and ``from``, ``LoopData.channel_timing``: the acquisition's skew, identified on the
        calibration part or given), kept in ``model.json`` so that ``drillpy predict`` reads any
        record it scores at the same timing; None: as recorded.
    """
    cfg: dict
    law: dict
    top_speed: float  #: constant top speed of the ideal drive [rad/s]
    wob: float        #: WOB W_0 at which the law is evaluated [N]
    effects: dict = field(default_factory=dict)
    n_law: int = 0    #: free parameters of the law
    damping_held: bool = False  #: the damping ratios are set by the limit cycle, not fitted (damping_hold.hold_damping)
    gj_tolerance: float = 0.0   #: relative tolerance of the declared GJ, within which it is calibrated
    gj_factor: float = 1.0      #: calibrated GJ over the declared GJ (within the tolerance)
    intervals: dict = field(default_factory=dict)  #: 95 % intervals of the effects' parameters
    wob_input: str = "measured"  #: the law's WOB channel: the recorded WOB or its trend
    wob_is_response: bool = False  #: the calibration record's WOB responded to the rotation
    metric_scale: tuple | None = None  #: (sd_v, sd_T) of the calibration part: the scale of E
    fluctuation: dict | None = None  #: Eq. (4.1)'s process of the long runs (rig_fluctuation.identify)
    channel_timing: dict | None = None  #: the acquisition's skew the calibration read its record at (None: as recorded)

    @property
    def predictive(self) -> bool:
        """True when the model takes from a record only what is known beforehand: no top speed fed
        from the record (the kinematic drive) and no recorded WOB fed to the law where that WOB is a
        response of the rotation (it then carries the stick-slip cycle)."""
        if any(CATALOGUE[n].feeds_cycle(p) for n, p in self.effects.items()):
            return False
        feeds = any(CATALOGUE[n].wob_input(p, self, np.zeros(1)) is not None for n, p in self.effects.items())
        return not (self.wob_is_response and self.wob_input == "measured" and feeds)

    def copy(self) -> "LoopModel":
        """A deep copy (configuration, law and effects' parameter dicts included)."""
        return copy.deepcopy(self)

    @property
    def damping_ratios(self) -> list | None:
        """Modal damping ratios (calibrated), or None for Rayleigh damping (held as declared)."""
        d = view(self.cfg).damping
        return list(d.ratios) if d.type == "modal" else None

    @property
    def gj_free(self) -> bool:
        """True when the GJ is calibrated within its tolerance (a tolerance, and no ``string_stiffness``)."""
        return self.gj_tolerance > 0 and STIFFNESS not in self.effects

    @property
    def k(self) -> int:
        """Number of calibrated parameters (law, damping ratios, GJ within its tolerance, effects)."""
        return (self.n_law + (0 if self.damping_held else len(self.damping_ratios or ())) + int(self.gj_free)
                + sum(CATALOGUE[n].count(p) for n, p in self.effects.items()))

    def engine_config(self) -> dict:
        """The engine configuration of the model, every effect applied (a new dict; the model's
        configuration is not modified).

        A dict edited in place, not :meth:`Configuration.replace <drillpy.model.configuration.Configuration.replace>`:
        the calibration builds one per trial, straight into ``_core.Config.from_dict``; one tree copy
        (:func:`_copy_tree`) and the effects' in-place :meth:`~drillpy.loop.effects.base.Effect.configure`
        cost no schema lookup and no second copy."""
        c = _copy_tree(self.cfg)
        c["law"] = dict(self.law)
        c["operation"]["wob_n"] = float(self.wob)
        c["operation"]["top_speed_rad_s"] = float(self.top_speed)
        if self.gj_factor != 1.0:
            CATALOGUE[STIFFNESS].configure(c, {"gj_factor": self.gj_factor}, self)
        for name, p in self.effects.items():
            CATALOGUE[name].configure(c, p, self)
        return c

    def parameters(self) -> dict:
        """The model's parameters for ``loop.json`` (SI; the law in its own speed unit)."""
        return {"law": dict(self.law), "top_speed_rad_s": self.top_speed, "wob_n": self.wob,
                "damping": view(self.cfg).damping.to_dict(), "gj_factor": self.gj_factor, "effects": copy.deepcopy(self.effects)}

    def to_dict(self) -> dict:
        """``model.json``: the engine configuration with every effect applied, the effects and the
        operating point (read back by :meth:`from_dict` and by ``drillpy predict``)."""
        return {"format": "drillpy.loop_model", "version": 1, "predictive": self.predictive,
                "inputs": {"top_speed": "the record's mean top speed (ideal drive) or the motor's command",
                           "wob": "the record's WOB trend below 0.5 Hz (a response of the rotation)"
                           if self.wob_input == "trend" else "the recorded WOB (an input)"},
                "config": self.engine_config(),
                "base_config": self.cfg, "law": self.law, "top_speed_rad_s": self.top_speed, "wob_n": self.wob,
                "effects": self.effects, "intervals": self.intervals, "n_law": self.n_law,
                "damping_held": self.damping_held, "gj_tolerance": self.gj_tolerance, "gj_factor": self.gj_factor,
                "wob_input": self.wob_input, "wob_is_response": self.wob_is_response,
                "metric_scale": None if self.metric_scale is None else
                {"bit_speed_rad_s": self.metric_scale[0], "torque_on_bit_nm": self.metric_scale[1],
                 "from": "the calibration part's spreads, stalls left out: E of drillpy predict is on this scale"},
                "long_run_fluctuation": self.fluctuation, "channel_timing": self.channel_timing}

    @classmethod
    def from_dict(cls, d: dict) -> "LoopModel":
        """Read a model back from the dict of ``model.json`` (:meth:`to_dict`).

        Parameters
        ----------
        d : dict
            ``{"format": "drillpy.loop_model", "base_config", "law", "top_speed_rad_s" [rad/s],
            "wob_n" [N], "effects", "n_law", "damping_held", "gj_tolerance" and "gj_factor" (these
            four optional), ...}``.

        Returns
        -------
        LoopModel
            The model; its engine configuration is rebuilt from ``base_config`` and the effects.

        Raises
        ------
        ValueError
            Not a loop model, an effect outside the catalogue, or a missing key.
        """
        if not isinstance(d, dict) or d.get("format") != "drillpy.loop_model":
            raise ValueError("model: not a drillpy loop model (format must be 'drillpy.loop_model')")
        try:
            eff = d["effects"]
            unknown = set(eff) - set(CATALOGUE)
            if unknown:
                raise ValueError(f"model: effects {sorted(unknown)} are not in the catalogue")
            return cls(d["base_config"], d["law"], float(d["top_speed_rad_s"]), float(d["wob_n"]), eff,
                       int(d.get("n_law", 0)), bool(d.get("damping_held", False)),
                       float(d.get("gj_tolerance", 0.0)), float(d.get("gj_factor", 1.0)),
                       dict(d.get("intervals", {})), str(d.get("wob_input", "measured")),
                       bool(d.get("wob_is_response", False)), _scale(d.get("metric_scale")),
                       d.get("long_run_fluctuation"), timing_of(d.get("channel_timing")))
        except KeyError as e:
            raise ValueError(f"model: lacks {e}") from None


def _copy_tree(x):
    """A copy of a configuration's dicts and lists, their leaves (numbers, strings) shared: what
    ``copy.deepcopy`` gives a JSON-like configuration, without its memo (a tenth of its time)."""
    if isinstance(x, dict):
        return {k: _copy_tree(v) for k, v in x.items()}
    if isinstance(x, list):
        return [_copy_tree(v) for v in x]
    return x


def simulation(cfg: dict, check: bool = True) -> "_core.Simulation":
    """The engine's Simulation of a configuration (built in about a millisecond for the rig's
    model, negligible beside the predictions it serves).

    Parameters
    ----------
    cfg : dict
        A complete engine configuration (e.g. :meth:`LoopModel.engine_config`).
    check : bool
        True: through :func:`drillpy.model.config.engine_config` (its plausibility warnings, the
        JSON text); False: the dict straight into the engine (``_core.Config.from_dict``, the same
        Config without the warnings), for the calibration's trials, whose plausibility the loop
        judges by the parameters' bounds (:func:`drillpy.loop.run.run_loop` silences the warnings).

    Returns
    -------
    drillpy._core.Simulation
        The engine's model of the configuration.
    """
    return _core.Simulation(engine_config(cfg) if check else _core.Config.from_dict(cfg))


def motor_inertia_floor(model: LoopModel) -> float:
    """Smallest motor inertia [kg m^2] for which the engine's modified-Euler bound with the motor
    (Eq. A.7, ``Simulation.motor_stability_bound``) admits the engine step: bisection in ln J.

    Parameters
    ----------
    model : LoopModel
        The model (its string, law, operating point and engine step ``simulation.dt_s`` [s]); its
        own top drive, if any, is ignored.

    Returns
    -------
    float
        The inertia J_m [kg m^2] between 1e-12 and 10 (60 bisections in ln J) at which the bound
        meets the step; 1e-12 when even that admits it.
    """
    dt = view(model.cfg).simulation.dt_s
    c = model.engine_config()
    c.pop("top_drive", None)
    sim = simulation(c)
    lo, hi = math.log(1e-12), math.log(10.0)
    if sim.motor_stability_bound(math.exp(lo)) >= dt:
        return math.exp(lo)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if sim.motor_stability_bound(math.exp(mid)) >= dt else (mid, hi)
    return math.exp(hi)


def sensor_delay(model: LoopModel) -> float:
    """Delay of the recorded channels behind the model's state [s] (its sensors; 0 without).

    Parameters
    ----------
    model : LoopModel
        The model; the delays of its effects (:meth:`~drillpy.loop.effects.base.Effect.delay_s`)
        add.

    Returns
    -------
    float
        The delay tau [s] (sqrt(2) / omega_c for a second-order Butterworth sensor).
    """
    return sum(CATALOGUE[n].delay_s(p) for n, p in model.effects.items())


def torque_sensor(model: LoopModel) -> tuple:
    """(s, b) of the torque channel: recorded torque T_rec = s T + b, T the true torque on bit.

    Parameters
    ----------
    model : LoopModel
        The model; its effects' :meth:`~drillpy.loop.effects.base.Effect.torque_sensor` compose
        (s1 (s2 T + b2) + b1).

    Returns
    -------
    tuple of float
        Scale s [-] and offset b [N m]; (1, 0) without a calibration effect (``sensor_gain``).
    """
    s, b = 1.0, 0.0
    for n, p in model.effects.items():
        si, bi = CATALOGUE[n].torque_sensor(p)
        s, b = si * s, si * b + bi
    return s, b


def true_torque(model: LoopModel, x, rate: bool = False) -> np.ndarray:
    """The true torque on bit (T_rec - b) / s [N m] of a recorded torque under the model's
    torque-channel calibration (:func:`torque_sensor`; SG.0 of docs/loop.md).

    Parameters
    ----------
    model : LoopModel
        The model (its ``sensor_gain``, if any).
    x : array_like
        Recorded torque T_rec [N m], or one of its time derivatives with ``rate``.
    rate : bool
        ``x`` is a derivative of the recorded torque: only the scale applies, x / s.

    Returns
    -------
    numpy.ndarray
        The true torque [N m] (or its derivative).
    """
    s, b = torque_sensor(model)
    x = np.asarray(x, float)
    return x / s if rate else (x - b) / s


def _wob_input(model: LoopModel, w, n: int, recorded=None) -> np.ndarray:
    """The WOB the law takes at each sample [N]: the recorded WOB ``recorded`` where an effect makes
    the WOB a state (``Effect.wob_state``: the law then sees the state, which the load cells record),
    else the first effect's ``wob_input`` of the law's WOB channel ``w``, else the constant W_0."""
    if recorded is not None and any(CATALOGUE[n_].wob_state for n_ in model.effects):
        return np.asarray(recorded, float)
    for name, p in model.effects.items():
        x = CATALOGUE[name].wob_input(p, model, w)
        if x is not None:
            return x
    return np.full(n, model.wob)


def state_channels(model: LoopModel, data: LoopData) -> dict:
    """The channels as the model's state sees them at each sample: bit speed ``v``, acceleration
    ``a``, torque ``T``, top speed ``top`` and its rate ``dtop``, WOB ``W`` and the law's WOB input
    ``W_eff``. With sensors the recorded channels lag the model's by about the filter's group delay
    tau: the model at time t is read off the record at t + tau (causal for a restart placed tau
    before the horizon: :func:`predict`).

    Parameters
    ----------
    model : LoopModel
        The model (its sensors' delay and the law's WOB input).
    data : LoopData
        The record on the analysis grid.

    Returns
    -------
    dict
        Arrays on the analysis grid: ``v`` [rad/s], ``a`` [rad/s^2], ``T`` [N m]; with a top-speed
        channel ``top`` [rad/s] and ``dtop`` [rad/s^2]; with a WOB channel ``W`` [N]; always
        ``W_eff`` [N] (the constant W_0 unless an effect such as ``wob_coupling`` maps the recorded
        WOB).
    """
    ch, t = data.ch, data.t
    tau = sensor_delay(model)

    def at(k):
        return np.interp(t + tau, t, ch[k]) if tau > 0 else ch[k]

    out = {"v": at("v"), "a": at("v1"), "T": true_torque(model, at("T"))}
    if data.has_top:
        out["top"], out["dtop"] = at("top"), at("top1")
    w = at("W") if data.has_wob else None
    if w is not None:
        out["W"] = w
    rec = (np.interp(t + tau, t, data.wob_measured) if tau > 0 else data.wob_measured) \
        if data.wob_measured is not None else w
    out["W_eff"] = _wob_input(model, w, t.size, rec)
    return out


def law_channels(model: LoopModel, data: LoopData) -> dict:
    """The channels for the law residual (simultaneous v, a, T, W): a second-order measurement chain
    is undone, x = y + c1 y' + c2 y'' (c1 = sqrt(2)/omega_c, c2 = 1/omega_c^2).

    Parameters
    ----------
    model : LoopModel
        The model (the measurement chains of its effects,
        :meth:`~drillpy.loop.effects.base.Effect.undo`, and the law's WOB input).
    data : LoopData
        The record on the analysis grid (the Savitzky-Golay derivatives ``ch``).

    Returns
    -------
    dict
        Arrays on the analysis grid: ``v`` [rad/s], ``a`` [rad/s^2], ``T`` [N m], ``W`` [N] (with a
        WOB channel) and ``W_eff`` [N], the law's WOB input.
    """
    ch = data.ch
    c1 = c2 = 0.0
    for name, p in model.effects.items():
        u1, u2 = CATALOGUE[name].undo(p)
        c1, c2 = c1 + u1, c2 + u2

    def undo(k):
        return ch[k] + c1 * ch[k + "1"] + c2 * ch[k + "2"]

    out = {"v": undo("v"), "a": ch["v1"] + c1 * ch["v2"] + c2 * ch["v3"], "T": true_torque(model, undo("T"))}
    w = undo("W") if data.has_wob else None
    if w is not None:
        out["W"] = w
    out["W_eff"] = _wob_input(model, w, data.t.size, data.wob_measured if data.wob_measured is not None else w)
    return out


def law_torque(model: LoopModel, chs: dict, index=None) -> np.ndarray:
    """The model's law T_law(v, a, W_eff) [N m] at the state channels (engine evaluation).

    Parameters
    ----------
    model : LoopModel
        The model (its calibrated ``law``).
    chs : dict
        Channels with ``v`` [rad/s], ``a`` [rad/s^2] and ``W_eff`` [N]
        (:func:`state_channels` or :func:`law_channels`).
    index : array_like of int or slice, optional
        Samples to evaluate (default: all).

    Returns
    -------
    numpy.ndarray
        The law's torque on bit [N m] at those samples.
    """
    sl = slice(None) if index is None else index
    return ident.law_eval(model.law, chs["v"][sl], chs["a"][sl], chs["W_eff"][sl])[0]


def predict(model: LoopModel, data: LoopData, horizons=None, threads: int = 0, top: bool = False,
            check: bool = True, wob: bool = False) -> tuple:
    """Predicted bit speed [rad/s] and torque on bit [N m] (and top speed [rad/s] with ``top``) of
    the horizons (rows; default all), after the model's sensors.

    Each horizon restarts D = ceil(tau / dt) samples before its first sample (tau: the sensors'
    delay, 0 without them) from the state read off the record (:func:`state_channels`), with the
    sensors' filters started from the recorded values and rates at the restart.

    The effects act through their prediction hooks: the top boundary
    (:meth:`~drillpy.loop.effects.base.Effect.top_state`; otherwise the ideal drive at
    ``model.top_speed``), the law's WOB series (``wob_input``), the torque fluctuation's forecast
    (``eta``), the restart torque's correction (``restart_torque``) and the WOB state of an axial
    model (``restart_wob``). The horizons are integrated in parallel by the engine
    (``_core.predict_horizons``).

    Parameters
    ----------
    model : LoopModel
        The model to predict with.
    data : LoopData
        The record on the analysis grid.
    horizons : array_like of int, optional
        Horizon indices (default: every horizon).
    threads : int
        Engine threads (0: OpenMP default).
    top : bool
        Also return the predicted top speed.
    check : bool
        The configuration's plausibility warnings (:func:`simulation`; False: the calibration's trials).
    wob : bool
        Also return the predicted WOB [N] (last): the axial jack's state, restarted from the recorded
        WOB and its rate, or the law's WOB input, after the sensors.

    Returns
    -------
    tuple of numpy.ndarray
        (bit speed [rad/s], torque on bit [N m]), with ``top`` the top speed [rad/s] after them and
        with ``wob`` the WOB [N] last, each of shape (horizons, L), aligned with
        :func:`drillpy.loop.data.measured`.
    """
    job = _horizon_job(model, data, horizons, check)
    # the batched SIMD integrator unless the options ask for the scalar reference one (LoopOptions.batched)
    r = _core.predict_horizons(job.sim, job.starts, data.dt, job.samples, top_speed=job.top_speed, wob=job.wob,
                               eta=job.eta, threads=engine_threads(threads), batched=data.batched)
    return job.outputs(r, top, wob)


@dataclass
class _HorizonJob:
    """One model's engine call of :func:`predict`: its Simulation, restarts and input series, and
    what turns the engine's output into the recorded channels (the restart lead D, the torque sensor)."""
    sim: object
    starts: list
    samples: int
    top_speed: np.ndarray | None
    wob: np.ndarray | None
    eta: np.ndarray | None
    D: int
    gain: float
    offset: float

    def outputs(self, r, top: bool, wob: bool = False) -> tuple:
        """(bit speed, torque[, top speed][, WOB]) of the engine's HorizonResult ``r``, after the model's sensors."""
        D = self.D
        T = self.gain * r.torque[:, D:] + self.offset if (self.gain, self.offset) != (1.0, 0.0) else r.torque[:, D:]
        return (r.bit_speed[:, D:], T) + ((r.top_speed[:, D:],) if top else ()) + ((r.wob[:, D:],) if wob else ())


def _horizon_job(model: LoopModel, data: LoopData, horizons=None, check: bool = True) -> _HorizonJob:
    """The engine call of :func:`predict` for a model (see there); ``check``: as :func:`simulation`'s."""
    h = np.arange(data.starts.size) if horizons is None else np.asarray(horizons)
    D = int(math.ceil(sensor_delay(model) / data.dt - 1e-9))
    idx = data.starts[h] - D
    sim = simulation(model.engine_config(), check)
    chs = state_channels(model, data)
    ch = data.ch
    n = idx.size
    om, dom, top_series = np.full(n, model.top_speed), np.zeros(n), None
    eta = None
    leads = np.arange(data.L + D + 1) * data.dt
    for name, p in model.effects.items():
        eff = CATALOGUE[name]
        ts = eff.top_state(p, model, chs, idx)
        if ts is not None:
            om, dom, top_series = ts
        e = eff.eta(p, model, data, chs, idx, leads)
        if e is not None:
            eta = e
    T0 = chs["T"][idx].copy()
    for name, p in model.effects.items():
        dT = CATALOGUE[name].restart_torque(p, model, data, chs, idx)
        if dT is not None:
            T0 = T0 + dT
    if data.has_top:
        ytop, dytop = ch["top"][idx], ch["top1"][idx]
    else:
        ytop, dytop = om, dom
    w0 = dw0 = None
    for name, p in model.effects.items():
        x = CATALOGUE[name].restart_wob(p, model, data, chs, idx)
        if x is not None:  # the state and, for the WOB sensor's filter, the recorded rate (central difference)
            w0 = x
            dw0 = (CATALOGUE[name].restart_wob(p, model, data, chs, idx + 1)
                   - CATALOGUE[name].restart_wob(p, model, data, chs, idx - 1)) / (2.0 * data.dt)
    starts = _core.HorizonStart.from_arrays(
        index=idx.tolist(), bit_speed=chs["v"][idx], bit_accel=chs["a"][idx], torque=T0, top_speed=om, top_accel=dom,
        y_bit_speed=ch["v"][idx], dy_bit_speed=ch["v1"][idx], y_torque=true_torque(model, ch["T"][idx]),
        dy_torque=true_torque(model, ch["T1"][idx], rate=True),
        y_top_speed=ytop, dy_top_speed=dytop, wob=w0, dy_wob=dw0)
    # the law's WOB input series (an axial model's set force: never the recorded state itself)
    wob_series = _wob_input(model, chs.get("W"), data.t.size) if any(
        CATALOGUE[n].wob_input(p, model, chs.get("W")) is not None for n, p in model.effects.items()) else None
    gain, offset = torque_sensor(model)  # the torque as the load cell records it
    return _HorizonJob(sim, starts, data.L + D, top_series, wob_series, eta, D, gain, offset)


def predict_many(models, data: LoopData, horizons=None, threads: int = 0, top: bool = False, check: bool = True) -> list:
    """:func:`predict` of several models in one engine call (``_core.predict_horizons_many``: the
    horizons of every model share the threads and the SIMD batches are formed per model), each
    model's predictions bit for bit those of :func:`predict` (the engine's guarantee: a horizon's
    numbers do not depend on the horizons that share its batch or its thread).

    Parameters
    ----------
    models : sequence of LoopModel
        The models (e.g. the perturbed models of one finite-difference Jacobian).
    data : LoopData
        The record on the analysis grid.
    horizons : array_like of int, optional
        Horizon indices (default: every horizon), the same for every model.
    threads : int
        Engine threads (0: OpenMP default).
    top : bool
        Also return the predicted top speed.
    check : bool
        The configurations' plausibility warnings (:func:`simulation`).

    Returns
    -------
    list
        Per model, the tuple :func:`predict` returns, or the exception (ValueError, RuntimeError)
        :func:`predict` would raise for that model, as an object (not raised).
    """
    jobs, out = [], []
    for m in models:
        try:
            jobs.append(_horizon_job(m, data, horizons, check))
        except (ValueError, RuntimeError) as e:  # a configuration the engine refuses
            jobs.append(e)
    ok = [j for j in jobs if not isinstance(j, BaseException)]
    rs = iter(_core.predict_horizons_many(
        [j.sim for j in ok], [j.starts for j in ok], data.dt, [j.samples for j in ok],
        top_speed=[j.top_speed for j in ok], wob=[j.wob for j in ok], eta=[j.eta for j in ok], threads=engine_threads(threads),
        batched=data.batched)) if ok else iter(())
    for j in jobs:
        if isinstance(j, BaseException):
            out.append(j)
            continue
        r = next(rs)
        out.append(r if isinstance(r, BaseException) else j.outputs(r, top))
    return out


@dataclass
class Evaluation:
    """A model with its predictions of every horizon and its errors.

    Attributes
    ----------
    model : LoopModel
        The model evaluated.
    v : numpy.ndarray
        Predicted bit speed, horizons x L [rad/s].
    T : numpy.ndarray
        Predicted torque on bit, horizons x L [N m].
    top : numpy.ndarray or None
        Predicted top speed, horizons x L [rad/s] (records with a top-speed channel; else None).
    e_h : numpy.ndarray
        Per-horizon normalized mean squared error [-] (:func:`score`).
    E_train : float
        Error E on the calibration horizons [-].
    E_test : float
        Error E on the validation horizons [-] (``baseline_error``, ``error_after``... of
        ``loop.json``).
    law_rmse_train : float
        Law residual RMSE on the calibration part's slip samples [N m] (NaN without any).
    law_rmse_test : float
        Law residual RMSE on the validation part's slip samples [N m].
    channel_rmse : dict
        Validation RMSE per channel: ``bit_speed_rad_s`` [rad/s], ``torque_on_bit_nm`` [N m].
    wob : numpy.ndarray or None
        Predicted WOB, horizons x L [N] (records with a WOB channel; else None): the axial jack's
        state or the law's WOB input. E does not score it (:func:`wob_errors` does).
    """
    model: LoopModel
    v: np.ndarray          #: predicted bit speed, horizons x L [rad/s]
    T: np.ndarray          #: predicted torque on bit [N m]
    top: np.ndarray | None  #: predicted top speed [rad/s] (records with a top-speed channel)
    e_h: np.ndarray        #: per-horizon normalized mean squared error
    E_train: float
    E_test: float
    law_rmse_train: float  #: law residual RMSE on the calibration part's slip samples [N m]
    law_rmse_test: float   #: ... on the validation part's [N m]
    channel_rmse: dict     #: validation RMSE per channel: bit speed [rad/s], torque [N m]
    wob: np.ndarray | None = None  #: predicted WOB, horizons x L [N] (records with a WOB channel)


def _reference(data: LoopData, h: np.ndarray) -> tuple:
    """What :func:`channel_errors` compares predictions of the horizons ``h`` with: the recorded bit
    speed and torque, and where the top speed is a measurement with its values (None, None without)."""
    Yv, YT = measured(data, h)
    if data.has_top:
        s = data.horizon_samples[h]
        return Yv, YT, data.top_ok[s], data.top_meas[s]
    return Yv, YT, None, None


def _scale(d) -> tuple | None:
    """``metric_scale`` of a model file as (sd_v, sd_T), or None when absent."""
    if d is None:
        return None
    try:
        sv, sT = float(d["bit_speed_rad_s"]), float(d["torque_on_bit_nm"])
    except (KeyError, TypeError, ValueError):
        sv = sT = float("nan")
    if not (sv > 0 and sT > 0):
        raise ValueError(f"model: metric_scale = {d!r}: needs positive 'bit_speed_rad_s' and 'torque_on_bit_nm'")
    return sv, sT


def channel_errors(v: np.ndarray, T: np.ndarray, top, data: LoopData, horizons=None, ref=None) -> list:
    """Normalized residuals per channel of predictions (horizons x L): bit speed over sd_v, torque
    over sd_T and, with a top-speed channel, top speed over sd_v (the bit speed's spread: a top that
    turns steadily adds nothing; a drive that gives way is an error of the same scale as the bit's),
    zero where the recorded top speed is not a measurement.

    Parameters
    ----------
    v : numpy.ndarray
        Predicted bit speed [rad/s], horizons x L.
    T : numpy.ndarray
        Predicted torque on bit [N m], horizons x L.
    top : numpy.ndarray or None
        Predicted top speed [rad/s], horizons x L (read only when the record has a top speed).
    data : LoopData
        The record (its recorded channels and sd_v [rad/s], sd_T [N m]).
    horizons : array_like of int, optional
        The horizons the rows are (default: every horizon).
    ref : tuple, optional
        The recorded channels of those horizons when already at hand (several models' predictions
        of the same horizons: :func:`residual_vectors`).

    Returns
    -------
    numpy.ndarray
        (prediction - record) / spread [-], channels x horizons x L (C order): bit speed, torque
        and, with a top-speed channel, top speed.
    """
    h = np.arange(data.starts.size) if horizons is None else np.asarray(horizons)
    Yv, YT, top_ok, Ytop = _reference(data, h) if ref is None else ref
    out = np.empty((3 if data.has_top else 2, *np.shape(v)))  # one buffer, no temporaries
    for o, x, y, sd in ((out[0], v, Yv, data.sigma_v), (out[1], T, YT, data.sigma_T)):
        np.subtract(x, y, out=o)
        o /= sd
    if data.has_top:
        np.subtract(top, Ytop, out=out[2])
        out[2] /= data.sigma_v
        out[2][~top_ok] = 0.0
    return out


def score(v: np.ndarray, T: np.ndarray, data: LoopData, top=None) -> tuple:
    """Per-horizon normalized mean squared errors and (E_train, E_test) of predictions (horizons x L):
    E^2 is the mean over the channels of :func:`channel_errors` squared.

    Parameters
    ----------
    v : numpy.ndarray
        Predicted bit speed [rad/s] of every horizon, horizons x L.
    T : numpy.ndarray
        Predicted torque on bit [N m], horizons x L.
    data : LoopData
        The record (its split ``is_test`` and spreads).
    top : numpy.ndarray, optional
        Predicted top speed [rad/s], horizons x L (needed when the record has a top speed).

    Returns
    -------
    tuple
        (e_h [-] per horizon, E_train [-] over the calibration horizons, E_test [-] over the
        validation horizons), E = sqrt(mean e_h).
    """
    parts = channel_errors(v, T, top, data)
    e_h = sum(np.mean(r ** 2, axis=1) for r in parts) / len(parts)
    te = data.is_test
    return e_h, float(np.sqrt(np.mean(e_h[~te]))), float(np.sqrt(np.mean(e_h[te])))


def evaluate(model: LoopModel, data: LoopData, threads: int = 0) -> Evaluation:
    """Predict every horizon and score the predictions: E on both parts, the law residual RMSE and
    the validation RMSE per channel.

    Parameters
    ----------
    model : LoopModel
        The model to evaluate.
    data : LoopData
        The record on the analysis grid.
    threads : int
        Engine threads (0: OpenMP default).

    Returns
    -------
    Evaluation
        The model with its predictions and errors.
    """
    v, T, top, W = predict(model, data, threads=threads, top=True, wob=True)
    Yv, YT = measured(data)
    e_h, e_tr, e_te = score(v, T, data, top)
    chs = law_channels(model, data)
    lr = {}
    for key, idx in (("train", data.law_train), ("test", data.law_test)):
        r = chs["T"][idx] - law_torque(model, chs, idx) if idx.size else np.zeros(0)
        lr[key] = float(np.sqrt(np.mean(r ** 2))) if r.size else float("nan")
    te = data.is_test
    rm = {"bit_speed_rad_s": float(np.sqrt(np.mean((v[te] - Yv[te]) ** 2))),
          "torque_on_bit_nm": float(np.sqrt(np.mean((T[te] - YT[te]) ** 2)))}
    return Evaluation(model, v, T, top if data.has_top else None, e_h, e_tr, e_te, lr["train"], lr["test"], rm,
                      W if data.has_wob else None)


def wob_errors(W: np.ndarray, data: LoopData, scale: float | None = None) -> np.ndarray:
    """Per-horizon normalized mean squared error of predicted WOB ``W`` (horizons x L, every horizon)
    against the recorded WOB (the record's own, also where the law takes its trend), on the
    scale ``scale`` [N] (None: the recorded WOB's standard deviation over the calibration horizons):
    the WOB's term of E, for a model whose WOB is a state (docs/records.md, section 4).

    Parameters
    ----------
    W : numpy.ndarray
        Predicted WOB [N], horizons x L (:attr:`Evaluation.wob`).
    data : LoopData
        The record on the analysis grid, with a WOB channel.
    scale : float, optional
        The WOB's spread [N] the errors are divided by.

    Returns
    -------
    numpy.ndarray
        Mean over each horizon's samples of ((W - recorded) / scale)^2 [-].
    """
    if not data.has_wob:
        raise ValueError("record: no WOB channel to score the predicted WOB against")
    rec = data.wob_measured if data.wob_measured is not None else data.ch["W"]
    Y = rec[data.horizon_samples]
    s = float(np.std(Y[~data.is_test])) if scale is None else float(scale)
    if not s > 0:
        raise ValueError(f"scale = {scale!r}: the WOB's spread must be positive")
    return np.mean(((W - Y) / s) ** 2, axis=1)


def residual_vector(model: LoopModel, data: LoopData, threads: int, check: bool = True) -> np.ndarray:
    """Normalized residuals of the calibration horizons (every channel of :func:`channel_errors`);
    their sum of squares is E_train^2.

    The vector the calibration's least squares minimizes (:func:`drillpy.loop.fitting.fit_dynamic`).

    Parameters
    ----------
    model : LoopModel
        The model to predict with.
    data : LoopData
        The record on the analysis grid.
    threads : int
        Engine threads (0: OpenMP default).
    check : bool
        The configuration's plausibility warnings (:func:`simulation`; False: the calibration's trials).

    Returns
    -------
    numpy.ndarray
        The residuals [-] of every channel and sample of the calibration horizons, divided by
        sqrt(channels x samples).
    """
    h = np.flatnonzero(~data.is_test)
    return _residuals(predict(model, data, h, threads, top=True, check=check), data, h)


def _residuals(pred: tuple, data: LoopData, h: np.ndarray, ref=None) -> np.ndarray:
    """:func:`residual_vector` of predictions (bit speed, torque, top speed) of the horizons ``h``
    (``ref``: :func:`channel_errors`')."""
    v, T, top = pred
    parts = channel_errors(v, T, top, data, h, ref)
    r = parts.reshape(-1)  # the channels one after the other
    r /= math.sqrt(len(parts) * v.size)
    return r


def residual_vectors(models, data: LoopData, threads: int, check: bool = True) -> list:
    """:func:`residual_vector` of several models in one engine call (:func:`predict_many`), each bit
    for bit the single model's.

    Parameters
    ----------
    models : sequence of LoopModel
        The models.
    data : LoopData
        The record on the analysis grid.
    threads : int
        Engine threads (0: OpenMP default).
    check : bool
        The configurations' plausibility warnings (:func:`simulation`).

    Returns
    -------
    list
        Per model, the residuals [-] of :func:`residual_vector`, or the exception (ValueError,
        RuntimeError) it would raise, as an object.
    """
    h = np.flatnonzero(~data.is_test)
    ref = _reference(data, h)  # the record's side, once for every model
    return [p if isinstance(p, BaseException) else _residuals(p, data, h, ref)
            for p in predict_many(models, data, h, threads, top=True, check=check)]


def bit_equation(model: LoopModel) -> dict:
    """The bit's equation of motion of the model's string as one torsional spring and a lumped
    inertia, J a = k phi + c (Omega - v) - T - T_extra (phi the twist, Omega the top speed):
    k = 1 / sum(L_i / (G_i J_p,i)) of the sections in series, J = the lumped bit inertia plus a third
    of the string's (the rig's first mode), c = 2 zeta sqrt(k J) with the first modal damping ratio,
    T_extra the model's torques outside the torque sensor (viscous c_v v, string friction).

    Parameters
    ----------
    model : LoopModel
        The model (its engine configuration: sections, lumped inertias at the bit, damping ratios,
        operation).

    Returns
    -------
    dict
        ``k_nm_rad`` k [N m/rad], ``J_kg_m2`` J [kg m^2], ``c_nms_rad`` c [N m s/rad] (0 with
        Rayleigh damping), ``viscous_nms_rad`` c_v [N m s/rad], ``string_friction_nm`` T_sf [N m].
    """
    cfg = view(model.engine_config())
    k, J = string_of(cfg)  # the sections in series, the bit's inertia and a third of the string's
    ratios = model.damping_ratios or [0.0]
    op = cfg.operation
    return {"k_nm_rad": k, "J_kg_m2": J, "c_nms_rad": 2.0 * ratios[0] * math.sqrt(k * J),
            "viscous_nms_rad": float(op.get("bit_viscous_nms", 0.0)),
            "string_friction_nm": float(op.get("string_friction_nm", 0.0))}


def equation_residual(model: LoopModel, data: LoopData, highpass_s: float = 2.0) -> tuple | None:
    """The residual of the bit's equation of motion (:func:`bit_equation`) on the record, in N m,
    and the channels the discovery step regresses it on (v, a, T, twist, top, dtop, W). The twist is
    the integral of top minus bit speed with its centred ``highpass_s`` moving average removed (its
    offset and a slow drift from an encoder scale mismatch are unknown; a constant term of the
    library takes the mean). Samples where the top speed is not a measurement, and those within
    ``highpass_s`` after one (the integral carries the error), are left out (NaN). None without a
    top-speed channel.

    The residual is J a - k phi - c (top - v) + T + T_extra, its mean over the samples kept removed;
    the string friction enters with a smooth sign v / sqrt(v^2 + eps^2), eps 5 % of mean |v|.

    Parameters
    ----------
    model : LoopModel
        The model (:func:`bit_equation`).
    data : LoopData
        The record on the analysis grid (top speed needed).
    highpass_s : float
        Window of the moving average removed from the twist [s].

    Returns
    -------
    tuple or None
        (residual [N m] per sample, NaN where left out; channels dict ``v`` [rad/s], ``a``
        [rad/s^2], ``T`` [N m], ``twist`` [rad], ``top`` [rad/s], ``dtop`` [rad/s^2] and ``W`` [N]
        with a WOB channel; the coefficients of :func:`bit_equation`), or None.
    """
    if not data.has_top:
        return None
    from scipy.ndimage import uniform_filter1d
    ch, dt = data.ch, data.dt
    eq = bit_equation(model)
    v, a, T, top = ch["v"], ch["v1"], true_torque(model, ch["T"]), ch["top"]
    slip = top - v
    phi = np.concatenate([[0.0], np.cumsum(0.5 * (slip[1:] + slip[:-1]) * dt)])
    w = max(3, int(round(highpass_s / dt)))
    phi = phi - uniform_filter1d(phi, w, mode="nearest")
    bad = ~(data.valid & data.top_ok)
    bad = np.convolve(bad.astype(float), np.ones(w), mode="full")[: bad.size] > 0  # and highpass_s after
    eps = 0.05 * float(np.mean(np.abs(v[~bad]))) if (~bad).any() else 1.0
    extra = eq["viscous_nms_rad"] * v + eq["string_friction_nm"] * v / np.sqrt(v ** 2 + eps ** 2)
    r = eq["J_kg_m2"] * a - eq["k_nm_rad"] * phi - eq["c_nms_rad"] * (top - v) + T + extra
    if (~bad).any():
        r = r - float(np.mean(r[~bad]))
    chans = {"v": v, "a": a, "T": T, "twist": phi, "top": top, "dtop": ch["top1"]}
    if data.has_wob:
        chans["W"] = ch["W"]
    return np.where(bad, np.nan, r), chans, eq
