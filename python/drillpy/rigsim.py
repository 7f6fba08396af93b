"""The test rig in simulation (beyond the thesis: its section 5.4 left this for future work).

The ``thesis-rig`` preset (Table 5.1: 1.7 m steel bar of radius 2.5 mm, 3.921 kg disk; first
frequency 2.89 Hz) is driven either at a constant top speed (the mean of the measured one) or by
the measured top-speed signal (the rig's motor is open loop, so the measured speed is the honest
boundary condition), with an identified bit-rock law. The simulated bit speed and torque go
through the rig's 10 Hz acquisition filter before they are compared with the measurement on SS,
cycle frequency, stick fraction, torque range and the torque-speed loop.

The modal damping ratio of the preset is an assumption; :func:`estimate_damping` scans it and
keeps the value whose simulation matches the measured stick-slip best (an *effective* damping
that lumps every dissipation the one-mode model lacks).
"""
from __future__ import annotations

import copy
from dataclasses import dataclass

import numpy as np

from .config import load_config, normalize
from .records import Record
from .signals import MeanCycle, derivative, mean_cycle, rig_lowpass, segment_cycles, stick_slip_metrics
from .simulation import simulate

#: Metrics compared between simulation and measurement (relative errors enter the mismatch).
MATCHED = ("ss", "stick_fraction", "bit_speed_p95", "torque_p5", "torque_p95", "median_period_s")


def rig_config(law: dict | None = None, damping_ratio: float | None = None, *, preset: str = "thesis-rig",
               duration_s: float | None = None, top_speed: float | None = None,
               wob: float | None = None) -> dict:
    """The rig preset with another law and/or modal damping ratio (normalized by the engine).

    ``wob`` defaults to the law's reference WOB, so the law is used at the WOB it was fitted at.
    """
    cfg = copy.deepcopy(load_config(preset=preset))
    if law is not None:
        cfg["law"] = dict(law)
    if damping_ratio is not None:
        cfg["damping"] = {"type": "modal", "ratios": [float(damping_ratio)]}
    if duration_s is not None:
        cfg["simulation"]["duration_s"] = float(duration_s)
        cfg["simulation"]["transient_s"] = min(cfg["simulation"]["transient_s"], 0.5 * float(duration_s))
    cfg["operation"]["wob_n"] = float(cfg["law"]["wob_ref_n"] if wob is None else wob)
    if top_speed is not None:
        cfg["operation"]["top_speed_rad_s"] = float(top_speed)
    return normalize(cfg)


def simulate_rig(record: Record, law: dict | None = None, damping_ratio: float | None = None, *,
                 drive: str = "measured", wob: str = "constant", filtered: bool = True,
                 preset: str = "thesis-rig") -> Record:
    """Simulate the rig over the span of a cleaned ``record``; return the simulation as a Record.

    Parameters
    ----------
    record : Record
        Cleaned measured record with a top-speed channel (and a WOB channel for ``wob="measured"``).
    law : dict, optional
        Engine law (default: the preset's).
    damping_ratio : float, optional
        Modal damping ratio of the first mode (default: the preset's).
    drive : {"measured", "constant"}
        Top speed: the measured series, or its mean held constant [rad/s].
    wob : {"constant", "measured"}
        WOB: the law's reference WOB, or the measured series (the law scales with W / W_ref).
    filtered : bool
        Pass the simulated bit speed, top speed and torque through the rig's 10 Hz filter.

    Returns
    -------
    Record
        On the record's time grid (engine output every 1 ms), provenance naming the model.
    """
    if drive not in ("measured", "constant"):
        raise ValueError(f"drive = {drive!r}: use 'measured' or 'constant'")
    if wob not in ("constant", "measured"):
        raise ValueError(f"wob = {wob!r}: use 'constant' or 'measured'")
    top = record.channel("top_speed")
    t = record.time_s
    dt = record.dt
    ok = record.valid("top_speed")
    if not ok.all():
        raise ValueError("simulate_rig: the top-speed channel has excluded samples; a drive signal "
                         "must be complete (clean the record, or select a span without them)")
    mean_top = float(np.mean(top))
    w_series = None
    if wob == "measured":
        w_series = record.channel("wob")
        if not record.valid("wob").all():
            raise ValueError("simulate_rig: the WOB channel has excluded samples")
    cfg = rig_config(law, damping_ratio, preset=preset, duration_s=float(t[-1] - t[0]), top_speed=mean_top)
    sim_dt = cfg["simulation"]["dt_s"]
    cfg["simulation"]["output_stride"] = max(1, int(round(dt / sim_dt)))
    cfg = normalize(cfg)
    res = simulate(cfg, None if drive == "measured" else mean_top,
                   top_speed_series=top if drive == "measured" else None,
                   wob_series=w_series, series_dt=dt)
    ts = res.t + t[0]
    n = min(ts.size, t.size)
    vb, vt, tq = res.bit_speed[:n], res.top_speed[:n], res.torque_on_bit[:n]
    fs = 1.0 / float(np.median(np.diff(res.t)))
    if filtered:
        vb, vt, tq = (rig_lowpass(x, fs) for x in (vb, vt, tq))
    w = w_series[:n] if w_series is not None else np.full(n, cfg["operation"]["wob_n"])
    return Record(time_s=ts[:n], bit_speed=vb, top_speed=vt, torque_on_bit=tq, wob=w,
                  units={"time": "s", "bit_speed": "rad_s", "top_speed": "rad_s", "torque_on_bit": "Nm", "wob": "N"},
                  provenance={"source": "simulation", "format": "drillpy.simulate", "preset": preset,
                              "drive": drive, "wob": wob, "filtered": filtered, "config": res.config})


@dataclass
class RigComparison:
    """Measured versus simulated stick-slip metrics and torque-speed loops."""
    measured: dict
    simulated: dict
    mismatch: float
    mean_cycle_measured: MeanCycle | None   #: None when there is no stick-slip cycle
    mean_cycle_simulated: MeanCycle | None
    loop_rms_nm: float  #: rms difference of the branch mean curves on the common speeds [N m]

    def rows(self) -> list:
        keys = ("ss", "cycle_frequency_hz", "median_period_s", "stick_fraction", "bit_speed_p95",
                "torque_p5", "torque_p95", "torque_min", "torque_max")
        return [(k, self.measured[k], self.simulated[k]) for k in keys]


def _loop(rec: Record, thr: float, t_start: float, grid) -> MeanCycle | None:
    """Mean cycle per branch after t_start, or None when there is no stick-slip cycle."""
    sel = rec.time_s >= t_start
    v = rec.bit_speed[sel]
    tq = rec.torque_on_bit[sel]
    cyc = segment_cycles(v, rec.dt, thr)
    lab = cyc.branch_labels(v.size)
    try:
        return mean_cycle(v, tq, derivative(v, rec.dt), lab, grid=grid)
    except ValueError:
        return None


def compare(measured: Record, simulated: Record, stick_threshold: float, t_start: float = 2.0) -> RigComparison:
    """Compare a simulated record with the measured one after ``t_start`` seconds of simulation
    (the start-up of the simulation is discarded from both)."""
    t0 = simulated.time_s[0] + t_start

    def metrics(rec):
        sel = (rec.time_s >= t0) & rec.valid("bit_speed", "top_speed", "torque_on_bit")
        return stick_slip_metrics(rec.time_s, rec.bit_speed, rec.top_speed, rec.torque_on_bit,
                                  stick_threshold, valid=sel)

    m, s = metrics(measured), metrics(simulated)
    # a simulation without stick-slip cycles has no period: its period error counts as 100 %
    rel = [((s[k] - m[k]) / m[k]) if np.isfinite(s[k]) else 1.0 for k in MATCHED]
    mis = float(np.sqrt(np.mean(np.square(rel))))
    grid = np.linspace(0.0, np.percentile(measured.bit_speed[measured.time_s >= t0], 99), 40)
    mm = _loop(measured, stick_threshold, t0, grid)
    ms = _loop(simulated, stick_threshold, t0, grid)
    loop = float("nan")
    if mm is not None and ms is not None:
        d = np.r_[mm.upper - ms.upper, mm.lower - ms.lower]
        d = d[np.isfinite(d)]
        loop = float(np.sqrt(np.mean(d ** 2))) if d.size else loop
    return RigComparison(m, s, mis, mm, ms, loop)


def estimate_damping(record: Record, law: dict, stick_threshold: float, ratios=None, *,
                     drive: str = "constant", preset: str = "thesis-rig") -> dict:
    """Effective modal damping ratio: the value of ``ratios`` whose simulation matches the
    measurement best (smallest rms relative error over :data:`MATCHED`).

    The default drive is the constant (mean measured) top speed, the way the preset is used: the
    stick-slip must then be self-excited. With the measured top-speed drive the estimate comes out
    much larger, because the measured top speed already oscillates with the stick-slip cycle and
    forces it.

    Returns ``{"ratio", "mismatch", "scan": [(ratio, mismatch), ...]}``. The scan is a grid search
    (the mismatch is not smooth in the ratio: stick-slip cycles appear and vanish), refined once
    around the best grid point.
    """
    grid = np.geomspace(0.01, 1.0, 11) if ratios is None else np.asarray(ratios, float)
    scan = []

    def run(z):
        sim = simulate_rig(record, law, float(z), drive=drive, preset=preset)
        return compare(record, sim, stick_threshold).mismatch

    for z in grid:
        scan.append((float(z), run(z)))
    if ratios is None:
        k = int(np.argmin([m for _, m in scan]))
        lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, grid.size - 1)]
        for z in np.geomspace(lo, hi, 7)[1:-1]:
            scan.append((float(z), run(z)))
    scan.sort()
    best = min(scan, key=lambda p: p[1])
    return {"ratio": best[0], "mismatch": best[1], "scan": scan}
