"""The bit's equation of motion measured on a rig record, at the stick-slip cycle's frequency.

The one-mode string of the rig (thesis sections 2.2 and 5.1: the bar of Table 5.1 as one spring
k = 1 / sum L_i / (G_i J_p,i), the disk's inertia J at its end; Eq. 2.9 with one mode) gives, for the
fluctuations at the cycle's angular frequency w (complex amplitudes, the means removed),

    i w J v = (k / (i w) + c) (Omega_top - v) - T                                        (1)

with v the bit speed, Omega_top the top speed, T the torque on bit and c the string's damping. Per unit
of bit speed, Y = Omega_top / v (two encoders) and G = T / v (the load cell) are measured, so (1) says
which damping c the record needs:

    c = (i w J + G) / (Y - 1) - k / (i w).                                                (2)

A steel bar's c is small and real (2 zeta sqrt(k J), about 0.01 N m s/rad at zeta 0.03): a large or
reactive c says the record's channels do not follow (1) as declared, through the string's stiffness
or inertia or through the channels' timing. The same balance carries the energy of the cycle: the
contact torque feeds it by -Re(G) |v|^2 / 2 per unit time (the bit's negative damping), the drive
takes Re(Z) |Y|^2 |v|^2 / 2 and the string Re(c) |Y - 1|^2 |v|^2 / 2, with Z the drive's impedance at
the top encoder (the torque the drive gives per unit of top-speed drop, T_top = -Z Omega_top):

    Z = (k / (i w) + c) (1 / Y - 1),                                                       (3)

(the string's torque at the top, elastic and damping, per unit of top speed), a droop c_m behind a
rotor J_m giving Z = c_m + i w J_m. With a stretch of bar of stiffness k_a
between the drive and the top encoder, 1 / Z_drive = 1 / Z - i w / k_a.

The channels' timing is explicit: ``torque_lag_s`` (the load cell's reading that late after the
encoders: G is advanced by it) and ``top_lead_s`` (the top encoder's reading that early: Y is delayed
by it). :func:`timing_fit` estimates both from the whole record by least squares on (1) in the time
domain. docs/records.md, section 4, "The bit's equation at the cycle's frequency".
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy import signal as sps

from drillpy.model.configuration import Configuration
from drillpy.records.io import Flag, Record
from drillpy.records.signals import cycle_response


@dataclass(frozen=True)
class CycleBalance:
    """Eqs. (1)-(3) of the module on one record.

    Attributes
    ----------
    frequency_hz : float
        The cycle's frequency (the bit speed's Welch peak in 1-6 Hz) [Hz].
    top : complex
        Y, top speed per unit of bit speed, after the timing correction [-].
    torque : complex
        G, torque on bit per unit of bit speed, after the timing correction [N m s/rad].
    string_damping : complex
        c of Eq. (2) [N m s/rad].
    drive : complex
        Z of Eq. (3) at the top encoder [N m s/rad].
    drive_at_motor : complex
        Z with the stretch of bar above the encoder taken off (``stiffness_above``; equal to ``drive``
        without it) [N m s/rad]: its real part is the droop c_m, its imaginary part over w the rotor J_m.
    feed, drive_loss, string_loss : float
        The energy terms per unit |v|^2 (-Re G, Re(Z) |Y|^2, Re(c) |Y - 1|^2) [N m s/rad]; the first
        equals the sum of the other two.
    coherence : float
        The smaller coherence of the top speed and the torque with the bit speed at the frequency.
    """
    frequency_hz: float
    top: complex
    torque: complex
    string_damping: complex
    drive: complex
    drive_at_motor: complex
    feed: float
    drive_loss: float
    string_loss: float
    coherence: float

    @property
    def motor_inertia(self) -> float:
        """Im(Z at the motor) / w: the rotor's inertia the drive shows [kg m^2]."""
        return self.drive_at_motor.imag / (2.0 * math.pi * self.frequency_hz)


def string_of(config) -> tuple:
    """(k [N m/rad], J [kg m^2]) of a configuration's string as one spring and one inertia: the
    sections' compliances L / (G J_p) summed (G = E / (2 (1 + nu))), the inertia lumped at the last
    node plus a third of the string's own (the fixed-free bar's first-mode share).

    Parameters
    ----------
    config : dict or Configuration
        Engine configuration (e.g. ``drillpy.load_config(preset="thesis-rig")``).

    Returns
    -------
    tuple
        (k, J).
    """
    c = Configuration.of(config)
    compliance, inertia = 0.0, 0.0
    n_nodes = 1
    for s in c.string.sections:
        jp = math.pi * (s.outer_radius_m ** 4 - s.inner_radius_m ** 4) / 2.0
        g = s.youngs_modulus_pa / (2.0 * (1.0 + s.poisson_ratio))
        compliance += s.length_m / (g * jp)
        inertia += s.density_kg_m3 * jp * s.length_m
        n_nodes += s.elements
    bit = sum(li.inertia_kg_m2 for li in c.string.lumped_inertias if li.node in (-1, n_nodes - 1))
    return 1.0 / compliance, bit + inertia / 3.0


#: Samples the balance needs [s of the record's rate].
MIN_BALANCE_S = 4.0


def _usable(record: Record, valid: np.ndarray | None) -> np.ndarray:
    """The samples with the bit speed, the top speed and the torque (and ``valid``)."""
    ok = record.valid("bit_speed", "top_speed", "torque_on_bit")
    return ok & np.asarray(valid, bool) if valid is not None else ok


def _channels(record: Record, valid: np.ndarray | None) -> tuple:
    """Bit speed, top speed and torque on the record's grid, excluded samples interpolated over."""
    ok = _usable(record, valid)
    if ok.sum() < MIN_BALANCE_S / record.dt:
        raise ValueError(f"record: {int(ok.sum())} samples with the bit speed, the top speed and the torque; "
                         f"the balance needs {MIN_BALANCE_S:g} s of them")
    t = record.time_s
    return tuple(np.interp(t, t[ok], x[ok]) for x in (record.bit_speed, record.top_speed, record.torque_on_bit))


def cycle_balance(record: Record, stiffness: float, inertia: float, *, torque_lag_s: float = 0.0,
                  top_lead_s: float = 0.0, stiffness_above: float | None = None,
                  valid: np.ndarray | None = None) -> CycleBalance:
    """The bit's equation at the cycle's frequency (module Eqs. 1-3).

    Parameters
    ----------
    record : Record
        A record with bit speed, top speed and torque on bit (the rig's: all three through one filter).
    stiffness : float
        k, the string between the two encoders as one spring [N m/rad] (:func:`string_of`).
    inertia : float
        J, the bit's inertia [kg m^2].
    torque_lag_s : float
        How late the torque channel reads after the encoders [s].
    top_lead_s : float
        How early the top encoder reads against the bit encoder [s].
    stiffness_above : float, optional
        A stretch of string between the drive and the top encoder [N m/rad] (None: the encoder at the
        drive).
    valid : numpy.ndarray, optional
        Samples to use (default: where the three channels are valid); the others are interpolated over.

    Returns
    -------
    CycleBalance

    Raises
    ------
    ValueError
        For a non-positive stiffness or inertia (naming it), fewer than 4 s of usable samples, or no
        cycle in 1-6 Hz.
    """
    for name, x in (("stiffness", stiffness), ("inertia", inertia)):
        if not (math.isfinite(x) and x > 0):
            raise ValueError(f"{name} = {x!r}: must be a positive number")
    if stiffness_above is not None and not (math.isfinite(stiffness_above) and stiffness_above > 0):
        raise ValueError(f"stiffness_above = {stiffness_above!r}: must be a positive number (or None)")
    v, top, tq = _channels(record, valid)
    fs = 1.0 / record.dt
    ry, rt = cycle_response(v, top, fs), cycle_response(v, tq, fs)
    f = ry["frequency_hz"]
    if not (math.isfinite(f) and np.isfinite(ry["response"]) and np.isfinite(rt["response"])):
        raise ValueError(f"record: no cycle in the bit speed between 1 and 6 Hz at {fs:.4g} Hz sampling (or a constant "
                         f"top speed or torque): the balance needs the cycle's frequency")
    w = 2.0 * math.pi * f
    Y = ry["response"] * np.exp(-1j * w * top_lead_s)
    G = rt["response"] * np.exp(1j * w * torque_lag_s)
    c = (1j * w * inertia + G) / (Y - 1.0) - stiffness / (1j * w)  # Eq. (2)
    Z = (stiffness / (1j * w) + c) * (1.0 / Y - 1.0)  # Eq. (3)
    Zm = Z if stiffness_above is None else 1.0 / (1.0 / Z - 1j * w / stiffness_above)
    return CycleBalance(f, complex(Y), complex(G), complex(c), complex(Z), complex(Zm), float(-G.real),
                        float(Z.real * abs(Y) ** 2), float(c.real * abs(Y - 1.0) ** 2),
                        float(min(ry["coherence"], rt["coherence"])))


def timing_scan(record: Record, stiffness: float, inertia: float, top_leads_s, torque_lags_s, *,
                valid: np.ndarray | None = None) -> list:
    """:func:`cycle_balance` over a grid of channel timings, the string held: the timings with which
    the bit's equation balances best, i.e. with the smallest |c| of Eq. (2).

    Parameters
    ----------
    record : Record
        As for :func:`cycle_balance`.
    stiffness, inertia : float
        k [N m/rad] and J [kg m^2] (:func:`string_of`).
    top_leads_s, torque_lags_s : sequence of float
        The grid [s].
    valid : numpy.ndarray, optional
        As for :func:`cycle_balance`.

    Returns
    -------
    list of (float, float, CycleBalance)
        (top lead [s], torque lag [s], balance), the smallest |c| first.
    """
    rows = [(float(lead), float(lag), cycle_balance(record, stiffness, inertia, torque_lag_s=lag, top_lead_s=lead,
                                                    valid=valid))
            for lead in top_leads_s for lag in torque_lags_s]
    return sorted(rows, key=lambda r: abs(r[2].string_damping))


def timing_fit(record: Record, top_leads_s, torque_lags_s, *, stiffness: float | None = None,
               inertia: float | None = None, highpass_hz: float = 0.5, valid: np.ndarray | None = None) -> list:
    """Eq. (1) in the time domain over a grid of channel timings: for each (top lead, torque lag),
    T(t + lag) = k phi(t) - J a(t) fitted by least squares, with phi the twist integrated from the
    encoders (the top read ``top lead`` earlier) and a the bit's acceleration (Savitzky-Golay, 31
    samples, order 3), all three high-passed at ``highpass_hz`` (the twist's drift is the encoders'
    offset, the torque's slow part the WOB's trend). Every sample of the record (excluded ones
    interpolated over), the first and last 0.2 s left out. k and J trade against the lag here: the
    frequency-domain balance (:func:`cycle_balance`) with the string's k and J is the sharper test.

    Parameters
    ----------
    record : Record
        As for :func:`cycle_balance`.
    top_leads_s, torque_lags_s : sequence of float
        The grid [s].
    stiffness, inertia : float, optional
        k [N m/rad] and J [kg m^2] held (both given: nothing is fitted, R^2 scores the timing alone);
        default: fitted at every grid point.
    highpass_hz : float
        The twist's high-pass (its drift is the encoders' offset) [Hz].
    valid : numpy.ndarray, optional
        As for :func:`cycle_balance`.

    Returns
    -------
    list of dict
        One per grid point, best R^2 first: ``top_lead_s``, ``torque_lag_s``, ``r2``, ``stiffness``
        [N m/rad], ``inertia`` [kg m^2].
    """
    v, top, tq = _channels(record, valid)
    dt = record.dt
    b, aa = sps.butter(2, highpass_hz * 2.0 * dt, "high")
    a = sps.filtfilt(b, aa, sps.savgol_filter(v, 31, 3, deriv=1, delta=dt))
    tq = sps.filtfilt(b, aa, tq)
    edge = int(round(0.2 / dt))
    sl = slice(edge, v.size - edge)
    rows = []
    for lead in top_leads_s:
        d = int(round(lead / dt))
        phi = sps.filtfilt(b, aa, np.cumsum(np.roll(top, d) - v) * dt)
        for lag in torque_lags_s:
            y = np.roll(tq, -int(round(lag / dt)))[sl]
            A = np.column_stack([phi[sl], -a[sl]])
            if stiffness is None or inertia is None:
                x, *_ = np.linalg.lstsq(A, y, rcond=None)
            else:
                x = np.array([stiffness, inertia], float)
            r = y - A @ x
            rows.append({"top_lead_s": float(lead), "torque_lag_s": float(lag), "r2": float(1.0 - r @ r / (y @ y)),
                         "stiffness": float(x[0]), "inertia": float(x[1])})
    return sorted(rows, key=lambda r: -r["r2"])


#: The timing grid of :func:`summary` [s]: 10 ms steps, the top encoder up to 80 ms early and the torque
#: up to 80 ms late (and 20 ms the other way).
TIMING_GRID_S = tuple(np.round(np.arange(-0.02, 0.0801, 0.01), 3))
#: Above this |c| [N m s/rad] the bit's equation does not balance: ten times a steel bar's damping
#: (2 zeta sqrt(k J), about 0.01 at zeta 0.03 on the rig).
UNBALANCED_NMS = 0.05


def summary(record: Record, config, valid: np.ndarray | None = None) -> dict:
    """The balance of the bit's equation at the cycle's frequency with the configuration's string,
    as recorded and at the channel timing that balances it best (:func:`timing_scan` on
    :data:`TIMING_GRID_S`), for ``drillpy analyze``'s summary.

    One frequency fixes one combination of the two timings (nearly their sum: the top encoder's lead
    over the torque); :func:`timing_fit` splits it on the whole band.

    Parameters
    ----------
    record : Record
        With bit speed, top speed and torque on bit.
    config : dict or Configuration
        The declared model (its string: :func:`string_of`).
    valid : numpy.ndarray, optional
        As for :func:`cycle_balance`.

    Returns
    -------
    dict
        ``stiffness_nm_rad``, ``inertia_kg_m2``, ``frequency_hz``, ``coherence``, ``as_recorded`` and
        ``best`` (each: ``top_lead_s``, ``torque_lag_s``, ``string_damping`` [re, im], ``motor_slope``,
        ``motor_inertia``, ``feed``, ``drive_loss``, ``string_loss``), ``balanced`` (the timings within
        :data:`UNBALANCED_NMS` / 5 of a balance, as [lead, lag] pairs) and ``statement``.
    """
    k, J = string_of(config)
    rows = timing_scan(record, k, J, TIMING_GRID_S, TIMING_GRID_S, valid=valid)

    def entry(lead, lag, b):
        c = b.string_damping
        return {"top_lead_s": lead, "torque_lag_s": lag, "string_damping": [c.real, c.imag],
                "motor_slope": b.drive_at_motor.real, "motor_inertia": b.motor_inertia, "feed": b.feed,
                "drive_loss": b.drive_loss, "string_loss": b.string_loss}
    raw = next(r for r in rows if r[0] == 0.0 and r[1] == 0.0)
    best = rows[0]
    out = {"stiffness_nm_rad": k, "inertia_kg_m2": J, "frequency_hz": raw[2].frequency_hz,
           "coherence": raw[2].coherence, "as_recorded": entry(*raw), "best": entry(*best),
           "balanced": [[r[0], r[1]] for r in rows if abs(r[2].string_damping) <= UNBALANCED_NMS / 5]}
    c0, c1 = raw[2].string_damping, best[2].string_damping
    if abs(c0) <= UNBALANCED_NMS:
        out["statement"] = (f"the bit's equation balances at the cycle's frequency as recorded (string damping "
                            f"{abs(c0):.3f} N m s/rad needed)")
    else:
        out["statement"] = (
            f"the bit's equation does not balance at the cycle's frequency ({raw[2].frequency_hz:.2f} Hz) as recorded: "
            f"it needs a string damping of {c0.real:+.3f}{c0.imag:+.3f}i N m s/rad (a steel bar's: about +0.01); "
            f"with the top encoder {1e3 * best[0]:.0f} ms early and the torque {1e3 * best[1]:.0f} ms late it needs "
            f"{c1.real:+.4f}{c1.imag:+.4f}i, and the drive is then c_m {best[2].drive_at_motor.real:.3f} N m s/rad with a "
            f"{best[2].motor_inertia:.4f} kg m^2 rotor; one frequency fixes about the sum of the two timings "
            f"(drillpy.records.bit_balance)")
    return out


#: Blocks the window is cut into for the drive's interval (:func:`drive_interval`).
DRIVE_BLOCKS = 4
#: The relative error of c_m and J_m from the string reduced to one spring and one inertia, taken into
#: the drive's interval (:func:`drive_interval`): on simulated rigs whose drive is known the balance
#: reads c_m 5 % and J_m 7 % high (drillpy's whole-rig model: 0.263 against 0.250, 0.0199 against
#: 0.0186 kg m^2) and c_m 1-5 % high on ``benchmarks/whole_rig.py``'s ten-segment string
#: (``tests/python/test_bit_balance.py``).
REDUCTION_ERROR = 0.08


def drive_interval(record: Record, config, balance: dict, valid: np.ndarray | None = None,
                   blocks: int = DRIVE_BLOCKS) -> dict:
    """95 % intervals of the drive the balance shows (c_m and J_m of ``balance["best"]``), from its two
    sources of uncertainty, the wider at each end:

    * the channels' timing: one frequency fixes about the sum of the two shifts, so every timing of
      ``balance["balanced"]`` balances the equation as well; the range of c_m and J_m over them;
    * the window: the balance at the best timing on ``blocks`` equal blocks of the window, the mean
      +- t(0.975, n - 1) sd / sqrt(n) over the n blocks with the samples the balance needs (a block
      whose artifacts leave too few is left out and said; with fewer than two this term is absent);
    * the string reduced to one spring and one inertia: +- :data:`REDUCTION_ERROR` of the value.

    Parameters
    ----------
    record : Record
        The window the balance was measured on.
    config : dict or Configuration
        The declared model (its string: :func:`string_of`).
    balance : dict
        :func:`summary` of ``record``.
    valid : numpy.ndarray, optional
        As for :func:`cycle_balance`.
    blocks : int
        At least 2; each block needs the 4 s :func:`cycle_balance` needs.

    Returns
    -------
    dict
        ``motor_slope`` and ``motor_inertia``: ``[low, high]`` [N m s/rad], [kg m^2]; ``blocks`` (per
        block: ``t0_s``, ``motor_slope``, ``motor_inertia``, or ``skipped`` with the reason) and ``timings`` (the balanced [lead, lag]
        pairs with their values).

    Raises
    ------
    ValueError
        For fewer than 2 blocks or a block too short for the balance (naming ``blocks``).
    """
    from scipy import stats
    if not (isinstance(blocks, int) and blocks >= 2):
        raise ValueError(f"blocks = {blocks!r}: an integer of at least 2")
    k, J = string_of(config)
    best = balance["best"]
    lead, lag = best["top_lead_s"], best["torque_lag_s"]
    t = record.time_s
    edges = np.linspace(t[0], t[-1], blocks + 1)
    per = []
    for a, b in zip(edges[:-1], edges[1:]):
        sel = (t >= a) & (t <= b)
        if b - a < 4.0:
            raise ValueError(f"blocks = {blocks}: blocks of {b - a:.2f} s, the balance needs 4 s each")
        try:
            cb = cycle_balance(record.take(np.flatnonzero(sel)), k, J, torque_lag_s=lag, top_lead_s=lead,
                               valid=None if valid is None else np.asarray(valid, bool)[sel])
        except ValueError as e:  # a block whose artifacts leave less than the balance needs: left out, said
            per.append({"t0_s": float(a), "skipped": str(e)})
            continue
        per.append({"t0_s": float(a), "motor_slope": cb.drive_at_motor.real, "motor_inertia": cb.motor_inertia})
    used = [p for p in per if "skipped" not in p]
    timings = []
    for ld, lg in balance["balanced"]:
        cb = cycle_balance(record, k, J, torque_lag_s=lg, top_lead_s=ld, valid=valid)
        timings.append({"top_lead_s": ld, "torque_lag_s": lg, "motor_slope": cb.drive_at_motor.real,
                        "motor_inertia": cb.motor_inertia})
    out = {"blocks": per, "timings": timings}
    for key in ("motor_slope", "motor_inertia"):
        x = np.array([p[key] for p in used])
        half = (float(stats.t.ppf(0.975, x.size - 1)) * float(np.std(x, ddof=1)) / math.sqrt(x.size)
                if x.size >= 2 else 0.0)
        vals = [best[key]] + [r[key] for r in timings]
        model = REDUCTION_ERROR * abs(best[key])
        out[key] = [min(min(vals), best[key] - half, best[key] - model), max(max(vals), best[key] + half, best[key] + model)]
    return out


#: R^2 within which two timings of :func:`identify_timing` are as good: the smaller shift is taken.
TIMING_R2_TIE = 1e-3
#: The bit's equation must hold at a timing (R^2 at least this) for the timing to be the acquisition's
#: (sample 175: 0.94 on 0-20 s, 0.88 on 20-40 s).
TIMING_MIN_R2 = 0.8
#: ... and it must fail as recorded by at least this much more. With the string's k and J fitted at every
#: timing, a string softer or with more modes than declared is read as a string, not as a skew: the
#: validation suite's motor truths and its motor with a string's GJ x 0.85 gain 0.015-0.039 from their
#: best shifts; sample 175's acquisition gains 0.22 and 0.29.
TIMING_MIN_GAIN = 0.1
#: The largest channel shift :func:`aligned` takes [s] (far beyond any acquisition's skew).
MAX_SHIFT_S = 0.2


def identify_timing(record: Record, config, valid: np.ndarray | None = None) -> dict:
    """The channels' timing that balances the bit's equation best on the whole band, the string's
    stiffness and inertia fitted at every timing (:func:`timing_fit` on :data:`TIMING_GRID_S`), so that a
    string that differs from the declared one is read as a string and not as a skew: on sample 175 the
    top encoder 40 ms early and the torque 30 ms late on 0-20 s, 50 and 30 ms on 20-40 s (docs/records.md,
    section 4). Of the timings within :data:`TIMING_R2_TIE` of the best R^2, the smallest shift: where
    the top speed is steady its lead changes nothing and stays 0.

    Parameters
    ----------
    record : Record
        A cleaned record with bit speed, top speed and torque on bit.
    config : dict or Configuration
        The declared model: its string's stiffness is reported beside the fitted one.
    valid : numpy.ndarray, optional
        As for :func:`cycle_balance`.

    Returns
    -------
    dict
        ``top_lead_s``, ``torque_lag_s`` [s], ``r2`` (the fit's), ``r2_as_recorded`` (no shift),
        ``stiffness_nm_rad`` (the fit's k at the timing), ``declared_stiffness_nm_rad`` and
        ``skew``: True when the timing is the acquisition's skew, False when the shifts are 0 or the
        record does not identify one (the equation does not hold at the best timing, R^2 below
        :data:`TIMING_MIN_R2`, or holds nearly as well as recorded, a gain below
        :data:`TIMING_MIN_GAIN`: then the shifts are those of the best fit; or the record holds less
        than :data:`MIN_BALANCE_S` of usable samples: shifts 0, R^2 None); with False, ``reason``
        says why.
    """
    k = string_of(config)[0]
    n = int(_usable(record, valid).sum())
    if n < MIN_BALANCE_S / record.dt:  # too short a record to say: read as recorded
        return {"top_lead_s": 0.0, "torque_lag_s": 0.0, "r2": None, "r2_as_recorded": None, "stiffness_nm_rad": None,
                "declared_stiffness_nm_rad": k, "skew": False,
                "reason": f"{n * record.dt:.2f} s of samples with the bit speed, the top speed and the torque; the "
                          f"bit's equation needs {MIN_BALANCE_S:g} s to tell a skew"}
    rows = timing_fit(record, TIMING_GRID_S, TIMING_GRID_S, valid=valid)  # k and J fitted at every timing
    raw = next(r for r in rows if r["top_lead_s"] == 0.0 and r["torque_lag_s"] == 0.0)
    # the smallest shift among those as good as the best: a steady top speed says nothing of its lead
    near = [r for r in rows if r["r2"] >= rows[0]["r2"] - TIMING_R2_TIE]
    best = min(near, key=lambda r: (abs(r["top_lead_s"]) + abs(r["torque_lag_s"]), -r["r2"]))
    out = {"top_lead_s": best["top_lead_s"], "torque_lag_s": best["torque_lag_s"], "r2": best["r2"],
           "r2_as_recorded": raw["r2"], "stiffness_nm_rad": best["stiffness"], "declared_stiffness_nm_rad": k,
           "skew": False}
    if best["top_lead_s"] == 0.0 and best["torque_lag_s"] == 0.0:
        out["reason"] = "the bit's equation holds best as recorded"
        return out
    if best["r2"] < TIMING_MIN_R2:
        out["reason"] = (f"the bit's equation does not hold at any timing (R^2 {best['r2']:.3f} at the best, below "
                         f"{TIMING_MIN_R2:g}): the one-spring string, not the acquisition, is what it misses")
    elif best["r2"] - raw["r2"] < TIMING_MIN_GAIN:
        out["reason"] = (f"the shift gains R^2 {best['r2'] - raw['r2']:.3f} only (below {TIMING_MIN_GAIN:g}): what a "
                         "one-spring reading of a string with more modes makes up, not an acquisition's skew")
    else:
        out["skew"] = True
    return out


def resolve_timing(record: Record, option, config, valid: np.ndarray | None = None) -> dict | None:
    """The channels' timing of a ``--channel-timing`` option on a cleaned calibration part.

    Parameters
    ----------
    record : Record
        The calibration part (``auto`` identifies the timing on it only).
    option : str or tuple
        ``"none"``, ``"auto"`` or (top lead, torque lag) [s].
    config : dict or Configuration
        The declared model (:func:`identify_timing`).
    valid : numpy.ndarray, optional
        As for :func:`cycle_balance`.

    Returns
    -------
    dict or None
        None for ``"none"``; else ``top_lead_s``, ``torque_lag_s`` [s] and ``from`` (``"auto"`` or
        ``"given"``): with ``auto``, :func:`identify_timing`'s result where it finds a skew, else zero
        shifts with that result under ``refused``.
    """
    if option == "none":
        return None
    if option != "auto":
        return timing_of({"top_lead_s": option[0], "torque_lag_s": option[1], "from": "given"})
    found = identify_timing(record, config, valid=valid)
    if found["skew"]:
        return {**found, "from": "auto"}
    return {"top_lead_s": 0.0, "torque_lag_s": 0.0, "from": "auto", "refused": found}


def applied_timing(timing: dict | None) -> dict | None:
    """What a model file keeps of a :func:`resolve_timing` result.

    Parameters
    ----------
    timing : dict or None
        A :func:`resolve_timing` result.

    Returns
    -------
    dict or None
        The shifts the record was read at, None when there were none (as recorded, or ``auto``
        without a skew).
    """
    if not timing or not (timing["top_lead_s"] or timing["torque_lag_s"]):
        return None
    return {k: v for k, v in timing.items() if k != "refused"}


def timing_line(timing: dict | None) -> str:
    """One line saying how the channels are read (the logs of ``drillpy loop`` and ``analyze``).

    Parameters
    ----------
    timing : dict or None
        A :func:`resolve_timing` result.

    Returns
    -------
    str
        The line.
    """
    if timing is None:
        return "channels read as recorded"
    if "refused" in timing:
        r = timing["refused"]
        return (f"channels read as recorded: {r['reason']} (best shift: the top speed {1e3 * r['top_lead_s']:.0f} ms "
                f"later, the torque {1e3 * r['torque_lag_s']:.0f} ms earlier)")
    how = (f"the bit's equation, the string's k and J fitted: R^2 {timing['r2']:.3f}, {timing['r2_as_recorded']:.3f} "
           "as recorded" if timing["from"] == "auto" else "as given")
    return (f"channels brought to the bit encoder's time: the top speed read {1e3 * timing['top_lead_s']:.0f} ms "
            f"later, the torque {1e3 * timing['torque_lag_s']:.0f} ms earlier ({how})")


def aligned(record: Record, top_lead_s: float, torque_lag_s: float) -> Record:
    """The record with its channels brought to the bit encoder's time: the top speed read
    ``top_lead_s`` later (it was that early), the torque ``torque_lag_s`` earlier (it was that late),
    to the nearest sample. Each reading's flags move with it; the samples a shift leaves without a
    reading are NaN and flagged non-finite, which the cleaning excludes
    (:func:`drillpy.records.cleaning.clean`); the other channels are untouched.

    Parameters
    ----------
    record : Record
        The record, raw or cleaned (its flags then stay on their readings).
    top_lead_s, torque_lag_s : float
        The shifts [s], each within +-:data:`MAX_SHIFT_S`.

    Returns
    -------
    Record
        A copy.

    Raises
    ------
    ValueError
        For a shift that is not finite or beyond :data:`MAX_SHIFT_S` (naming it), or a shift of a
        channel the record lacks.
    """
    out, flags = {}, dict(record.flags)
    for name, shift, channel, sign in (("top_lead_s", top_lead_s, "top_speed", 1),
                                       ("torque_lag_s", torque_lag_s, "torque_on_bit", -1)):
        if not (math.isfinite(shift) and abs(shift) <= MAX_SHIFT_S):
            raise ValueError(f"{name} = {shift!r}: must be a finite shift within +-{MAX_SHIFT_S:g} s")
        n = int(round(shift / record.dt))
        if n == 0:
            continue
        x = getattr(record, channel)
        if x is None:
            raise ValueError(f"{name} = {shift!r}: the record has no {channel} channel to shift")
        n *= sign  # > 0: the reading moves later
        out[channel] = _shifted(np.asarray(x, float), n, np.nan)
        # a reading's flags travel with it (a cleaned record's artifacts stay on their samples)
        flags[channel] = _shifted(record.flags[channel], n, int(Flag.NONFINITE))
    return dataclasses.replace(record, flags=flags, **out)


def timing_of(d) -> dict | None:
    """The channels' timing a model file keeps (``channel_timing``: ``top_lead_s``, ``torque_lag_s``
    [s], and how it was found), checked; None when the file has none (the record as recorded).

    Parameters
    ----------
    d : dict or None
        The ``channel_timing`` entry of a ``model.json``.

    Returns
    -------
    dict or None
        ``d`` with its two shifts as floats.

    Raises
    ------
    ValueError
        For a shift that is missing, not a finite number, or beyond :data:`MAX_SHIFT_S` (naming
        the entry and its value).
    """
    if d is None:
        return None
    try:
        lead, lag = float(d["top_lead_s"]), float(d["torque_lag_s"])
    except (KeyError, TypeError, ValueError):
        lead = lag = float("nan")
    if not all(math.isfinite(x) and abs(x) <= MAX_SHIFT_S for x in (lead, lag)):
        raise ValueError(f"model: channel_timing = {d!r}: needs 'top_lead_s' and 'torque_lag_s' [s], finite "
                         f"shifts within +-{MAX_SHIFT_S:g} s")
    return {**d, "top_lead_s": lead, "torque_lag_s": lag}


def _shifted(x: np.ndarray, n: int, fill) -> np.ndarray:
    """``x`` moved ``n`` samples later (earlier for n < 0), the vacated samples ``fill``."""
    y = np.full_like(x, fill)
    if n > 0:
        y[n:] = x[:-n]
    else:
        y[:n] = x[-n:]
    return y
