"""The outputs of ``drillpy control`` (issue 15; docs/control.md): :func:`write_control` writes a
:class:`drillpy.control.study.ControlStudy` as ``control.json``, ``report.md`` and the figures.
"""
from __future__ import annotations

from pathlib import Path

from drillpy.outputs import write_text
from drillpy.control.study import ControlStudy, summary
from drillpy.model.configuration import Configuration
from drillpy.control.tuning import TUNABLE, UNITS
from drillpy.jsonio import dumps
from drillpy.provenance import provenance, with_markdown_footer
from drillpy.text import number_text


def _threshold_text(r: dict) -> str:
    """A drive's deterministic threshold [rad/s] with its bisection precision and its RPM equivalent."""
    t = r["deterministic_threshold"]
    if t["threshold_rad_s"] is None:
        return "none in window"
    return (f"{t['threshold_rad_s']:.2f} +- {t['threshold_precision_rad_s']:.2f} "
            f"({t['threshold_rpm']:.1f} +- {t['threshold_precision_rpm']:.1f} RPM)")


def report_text(study: ControlStudy) -> str:
    """The Markdown report (``report.md``).

    Parameters
    ----------
    study : ControlStudy
        What :func:`drillpy.control.study.control_study` returned.

    Returns
    -------
    str
        The report, without the provenance footer.
    """
    c, tw, vw = study.comparison, study.tuning_window, study.validation_window
    lines = [f"# Top-drive control under uncertainty: {study.config.get('name', '')}", "",
             f"Drive inertia J = {study.inertia:g} kg m^2; motor torque limit "
             f"{'none' if study.torque_limit is None else f'{study.torque_limit:g} N m'}. Operating window: speeds "
             f"{', '.join(f'{s:.4g}' for s in tw.speeds)} rad/s x WOB {', '.join(f'{w / 1e3:g}' for w in tw.wobs)} kN. "
             f"Uncertainty: the chapter-4 stochastic bit-rock law (Eq. 4.1; eta's PSD {tw.psd.as_dict()}), runs of {tw.duration:g} s "
             f"after a {tw.warmup:g} s deterministic warm start, SS after {tw.transient:g} s.", "",
             f"Tuning: {tw.samples} samples (seed {tw.seed}) per (speed, WOB), common random numbers. "
             f"Comparison: {vw.samples} new samples (seed {vw.seed}), the same for every drive.", "",
             "## Tuned gains", "",
             f"Searched: each gain x {study.factor_range[0]:g} to x {study.factor_range[1]:g} of the nominal tuning "
             "(log scale). A gain on a bound of that range is flagged: the best value may lie beyond it.", "",
             "| controller | gain | nominal | tuned | factor | bootstrap 5-95 % of the factor | P tuning samples: nominal -> tuned |",
             "|---|---|---|---|---|---|---|"]
    for name, t in study.tunings.items():
        for key in TUNABLE[name]:
            sp = t.spread.get("factors", {}).get(key)
            band = f"{sp['q05']:.3g} - {sp['q95']:.3g}" if sp else "n/a"
            bound = " (**on the search bound**)" if key in t.at_bound else ""
            lines.append(f"| {name} | {key} [{UNITS[key]}] | {t.nominal[key]:.4g} | {t.gains[key]:.4g} | "
                         f"{t.factors[key]:.3g}{bound} | {band} | {t.nominal_p:.3f} -> {t.p_stick_slip:.3f} |")
    lines += ["", "## The drives on new samples", "",
              "P = P(SS > 0.5 or stalled) over the whole window (90 % Wilson interval, the samples as trials); a run "
              "is stalled when "
              "its mean bit speed is below half the command (the bit stuck, SS then small). The difference to the "
              "stiff drive is paired (same samples). Threshold: the speed below which the deterministic SS > 0.5 "
              "at the nominal WOB, located by bisection from the window's speeds with its precision (half the "
              "final bracket) and its RPM equivalent: drillpy sweep's definition, so `drillpy sweep` with the "
              "same drive and WOB gives the same value; 5 % speed: the lowest speed from which P <= 5 % "
              "(section 4.2.2) with its 90 % bootstrap interval.", "",
              "| drive | P window | P - P(stiff) | stalled runs | mean SS | deterministic threshold, bisection [rad/s] | "
              "5 % speed [rad/s] |",
              "|---|---|---|---|---|---|---|"]
    for label, r in c.items():
        pw, pd, iv = r["p_window"], r["p_vs_reference"], r["p05_interval"]
        p05 = (f"{r['p05_speed_rad_s']:.2f} [{number_text(iv['low'], '.2f')}, {number_text(iv['high'], '.2f')}]"
               if r["p05_speed_rad_s"] is not None else r["p05_reading"])
        lines.append(f"| {label} | {pw['value']:.3f} [{pw['low']:.3f}, {pw['high']:.3f}] | "
                     f"{pd['value']:+.3f} [{pd['low']:+.3f}, {pd['high']:+.3f}] | {r['stalled_fraction']:.3f} | "
                     f"{r['mean_ss']:.3f} | "
                     f"{_threshold_text(r)} | {p05} |")
    t0 = Configuration.of(study.config).simulation.transient_s
    lines += ["", f"## Stick-slip episode at {study.episode_speed:.4g} rad/s (nominal WOB)", "",
              "| drive | SS | stick fraction | peak motor torque [N m] | mean motor torque [N m] | within limit |",
              "|---|---|---|---|---|---|"]
    for label, e in study.episodes.items():
        s = e.summary(t0)
        within = "n/a" if s["within_limit"] is None else ("yes" if s["within_limit"] else "NO")
        lines.append(f"| {label} | {s['ss']:.3f} | {s['stick_fraction']:.3f} | {s['peak_motor_torque_nm']:.4g} | "
                     f"{s['mean_motor_torque_nm']:.4g} | {within} |")
    lines += ["", "## Peak motor torque per speed (deterministic runs, nominal WOB) [N m]", "",
              "| drive | " + " | ".join(f"{s:.4g}" for s in tw.speeds) + " |", "|---|" + "---|" * len(tw.speeds)]
    for label, rows in study.motor_torque.items():
        lines.append(f"| {label} | " + " | ".join(f"{r['peak_motor_torque_nm']:.3g}" for r in rows) + " |")
    lines += ["", "Motor torque: the interval mean of u = J Omega' + T_top on the recorded series "
              "(drillpy.control.episode); the ideal drive's is the string's top torque.", "",
              "Figures: maps.png (deterministic SS per drive), p_vs_speed.png (P(SS > 0.5) at the nominal WOB, "
              "Wilson 90 % bands), episode.png (bit speed, top speed, motor torque), tuning_*.png (the score of every "
              "evaluated gain pair)."]
    return "\n".join(lines) + "\n"


def write_control(study: ControlStudy, out_dir, figure_units: str = "si") -> dict:
    """Write ``control.json``, ``report.md`` and the figures to ``out_dir``.

    Parameters
    ----------
    study : ControlStudy
        What :func:`drillpy.control.study.control_study` returned.
    out_dir : str or Path
        Output folder (created if missing).
    figure_units : str
        Axis units of the figures (``si`` or ``field``, :data:`drillpy.figures.simulation.FIGURE_UNITS`);
        ``control.json`` and ``report.md`` stay SI.

    Returns
    -------
    dict
        The content of ``control.json``.
    """
    from drillpy.figures.control import control_figures

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    js = summary(study)
    prov = provenance(seed=study.tuning_window.seed, samples=study.tuning_window.samples,
                      validation_seed=study.validation_window.seed, validation_samples=study.validation_window.samples)
    js["figures"] = [p.name for p in control_figures(study, out, figure_units)]
    write_text((out / "control.json"), dumps({**js, "provenance": prov}))
    write_text((out / "report.md"), with_markdown_footer(report_text(study), prov))
    return js

