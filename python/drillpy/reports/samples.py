"""``drillpy analyze`` given several records (thesis section 5.3) composed:
:func:`drillpy.records.samples.compute_samples` -> :func:`drillpy.figures.records.samples_boxplot` ->
``samples.json`` and ``samples.md`` (:func:`render_samples`).
"""
from __future__ import annotations

from pathlib import Path

from drillpy.figures.records import samples_boxplot
from drillpy.jsonio import write_json
from drillpy.outputs import write_text
from drillpy.provenance import provenance, with_markdown_footer
from drillpy.records.samples import SampleOptions, compute_samples
from drillpy.text import number_text as _f


def analyze_samples(records, out_dir: str | Path, options: SampleOptions | None = None, log=print) -> dict:
    """Section 5.3 across samples: writes ``samples.json``, ``samples.md`` and ``fig5_4_boxplot.png``.

    Parameters
    ----------
    records : list
        As for :func:`drillpy.records.samples.compute_samples` (at least two samples).
    out_dir : path
        Folder the three files are written to (created if needed).
    options : SampleOptions, optional
        As for :func:`drillpy.records.samples.compute_samples`.
    log : callable
        Progress lines (``print`` by default).

    Returns
    -------
    dict
        The content of ``samples.json``.

    Raises
    ------
    ValueError
        As :func:`drillpy.records.samples.compute_samples`.
    """
    S = compute_samples(records, options, log=log)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    samples_boxplot(out / "fig5_4_boxplot.png", S["samples"])
    S["figures"] = ["fig5_4_boxplot.png"]
    prov = provenance()
    write_json(out / "samples.json", {**S, "provenance": prov})
    write_text((out / "samples.md"), with_markdown_footer(render_samples(S), prov))
    acc = S["acceptance"]
    log(f"acceptance: {len(acc['accepted'])} of {len(S['table_5_2'])} samples accepted "
        f"({', '.join(acc['accepted']) or 'none'}); validates the rig: {acc['validates']}")
    log(f"samples.json, samples.md and fig5_4_boxplot.png written to {out}")
    return S


def render_samples(S: dict) -> str:
    """The Markdown tables of an :func:`analyze_samples` summary (``samples.md``).

    Table 5.2 with the acceptance verdicts, the criterion and its per-sample table, the Fig. 5.4
    box plot link, the law parameters per sample with their mean, std and CV, and the thesis's
    own Table 5.2 under the same criterion.

    Parameters
    ----------
    S : dict
        The summary returned by :func:`analyze_samples` (the content of ``samples.json``).

    Returns
    -------
    str
        Markdown text ending with a newline.
    """
    laws = list(S["laws"])
    acc = S["acceptance"]
    verdict = {p["sample"]: p for p in acc["per_sample"]}
    L = [f"# Statistics across {S['n_samples']} samples (thesis section 5.3)", "",
         f"Method: {S['method']}.", "", "## Table 5.2", "",
         "| sample | " + " | ".join(f"Var[MSE] {S['laws'][k]}" for k in laws)
         + " | mean(T) [N m] | std(T) [N m] | CV | cycles with SS | median SS | mean top speed [RPM] | accepted |",
         "|---|" + "---:|" * (len(laws) + 7)]
    for r in S["table_5_2"]:
        L.append(f"| {r['sample']} | " + " | ".join(_f(r["var_mse"].get(k), ".4g") for k in laws)
                 + f" | {_f(r['mean'])} | {_f(r['std'])} | {_f(r['cv'])} | {r['n_cycles_ss']} | "
                 f"{_f(r['ss_median'], '.3f')} | {_f(r['mean_top_speed_rpm'], '.1f')} | "
                 f"{'yes' if verdict[r['sample']]['accepted'] else 'no'} |")
    a = S["across_samples"]
    L += ["", f"Across samples: mean torque {_f(a['torque_mean'].get('mean'))} +/- {_f(a['torque_mean'].get('std'))} "
          f"N m (CV {_f(a['torque_mean'].get('cv'))}); CV average {_f(acc['cv_average'])} (thesis Table 5.2: 0.329 "
          "stated).", "", "## Acceptance criterion (section 5.3.3)", "",
          f"Rule: {acc['rule']}.", "",
          "Thresholds: " + ", ".join(f"Var[MSE] {k} <= {v:g}" for k, v in acc["max_var_mse"].items())
          + f"; variation limit {acc['cv_reference']:.3f} ({acc['cv_reference_source']}) + "
          f"{acc['concrete_variation']:.2f} = {acc['variation_limit']:.3f}.", "",
          "| sample | " + " | ".join(f"Var[MSE] {k} ok" for k in acc["max_var_mse"])
          + " | CV within limit | accepted |",
          "|---|" + "---|" * (len(acc["max_var_mse"]) + 2)]
    for p in acc["per_sample"]:
        L.append(f"| {p['sample']} | " + " | ".join("yes" if p["passes"][k] else "no" for k in acc["max_var_mse"])
                 + f" | {'yes' if p['cv_within_variation_limit'] else 'no'} | {'yes' if p['accepted'] else 'no'} |")
    L += ["", f"{len(acc['accepted'])} of {len(acc['per_sample'])} samples accepted "
          f"({100 * acc['accepted_fraction']:.0f} %); the rig is "
          f"{'validated' if acc['validates'] else 'not validated'} (needs more than "
          f"{100 * acc['min_accepted_fraction']:.0f} %).", "",
          "![Fig. 5.4](fig5_4_boxplot.png)", "", f"## Law parameters per sample (speed unit {S['speed_unit']})", ""]
    for law, blk in S["parameters"].items():
        names = list(blk["parameters"])
        fx = ", ".join(f"{k} = {v:g}" for k, v in blk["fixed"].items())
        L += [f"### {law} (Eq. {blk['equation']}); fixed: {fx or 'none'}", "",
              "| sample | " + " | ".join(names) + " |", "|---|" + "---:|" * len(names)]
        for i, s in enumerate(S["samples"]):
            L.append(f"| {s['sample']} | " + " | ".join(
                f"{blk['parameters'][n]['values'][i]:.4g}" + (" (at bound)" if s["sample"] in
                                                               blk["parameters"][n]["at_bound_in"] else "")
                for n in names) + " |")
        for key in ("mean", "std", "cv"):
            L.append(f"| **{key}** | " + " | ".join(_f(blk["parameters"][n][key], ".4g") for n in names) + " |")
        L.append("")
    th = S["thesis_table_5_2"]["acceptance_with_these_thresholds"]
    L += ["## The thesis's Table 5.2 under the same criterion", "",
          f"Accepted: {', '.join(th['accepted'])} ({len(th['accepted'])} of {len(th['per_sample'])}); "
          f"CV average of the table as printed {th['cv_average']:.3f}. The thesis lists 14-20 as accepted and "
          "concludes 8 of 10; sample 13 (20.86, 0.0017) is below both thresholds.", ""]
    return "\n".join(L) + "\n"


