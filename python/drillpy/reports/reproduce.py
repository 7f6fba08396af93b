"""`drillpy reproduce`: the thesis's studies run chapter by chapter, each figure written under the
thesis's figure number, and a table quantity | thesis | drillpy | tolerance | pass.

Every ambiguity of the thesis is an explicit option of the engine (docs/validation.md has the
evidence for each default): the weight on bit and the retained modes (presets ``thesis-field``
and ``thesis-ch4``), the bit acceleration in Eq. (3.3) (``simulation.acceleration``), the
initial state (``start``: Eq. 2.10 rest or Eq. 2.3 rigid rotation), the Monte Carlo protocol
(Algorithm 1 literally, from rest with eta from t = 0, or drillpy's shared warm start) and the PSD
convention of Eq. (4.4). Rows of kind ``target`` are the thesis's numbers and conclusions with a
tolerance; rows of kind ``reading`` show what the other readings of an ambiguity give, so that a
departure is named in the output and not hidden in a default.

``quick=True`` runs a reduced version of every study (coarser grids, fewer samples, shorter
runs) for the tests; its numbers are not the thesis's targets and the table says so.
"""
from __future__ import annotations

import json
import math
import shutil
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from drillpy.outputs import write_text
from drillpy.model.config import load_config, with_overrides
from drillpy.model.configuration import Configuration
from drillpy.provenance import provenance, with_markdown_footer
from drillpy.jsonio import dumps

CHAPTERS = ("3", "4", "5", "6")
THESIS_FREQUENCIES_HZ = (0.13, 0.42, 0.74, 1.07, 1.41)           # section 4.2.1
THESIS_THRESHOLD_RAD_S = 16.0                                     # Fig. 4.8
THESIS_P05_SPEED_RAD_S = 20.5                                     # Fig. 4.9
THESIS_STICK_S = (1.34, 2.53, 2.48)                               # section 4.2.1, Fig. 4.6
THESIS_SLIP_S = (5.4, 6.28, 6.41)
THREE_CYCLE_SPEED_RAD_S = 14.0   # the thesis does not state the speed of Fig. 4.6 (docs/validation.md)
#: eta of Fig. 4.9: the shape of Eq. (4.4) at the level the thesis reads in the field torque,
#: "+-20 %" (section 4.0) taken as the +-3 sigma range of a Gaussian (docs/validation.md)
MC_ETA_STD = 0.20 / 3.0
ALGORITHM1 = {"warmup": 0.0, "duration": 300.0, "transient": 200.0}   # from rest, eta from t = 0
WARM_START = {"warmup": 100.0, "duration": 60.0, "transient": 20.0}   # drillpy's `mc` default


@dataclass
class Row:
    """One line of the reproduction table (``table.md``, ``reproduce.json``'s ``rows``).

    ``passed`` is None for rows of kind ``reading`` (reported, not a target); docs/validation.md
    lists the rows of a full run and the evidence behind each default.

    Attributes
    ----------
    chapter : str
        Thesis chapter the row belongs to: ``"3"``, ``"4"``, ``"5"`` or ``"6"``.
    quantity : str
        What is compared, with its unit in brackets and the thesis figure, equation or section
        it comes from (e.g. "top speed below which SS > 0.5 [rad/s] (Fig. 4.8), thesis-ch4").
    thesis : str
        The thesis's value or conclusion, as text.
    drillpy : str
        What drillpy computes for the same quantity, as text.
    tolerance : str
        The pass criterion (e.g. "+-0.5", "rank correlation < -0.8"), or "reported" for a
        reading.
    passed : bool or None
        Whether the criterion holds; None for a reading (coerced to bool otherwise).
    kind : str
        ``"target"`` (the thesis's number or conclusion, counted in the pass tally) or
        ``"reading"`` (what another reading of an ambiguity of the thesis gives, not counted).
    note : str
        Evidence and setting shown in the table's last column (protocol, bracket, bootstrap
        interval, ...); empty when there is nothing to add.
    figure : str
        File name of the figure the row refers to, relative to the output folder (empty when
        none).
    """
    chapter: str
    quantity: str
    thesis: str
    drillpy: str
    tolerance: str
    passed: bool | None
    kind: str = "target"
    note: str = ""
    figure: str = ""

    def __post_init__(self):
        if self.passed is not None:
            self.passed = bool(self.passed)


@dataclass
class Options:
    """Settings of :func:`reproduce` shared by every chapter.

    Attributes
    ----------
    quick : bool
        Run reduced studies (coarser grids, fewer samples, shorter runs, fewer readings) for the
        tests; the numbers are not the thesis's targets and the table says so.
    threads : int
        Engine threads (0: all cores).
    progress : bool
        Show progress bars during the sweeps and Monte Carlo studies.
    seed : int
        Seed of every Monte Carlo study and bootstrap (chapters 4 and 6).
    """
    quick: bool = False
    threads: int = 0
    progress: bool = True
    seed: int = 1


@dataclass
class Result:
    """What :func:`reproduce` ran: the table rows, the figures and the wall time per chapter.

    Attributes
    ----------
    rows : list of Row
        The table's rows in chapter order.
    figures : list of str
        Paths of the figures written.
    seconds : dict
        Chapter (``"3"`` to ``"6"``) -> wall time of its studies [s].
    """
    rows: list = field(default_factory=list)
    figures: list = field(default_factory=list)
    seconds: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        """The result as JSON-ready data (the content of ``reproduce.json`` but for ``quick``
        and ``seed``).

        Returns
        -------
        dict
            ``rows`` (each :class:`Row` as a dict), ``figures`` (paths), ``seconds`` (chapter ->
            wall time [s]), ``targets`` (number of rows of kind ``target``) and ``passed`` (how
            many of them pass).
        """
        targets = [r for r in self.rows if r.kind == "target"]
        return {"rows": [asdict(r) for r in self.rows], "figures": self.figures, "seconds": self.seconds,
                "targets": len(targets), "passed": sum(bool(r.passed) for r in targets)}


def _fmt(x, nd=2) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "none"
    return f"{x:.{nd}f}"


def _seq(xs, nd=2) -> str:
    return "(" + ", ".join(_fmt(float(x), nd) for x in xs) + ")"


# --------------------------------------------------------------------------------- chapter 3
def chapter3(out: Path, o: Options) -> tuple[list, list]:
    """Figs. 3.11-3.12: stability maps of models 1-3 and the two conclusions of section 3.3, with
    the implicit bit acceleration (default) and the lagged reading.

    Runs the ``thesis-field`` preset over 23 top speeds from 50 to 160 RPM and 12 WOBs from 22 to
    267 kN (quick: 8 x 5, 10 modes, 120-s runs) for beta1 = 0, 0.14 and 0.56, once with the bit
    acceleration of Eq. (3.3) implicit (rows of kind ``target``) and once lagged (rows of kind
    ``reading``). The verdicts come from :func:`drillpy.reports.preset.map_conclusions`: the stable
    fraction (SS < 0.5) grows with hysteresis (model 3 above model 1, model 2 not below it), and
    model 3's mean SS in the low-speed / high-WOB quadrant exceeds model 1's while its largest SS
    on the map exceeds those of models 1 and 2.

    Parameters
    ----------
    out : Path
        Output folder; receives ``fig3_11.png``, ``fig3_12.png`` and their ``_lagged`` variants.
    o : Options
        Quick mode, threads and progress.

    Returns
    -------
    rows : list of Row
        Two rows per reading of the acceleration (stable fraction; severity at low speed and high
        WOB).
    figures : list of str
        Paths of the four figures.
    """
    from drillpy.figures import simulation as plotting
    from drillpy.reports.preset import MODEL_BETA1, map_conclusions
    from drillpy.model.simulation import stability_map
    cfg = load_config(preset="thesis-field")
    sp_rpm = np.linspace(50, 160, 23 if not o.quick else 8)
    w_kn = np.linspace(22, 267, 12 if not o.quick else 5)
    if o.quick:
        cfg = with_overrides(cfg, modes=10, duration=120, transient=60)
    rows, figs = [], []
    for acc in ("implicit", "lagged"):
        maps = {lab: stability_map(with_overrides(cfg, beta1=b, acceleration=acc), sp_rpm * np.pi / 30.0,
                                   w_kn * 1e3, progress=o.progress, threads=o.threads)
                for lab, b in MODEL_BETA1.items()}
        labels = list(maps)
        vmax = max(float(np.max(m)) for m in maps.values())
        sfx = "" if acc == "implicit" else "_lagged"
        f1 = out / f"fig3_11{sfx}.png"
        plotting.stability_map_plot(f1, sp_rpm, w_kn,
                                     {k: maps[k] for k in labels[:2]}, vmax=vmax)
        f2 = out / f"fig3_12{sfx}.png"
        plotting.stability_map_plot(f2, sp_rpm, w_kn, {labels[2]: maps[labels[2]]}, vmax=vmax)
        figs += [str(f1), str(f2)]
        c = map_conclusions(sp_rpm, w_kn, maps)
        frac = [c[k]["stable_fraction_all"] for k in labels]
        quad = [c[k]["stable_fraction_high_speed_low_wob"] for k in labels]
        sev = [c[k]["mean_ss_low_speed_high_wob"] for k in labels]
        mx = [c[k]["max_ss"] for k in labels]
        kind = "target" if acc == "implicit" else "reading"
        tag = "" if acc == "implicit" else " [acceleration lagged]"
        grows = frac[2] > frac[0] and frac[1] >= frac[0]
        rows.append(Row("3", f"stable fraction of the map (SS < 0.5), models 1 / 2 / 3{tag}",
                        "grows with hysteresis: model 2 a little, model 3 most", _seq(frac, 3),
                        "model 3 > model 1, model 2 >= model 1", grows if kind == "target" else None, kind,
                        f"high-speed / low-WOB quadrant: {_seq(quad, 3)}", f1.name))
        worse = sev[2] > sev[0] and mx[2] > max(mx[0], mx[1])
        rows.append(Row("3", f"severity at low speed and high WOB, models 1 / 2 / 3{tag}",
                        "higher with hysteresis (model 3's unstable region the most severe)",
                        f"mean SS {_seq(sev)}; max SS {_seq(mx)}",
                        "model 3 above model 1 (mean) and above models 1-2 (max)",
                        worse if kind == "target" else None, kind,
                        "" if kind == "target" else f"with this reading the stable region "
                        f"{'grows' if grows else 'does not grow'} and the severity {'rises' if worse else 'does not rise'}",
                        f2.name))
    return rows, figs


# --------------------------------------------------------------------------------- chapter 4
def chapter4(out: Path, o: Options) -> tuple[list, list]:
    """Section 4.2: natural frequencies, Fig. 4.8 with its threshold and the readings of the
    ambiguities, the 3-cycle regime (Fig. 4.6), Fig. 4.9 with its 5 % speed, Fig. 4.7, Conv1.

    On the ``thesis-ch4`` preset (WOB 200 kN, 100 modes): the first five natural frequencies
    against (0.13, 0.42, 0.74, 1.07, 1.41) Hz within 0.005 Hz; SS (Eq. 3.4) over 6-27 rad/s with
    the speed below which SS > 0.5 located by bisection (thesis 16 rad/s, +-0.5) and its
    decrease with speed (Spearman rank correlation < -0.8); the same threshold under the readings of the ambiguities (rigid initial
    state of Eq. 2.3, lagged acceleration in Eq. 3.3, ``thesis-field`` with 20 and 100 modes;
    quick: the first only); the periodic regime at 14 rad/s (3 cycles, stick (1.34, 2.53,
    2.48) s, slip (5.4, 6.28, 6.41) s, each within 0.3 s) and, as a reading, ``thesis-field``
    with 100 modes at 16 rad/s; then the Monte Carlo rows of Figs. 4.9, C.1 and 4.7 (5 % speed
    20.5 rad/s, shift over the deterministic threshold 4.5 rad/s, band width, Conv1, stick/slip
    modes) and, outside quick mode, their readings of the eta level, PSD convention and
    protocol.

    Parameters
    ----------
    out : Path
        Output folder; receives ``fig4_8.png``, ``fig4_8_readings.png``, ``fig4_6.png``,
        ``fig4_9.png``, ``figC_1.png`` and ``fig4_7.png``.
    o : Options
        Quick mode, threads, progress and the Monte Carlo seed.

    Returns
    -------
    rows : list of Row
        The chapter-4 rows, targets and readings.
    figures : list of str
        Paths of the figures written.
    """
    from drillpy.figures import simulation as plotting
    from scipy.stats import spearmanr

    from drillpy.model.simulation import natural_frequencies, refine_threshold, simulate, sweep_severity
    rows, figs = [], []
    cfg = load_config(preset="thesis-ch4")
    f = natural_frequencies(cfg, 5)
    ok = bool(np.all(np.abs(f - np.array(THESIS_FREQUENCIES_HZ)) <= 0.005))
    rows.append(Row("4", "first five natural frequencies [Hz] (100 elements)", _seq(THESIS_FREQUENCIES_HZ),
                    _seq(f, 4), "+-0.005 Hz (the thesis's rounding)", ok))

    speeds = np.arange(6.0, 28.0)
    ss = sweep_severity(cfg, speeds, progress=o.progress, threads=o.threads)
    ref = refine_threshold(cfg, speeds, ss, tol=0.02 if not o.quick else 0.1, threads=o.threads)
    thr = None if ref is None else ref.threshold
    fig = out / "fig4_8.png"
    plotting.severity_plot(fig, speeds, ss, thr,
                                  title="thesis-ch4 (WOB 200 kN, 100 modes): SS vs top speed (Fig. 4.8)")
    figs.append(str(fig))
    rows.append(Row("4", "top speed below which SS > 0.5 [rad/s] (Fig. 4.8), thesis-ch4", "16",
                    "none" if ref is None else f"{ref.threshold:.2f} +- {ref.precision:.2f}", "+-0.5",
                    ref is not None and abs(ref.threshold - THESIS_THRESHOLD_RAD_S) <= 0.5,
                    note="bisection of the grid's crossing (`drillpy sweep --preset thesis-ch4 --refine 0.02`)",
                    figure=fig.name))
    rho = float(spearmanr(speeds, ss)[0])
    rows.append(Row("4", "SS decreases with the top speed (Fig. 4.8)", "decreasing over [6, 27] rad/s",
                    f"SS(6) = {ss[0]:.2f}, SS(27) = {ss[-1]:.3f}; Spearman {rho:.2f}",
                    "rank correlation < -0.8", rho < -0.8, figure=fig.name))

    # the readings of the ambiguities, each a full sweep located to 0.1 rad/s
    extra = []
    readings = [("initial state Eq. (2.3): string turning rigidly at t = 0", cfg, "rigid"),
                ("bit acceleration lagged in Eq. (3.3)", with_overrides(cfg, acceleration="lagged"), "rest"),
                ("thesis-field (WOB 245 kN, 20 modes)", load_config(preset="thesis-field"), "rest"),
                ("thesis-field with 100 modes (WOB 245 kN)", with_overrides(load_config(preset="thesis-field"),
                                                                            modes=100), "rest")]
    for label, c, start in readings if not o.quick else readings[:1]:
        s2 = sweep_severity(c, speeds, progress=o.progress, threads=o.threads, start=start)
        r2 = refine_threshold(c, speeds, s2, tol=0.1, threads=o.threads, start=start)
        extra.append((label, speeds, s2))
        rows.append(Row("4", f"Fig. 4.8 threshold [rad/s], {label}", "16",
                        "none (no crossing)" if r2 is None else f"{r2.threshold:.2f} +- {r2.precision:.2f}",
                        "reported", None, "reading",
                        "SS > 0.5 at every speed" if r2 is None and s2.min() > 0.5 else ""))
    if extra:
        fig = out / "fig4_8_readings.png"
        plotting.severity_plot(fig, speeds, ss, thr, extra=extra,
                                      title="Fig. 4.8 under the readings of the thesis's ambiguities")
        figs.append(str(fig))

    # the 3-cycle periodic regime (section 4.2.1, Fig. 4.6): the thesis does not state its speed
    for c3, speed, kind in ((cfg, THREE_CYCLE_SPEED_RAD_S, "target"),
                            (with_overrides(load_config(preset="thesis-field"), modes=100), 16.0, "reading")):
        c3 = with_overrides(c3, duration=400, transient=200)
        run = simulate(c3, speed)
        err = _cycle_error(run.period_stick, run.period_slip) if run.period_cycles == 3 else math.inf
        name = "thesis-ch4" if Configuration.of(c3).operation.wob_n == 200e3 else "thesis-field with 100 modes (245 kN)"
        if kind == "target":
            fig = out / "fig4_6.png"
            plotting.time_series_plot(fig, run.t, run.bit_speed, run.torque_on_bit, run.top_speed,
                                       t_window=(340.0, 400.0),
                                       title=f"{name}, {speed:g} rad/s (Fig. 4.6, last 60 s)")
            figs.append(str(fig))
        rows.append(Row("4", f"periodic regime, {name} at {speed:g} rad/s: stick / slip durations [s] (section 4.2.1)",
                        f"3 cycles; stick {_seq(THESIS_STICK_S)}; slip {_seq(THESIS_SLIP_S)}",
                        f"{run.period_cycles} cycle(s); stick {_seq(run.period_stick)}; slip {_seq(run.period_slip)}",
                        "3 cycles, each duration within 0.3 s", err <= 0.3 if kind == "target" else None, kind,
                        f"largest difference {_fmt(err)} s (each list matched at its best cyclic shift: the thesis "
                        "does not say which slip follows which stick); the thesis does not state the speed of "
                        "Fig. 4.6 (thesis-ch4 is 3-periodic from 13.5 to 14.5 rad/s)",
                        "fig4_6.png" if kind == "target" else ""))

    rows_mc, figs_mc = _fig49(out, o, cfg)
    return rows + rows_mc, figs + figs_mc


def _cycle_error(stick, slip) -> float:
    """Largest |drillpy - thesis| over the 3 stick and the 3 slip durations, each list at its best
    cyclic shift."""
    st, sl = np.asarray(stick, float), np.asarray(slip, float)
    return max(min(float(np.max(np.abs(np.roll(x, k) - ref))) for k in range(3))
               for x, ref in ((st, THESIS_STICK_S), (sl, THESIS_SLIP_S)))


def _fig49(out: Path, o: Options, cfg: dict) -> tuple[list, list]:
    """Fig. 4.9 (Algorithm 1 literally, two-sided per-rad/s PSD), its 5 % speed refined with a
    bootstrap interval, the band, Conv1 (Fig. C.1), Fig. 4.7; the drillpy-default reading beside it."""
    from drillpy.figures import stochastic as ps
    from drillpy.uncertainty.montecarlo import phase_study, stochastic_study
    from drillpy.uncertainty.process import THESIS_PSD, convert_psd_model, scaled_to_std
    from drillpy.uncertainty.robust_speed import bootstrap_interval, exceedance, p_speed, refine_p_speed
    rows, figs = [], []
    psd = scaled_to_std(THESIS_PSD, MC_ETA_STD)
    samples = 500 if not o.quick else 24
    speeds = np.arange(6.0, 28.0) if not o.quick else np.arange(14.0, 26.0, 2.0)
    proto = dict(ALGORITHM1) if not o.quick else {"warmup": 0.0, "duration": 150.0, "transient": 100.0}
    kw = dict(psd=psd, threads=o.threads, progress=o.progress, **proto)
    st = stochastic_study(cfg, speeds, samples, o.seed, **kw)
    ref = refine_p_speed(st.severity, st.speeds,
                         lambda sp: stochastic_study(cfg, sp, samples, o.seed, deterministic=False,
                                                     **{**kw, "progress": False}).severity,
                         tol=0.1 if not o.quick else 0.5)
    sev, sp = (st.severity, st.speeds) if ref is None else (ref.severity, ref.speeds)
    p05 = p_speed(sev, sp)
    boot = bootstrap_interval(sev, sp, seed=o.seed)
    fig = out / "fig4_9.png"
    ps.severity_band_plot(fig, st)
    figs.append(str(fig))
    figc = out / "figC_1.png"
    ps.conv1_plot(figc, st.conv1)
    figs.append(str(figc))
    setting = (f"{samples} samples, Algorithm 1 from rest, {proto['duration']:g} s runs ({proto['transient']:g} s "
               f"discarded), eta with the shape of Eq. (4.4) and std {st.eta_std:.4f} (+-20 % as +-3 sigma)")
    ok = p05 is not None and abs(p05 - THESIS_P05_SPEED_RAD_S) <= 1.0
    rows.append(Row("4", "speed from which P(SS > 0.5) <= 5 % [rad/s] (Fig. 4.9)", "20.5",
                    f"{_fmt(p05)} (bracket {_fmt(ref.below) if ref else '-'}-{_fmt(ref.above) if ref else '-'}; "
                    f"90 % bootstrap {_fmt(boot['low'])}-{_fmt(boot['high'])})", "+-1", ok,
                    note=setting, figure=fig.name))
    det = st.deterministic_threshold
    shift = None if p05 is None or det is None else p05 - det
    rows.append(Row("4", "stochastic shift: 5 % speed minus the deterministic threshold [rad/s]", "4.5 (20.5 - 16)",
                    _fmt(shift), "+-1", shift is not None and abs(shift - 4.5) <= 1.0,
                    note=f"deterministic threshold of the same runs (eta = 0): {_fmt(det)} rad/s"))
    # the band: "large fluctuation" (section 4.2.2); quantified as the width of the 90 % band of SS
    # and the speed span over which the outcome is uncertain (5 % < P(SS > 0.5) < 95 %)
    pe = exceedance(sev)
    unc = sp[(pe > 0.05) & (pe < 0.95)]
    span = float(unc.max() - unc.min()) if unc.size else 0.0
    width = float(np.max(st.q95 - st.q05))
    rows.append(Row("4", "width of the statistical envelope (Fig. 4.9)",
                    "large fluctuation of SS; P(SS > 0.5) from 5 % at 20.5 to certainty below 16",
                    f"largest 90 % band width {width:.2f}; 5 % < P < 95 % over {span:.1f} rad/s "
                    f"({_fmt(unc.min() if unc.size else None, 1)}-{_fmt(unc.max() if unc.size else None, 1)})",
                    "band width >= 0.5 and uncertain span >= 2 rad/s", width >= 0.5 and span >= 2.0,
                    figure=fig.name))
    c1 = st.conv1
    n = c1.size
    tail = np.max(np.abs(c1[n // 2:] / c1[-1] - 1.0)) if n >= 2 else math.inf
    rows.append(Row("4", "Conv1 converged (Fig. C.1, Eq. C.1)", "converged at 500 samples",
                    f"max |Conv1(n) / Conv1({n}) - 1| over n >= {n // 2}: {tail:.4f}", "<= 0.01", tail <= 0.01,
                    figure=figc.name))

    # Fig. 4.7: stick and slip durations of the stochastic model at the speed of the 3-cycle regime
    ph = phase_study(cfg, THREE_CYCLE_SPEED_RAD_S, seed=o.seed, cycles=750 if not o.quick else 60, psd=psd,
                     threads=o.threads, progress=o.progress)
    fig = out / "fig4_7.png"
    ps.phase_pdf_plot(fig, ph)
    figs.append(str(fig))
    modes = [_pdf_mode(ph.stick), _pdf_mode(ph.slip)]
    dist = [min(abs(m - d) for d in ds) if len(ds) and m is not None else math.inf
            for m, ds in zip(modes, (ph.deterministic_stick, ph.deterministic_slip))]
    rows.append(Row("4", "most probable stick / slip durations near the deterministic ones [s] (Fig. 4.7)",
                    "large variability; modes close to the deterministic values",
                    f"modes {_fmt(modes[0])} / {_fmt(modes[1])} from {ph.stick.size} phases; deterministic stick "
                    f"{_seq(ph.deterministic_stick)}, slip {_seq(ph.deterministic_slip)}",
                    "each mode within 0.5 s of a deterministic duration", max(dist) <= 0.5,
                    note=f"coefficient of variation: stick {np.std(ph.stick) / np.mean(ph.stick):.2f}, "
                         f"slip {np.std(ph.slip) / np.mean(ph.slip):.2f}" if ph.stick.size else "",
                    figure=fig.name))

    if not o.quick:
        # the other readings of the fluctuation level and of the protocol (200 samples, 12-27 rad/s)
        sp2 = np.arange(12.0, 28.0)
        readings = [("Algorithm 1, Eq. (4.4) read two-sided per rad/s", convert_psd_model(THESIS_PSD, "two-sided-rad-s"),
                     ALGORITHM1),
                    ("Algorithm 1, +-20 % read as +-2 sigma", scaled_to_std(THESIS_PSD, 0.10), ALGORITHM1),
                    ("warm start (100 s) + 40-s window, Eq. (4.4) one-sided per Hz (drillpy's mc default)", THESIS_PSD,
                     WARM_START)]
        for label, p, pr in readings:
            alt = stochastic_study(cfg, sp2, 200, o.seed, psd=p, threads=o.threads, progress=o.progress, **pr)
            b = bootstrap_interval(alt.severity, alt.speeds, seed=o.seed)
            rows.append(Row("4", f"Fig. 4.9 5 % speed [rad/s], {label}", "20.5",
                            f"{_fmt(alt.p05_speed)} (90 % bootstrap {_fmt(b['low'])}-{_fmt(b['high'])}; "
                            f"deterministic {_fmt(alt.deterministic_threshold)})", "reported", None, "reading",
                            f"200 samples; std of eta {alt.eta_std:.4f}"))
    return rows, figs


def _pdf_mode(x: np.ndarray) -> float | None:
    if x.size < 5 or np.ptp(x) == 0:
        return None
    from scipy.stats import gaussian_kde
    grid = np.linspace(x.min(), x.max(), 800)
    return float(grid[np.argmax(gaussian_kde(x)(grid))])


# --------------------------------------------------------------------------------- chapter 5
SAMPLE175_NAME = Path("shared") / "data" / "testrig" / "sample175_0-40s.mat"


def default_record() -> Path:
    """Sample 175 beside the working directory (``../shared``, the README's layout) or beside the
    source tree; the first that exists (the first candidate when none does, for the message).

    Returns
    -------
    Path
        ``shared/data/testrig/sample175_0-40s.mat`` under the working directory's parent, or
        under the parent of the repository holding this package; not checked to exist when
        neither candidate does.
    """
    cands = [Path.cwd().parent / SAMPLE175_NAME, Path(__file__).resolve().parents[4] / SAMPLE175_NAME]
    return next((c for c in cands if c.is_file()), cands[0])


def chapter5(out: Path, o: Options, record: Path | None = None) -> tuple[list, list]:
    """Section 5.3: the test-rig record of sample 175 (the thesis's Figs. 5.5-5.7) and the
    comparison of the regularized (3.1) and non-regularized (5.1) laws by Var[MSE] (Eq. 5.2).

    Analyses the record with :func:`drillpy.reports.analysis.analyze_record` (no rig simulation,
    5 cross-validation folds, quick: 2; the cycle shown taken around 35.5 s) into
    ``out/sample175`` and checks: mean top-drive speed 78 RPM (+-5), largest bit speed "almost
    200" RPM (170-210), stick-slip throughout (SS > 0.5 and at least one valid cycle per second),
    the Fig. 5.7 cycle 35.3-35.67 s (each end within 0.05 s) and Eq. (5.1) fitting with a lower
    Var[MSE] than Eq. (3.1); the standard deviation of eta_exp (section 5.3.2, thesis 0.4674 over
    210 samples) is a reading. Without the record a single ``reading`` row names the missing
    file.

    Parameters
    ----------
    out : Path
        Output folder; receives ``sample175/`` (the analysis report) and copies of its figures as
        ``fig5_5.png``, ``fig5_7.png`` and ``fig5_laws_sample175.png``.
    o : Options
        Quick mode (fewer cross-validation folds).
    record : Path, optional
        The sample-175 ``.mat`` file (default :func:`default_record`).

    Returns
    -------
    rows : list of Row
        The chapter-5 rows.
    figures : list of str
        Paths of the figures copied into ``out``.
    """
    from drillpy.records.analysis import AnalysisOptions
    from drillpy.reports.analysis import analyze_record
    rec = Path(record) if record else default_record()
    if not rec.exists():
        return [Row("5", "test-rig sample 175", "Figs. 5.5-5.7", f"record not found: {rec}", "-", None, "reading",
                    "give --record PATH (the .mat of ../shared/data/testrig)")], []
    S = analyze_record(rec, out / "sample175", AnalysisOptions(simulate=False, folds=5 if not o.quick else 2,
                                                               cycle_at_s=35.5), log=lambda *_: None)
    sv, cy = S["severity"], S["cycles"]
    rows = [
        Row("5", "sample 175: mean top-drive speed [RPM] (Fig. 5.5)", "78", _fmt(sv["mean_top_speed_rpm"], 1),
            "+-5", abs(sv["mean_top_speed_rpm"] - 78.0) <= 5.0, note="first 40 s of the 59-s record (the thesis: whole record)"),
        Row("5", "sample 175: largest bit speed [RPM] (Fig. 5.5)", "almost 200", _fmt(sv["max_bit_speed_rpm"], 1),
            "170-210", 170.0 <= sv["max_bit_speed_rpm"] <= 210.0),
        Row("5", "sample 175: stick-slip almost all the time (Fig. 5.5)", "stick-slip throughout",
            f"SS {_fmt(sv['ss'])}; {cy['n_valid']} cycles at {cy['dominant_frequency_hz']:.2f} Hz; stick fraction "
            f"{sv['stick_fraction']:.2f}", "SS > 0.5 and a cycle at least every second",
            sv["ss"] is not None and sv["ss"] > 0.5 and cy["n_valid"] >= S["record"]["duration_s"]),
    ]
    c0, c1 = S["shown_cycle_s"]
    rows.append(Row("5", "the stick-slip cycle of Fig. 5.7 [s]", "35.3-35.67", f"{c0:.3f}-{c1:.3f}",
                    "each end within 0.05 s", abs(c0 - 35.3) <= 0.05 and abs(c1 - 35.67) <= 0.05,
                    note="the cycle found by drillpy's segmentation (stick start to stick start) around 35.5 s",
                    figure="fig5_7.png"))
    fits = {f["law"]: f for f in S["identification"]["constant_wob"]["fits"]}
    vr, vn = fits.get("tucker_wang", {}).get("var_mse"), fits.get("polynomial", {}).get("var_mse")
    rows.append(Row("5", "Var[MSE] of Eq. (5.2): regularized Eq. (3.1) vs non-regularized Eq. (5.1)",
                    "20.86 vs 0.0017 (sample 13): Eq. (5.1) fits better", f"{_fmt(vr, 4)} vs {_fmt(vn, 4)} (sample 175)",
                    "Eq. (5.1) lower", vr is not None and vn is not None and vn < vr,
                    note="the thesis's sample 13 is not in the shared data; the conclusion is checked on sample 175"))
    rows.append(Row("5", "standard deviation of eta_exp (section 5.3.2)", "0.4674 (average over the 210 samples)",
                    f"{S['eta']['std']:.3f} (sample 175 alone)", "reported", None, "reading",
                    "one sample against the average of 210: not comparable as a target"))
    figs = []
    for src, dst in (("time_series.png", "fig5_5.png"), ("cycle.png", "fig5_7.png"), ("laws.png", "fig5_laws_sample175.png")):
        if (out / "sample175" / src).is_file():
            shutil.copyfile(out / "sample175" / src, out / dst)
            figs.append(str(out / dst))
    return rows, figs


# --------------------------------------------------------------------------------- chapter 6
def chapter6(out: Path, o: Options) -> tuple[list, list]:
    """Section 6.6 and appendix C: every conclusion checked over every model and case (the
    verdicts of :func:`drillpy.uncertainty.chapter6.conclusions`), the narrow DP envelopes near
    3.7 Hz, Conv2 converged.

    Runs :func:`drillpy.reports.uncertainty.chapter6_report` on the ``thesis-ch6`` preset with
    2500 samples per envelope and 400 per point of Conv2 versus modes (1-25 modes; quick: 60 and
    20 samples, modes 2, 5, 10). Each conclusion becomes a row whose thesis value is "holds";
    Conv2 versus samples (Fig. C.2, Eq. C.2) passes when its last two checkpoints are within 1 %
    of the final value.

    Parameters
    ----------
    out : Path
        Output folder; the study's figures and ``summary.json`` go to ``out/chapter6``.
    o : Options
        Quick mode, threads, progress and the Monte Carlo seed.

    Returns
    -------
    rows : list of Row
        One row per conclusion of section 6.6 and the Conv2 row.
    figures : list of str
        Paths of the PNG figures in ``out/chapter6``, sorted.
    """
    from drillpy.reports.uncertainty import chapter6_report
    cfg = load_config(preset="thesis-ch6")
    d = out / "chapter6"
    S = chapter6_report(cfg, d, samples=2500 if not o.quick else 60, mode_samples=400 if not o.quick else 20,
                        seed=o.seed, progress=o.progress, threads=o.threads,
                        modes=(1, 2, 3, 5, 7, 10, 15, 20, 25) if not o.quick else (2, 5, 10))
    rows = []
    for c in S["conclusions"]:
        if "does_not_hold_for" in c:
            note = "fails for " + ", ".join(c["does_not_hold_for"]) if c["does_not_hold_for"] else "every model and case"
        elif "thinnest_at_hz" in c:
            note = "thinnest at " + ", ".join(f"{x:.2f}" for x in c["thinnest_at_hz"]) + " Hz (P_obs1-3)"
        else:
            note = "widths [dB] " + json.dumps(c.get("widths_db", {}))
        rows.append(Row("6", c["claim"], "holds", "holds" if c["holds"] else "does NOT hold", c["test"],
                        bool(c["holds"]), note=note))
    n = S["conv2_samples"]["relative_to_final"]
    rows.append(Row("6", "Conv2 converged in the samples (Fig. C.2)", "converged at 2500 samples",
                    f"Conv2(n) / Conv2(final) at n = {S['conv2_samples']['n']}: {n}", "last two within 1 %",
                    all(abs(x - 1) <= 0.01 for v in n[-2:] for x in np.atleast_1d(v)),
                    figure="chapter6/figC_2_conv2_samples.png"))
    figs = sorted(str(p) for p in d.glob("*.png"))
    return rows, figs


# --------------------------------------------------------------------------------- driver
RUNNERS = {"3": chapter3, "4": chapter4, "5": chapter5, "6": chapter6}


def reproduce(chapters, out_dir, options: Options | None = None, record=None) -> Result:
    """Run the chapters (``"3"``...``"6"`` or ``"all"``), write the figures, ``table.md`` and
    ``reproduce.json`` into ``out_dir`` and return the result (``drillpy reproduce``).

    Parameters
    ----------
    chapters : str, int or sequence
        ``"all"`` (or ``["all"]``) for chapters 3-6, or one chapter or a list of them (``3`` or
        ``"3"``, ...), run in the order given.
    out_dir : str or Path
        Output folder, created if missing.
    options : Options, optional
        Quick mode, threads, progress and seed (default ``Options()``: the thesis's settings).
    record : str or Path, optional
        The sample-175 record for chapter 5 (default :func:`default_record`).

    Returns
    -------
    Result
        The rows, figures and wall time [s] per chapter. ``reproduce.json`` holds
        :meth:`Result.as_dict` with ``quick`` and ``seed``.

    Raises
    ------
    ValueError
        A chapter other than 3, 4, 5, 6 or all.
    """
    o = options or Options()
    want = list(CHAPTERS) if chapters in ("all", ["all"]) else [str(c) for c in np.atleast_1d(chapters)]
    for c in want:
        if c not in RUNNERS:
            raise ValueError(f"chapter = {c!r}: use 3, 4, 5, 6 or all")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    res = Result()
    for c in want:
        t0 = time.perf_counter()
        rows, figs = chapter5(out, o, record) if c == "5" else RUNNERS[c](out, o)
        res.rows += rows
        res.figures += figs
        res.seconds[c] = round(time.perf_counter() - t0, 1)
    prov = provenance(seed=o.seed, quick=o.quick)
    write_text((out / "table.md"), with_markdown_footer(render_table(res, o), prov))
    write_text((out / "reproduce.json"), dumps({**res.as_dict(), "quick": o.quick, "seed": o.seed, "provenance": prov}))
    return res


def render_table(res: Result, o: Options) -> str:
    """The Markdown table of ``table.md``: ch. | quantity | thesis | drillpy | tolerance | pass |
    evidence, setting.

    The pass column reads "yes", "**NO**" or "reading"; the line after the table counts the
    targets that pass, flags quick mode and gives the wall time per chapter [s].

    Parameters
    ----------
    res : Result
        What :func:`reproduce` collected.
    o : Options
        The options it ran with (only ``quick`` is used, for the footnote).

    Returns
    -------
    str
        The Markdown text, ending with a newline.
    """
    d = res.as_dict()
    L = ["| ch. | quantity | thesis | drillpy | tolerance | pass | evidence, setting |", "|---|---|---|---|---|---|---|"]
    for r in res.rows:
        mark = "reading" if r.passed is None else ("yes" if r.passed else "**NO**")
        fig = f" [{r.figure}]" if r.figure else ""
        L.append(f"| {r.chapter} | {r.quantity} | {r.thesis} | {r.drillpy} | {r.tolerance} | {mark} | {r.note}{fig} |")
    L += ["", f"{d['passed']} of {d['targets']} targets pass"
          + (" (quick mode: reduced studies, not the thesis's settings)" if o.quick else "")
          + "; wall time per chapter [s]: " + ", ".join(f"{k}: {v}" for k, v in res.seconds.items())]
    return "\n".join(L) + "\n"
