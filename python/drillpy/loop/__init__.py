"""``drillpy loop``: residual -> missing effect -> corrected model, with the error before and after.

Starting from a declared model (a preset or a JSON configuration), :func:`run_loop`

1. calibrates it on the first part of a record (the *calibration part*; the rest is the
   *validation part*, never used to fit anything): the bit-rock law's parameters by least squares
   on the law residual, the constant top speed and WOB as the calibration part's means;
2. computes residuals at two levels:

   * the **law residual** r_law = T - T_model(v, a, W) on the slip samples (bit speed above the
     stick threshold), the law evaluated on the measured bit speed, acceleration and WOB;
   * the **dynamic residual**: every ``horizon_s`` the model is restarted from the state that
     reproduces the measured bit speed, bit acceleration, torque on bit and top speed
     (``Integrator::state_from_bit``; exact for the rig's one mode) and integrated over the next
     ``horizon_s`` by the engine (``drill/horizons.hpp``), driven by the boundary inputs the model
     takes from the record; the predicted bit speed and torque on bit are compared with the
     measured ones;

3. fits every effect of the catalogue (:mod:`drillpy.effects`) that the model lacks, on the
   calibration part, and keeps the one with the lowest validation error among those that pass the
   guard against false discoveries (:class:`LoopOptions`): a relative validation improvement of at
   least ``min_gain``, a one-sided paired test over the validation horizons significant at
   ``alpha`` / (number of candidates) (Bonferroni), and a BIC improvement of more than
   ``min_delta_bic`` on the calibration part. The model with the effect is refitted and the round
   repeats until no candidate passes.

**Metric** (the number ``loop.json`` reports): the normalized short-horizon prediction error

    E = sqrt( 1/2 [ mean (v_pred - v)^2 / s_v^2 + mean (T_pred - T)^2 / s_T^2 ] )

over all samples of the horizons of a part (v bit speed, T torque on bit as recorded; s_v, s_T their
standard deviations over the calibration part, fixed for the whole loop). E = 0 is a perfect
prediction; E = 1 is as far off, on average, as the channels' own spread. ``error_before``,
``error_after``, ``baseline_error`` and ``final_error`` are E on the validation part.
"""
from __future__ import annotations

import copy
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import optimize, stats
from scipy import signal as sps

from .. import _core
from .. import identification as ident
from .. import signals
from ..cleaning import CleaningOptions, clean
from ..config import normalize, to_json_text
from ..effects import CATALOGUE, NAMES, declared_effects
from ..records import RPM, Record, read_record

SQRT2 = math.sqrt(2.0)
#: Channels the cleaning searches for spikes: the encoders (the load cells' torque and WOB drop
#: sharply, and genuinely, when the bit nearly sticks).
ENCODER_CHANNELS = ("bit_speed", "top_speed")
#: The first horizon starts this late [s]: the sensors' delay sqrt(2)/omega_c is at most 0.11 s
#: (cutoffs from 2 Hz), and restarts are placed that much before a horizon.
FIRST_START_S = 0.12


@dataclass
class LoopOptions:
    """Choices of :func:`run_loop`.

    Attributes
    ----------
    horizon_s : float
        Length of the prediction horizons; the model is restarted from the measured state at the
        start of each [s].
    calibration_fraction : float
        Fraction of the record (from its start) used to calibrate; the rest validates.
    rate_hz : float
        Analysis sampling rate [Hz] (the record is decimated by an integer factor to at most this).
    derivative_window_s : float
        Width of the Savitzky-Golay filters (polynomial order 4) that give the channels'
        derivatives and smoothed values [s].
    min_gain : float
        Minimum relative improvement of the validation error for an effect to be added.
    alpha : float
        Family-wise level of the one-sided paired test per round (divided by the number of
        candidates of the round: Bonferroni).
    min_delta_bic : float
        Minimum BIC improvement on the calibration part (6: "strong" on the Kass-Raftery scale).
    max_steps : int
        At most this many effects are added.
    effects : tuple
        Candidate effects (default: the whole catalogue).
    stick_fraction : float
        The bit is stuck at or below this fraction of the median top speed.
    threads : int
        Engine threads (0: OpenMP default).
    dt_s : float, optional
        Engine time step of the predictions [s] (default: the declared configuration's); it is
        lowered, if needed, to divide the analysis sampling interval.
    """
    horizon_s: float = 0.25
    calibration_fraction: float = 0.5
    rate_hz: float = 1000.0
    derivative_window_s: float = 0.031
    min_gain: float = 0.05
    alpha: float = 0.05
    min_delta_bic: float = 6.0
    max_steps: int = 6
    effects: tuple = NAMES
    stick_fraction: float = 0.05
    threads: int = 0
    dt_s: float | None = None

    def validate(self) -> None:
        def pos(name, v, lo=0.0, hi=math.inf, closed=False):
            ok = isinstance(v, (int, float)) and math.isfinite(v) and (lo <= v if closed else lo < v) and v < hi
            if not ok:
                raise ValueError(f"{name} = {v!r}: must be a number in {'[' if closed else '('}{lo:g}, {hi:g})")
        pos("horizon_s", self.horizon_s)
        pos("calibration_fraction", self.calibration_fraction, 0.0, 1.0)
        pos("rate_hz", self.rate_hz)
        pos("derivative_window_s", self.derivative_window_s)
        pos("min_gain", self.min_gain, 0.0, 1.0, closed=True)
        pos("alpha", self.alpha, 0.0, 1.0)
        pos("min_delta_bic", self.min_delta_bic, -math.inf)
        pos("stick_fraction", self.stick_fraction, 0.0, 1.0)
        if self.dt_s is not None:
            pos("dt_s", self.dt_s)
        if not isinstance(self.max_steps, int) or self.max_steps < 0:
            raise ValueError(f"max_steps = {self.max_steps!r}: must be a non-negative integer")
        for e in self.effects:
            if e not in NAMES:
                raise ValueError(f"effects: unknown effect {e!r} (known: {', '.join(NAMES)})")


# ------------------------------------------------------------------------------------- data
@dataclass
class LoopData:
    """A cleaned record on the analysis grid, split into calibration and validation horizons.

    ``ch`` holds Savitzky-Golay estimates of the recorded channels and their derivatives
    (``v``, ``v1``, ``v2``, ``v3``: bit speed and its first three derivatives; ``T``, ``T1``, ``T2``;
    ``top``..``top3``; ``W``, ``W1``, ``W2``); ``v_meas`` and ``T_meas`` are the recorded values the
    predictions are compared with. Horizon h starts at sample ``starts[h]`` and predicts the next
    ``L`` samples; ``is_test[h]`` marks the validation horizons.
    """
    source: str
    t: np.ndarray
    dt: float
    ch: dict
    v_meas: np.ndarray
    T_meas: np.ndarray
    valid: np.ndarray
    has_top: bool
    has_wob: bool
    stick_threshold: float
    t_split: float
    starts: np.ndarray
    is_test: np.ndarray
    L: int
    sigma_v: float
    sigma_T: float
    top_meas: np.ndarray | None
    sigma_top: float
    law_train: np.ndarray
    law_test: np.ndarray
    cleaning: list
    decimation: int
    record_rate_hz: float

    @property
    def horizon_samples(self) -> np.ndarray:
        """Sample indices of every horizon, shape (horizons, L)."""
        return self.starts[:, None] + 1 + np.arange(self.L)[None, :]

    def channels(self) -> tuple:
        return tuple(c for c, ok in (("top_speed", self.has_top), ("wob", self.has_wob)) if ok)


def _savgol_set(x: np.ndarray, dt: float, window_s: float, orders) -> list:
    n = signals.savgol_length(window_s, dt, x.size, minimum=7)
    return [sps.savgol_filter(x, n, 4, deriv=k, delta=dt, mode="interp") for k in orders]


def prepare(record: Record | str | Path, cfg: dict, opt: LoopOptions) -> LoopData:
    """Clean a record, estimate derivatives, decimate, cut horizons and split them."""
    raw = read_record(record) if isinstance(record, (str, Path)) else record
    for need in ("bit_speed", "torque_on_bit"):
        raw.channel(need)
    rec, rep = clean(raw, CleaningOptions(spike_channels=ENCODER_CHANNELS))
    names = ["bit_speed", "torque_on_bit"] + [c for c in ("top_speed", "wob") if getattr(rec, c) is not None]
    valid = rec.valid(*names)
    if valid.sum() < 10:
        raise ValueError("record: fewer than 10 valid samples after cleaning")
    fs = rec.sample_rate_hz
    q = max(1, int(math.floor(fs / opt.rate_hz + 1e-9)))
    idx = np.arange(len(rec))

    def filled(x):
        ok = valid & np.isfinite(x)
        return np.interp(idx, idx[ok], x[ok])

    ch = {}
    spec = {"v": ("bit_speed", (0, 1, 2, 3)), "T": ("torque_on_bit", (0, 1, 2)),
            "top": ("top_speed", (0, 1, 2, 3)), "W": ("wob", (0, 1, 2))}
    for key, (name, orders) in spec.items():
        x = getattr(rec, name)
        if x is None:
            continue
        for k, y in zip(orders, _savgol_set(filled(x), rec.dt, opt.derivative_window_s, orders)):
            ch[key if k == 0 else f"{key}{k}"] = y[::q]
    # samples within a filter half-width of an excluded sample are excluded too
    half = max(int(round(opt.derivative_window_s / rec.dt)) // 2, 3)
    bad = np.convolve((~valid).astype(float), np.ones(2 * half + 1), mode="same") > 0
    ok = (~bad)[::q]
    t = rec.time_s[::q]
    dt = rec.dt * q
    v_meas, T_meas = filled(rec.bit_speed)[::q], filled(rec.torque_on_bit)[::q]
    has_top, has_wob = rec.top_speed is not None, rec.wob is not None
    top_ref = float(np.median(ch["top"][ok])) if has_top else float(cfg["operation"]["top_speed_rad_s"])
    thr = opt.stick_fraction * abs(top_ref)
    t_split = float(t[0] + opt.calibration_fraction * (t[-1] - t[0]))
    L = int(round(opt.horizon_s / dt))
    if L < 2:
        raise ValueError(f"horizon_s = {opt.horizon_s}: shorter than two samples of {dt:g} s")
    starts, is_test = [], []
    cum = np.r_[0, np.cumsum(~ok)]
    first = int(math.ceil(FIRST_START_S / dt))  # room for the restart before a lagging sensor's horizon
    for s in range(first, t.size - L, L):
        if cum[s + L + 1] - cum[s] > 0:
            continue  # an excluded sample in the horizon
        if t[s + L] < t_split:
            starts.append(s), is_test.append(False)
        elif t[s] >= t_split:
            starts.append(s), is_test.append(True)
    starts, is_test = np.asarray(starts, dtype=np.int64), np.asarray(is_test, bool)
    n_tr, n_te = int((~is_test).sum()), int(is_test.sum())
    if n_tr < 4 or n_te < 4:
        raise ValueError(f"record: {n_tr} calibration and {n_te} validation horizons of {opt.horizon_s:g} s; need "
                         f"at least 4 each (a longer record, a shorter horizon_s or another calibration_fraction)")
    train = ok & (t < t_split)
    sv, sT = float(np.std(v_meas[train])), float(np.std(T_meas[train]))
    top_meas = filled(rec.top_speed)[::q] if has_top else None
    s_top = float(np.std(top_meas[train])) if has_top else float("nan")
    if not (sv > 0 and sT > 0):
        raise ValueError("record: the bit speed or the torque on bit is constant over the calibration part")
    every = max(1, int(round(0.01 / dt)))  # law fits on 100 Hz: the channels are smooth at that scale
    slip = ok & (ch["v"] > thr)
    sub = np.zeros(t.size, bool)
    sub[::every] = True
    law_train = np.flatnonzero(slip & sub & (t < t_split))
    law_test = np.flatnonzero(slip & sub & (t >= t_split))
    if law_train.size < 20:
        raise ValueError(f"record: only {law_train.size} slip samples in the calibration part to fit the law")
    return LoopData(str(rec.provenance.get("source", "record")), t, dt, ch, v_meas, T_meas, ok, has_top, has_wob, thr,
                    t_split, starts, is_test, L, sv, sT, top_meas, s_top, law_train, law_test, rep.lines(), q, fs)


# ------------------------------------------------------------------------------------ model
@dataclass
class LoopModel:
    """A calibrated model: the declared configuration, its calibrated law and operating point, and
    the effects added to it with their parameters (SI)."""
    cfg: dict
    law: dict
    top_speed: float  #: constant top speed of the ideal drive [rad/s]
    wob: float        #: WOB W_0 at which the law is evaluated [N]
    effects: dict = field(default_factory=dict)
    n_law: int = 0    #: free parameters of the law

    def copy(self) -> "LoopModel":
        return copy.deepcopy(self)

    @property
    def k(self) -> int:
        """Number of calibrated parameters (the law's and the effects')."""
        k = self.n_law
        for name, p in self.effects.items():
            if name == "top_drive_dynamics":
                k += 3 if p.get("variant") == "motor" else 0
            elif name == "torque_fluctuation":
                k += 2
            elif name != "bit_hysteresis":  # counted with the law
                k += len(CATALOGUE[name].parameters)
        return k

    def engine_config(self) -> dict:
        """The engine configuration of the model (top drive, sensors and bit damping included)."""
        c = copy.deepcopy(self.cfg)
        c["law"] = dict(self.law)
        op = c["operation"]
        op["wob_n"] = float(self.wob)
        op["top_speed_rad_s"] = float(self.top_speed)
        td = self.effects.get("top_drive_dynamics")
        c.pop("top_drive", None)
        if td is not None and td.get("variant") == "motor":
            c["top_drive"] = {"type": "motor", "slope_nms_rad": 1.0 / td["droop_rad_s_per_nm"],
                              "inertia_kg_m2": td["inertia_kg_m2"]}
            op["top_speed_rad_s"] = float(td["command_rad_s"])
        op["bit_viscous_nms"] = float(self.effects.get("viscous_damping", {}).get("bit_viscous_nms", 0.0))
        fc = float(self.effects.get("sensor_lag", {}).get("lowpass_hz", 0.0))
        c.pop("sensors", None)
        if fc > 0:
            c["sensors"] = {"lowpass_hz": fc}
        return c

    def parameters(self) -> dict:
        """The model's parameters for ``loop.json`` (SI; the law in its own speed unit)."""
        return {"law": dict(self.law), "top_speed_rad_s": self.top_speed, "wob_n": self.wob,
                "damping": self.cfg["damping"], "effects": copy.deepcopy(self.effects)}


_SIMS: dict = {}


def _simulation(cfg: dict) -> "_core.Simulation":
    text = to_json_text(cfg)
    sim = _SIMS.get(text)
    if sim is None:
        if len(_SIMS) > 64:
            _SIMS.clear()
        sim = _SIMS[text] = _core.Simulation(text)
    return sim


def sensor_delay(model: LoopModel) -> float:
    """Low-frequency group delay sqrt(2) / omega_c of the model's sensors [s] (0 without)."""
    fc = float(model.effects.get("sensor_lag", {}).get("lowpass_hz", 0.0))
    return SQRT2 / (2 * math.pi * fc) if fc > 0 else 0.0


def _wob_input(model: LoopModel, w, n: int) -> np.ndarray:
    k = model.effects.get("wob_coupling", {}).get("gain")
    if k is None or w is None:
        return np.full(n, model.wob)
    return model.wob * (1.0 + k * (w / model.wob - 1.0))


def state_channels(model: LoopModel, data: LoopData) -> dict:
    """The channels as the model's state sees them at each sample: bit speed ``v``, acceleration
    ``a``, torque ``T``, top speed ``top`` and its rate ``dtop``, WOB ``W`` and the law's WOB input
    ``W_eff``. With ``sensor_lag`` the recorded channels lag the model's by about the filter's
    group delay tau = sqrt(2) / omega_c: the model at time t is read off the record at t + tau
    (causal for a restart placed tau before the horizon: :func:`predict`)."""
    ch, t = data.ch, data.t
    tau = sensor_delay(model)

    def at(k):
        return np.interp(t + tau, t, ch[k]) if tau > 0 else ch[k]

    out = {"v": at("v"), "a": at("v1"), "T": at("T")}
    if data.has_top:
        out["top"], out["dtop"] = at("top"), at("top1")
    w = at("W") if data.has_wob else None
    if w is not None:
        out["W"] = w
    out["W_eff"] = _wob_input(model, w, t.size)
    return out


def law_channels(model: LoopModel, data: LoopData) -> dict:
    """The channels for the law residual (simultaneous v, a, T, W): with ``sensor_lag`` the
    second-order filter is undone, x = y + (sqrt(2)/omega_c) y' + y''/omega_c^2."""
    ch = data.ch
    fc = model.effects.get("sensor_lag", {}).get("lowpass_hz", 0.0)
    c1, c2 = (SQRT2 / (2 * math.pi * fc), 1.0 / (2 * math.pi * fc) ** 2) if fc > 0 else (0.0, 0.0)

    def undo(k):
        return ch[k] + c1 * ch[k + "1"] + c2 * ch[k + "2"]

    out = {"v": undo("v"), "a": ch["v1"] + c1 * ch["v2"] + c2 * ch["v3"], "T": undo("T")}
    w = undo("W") if data.has_wob else None
    if w is not None:
        out["W"] = w
    out["W_eff"] = _wob_input(model, w, data.t.size)
    return out


def law_torque(model: LoopModel, chs: dict, index=None) -> np.ndarray:
    """The model's law T_law(v, a, W_eff) [N m] at the state channels (engine evaluation)."""
    sl = slice(None) if index is None else index
    return ident.law_eval(model.law, chs["v"][sl], chs["a"][sl], chs["W_eff"][sl])[0]


def eta_estimate(model: LoopModel, data: LoopData, chs: dict) -> tuple:
    """Per sample, the state (eta, eta') of the fluctuation estimated from the record's past: the
    straight line fitted by least squares to eta_obs = T / T_law - 1 over the slip samples up to and
    including that sample, with weights exp(-age / m) (m: ``memory_s``). The weighted sums are
    recursive: filters with the kernels lambda^n, n lambda^n, n^2 lambda^n (lambda = exp(-dt / m))."""
    p = model.effects["torque_fluctuation"]
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


def eta_forecast(model: LoopModel, level: np.ndarray, slope: np.ndarray, lead: np.ndarray) -> np.ndarray:
    """Conditional mean of eta at the leads [s] (columns) from (eta, eta') at the restarts (rows):
    eta is modelled as white noise through a critically damped second-order low-pass of time
    constant tau (PSD falling as f^-4 above 1/(2 pi tau), the steep coloured shape of Eq. 4.4), whose
    free response is exp(-s/tau) [eta (1 + s/tau) + s eta']."""
    tau = model.effects["torque_fluctuation"]["tau_s"]
    s = lead[None, :]
    return np.exp(-s / tau) * (level[:, None] * (1.0 + s / tau) + s * slope[:, None])


def predict(model: LoopModel, data: LoopData, horizons=None, threads: int = 0, top: bool = False) -> tuple:
    """Predicted bit speed [rad/s] and torque on bit [N m] (and top speed [rad/s] with ``top``) of
    the horizons (rows; default all), after the model's sensors.

    Each horizon restarts D = ceil(tau / dt) samples before its first sample (tau: the sensors'
    delay, 0 without them) from the state read off the record (:func:`state_channels`), with the
    sensors' filters started from the recorded values and rates at the restart."""
    h = np.arange(data.starts.size) if horizons is None else np.asarray(horizons)
    D = int(math.ceil(sensor_delay(model) / data.dt - 1e-9))
    idx = data.starts[h] - D
    sim = _simulation(model.engine_config())
    chs = state_channels(model, data)
    ch = data.ch
    td = model.effects.get("top_drive_dynamics")
    n = idx.size
    if td is not None:  # the top at its measured speed (motor state or kinematic drive)
        om, dom = chs["top"][idx], chs["dtop"][idx]
        if td.get("variant") == "motor":  # its rate from the motor equation, not the noisy record
            dom = np.full(n, np.nan)
    else:
        om, dom = np.full(n, model.top_speed), np.zeros(n)
    state = np.column_stack([chs["v"][idx], chs["a"][idx], chs["T"][idx], om, dom])
    if data.has_top:
        ytop, dytop = ch["top"][idx], ch["top1"][idx]
    else:
        ytop, dytop = om, dom
    sensor = np.column_stack([ch["v"][idx], ch["v1"][idx], ch["T"][idx], ch["T1"][idx], ytop, dytop])
    top_series = chs["top"] if (td is not None and td.get("variant") == "measured") else None
    wob_series = chs["W_eff"] if "wob_coupling" in model.effects else None
    eta = None
    if "torque_fluctuation" in model.effects:
        level, slope = eta_estimate(model, data, chs)
        eta = eta_forecast(model, level[idx], slope[idx], np.arange(data.L + D + 1) * data.dt)
    r = _core.predict_horizons(sim, idx.tolist(), np.ascontiguousarray(state), np.ascontiguousarray(sensor),
                               data.dt, data.L + D, top_speed=top_series, wob=wob_series, eta=eta, threads=threads)
    if top:
        return r["bit_speed"][:, D:], r["torque"][:, D:], r["top_speed"][:, D:]
    return r["bit_speed"][:, D:], r["torque"][:, D:]


def measured(data: LoopData, horizons=None) -> tuple:
    h = np.arange(data.starts.size) if horizons is None else np.asarray(horizons)
    s = data.horizon_samples[h]
    return data.v_meas[s], data.T_meas[s]


# ----------------------------------------------------------------------------- evaluation
@dataclass
class Evaluation:
    """A model with its predictions of every horizon and its errors."""
    model: LoopModel
    v: np.ndarray          #: predicted bit speed, horizons x L [rad/s]
    T: np.ndarray          #: predicted torque on bit [N m]
    e_h: np.ndarray        #: per-horizon normalized mean squared error
    E_train: float
    E_test: float
    law_rmse_train: float  #: law residual RMSE on the calibration part's slip samples [N m]
    law_rmse_test: float   #: ... on the validation part's [N m]
    channel_rmse: dict     #: validation RMSE per channel: bit speed [rad/s], torque [N m]


def evaluate(model: LoopModel, data: LoopData, threads: int = 0) -> Evaluation:
    v, T = predict(model, data, threads=threads)
    Yv, YT = measured(data)
    e_h = 0.5 * (np.mean((v - Yv) ** 2, axis=1) / data.sigma_v ** 2 + np.mean((T - YT) ** 2, axis=1) / data.sigma_T ** 2)
    chs = law_channels(model, data)
    lr = {}
    for key, idx in (("train", data.law_train), ("test", data.law_test)):
        r = chs["T"][idx] - law_torque(model, chs, idx) if idx.size else np.zeros(0)
        lr[key] = float(np.sqrt(np.mean(r ** 2))) if r.size else float("nan")
    te = data.is_test
    rm = {"bit_speed_rad_s": float(np.sqrt(np.mean((v[te] - Yv[te]) ** 2))),
          "torque_on_bit_nm": float(np.sqrt(np.mean((T[te] - YT[te]) ** 2)))}
    return Evaluation(model, v, T, e_h, float(np.sqrt(np.mean(e_h[~te]))), float(np.sqrt(np.mean(e_h[te]))),
                      lr["train"], lr["test"], rm)


def _residual_vector(model: LoopModel, data: LoopData, threads: int, top: bool = False) -> np.ndarray:
    """Normalized residuals of the calibration horizons; their sum of squares is E_train^2. With
    ``top`` the top speed's residual (normalized by its standard deviation over the calibration
    part) is appended: a motor model must also reproduce the recorded top speed."""
    h = np.flatnonzero(~data.is_test)
    out = predict(model, data, h, threads, top=top)
    Yv, YT = measured(data, h)
    n = Yv.size
    parts = [((out[0] - Yv) / data.sigma_v).ravel(), ((out[1] - YT) / data.sigma_T).ravel()]
    if top:
        s_top = max(data.sigma_top, 1e-3 * data.sigma_v)
        parts.append(((out[2] - data.top_meas[data.horizon_samples[h]]) / s_top).ravel())
    return np.concatenate(parts) / math.sqrt(2 * n)


# -------------------------------------------------------------------------------- law fits
class _FamilyData:
    """What identification.FAMILIES' builders read: the reference WOB and speed [rad/s]."""
    def __init__(self, wob_ref: float, speed_ref: float):
        self.wob_ref, self.speed_ref = wob_ref, speed_ref


def _law_family(law: dict, hysteresis: bool, a_scale: float) -> tuple:
    """(family name, starting parameters, fixed parameters, _FamilyData) of a law."""
    t, unit = law["type"], law["speed_unit"]
    s = RPM if unit == "rpm" else 1.0
    hyst0 = [float(law.get("beta1", 0.0)) or 0.1, float(law.get("beta2", 0.0)) or 1.0 / (a_scale * s)]
    if t in ("polynomial", "polynomial_hysteretic"):
        p = [law["a4"], law["a5"], law["a6"], law["a7"]]
        fd = _FamilyData(law["wob_ref_n"], law["ref_speed"] / s)
        name = "polynomial_hysteretic" if hysteresis else "polynomial"
        return name, p + (hyst0 if hysteresis else []), {"gain": law["gain"]}, fd
    fd = _FamilyData(law["wob_ref_n"], 1.0)
    if t == "hysteretic":
        knee = law["b3"] ** (-1.0 / law["b5"]) if law["b3"] > 0 else 1e6
        p = [law["b0"], law["b0"] * law["b2"], knee, law["b4"], law["b5"]]
        return ("hysteretic" if hysteresis else "hysteretic_reversible"), p + (hyst0 if hysteresis else []), \
            {"b1": law["b1"]}, fd
    if t == "tucker_wang":
        if hysteresis:  # Eq. (3.2) with b4 = 1, b5 = 2 is Eq. (3.1); H acts on the fraction
            knee = law["alpha2"] ** -0.5 if law["alpha2"] > 0 else 1e6
            return "hysteretic", [law["c0"], law["c0"] * law["alpha1"], knee, 1.0, 2.0] + hyst0, \
                {"b1": law["alpha0"]}, fd
        return "tucker_wang", [law["c0"], law["alpha1"], law["alpha2"]], {"alpha0": law["alpha0"]}, fd
    raise ValueError(f"law.type = {t!r}: not supported by drillpy loop")


def fit_law(model: LoopModel, data: LoopData) -> LoopModel:
    """Least squares on the law residual of the calibration part's slip samples: the law's free
    parameters, with the hysteresis term when ``bit_hysteresis`` is in the model and the coupling
    gain k when ``wob_coupling`` is."""
    m = model.copy()
    chs = law_channels(m, data)
    idx = data.law_train
    v, a, T = chs["v"][idx], chs["a"][idx], chs["T"][idx]
    hyst = "bit_hysteresis" in m.effects
    wob = "wob_coupling" in m.effects
    W = chs["W"][idx] if wob else np.full(idx.size, m.wob)
    name, p0, fx, fd = _law_family(m.law, hyst, float(np.std(a)) or 1.0)
    fam = ident.FAMILIES[name]
    unit = m.law["speed_unit"]
    x0 = list(p0) + ([m.effects["wob_coupling"].get("gain", 1.0)] if wob else [])
    lb = list(fam.lower) + ([-5.0] if wob else [])
    ub = list(fam.upper) + ([5.0] if wob else [])
    lo, hi = np.array(lb, float), np.array(ub, float)
    x0 = np.clip(np.array(x0, float), _inside(lo, +1), _inside(hi, -1))
    npar = len(fam.names)

    def resid(x):
        law = fam.build(x[:npar], fd, unit, fx)
        w = m.wob * (1.0 + x[npar] * (W / m.wob - 1.0)) if wob else W
        return ident.law_eval(law, v, a, w)[0] - T

    res = optimize.least_squares(resid, x0, bounds=(lo, hi), x_scale="jac", method="trf", max_nfev=200 * len(x0),
                                 xtol=1e-10, ftol=1e-10)
    law = fam.build(res.x[:npar], fd, unit, fx)
    m.law = law
    m.n_law = npar - (2 if hyst else 0)
    if hyst:
        m.effects["bit_hysteresis"] = {"beta1": float(law["beta1"]), "beta2": float(law["beta2"])}
    if wob:
        m.effects["wob_coupling"] = {"gain": float(res.x[npar])}
    return m


# ---------------------------------------------------------------------------- dynamic fits
#: Dynamic parameters: (name, transform, lower, upper); "log" parameters are fitted in ln.
DYNAMIC = {
    "top_drive_dynamics": (("droop_rad_s_per_nm", "log", 1e-3, 1e3), ("inertia_kg_m2", "log", 1e-6, 10.0),
                           ("command_rad_s", "lin", 0.0, np.inf)),
    "sensor_lag": (("lowpass_hz", "log", 2.0, 200.0),),
    "torque_fluctuation": (("tau_s", "log", 0.01, 1e3), ("memory_s", "log", 0.002, 100.0)),
    "viscous_damping": (("bit_viscous_nms", "lin", 0.0, np.inf),),
}


LAW = "law"  #: pseudo-effect of fit_dynamic: the law's free parameters (and the WOB coupling gain)


def _free(model: LoopModel, name: str) -> tuple:
    if name == "top_drive_dynamics" and model.effects[name].get("variant") != "motor":
        return ()
    return DYNAMIC.get(name, ())


def _law_vector(model: LoopModel) -> tuple:
    """The law's free parameters as fit_law sees them: (family, p, fixed, family data, bounds)."""
    name, p0, fx, fd = _law_family(model.law, "bit_hysteresis" in model.effects, 1.0)
    fam = ident.FAMILIES[name]
    return fam, np.array(p0, float), fx, fd


def _pack(model: LoopModel, names) -> tuple:
    x, lo, hi, where = [], [], [], []
    for name in names:
        if name == LAW:
            fam, p0, _, _ = _law_vector(model)
            x += list(p0)
            lo += list(fam.lower)
            hi += list(fam.upper)
            where += [(LAW, i, "lin") for i in range(p0.size)]
            if "wob_coupling" in model.effects:
                x.append(model.effects["wob_coupling"]["gain"])
                lo.append(-5.0)
                hi.append(5.0)
                where.append(("wob_coupling", "gain", "lin"))
            continue
        for pname, tr, a, b in _free(model, name):
            if pname == "inertia_kg_m2":  # the modified-Euler bound with the motor (Eq. A.7)
                a = max(a, 2.0 * _motor_inertia_floor(model, model.cfg["simulation"]["dt_s"]))
            val = float(model.effects[name][pname])
            if tr == "log":
                x.append(math.log(min(max(val, a * 1.0001), b / 1.0001)))
                lo.append(math.log(a))
                hi.append(math.log(b))
            else:
                x.append(val)
                lo.append(a)
                hi.append(b)
            where.append((name, pname, tr))
    return np.array(x), np.array(lo), np.array(hi), where


def _unpack(model: LoopModel, x, where) -> LoopModel:
    m = model.copy()
    law_p = [xi for xi, w in zip(x, where) if w[0] == LAW]
    if law_p:
        fam, _, fx, fd = _law_vector(model)
        m.law = fam.build(np.array(law_p), fd, model.law["speed_unit"], fx)
        if "bit_hysteresis" in m.effects:
            m.effects["bit_hysteresis"] = {"beta1": float(m.law["beta1"]), "beta2": float(m.law["beta2"])}
    for xi, (name, pname, tr) in zip(x, where):
        if name != LAW:
            m.effects[name][pname] = float(math.exp(xi) if tr == "log" else xi)
    return m


def _inside(bound: np.ndarray, sign: int) -> np.ndarray:
    """Bounds moved inside by a relative 1e-9 (infinite ones unchanged)."""
    b = np.asarray(bound, float).copy()
    f = np.isfinite(b)
    b[f] += sign * 1e-9 * (1.0 + np.abs(b[f]))
    return b


def fit_dynamic(model: LoopModel, data: LoopData, names, threads: int = 0) -> LoopModel:
    """Least squares on the calibration horizons' normalized residuals over the free parameters
    of the dynamic effects ``names`` (the others held)."""
    x0, lo, hi, where = _pack(model, names)
    if x0.size == 0:
        return model.copy()
    x0 = np.clip(x0, _inside(lo, +1), _inside(hi, -1))
    top = model.effects.get("top_drive_dynamics", {}).get("variant") == "motor"
    size = (3 if top else 2) * int((~data.is_test).sum()) * data.L

    def res(x):
        try:
            return _residual_vector(_unpack(model, x, where), data, threads, top)
        except (ValueError, RuntimeError):  # an unstable or diverging trial: a large residual
            return np.full(size, 10.0)

    r = optimize.least_squares(res, x0, bounds=(lo, hi), method="trf", diff_step=1e-2, max_nfev=20 * x0.size,
                               x_scale="jac", xtol=1e-4, ftol=1e-4)
    return _unpack(model, r.x, where)


def _e_train(model: LoopModel, data: LoopData, threads: int) -> float:
    try:
        r = _residual_vector(model, data, threads)
    except (ValueError, RuntimeError):
        return math.inf
    with np.errstate(over="ignore", invalid="ignore"):
        e = float(np.sqrt(r @ r))
    return e if math.isfinite(e) else math.inf


def _best_start(model: LoopModel, data: LoopData, name: str, grid, threads: int) -> LoopModel:
    """The candidate start on a grid of parameter sets with the lowest calibration error."""
    best, err = None, math.inf
    for params in grid:
        m = model.copy()
        m.effects[name] = dict(params)
        e = _e_train(m, data, threads)
        if e < err:
            best, err = m, e
    return best


def _motor_inertia_floor(model: LoopModel, dt: float) -> float:
    """Smallest motor inertia the modified-Euler bound (Eq. A.7) allows at the engine step."""
    sim = _simulation(model.engine_config())
    rm = sim.reduced_matrices()
    coupling = abs(float(np.asarray(rm["top_load"]) @ np.asarray(rm["top_torque"])))
    wmax = math.pi / (5.0 * dt)
    w2 = float(np.max(np.linalg.eigvals(np.linalg.solve(rm["M"], rm["K"])).real))
    return 2.0 * coupling / max(wmax ** 2 - w2, 1e-12)


def fit_candidate(model: LoopModel, data: LoopData, name: str, threads: int = 0) -> LoopModel:
    """The model with effect ``name`` added and its parameters fitted on the calibration part (the
    parameters already in the model are held, except the law's for the law-level effects)."""
    m = model.copy()
    if name in ("bit_hysteresis", "wob_coupling"):
        m.effects[name] = {} if name == "bit_hysteresis" else {"gain": 1.0}
        return _calibrate(fit_law(m, data), data, threads)  # the law's new term on the law residual first
    chs = state_channels(m, data)
    tr = np.flatnonzero(data.valid & (data.t < data.t_split))
    if name == "top_drive_dynamics":
        motor = _calibrate(_best_start(m, data, name, _motor_starts(m, data, chs, tr), threads), data, threads)
        kin = m.copy()
        kin.effects[name] = {"variant": "measured"}
        kin = _calibrate(kin, data, threads)
        return motor if _e_train(motor, data, threads) <= _e_train(kin, data, threads) else kin
    if name == "sensor_lag":
        grid = [{"lowpass_hz": f} for f in (2.0, 4.0, 8.0, 16.0, 32.0)]
    elif name == "torque_fluctuation":
        grid = [{"tau_s": tau, "memory_s": mem} for tau in (0.1, 1.0, 10.0) for mem in (0.03, 0.3)]
    elif name == "viscous_damping":
        slip = data.valid & (chs["v"] > data.stick_threshold)
        cref = float(np.mean(chs["T"][slip]) / max(np.mean(chs["v"][slip]), 1e-9))
        grid = [{"bit_viscous_nms": f * cref} for f in (0.01, 0.05, 0.2)]
    else:
        raise ValueError(f"effect = {name!r}: unknown")
    best = _calibrate(_best_start(m, data, name, grid, threads), data, threads)
    if name == "torque_fluctuation":
        best.effects[name]["std"] = _eta_std(best, data)
    return best


def _motor_starts(model: LoopModel, data: LoopData, chs: dict, tr: np.ndarray) -> list:
    """Starting motor parameters: the motor equation J_m Omega' + c_m Omega - c_m Omega_c = -T_top
    is linear in (J_m, c_m, c_m Omega_c) given the top speed, its rate and the string's top torque of
    the states read off the record; least squares over the calibration part, plus a few droops."""
    sim = _simulation(model.engine_config())
    cv = model.effects.get("viscous_damping", {}).get("bit_viscous_nms", 0.0)
    i = tr[::max(1, int(round(0.005 / data.dt)))]
    top, dtop = chs["top"][i], chs["dtop"][i]
    ttop = np.asarray(_core.top_torque_from_bit(sim, chs["v"][i], chs["a"][i], chs["T"][i] + cv * chs["v"][i],
                                                top, dtop))
    jmin = 3.0 * _motor_inertia_floor(model, model.cfg["simulation"]["dt_s"])
    mean_top, mean_t = float(np.mean(top)), float(np.mean(ttop))
    starts = []
    A = np.column_stack([dtop, top, -np.ones(i.size)])
    (J, c, c_om), *_ = np.linalg.lstsq(A, -ttop, rcond=None)
    if J > jmin and c > 0:
        starts.append({"variant": "motor", "droop_rad_s_per_nm": float(np.clip(1.0 / c, 1e-3, 1e3)),
                       "inertia_kg_m2": float(J), "command_rad_s": float(c_om / c)})
    slope, icpt = np.polyfit(ttop, top, 1)  # quasi-static droop: Omega = Omega_c - T_top / c_m
    if slope < 0:
        droop = float(np.clip(-slope, 1e-3, 1e3))
        for tau in (0.01, 0.05):
            starts.append({"variant": "motor", "droop_rad_s_per_nm": droop, "inertia_kg_m2": max(tau / droop, jmin),
                           "command_rad_s": float(icpt)})
    for droop in (1.0, 4.0):
        starts.append({"variant": "motor", "droop_rad_s_per_nm": droop, "inertia_kg_m2": max(0.05 / droop, jmin),
                       "command_rad_s": mean_top + droop * mean_t})
    return starts


def _eta_std(model: LoopModel, data: LoopData) -> float:
    chs = law_channels(model, data)
    idx = data.law_train
    Tl = law_torque(model, chs, idx)
    ok = np.abs(Tl) > 0.1 * np.median(np.abs(Tl))
    return float(np.std(chs["T"][idx][ok] / Tl[ok] - 1.0, ddof=1))


def _calibrate(model: LoopModel, data: LoopData, threads: int = 0) -> LoopModel:
    """The law and every dynamic effect's parameters jointly on the calibration horizons, from the
    model's values (the same procedure for the baseline and for every candidate, so that a
    candidate gains only through its own parameters)."""
    return fit_dynamic(model, data, [LAW] + [e for e in model.effects if _free(model, e)], threads)


def refit(model: LoopModel, data: LoopData, threads: int = 0) -> LoopModel:
    """Calibrate every parameter of a model: the law (with its law-level effects) on the law
    residual as a start, then the law and the dynamic effects' parameters jointly on the
    calibration horizons. The calibration (never the validation) error decides whether the new
    start beats the model's own values."""
    m = _calibrate(fit_law(model, data), data, threads)
    if _e_train(model, data, threads) < _e_train(m, data, threads):
        m = model.copy()  # a candidate arrives calibrated: keep it if the fresh start does worse
    if "torque_fluctuation" in m.effects:
        m.effects["torque_fluctuation"]["std"] = _eta_std(m, data)
    return m


def calibrate(cfg: dict, data: LoopData, threads: int = 0) -> LoopModel:
    """The declared model calibrated on the calibration part: law, top speed and WOB (the means
    over the calibration part), and the parameters of the effects it declares."""
    tr = data.valid & (data.t < data.t_split)
    om = float(np.mean(data.ch["top"][tr])) if data.has_top else float(cfg["operation"]["top_speed_rad_s"])
    w0 = float(np.mean(data.ch["W"][tr])) if data.has_wob else float(cfg["operation"]["wob_n"])
    m = LoopModel(cfg, dict(cfg["law"]), om, w0, declared_effects(cfg))
    return refit(m, data, threads)


# ---------------------------------------------------------------------------------- evidence
def _autocorrelation_time(x: np.ndarray) -> float:
    x = np.asarray(x, float)
    if x.size < 3 or np.std(x) == 0:
        return 1.0
    return max(1.0, ident.autocorrelation_time(x))


def evidence(before: Evaluation, after: Evaluation, data: LoopData, n_candidates: int, opt: LoopOptions) -> dict:
    """The evidence for adding an effect: signature, validation improvement and its significance,
    information criterion, and the guard's decision."""
    te, tr = data.is_test, ~data.is_test
    gain = 1.0 - after.E_test / before.E_test
    d = np.log(before.e_h[te] / after.e_h[te])
    tau = _autocorrelation_time(d)
    k_eff = d.size / tau
    sd = float(np.std(d, ddof=1))
    tstat = float(np.mean(d) / (sd / math.sqrt(k_eff))) if sd > 0 else (math.inf if np.mean(d) > 0 else 0.0)
    p = float(stats.t.sf(tstat, max(k_eff - 1.0, 1.0)))
    Yv, YT = measured(data)
    rv = ((Yv - before.v) / data.sigma_v)[tr].ravel()
    rT = ((YT - before.T) / data.sigma_T)[tr].ravel()
    sv = ((after.v - before.v) / data.sigma_v)[tr].ravel()
    sT = ((after.T - before.T) / data.sigma_T)[tr].ravel()
    R, S = np.r_[rv, rT], np.r_[sv, sT]
    explained = float((R @ S) ** 2 / ((R @ R) * (S @ S))) if (S @ S) > 0 and (R @ R) > 0 else 0.0
    tau_r = 0.5 * (_autocorrelation_time(rv) + _autocorrelation_time(rT))
    n_eff = rv.size / tau_r
    dk = after.model.k - before.model.k
    dbic = float(n_eff * math.log(before.E_train ** 2 / after.E_train ** 2) - dk * math.log(n_eff))
    level = opt.alpha / max(n_candidates, 1)
    reasons = []
    if gain < opt.min_gain:
        reasons.append(f"validation gain {100 * gain:.1f} % < {100 * opt.min_gain:.0f} %")
    if not p < level:
        reasons.append(f"p = {p:.2g} >= {level:.2g}")
    if not dbic > opt.min_delta_bic:
        reasons.append(f"dBIC = {dbic:.1f} <= {opt.min_delta_bic:g}")
    return {"explained_fraction": explained, "error_train_before": before.E_train, "error_train_after": after.E_train,
            "error_test_before": before.E_test, "error_test_after": after.E_test, "relative_gain": gain,
            "t_statistic": tstat, "p_value": p, "level": level, "validation_horizons": int(d.size),
            "effective_horizons": k_eff, "delta_bic": dbic, "n_eff": n_eff, "added_parameters": dk,
            "law_rmse_train_before_nm": before.law_rmse_train, "law_rmse_train_after_nm": after.law_rmse_train,
            "law_rmse_test_before_nm": before.law_rmse_test, "law_rmse_test_after_nm": after.law_rmse_test,
            "accepted": not reasons, "reasons": reasons}


# ------------------------------------------------------------------------------------ the loop
@dataclass
class LoopResult:
    data: LoopData
    baseline: Evaluation
    final: Evaluation
    steps: list        #: dicts: effect, error_before, error_after, evidence (+ the evaluations)
    rounds: list       #: every round's candidates with their evidence
    options: LoopOptions
    config: dict       #: declared configuration (normalized, analysis time step)
    notes: list
    last_round: dict = field(default_factory=dict)  #: candidate -> Evaluation of the last round

    def metric(self) -> str:
        d = self.data
        return (f"normalized short-horizon prediction error E = sqrt(((v_pred - v)^2 / sd(v)^2 + (T_pred - T)^2 / "
                f"sd(T)^2) / 2), averaged over every sample of the validation part (t >= {d.t_split:.3f} s); "
                f"v bit speed, T torque on bit as recorded, sd over the calibration part (sd(v) = {d.sigma_v:.4g} "
                f"rad/s, sd(T) = {d.sigma_T:.4g} N m); predictions restarted every {self.options.horizon_s:g} s "
                f"from the measured state")

    def loop_json(self) -> dict:
        return {"metric": self.metric(), "baseline_error": self.baseline.E_test,
                "steps": [{"effect": s["effect"], "error_before": s["error_before"], "error_after": s["error_after"],
                           "evidence": s["evidence"]} for s in self.steps],
                "final_error": self.final.E_test, "parameters": self.final.model.parameters()}


def _analysis_config(cfg: dict, dt: float, dt_engine: float | None = None) -> dict:
    """The declared configuration with an engine step (``dt_engine`` or its own) that divides the
    analysis interval ``dt``."""
    c = copy.deepcopy(cfg)
    k = max(1, math.ceil(dt / (dt_engine or c["simulation"]["dt_s"]) - 1e-9))
    c["simulation"]["dt_s"] = dt / k
    c["simulation"]["duration_s"] = max(c["simulation"]["duration_s"], 2 * dt)
    c["simulation"]["transient_s"] = min(c["simulation"]["transient_s"], 0.5 * c["simulation"]["duration_s"])
    return normalize(c)


def run_loop(record, cfg: dict, options: LoopOptions | None = None, log=print) -> LoopResult:
    """Run the loop on a record (path or :class:`Record`) from the declared configuration ``cfg``."""
    opt = options or LoopOptions()
    opt.validate()
    cfg = normalize(cfg)
    data = prepare(record, cfg, opt)
    notes = []
    if cfg["rom"]["modes"] > 1:
        notes.append(f"the model keeps {cfg['rom']['modes']} modes: the restart state puts the first mode in "
                     "motion and the others in quasi-static equilibrium (exact only with one mode)")
    if cfg["simulation"]["scheme"] != "modified_euler":
        cfg = normalize({**cfg, "simulation": {**cfg["simulation"], "scheme": "modified_euler"}})
        notes.append("the loop integrates with the modified Euler scheme (the motor top drive needs it)")
    cfg = _analysis_config(cfg, data.dt, opt.dt_s)
    th = opt.threads
    log(f"record: {data.source}; {data.t.size} samples at {1 / data.dt:.0f} Hz; calibration t < {data.t_split:.2f} s "
        f"({int((~data.is_test).sum())} horizons), validation ({int(data.is_test.sum())} horizons of {opt.horizon_s:g} s)")
    base = evaluate(calibrate(cfg, data, th), data, th)
    log(f"baseline (declared model calibrated): validation error E = {base.E_test:.4f} (calibration {base.E_train:.4f}); "
        f"law residual RMSE {base.law_rmse_test:.4f} N m")
    cur, steps, rounds, last = base, [], [], {}
    for _ in range(opt.max_steps):
        cands = [e for e in opt.effects if e not in cur.model.effects
                 and all(c in data.channels() for c in CATALOGUE[e].needs)]
        if not cands:
            break
        results = []
        for name in cands:
            try:
                ev_model = fit_candidate(cur.model, data, name, th)
                ev = evaluate(ev_model, data, th)
                e = evidence(cur, ev, data, len(cands), opt)
                e["parameters"] = copy.deepcopy(ev_model.effects.get(name, {}))
            except (ValueError, RuntimeError) as err:  # a candidate the engine refuses is not evidence
                ev, e = None, {"accepted": False, "reasons": [f"fit failed: {err}"]}
            results.append((name, ev, e))
            log(f"  candidate {name:<20} " + (
                f"E_val {e['error_test_after']:.4f} (gain {100 * e['relative_gain']:+.1f} %), p {e['p_value']:.2g}, "
                f"dBIC {e['delta_bic']:.1f}, explained {e['explained_fraction']:.2f}"
                if ev is not None else e["reasons"][0]) + ("  <- passes" if e["accepted"] else ""))
        rounds.append([{"effect": n, **e} for n, _, e in results])
        last = {n: ev for n, ev, _ in results if ev is not None}
        ok = [(n, ev, e) for n, ev, e in results if e["accepted"]]
        if not ok:
            log("no candidate passes the guard: stop")
            break
        name, ev, e = min(ok, key=lambda r: r[1].E_test)
        new = evaluate(refit(ev.model, data, th), data, th)
        e = dict(e)
        e["error_test_refit"] = new.E_test
        e["parameters"] = copy.deepcopy(new.model.effects[name])
        e["candidates"] = rounds[-1]
        steps.append({"effect": name, "error_before": cur.E_test, "error_after": new.E_test, "evidence": e,
                      "before": cur, "candidate": ev, "after": new})
        log(f"step {len(steps)}: add {name}: validation error {cur.E_test:.4f} -> {new.E_test:.4f}")
        cur = new
    return LoopResult(data, base, cur, steps, rounds, opt, cfg, notes, last)


def loop_record(record, out_dir, *, preset: str | None = None, config_path: str | None = None,
                config: dict | None = None, options: LoopOptions | None = None, log=print) -> dict:
    """``drillpy loop``: run the loop and write ``loop.json``, ``evidence.json``, ``predictions.csv``,
    ``model.json``, ``report.md`` and the figures to ``out_dir``. Returns the content of loop.json."""
    from ..config import load_config
    from ..loop_report import write_outputs
    cfg = load_config(preset=preset, path=config_path, config=config)
    res = run_loop(record, cfg, options, log=log)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    js = write_outputs(res, out)
    log(f"loop.json, predictions.csv, report.md and figures written to {out}")
    return js


def dumps(o) -> str:
    """JSON text of plain and NumPy values (NaN and inf become null)."""
    from ..analysis import _jsonable
    return json.dumps(_jsonable(o), indent=2)
