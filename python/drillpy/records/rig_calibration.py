"""Calibration of the rig model on a record: the drive and damping of the thesis's chapter-5 model
(:func:`calibrate`, :func:`select_model` across laws) and the rig modelled whole (:func:`calibrate_rig`:
motor, jack, platform, bar and disk inside their physical ranges, ``rigsim.RIG_PARAMETERS``).

Each search's trial configurations are judged by their bounds, not by the typed-input check
(:func:`drillpy.model.plausibility.fitted_values`).
"""
from __future__ import annotations

import math
import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
from scipy import optimize

from drillpy.model.plausibility import fitted_values
from drillpy.records.io import Record
from drillpy.records.rigsim import (DRIVES, MATCHED, MATCHED_RIG, RIG_PARAMETERS, RigModel, operating_point,
                                    reliable_top_speed, simulate_model, simulate_models)
from drillpy.records.rig_comparison import (RigComparison, compare, measured_side, metric_scale, record_metrics,
                                            outside_stalls, relative_error)


def scale_of(record: Record, stick_threshold: float) -> dict:
    """The scale of the short-horizon error E on the calibration record (``model.json`` ->
    ``calibration.metric_scale``; :func:`drillpy.records.rig_comparison.metric_scale`): every
    record a model predicts is scored on the scale it was calibrated with, as the loop does.

    Parameters
    ----------
    record : Record
        The calibration record (cleaned).
    stick_threshold : float
        Bit speed at or below which the bit is stuck [rad/s].
    """
    ok = record.valid("bit_speed") & record.valid("torque_on_bit")
    sv, sT = metric_scale(record.bit_speed, record.torque_on_bit, ok, record.dt, stick_threshold)
    out = {"bit_speed_rad_s": sv, "torque_on_bit_nm": sT,
           "from": "the calibration window's spreads, stalls left out: E of drillpy predict is on this scale"}
    if record.wob is not None:  # the WOB's term of the calibration's E, the stalls left out as well
        w = outside_stalls(record.bit_speed, record.valid("wob") & np.isfinite(record.wob), record.dt, stick_threshold)
        if w.sum() > 1 and np.std(record.wob[w]) > 0:
            out["wob_n"] = float(np.std(record.wob[w]))
    return out


@dataclass
class Calibration:
    """What :func:`calibrate` found: the chosen model, its comparison on the calibration part and,
    per drive, the best model with its mismatch and the points scanned.

    Attributes
    ----------
    model : RigModel
        The drive and parameters with the smallest mismatch, ``calibration`` filled in.
    comparison : RigComparison
        The chosen model against the calibration record.
    per_drive : dict
        Drive -> ``damping_ratio``, ``mismatch`` and ``scan`` (the (ratio, mismatch) pairs
        tried) for the constant and measured drives; ``damping_ratio``, ``motor_slope_nms_rad``,
        ``motor_inertia_kg_m2``, ``mismatch`` and ``evaluations`` for the motor.
    """
    model: RigModel
    comparison: RigComparison
    per_drive: dict

    def summary(self) -> dict:
        """The calibration as a JSON-ready dict.

        Returns
        -------
        dict
            ``drive``, ``damping_ratio``, ``motor_slope_nms_rad``, ``motor_inertia_kg_m2``,
            ``mismatch``, the ``measured`` and ``simulated`` metrics, and ``per_drive``.
        """
        return {"drive": self.model.drive, "damping_ratio": self.model.damping_ratio,
                "motor_slope_nms_rad": self.model.motor_slope_nms_rad,
                "motor_inertia_kg_m2": self.model.motor_inertia_kg_m2,
                "mismatch": self.comparison.mismatch, "measured": self.comparison.measured,
                "simulated": self.comparison.simulated,
                "per_drive": self.per_drive}


@fitted_values()
def calibrate(record: Record, law: dict, stick_threshold: float, *, drives=DRIVES, preset: str = "thesis-rig",
              log=None, threads: int = 0) -> Calibration:
    """Calibrate the effective damping ratio and the top drive of the rig model with ``law`` on a
    cleaned ``record``: for each drive the parameters with the smallest mismatch (rms relative
    error over :data:`MATCHED`, :func:`compare`), then the drive with the smallest mismatch.

    The mismatch is not smooth in the parameters (stick-slip cycles appear and vanish), so each
    drive is searched on a grid first: the damping ratio on 14 log-spaced values in [0.01, 1.5]
    refined once around the best; for the motor, damping x slope c_m x inertia J_m on a 4 x 5 x 3
    log grid, then a Nelder-Mead polish in the logarithms from the best grid point. The motor's
    command always reproduces the record's reliable mean top speed (:func:`simulate_model`).
    A parameter set whose simulation fails (unstable, diverged) counts as an infinite mismatch.
    The grid points are independent simulations. A damping scan's models differ in their damping
    only: its points run in one call, in SIMD lockstep (:func:`simulate_models`); the motor's points
    run ``threads`` at a time (the engine releases the GIL). The results do not depend on the
    thread count.

    Parameters
    ----------
    record : Record
        The cleaned calibration part of a record, with top speed, bit speed and torque.
    law : dict
        Engine bit-rock law, identified on the same data (Eq. 5.1 or 5.3).
    stick_threshold : float
        Bit speed at or below which the bit counts as stuck [rad/s] (:func:`stick_threshold`).
    drives : iterable of str
        Drives tried, from :data:`DRIVES` (``rig``: :func:`calibrate_rig`).
    preset : str
        Engine preset of the rig.
    log : callable, optional
        Called with one progress line (str) per drive.
    threads : int
        Grid points simulated at once (0: one per core).

    Returns
    -------
    Calibration

    Raises
    ------
    ValueError
        For an unknown drive, or when the operating point cannot be taken.
    """
    drives = tuple(drives)
    for d in drives:
        if d not in DRIVES:
            raise ValueError(f"drives: unknown drive {d!r} (use {', '.join(DRIVES)})")
    op = operating_point(record)
    cache = {}

    def mismatch(drive, z, cm=None, J=None):
        key = (drive, round(z, 12), cm and round(cm, 12), J and round(J, 12))
        if key not in cache:
            try:
                m = RigModel(law, float(z), drive, cm, J, preset=preset)
                cache[key] = compare(record, simulate_model(m, record), stick_threshold).mismatch
            except (ValueError, RuntimeError):  # outside the stability bound, diverged, ...
                cache[key] = math.inf
        return cache[key]

    def scan_of(drive, grid):
        if drive == "motor":  # each point searches its own command: one simulate_model per point
            with ThreadPoolExecutor(max_workers=workers) as pool:
                return list(zip(grid, pool.map(lambda p: mismatch(drive, *p), grid)))
        # a damping scan: the grid's models differ in their damping only, one lockstep call
        todo = [z for z in grid if (drive, round(z, 12), None, None) not in cache]
        try:
            sims = simulate_models([RigModel(law, z, drive, preset=preset) for z in todo], record, threads=threads)
        except (ValueError, RuntimeError):  # outside the stability bound, ...
            sims = [None] * len(todo)
        side = measured_side(record, stick_threshold, float(record.time_s[0]), drive)
        for z, sim in zip(todo, sims):
            try:
                mis = math.inf if sim is None else compare(record, sim, stick_threshold, side=side).mismatch
            except (ValueError, RuntimeError):
                mis = math.inf
            cache[(drive, round(z, 12), None, None)] = mis
        return [(z, cache[(drive, round(z, 12), None, None)]) for z in grid]

    workers = threads if threads > 0 else (os.cpu_count() or 1)
    per = {}
    for drive in drives:
        if drive == "motor":
            grid = [(z, cm, J) for z in (0.05, 0.1, 0.2, 0.4) for cm in np.geomspace(0.05, 2.0, 5)
                    for J in np.geomspace(5e-3, 5e-2, 3)]
            scan = scan_of("motor", grid)
            best = min(scan, key=lambda q: q[1])[0]
            res = optimize.minimize(lambda x: mismatch("motor", *np.exp(x)), np.log(best), method="Nelder-Mead",
                                    options={"maxfev": 40, "xatol": 0.02, "fatol": 1e-3})
            p = tuple(np.exp(res.x)) if res.fun < mismatch("motor", *best) else best
            per[drive] = {"damping_ratio": float(p[0]), "motor_slope_nms_rad": float(p[1]),
                          "motor_inertia_kg_m2": float(p[2]), "mismatch": mismatch("motor", *p),
                          "evaluations": len(scan) + int(res.nfev)}
        else:
            grid = np.geomspace(0.01, 1.5, 14)
            grid = grid[grid <= 1.0]  # the engine refuses a damping ratio above critical
            scan = scan_of(drive, [float(z) for z in grid])
            k = int(np.argmin([m for _, m in scan]))
            scan += scan_of(drive, [float(z) for z in np.geomspace(grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)],
                                                                   7)[1:-1]])
            z, mis = min(scan, key=lambda q: q[1])
            per[drive] = {"damping_ratio": z, "mismatch": mis, "scan": sorted(scan)}
        if log:
            log(f"rig calibration: {drive} drive: mismatch {per[drive]['mismatch']:.3f} at damping ratio "
                f"{per[drive]['damping_ratio']:.3g}" + (f", c_m {per[drive]['motor_slope_nms_rad']:.3g} N m s/rad, "
                                                        f"J_m {per[drive]['motor_inertia_kg_m2']:.3g} kg m^2"
                                                        if drive == "motor" else ""))
    drive = min(per, key=lambda d: per[d]["mismatch"])
    b = per[drive]
    model = RigModel(law, b["damping_ratio"], drive, b.get("motor_slope_nms_rad"), b.get("motor_inertia_kg_m2"),
                     preset=preset)
    sim = simulate_model(model, record)
    cmp = compare(record, sim, stick_threshold)
    model.calibration = {"window_s": [float(record.time_s[0]), float(record.time_s[-1])], "operating_point": op,
                         "command_rad_s": sim.provenance["command_rad_s"], "mismatch": cmp.mismatch,
                         "matched": list(MATCHED), "stick_threshold_rad_s": float(stick_threshold),
                         "per_drive": {k: {kk: vv for kk, vv in v.items() if kk != "scan"} for k, v in per.items()},
                         "metric_scale": scale_of(record, stick_threshold)}
    return Calibration(model, cmp, per)


@dataclass
class Selection:
    """What :func:`select_model` found: per candidate (law name, drive) the mismatch of the model
    calibrated on the first half of the calibration part when it predicts the second half, the
    chosen pair, and the chosen pair recalibrated on the whole part.

    Attributes
    ----------
    scores : dict
        ``"<law>, <drive>"`` -> ``calibration_half_mismatch`` (on the first half) and
        ``prediction_half_mismatch`` (predicting the second half; inf when the simulation
        failed).
    law_name : str
        The chosen law's name (a key of the ``laws`` given).
    calibration : Calibration
        The chosen law and drive recalibrated on the whole part.
    """
    scores: dict
    law_name: str
    calibration: Calibration


@fitted_values()
def select_model(record: Record, laws: dict, stick_threshold: float, *, drives=DRIVES, preset: str = "thesis-rig",
                 log=None, threads: int = 0) -> Selection:
    """Choose the law and the top drive by how well they predict data they were not calibrated on.

    ``laws`` maps names to engine laws (identified on ``record``). Each law is calibrated
    (:func:`calibrate`) on the first half of ``record``, each drive's best model predicts the second
    half at its operating point, and the (law, drive) with the smallest mismatch there is chosen and
    recalibrated on the whole record. A calibration-only choice prefers the most flexible
    description (the motor's three parameters fit one part and extrapolate poorly: docs/records.md).

    Parameters
    ----------
    record : Record
        The cleaned calibration part, split at its midpoint in time.
    laws : dict
        Candidate name -> engine law (e.g. ``polynomial`` and ``polynomial_hysteretic``).
    stick_threshold : float
        Bit speed at or below which the bit counts as stuck [rad/s].
    drives : iterable of str
        Drives tried for every law, from :data:`DRIVES`.
    preset : str
        Engine preset of the rig.
    log : callable, optional
        Called with one progress line (str) per candidate and per drive of the final calibration.
    threads : int
        Simulations run at once by the calibrations (0: one per core).

    Returns
    -------
    Selection

    Raises
    ------
    ValueError
        If ``laws`` is empty.
    """
    if not laws:
        raise ValueError("select_model: no candidate law")
    t = record.time_s
    mid = t[0] + 0.5 * (t[-1] - t[0])
    first, second = record.select(t[0], mid), record.select(mid + 0.5 * record.dt, t[-1])
    scores = {}
    for name, law in laws.items():
        cal = calibrate(first, law, stick_threshold, drives=drives, preset=preset, threads=threads)
        for drive, b in cal.per_drive.items():
            m = RigModel(law, b["damping_ratio"], drive, b.get("motor_slope_nms_rad"), b.get("motor_inertia_kg_m2"),
                         preset=preset)
            try:
                mis = compare(second, simulate_model(m, second), stick_threshold).mismatch
            except (ValueError, RuntimeError):
                mis = math.inf
            scores[(name, drive)] = {"calibration_half_mismatch": b["mismatch"], "prediction_half_mismatch": mis}
            if log:
                log(f"rig model selection: {name}, {drive} drive: mismatch {b['mismatch']:.3f} on the first half, "
                    f"{mis:.3f} predicting the second half")
    name, drive = min(scores, key=lambda k: scores[k]["prediction_half_mismatch"])
    cal = calibrate(record, laws[name], stick_threshold, drives=(drive,), preset=preset, log=log, threads=threads)
    return Selection({f"{k[0]}, {k[1]}": v for k, v in scores.items()}, name, cal)


def droop_estimate(record: Record) -> tuple:
    """The open-loop motor's characteristic read off a record: the least-squares line of the
    reliable top speed on the measured torque, Omega_top = Omega_0 - T / c_m (sample 175: 18.1 rad/s
    and c_m = 0.225 N m s/rad). A start for :func:`calibrate_rig`, not a result: the measured torque
    is the bit's, not the top's.

    Parameters
    ----------
    record : Record
        A cleaned record with top speed and torque.

    Returns
    -------
    tuple of float
        (Omega_0 [rad/s], c_m [N m s/rad]); (mean top speed x 2, 0.25) when the line does not droop.
    """
    ok = reliable_top_speed(record) & record.valid("torque_on_bit")
    om = record.top_speed[ok]
    if ok.sum() > 10:
        slope, icpt = np.polyfit(record.torque_on_bit[ok], om, 1)
        if slope < 0:
            return float(icpt), float(-1.0 / slope)
    return float(2.0 * np.mean(om)) if om.size else 16.8, 0.25


def _linearized_variances(A: np.ndarray, rcond: float = 1e-10) -> np.ndarray:
    """Each parameter's variance from the weighted Jacobian ``A`` (residuals x parameters): the diagonal of
    (A^T A)^-1 over its eigen-directions, a direction whose eigenvalue is below ``rcond`` times the largest
    counting as undetermined (an infinite variance for every parameter with a share above 1e-8 in it,
    rather than the zero a pseudo-inverse would give it)."""
    w, V = np.linalg.eigh(A.T @ A)
    ok = w > rcond * max(float(w.max()), 0.0)
    share = V ** 2  # each parameter's share of each direction; one above 1e-8 in an undetermined one: infinite
    return np.where((share[:, ~ok] > 1e-8).any(axis=1), math.inf, (share[:, ok] / w[ok]).sum(axis=1))


def _block_values(record: Record, measure, blocks: int) -> list:
    """``measure(piece)`` on each of ``blocks`` consecutive blocks of ``record``; a block it cannot measure
    (ValueError, RuntimeError) is left out."""
    edges = np.linspace(record.time_s[0], record.time_s[-1], blocks + 1)
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        try:
            out.append(measure(record.select(a, b)))
        except (ValueError, RuntimeError):
            continue
    return out


def _horizon_noise(record: Record, error, blocks: int = 4) -> float:
    """Standard error of the short-horizon error E over ``record``: the spread of ``error(piece)`` between
    ``blocks`` consecutive blocks, over sqrt(blocks), at least 0.01 (0.05 with fewer than two blocks)."""
    v = np.asarray([x for x in _block_values(record, error, blocks) if math.isfinite(x)])
    return float(max(np.std(v, ddof=1) / math.sqrt(v.size), 0.01)) if v.size >= 2 else 0.05


def _metric_noise(record: Record, stick_threshold: float, keys: tuple, blocks: int = 4) -> np.ndarray:
    """Relative standard error of each metric over ``record``: the spread of the metric between
    ``blocks`` consecutive blocks, divided by sqrt(blocks) and by the metric's magnitude (at least 1 %)."""
    def metrics(piece):
        m = record_metrics(piece, stick_threshold, float(piece.time_s[0]), np.zeros(len(piece), bool))
        return [m.get(k, np.nan) for k in keys]
    v = np.asarray(_block_values(record, metrics, blocks), float)
    if v.shape[0] < 2:
        return np.full(len(keys), 0.05)
    sd = np.nanstd(v, axis=0, ddof=1) / np.sqrt(v.shape[0])
    mag = np.maximum(np.abs(np.nanmean(v, axis=0)), 1e-12)
    return np.maximum(np.nan_to_num(sd / mag, nan=0.05), 0.01)


#: Rig parameters held by default (:func:`calibrate_rig`): the static-torque factor at 1, the law's static
#: torque as identified. Calibrated, on sample 175 it is not determined by the metrics (its interval
#: spans the range), the calibration ends at a higher mismatch and the cycle stays as marginal as at 1;
#: on the independent whole-rig truth the search ends in a model that loses its cycle on the held-out
#: half (docs/records.md, section 4, "The static torque"). And the stall's elements at none: the motor's
#: 8 N m rating and no ageing of the static torque (``--rig-fix NAME=free`` calibrates them, on a part with a
#: stall: docs/records.md, section 4, "Where the stall comes from").
DEFAULT_FIXED = {"static_torque_factor": 1.0, "motor_max_torque_nm": 8.0, "static_ageing": 0.0, "static_ageing_s": 0.3}
#: Metrics :func:`calibrate_rig` can match beside :data:`MATCHED_RIG`: the cycle frequency, and the top
#: speed's part in phase with the bit speed at it (``rig_comparison.record_metrics``), which the calibration
#: does not match by default (docs/records.md, section 4: no model of the rig family matches it and keeps
#: the cycle), and the smallest stick fraction of the part's 5 s blocks (``block_stick_min``: the cycle kept
#: where the WOB trend dips), and the share of the time in stalls (``stall_fraction``: with the motor's torque
#: limit and the static torque's ageing calibrated, ``--rig-fix NAME=free``).
EXTRA_KEYS = ("cycle_frequency_hz", "top_in_phase", "block_stick_min", "stall_fraction")


#: Points of the scan of :func:`_scan_interval` across a parameter's range.
SCAN_POINTS = 13
#: The weighted misfit's rise that bounds a scanned interval: chi-square with one degree of freedom at 95 %.
SCAN_CHI2 = 3.84
#: Weight of the short-horizon error E on the calibration part beside the long-run metrics' mismatch in
#: :func:`calibrate_rig`'s objective (both dimensionless: a relative RMS and a normalized RMS). 1 weighs a
#: unit of E as a unit of mismatch; 0 matches the long-run metrics alone (the calibration before issue 28's
#: "one calibration": docs/records.md, section 4).
HORIZON_WEIGHT = 1.0
#: The channels of that short-horizon error (:func:`calibrate_rig`'s ``horizon_channels``): ``"loop"``, the
#: bit speed, the torque and the top speed (the loop's E); ``"all"`` adds the WOB, the jack's state against
#: the recorded WOB (docs/records.md, section 4: no better on the independent truth or on sample 175).
HORIZON_CHANNELS = "loop"


def _scan_interval(residuals, p: dict, k: str, lo: float, hi: float, sigma: np.ndarray, workers: int) -> list | None:
    """95 % interval of parameter ``k`` where no local slope holds: the weighted misfit
    chi^2(q) = sum_m (r_m(q) / sigma_m)^2 of the relative errors r (``residuals``) on
    :data:`SCAN_POINTS` values evenly across [lo, hi] and at the optimum, the others held at ``p``
    (a conditional interval: narrower than one with the others refitted). The interval spans the
    values whose chi^2 is within :data:`SCAN_CHI2` of the optimum's, widened by half a grid step on
    each side within the range (the scan's resolution). None when the optimum's own simulation fails.
    """
    grid = np.unique(np.append(np.linspace(lo, hi, SCAN_POINTS), p[k]))

    def chi2(v):
        try:
            r = residuals({**p, k: float(v)})
        except (ValueError, RuntimeError):  # a stalled or unstable run: outside
            return math.inf
        x = float(np.sum((r / sigma) ** 2))
        return x if math.isfinite(x) else math.inf
    with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:
        c = np.array(list(pool.map(chi2, grid)))
    at = int(np.flatnonzero(grid == p[k])[0])
    if not math.isfinite(c[at]):
        return None
    ok = np.flatnonzero(c <= c[at] + SCAN_CHI2)
    half = 0.5 * (hi - lo) / (SCAN_POINTS - 1)
    return [float(max(lo, grid[ok].min() - half)), float(min(hi, grid[ok].max() + half))]


@fitted_values()
def calibrate_rig(record: Record, law: dict, stick_threshold: float, *, preset: str = "thesis-rig", screen: int = 64,
                  starts: int = 4, evaluations: int = 200, seed: int = 175, log=None, threads: int = 0,
                  fixed: dict | None = None, keys: tuple = MATCHED_RIG, horizon_error=None,
                  horizon_weight: float = HORIZON_WEIGHT, channel_timing: dict | None = None,
                  horizon_channels: str = HORIZON_CHANNELS) -> Calibration:
    """Calibrate the rig modelled whole (the ``rig`` drive) on a cleaned calibration part.

    The parameters of :data:`RIG_PARAMETERS`, each inside its physical range (a logistic map of
    the range, so that no value outside it is tried), minimize the mismatch over
    :data:`MATCHED_RIG` (:func:`compare`; the regular cycle's SS, stick fraction, cycle frequency,
    bit-speed p95, torque p5 and p95, the top speed's standard deviation and mean, the WOB's
    standard deviation) plus ``horizon_weight`` times the short-horizon error of the model on the same
    part (``horizon_error``: each 0.25 s horizon restarted from the measured state; over
    ``horizon_channels``, by default the loop's criterion E over the bit speed, the torque and the top
    speed), so that one calibration answers both the long-run statistics and what the next quarter
    second does. With ``"all"`` the WOB is scored beside them (the jack's state against the recorded
    WOB); ``calibration.wob_horizon_error`` reports the WOB's error either way. The mismatch jumps where cycles appear and vanish, so the search screens
    ``screen`` points, a start from the record's droop line (:func:`droop_estimate`) and typical
    values and others scattered around it (normal, sd 0.7 in the logistic coordinates, from
    ``seed``: most of the ranges' corners stall the rig or stop the cycle, where the mismatch is
    flat), and runs a Nelder-Mead from the ``starts`` best; the best result is polished once more
    from its own point. The result depends on the seed, never on the thread count.

    95 % intervals: the relative errors are linearized around the optimum (central differences at
    6 % of each range) and weighted by each metric's own sampling uncertainty, the spread of the
    metric between four blocks of the part (:func:`_metric_noise`). Where the metrics do not determine
    a parameter that way, or where its slope at 2 % of the range differs from the one at 6 % by more
    than half (a cycle or a stall appears in between: no local linearization holds), its interval is
    scanned instead (:func:`_scan_interval`: the weighted misfit across the range, the others held).
    ``per_drive["rig"]["interval_method"]`` says which gave each. With E in the objective it is one
    more residual, weighted by its own sampling uncertainty (the spread of E between four blocks of
    the part, over 2, and at least 0.01).

    Parameters
    ----------
    record : Record
        The cleaned calibration part (with top speed, bit speed, torque and WOB).
    law : dict
        Engine bit-rock law identified on it (the measured-WOB fit suits: the WOB is a state here).
    stick_threshold : float
        Bit speed at or below which the bit counts as stuck [rad/s].
    preset : str
        Engine preset of the rig.
    screen : int
        Points screened for the starts (at least 1).
    starts : int
        Nelder-Mead starts, the best screened points (at least 1).
    evaluations : int
        Simulations per start.
    seed : int
        Seed of the random starts.
    log : callable, optional
        Called with one progress line (str) per start.
    threads : int
        Starts run at once (0: one per core).
    fixed : dict, optional
        Parameters of :data:`RIG_PARAMETERS` held at a value inside their range instead of searched
        (no interval; the others are searched exactly as without them); default
        :data:`DEFAULT_FIXED` (the static torque as identified). ``{}`` calibrates every parameter.
    keys : tuple
        The metrics of the mismatch (default :data:`MATCHED_RIG`); :data:`EXTRA_KEYS` may be added, e.g.
        ``top_in_phase``, the drive's phase in the cycle (docs/records.md, section 4).
    horizon_error : callable, optional
        ``horizon_error(model, record, command, channels=...)``: the short-horizon error [-] of a rig
        model on a record over the channels ``"loop"``, ``"wob"`` or ``"all"``
        (:func:`drillpy.loop.prediction.short_horizon_error`); None: the long-run metrics alone.
    horizon_weight : float
        E's weight in the objective (>= 0; :data:`HORIZON_WEIGHT`).
    horizon_channels : str
        The channels of the objective's short-horizon error (:data:`HORIZON_CHANNELS`): ``"loop"``
        (the bit speed, the torque and the top speed) or ``"all"`` (the WOB beside them).
    channel_timing : dict, optional
        The acquisition's skew the model keeps and E reads the record at
        (:func:`drillpy.records.bit_balance.applied_timing`); None: as recorded.

    Returns
    -------
    Calibration
        ``per_drive["rig"]`` holds the parameters, their intervals, the mismatch and the
        evaluations.
    """
    keys = tuple(keys)
    if not (math.isfinite(horizon_weight) and horizon_weight >= 0.0):
        raise ValueError(f"horizon_weight = {horizon_weight!r}: must be a finite number >= 0")
    weight = float(horizon_weight) if horizon_error is not None else 0.0
    for k in keys:
        if k not in MATCHED_RIG + EXTRA_KEYS:
            raise ValueError(f"keys: {k!r} is not a rig metric (use {', '.join(MATCHED_RIG + EXTRA_KEYS)})")
    fixed = {k: float(v) for k, v in (DEFAULT_FIXED if fixed is None else fixed).items()}
    for k, v in fixed.items():
        if k not in RIG_PARAMETERS:
            raise ValueError(f"fixed: {k!r} is not a rig parameter (use {', '.join(RIG_PARAMETERS)})")
        if not RIG_PARAMETERS[k][0] <= v <= RIG_PARAMETERS[k][1]:
            raise ValueError(f"fixed: {k} = {v!r}: outside its range [{RIG_PARAMETERS[k][0]:g}, "
                             f"{RIG_PARAMETERS[k][1]:g}] {RIG_PARAMETERS[k][2]}")
    names = [k for k in RIG_PARAMETERS if k not in fixed]
    lo = np.array([RIG_PARAMETERS[k][0] for k in names])
    hi = np.array([RIG_PARAMETERS[k][1] for k in names])
    op = operating_point(record)
    scale = scale_of(record, stick_threshold)  # E's unit: the part's spreads, as the model file keeps them

    def params(x):
        return {**dict(zip(names, lo + (hi - lo) / (1.0 + np.exp(-np.clip(x, -30, 30))))), **fixed}

    def internal(p):
        u = np.clip((np.array([p[k] for k in names]) - lo) / (hi - lo), 1e-6, 1 - 1e-6)
        return np.log(u / (1 - u))

    def model_of(p):
        return RigModel(law, p["damping_ratio"], "rig", p["motor_slope_nms_rad"], p["motor_inertia_kg_m2"],
                        preset=preset, command_rad_s=p["command_rad_s"], jack_gain_n_rad=p["jack_gain_n_rad"],
                        jack_relaxation_s=p["jack_relaxation_s"], platform_damping=p["platform_damping"],
                        gj_factor=p["gj_factor"], bit_inertia_factor=p["bit_inertia_factor"],
                        coupling_stiffness_nm_rad=p["coupling_stiffness_nm_rad"],
                        static_torque_factor=p["static_torque_factor"], channel_timing=channel_timing,
                        motor_max_torque_nm=p["motor_max_torque_nm"], static_ageing=p["static_ageing"],
                        static_ageing_s=p["static_ageing_s"],
                        calibration={"metric_scale": scale})

    side = measured_side(record, stick_threshold, float(record.time_s[0]), "rig")

    def comparison(p):
        return compare(record, simulate_model(model_of(p), record), stick_threshold, side=side, keys=keys)

    if horizon_channels not in ("all", "loop"):
        raise ValueError(f"horizon_channels = {horizon_channels!r}: use all or loop")

    def short(p, rec=record, channels=horizon_channels):  # E on the part (or a block of it), the motor at the parameters' command
        return float(horizon_error(model_of(p), rec, p["command_rad_s"], channels=channels)) if weight > 0 else 0.0

    def cost(x):
        try:
            p = params(x)
            return comparison(p).mismatch + weight * short(p)
        except (ValueError, RuntimeError):  # diverged, unstable step
            return math.inf

    om0, cm0 = droop_estimate(record)
    first = {"damping_ratio": 0.04, "motor_slope_nms_rad": float(np.clip(cm0, lo[1], hi[1])),
             "motor_inertia_kg_m2": 0.015, "command_rad_s": float(np.clip(om0, lo[3], hi[3])),
             "jack_gain_n_rad": 150.0, "jack_relaxation_s": 0.2, "platform_damping": 0.7, "gj_factor": 1.05,
             "bit_inertia_factor": 1.05, "coupling_stiffness_nm_rad": 30.0, "static_torque_factor": 1.08,
             "motor_max_torque_nm": 4.0, "static_ageing": 0.3, "static_ageing_s": 0.3}
    first = {k: v for k, v in first.items() if k in names}
    rng = np.random.default_rng(seed)
    scatter = [internal(first)] + [internal(first) + rng.normal(0.0, 0.7, len(names)) for _ in range(screen - 1)]
    workers = threads if threads > 0 else (os.cpu_count() or 1)
    with ThreadPoolExecutor(max_workers=workers) as pool:
        screened = list(pool.map(cost, scatter))
    order = sorted(range(len(scatter)), key=lambda i: (screened[i], i))
    x0s = [scatter[i] for i in order[:max(starts, 1)]]

    def search(x0):
        return optimize.minimize(cost, x0, method="Nelder-Mead",
                                 options={"maxfev": evaluations, "xatol": 1e-3, "fatol": 1e-4, "adaptive": True})

    with ThreadPoolExecutor(max_workers=workers) as pool:
        results = list(pool.map(search, x0s))
    for i, r in enumerate(results):
        if log:
            log(f"rig calibration (whole rig): start {i + 1} of {len(results)}: "
                + (f"mismatch + {weight:g} E {r.fun:.3f}" if weight > 0 else f"mismatch {r.fun:.3f}")
                + f" after {r.nfev} simulations")
    best = min(results, key=lambda r: (r.fun, results.index(r)))
    polish = search(best.x)
    if polish.fun < best.fun:
        best = polish
    p = params(best.x)
    cmp = comparison(p)
    # 95 % intervals from the linearized relative errors weighted by the metrics' own noise
    sigma = _metric_noise(record, stick_threshold, keys)
    e_cal = short(p, channels="loop") if weight > 0 else None
    e_wob = short(p, channels="wob") if weight > 0 and "wob_n" in scale else None
    if weight > 0:
        sigma = np.append(sigma, _horizon_noise(record, lambda piece: short(p, piece)) / math.sqrt(weight))

    def residuals(q):
        c = compare(record, simulate_model(model_of(q), record), stick_threshold, side=side, keys=keys)
        r = [relative_error(c.simulated[k], c.measured[k]) for k in keys]
        return np.array(r + ([short(q)] if weight > 0 else []))

    intervals = {}
    try:
        def slope(j, k, frac):
            h = frac * (hi[j] - lo[j])
            up, dn = dict(p), dict(p)
            up[k], dn[k] = min(p[k] + h, hi[j]), max(p[k] - h, lo[j])
            return (residuals(up) - residuals(dn)) / (up[k] - dn[k])

        cols, kept = [], []
        for j, k in enumerate(names):
            fine, coarse = slope(j, k, 0.02), slope(j, k, 0.06)
            # a metric that jumps (a cycle or a stall appearing) between the two steps: no local slope
            if np.linalg.norm(fine - coarse) <= 0.5 * max(np.linalg.norm(coarse), 1e-12):
                cols.append(coarse)
                kept.append(j)
        if cols:
            A = np.column_stack(cols) / sigma[:, None]
            var = _linearized_variances(A)
            for c, j in enumerate(kept):
                k = names[j]
                sd = math.sqrt(var[c])
                if math.isfinite(sd) and sd < (hi[j] - lo[j]):  # determined by the metrics
                    intervals[k] = [float(max(p[k] - 1.96 * sd, lo[j])), float(min(p[k] + 1.96 * sd, hi[j]))]
    except (ValueError, RuntimeError, np.linalg.LinAlgError):
        intervals = {}
    method = {k: "linearized" for k in intervals}
    # where no local slope holds, the misfit scanned across the range (the others held)
    for j, k in enumerate(names):
        if k not in intervals:
            iv = _scan_interval(residuals, p, k, lo[j], hi[j], sigma, workers)
            if iv is not None:
                intervals[k], method[k] = iv, "scan"
    model = model_of(p)
    model.intervals = intervals
    per = {"rig": {**{k: float(v) for k, v in p.items()},
                   "mismatch": cmp.mismatch, "evaluations": int(sum(r.nfev for r in results) + polish.nfev),
                   "horizon_weight": weight, "short_horizon_error": e_cal, "wob_horizon_error": e_wob,
                   "horizon_channels": horizon_channels, "fixed": dict(fixed),
                   "intervals": intervals, "interval_method": method,
                   "metric_noise": dict(zip(keys, map(float, sigma)))}}
    model.calibration = {"window_s": [float(record.time_s[0]), float(record.time_s[-1])], "operating_point": op,
                         "command_rad_s": p["command_rad_s"], "mismatch": cmp.mismatch,
                         "matched": list(keys), "stick_threshold_rad_s": float(stick_threshold),
                         "horizon_weight": weight, "short_horizon_error": e_cal, "wob_horizon_error": e_wob,
                         "horizon_channels": horizon_channels, "per_drive": per, "metric_scale": scale}
    if log:
        log("rig calibration (whole rig): mismatch %.3f; " % cmp.mismatch
            + (f"short-horizon E {e_cal:.3f}, the WOB's {e_wob if e_wob is None else round(e_wob, 3)} "
               f"(weight {weight:g}); " if weight > 0 else "")
            + ", ".join(f"{k} {v:.4g}" for k, v in p.items()))
    return Calibration(model, cmp, per)
