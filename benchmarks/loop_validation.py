"""Validation of ``drillpy loop`` on records its declared model did not generate.

Every case simulates a *truth* away from the declared model (:func:`drillpy.loop.synthetic.truth_config`:
damping ratio 0.03-0.08 against 0.05 declared, GJ +-1.5 %, the law's slip branch rescaled, 3 modes of
40 elements against 1 of 20, a time step 4 x finer than the loop's), switches on the case's effects
(full size: the catalogue's defaults; half size; two at once; outside the loop's catalogue: the
loop then searches only the original six effects; larger noise), adds measurement noise, and runs
the loop from :func:`drillpy.loop.synthetic.declared_config`. One table row per case: truth, answer,
E before -> after the first step -> final, the long-run metrics (SS, stick fraction, cycle
frequency: record, baseline, final) and the unexplained fraction.

Pass rules: ``clean``: nothing added; ``single``/``noise``: that effect named first with E after
it <= 0.6 E before the loop (the calibrated declared model's: a recalibration step inside the GJ
tolerance may come first, decided on a margin the rounding can tip, and the effect is measured
against the null class, not against whichever member of it the path reached); ``half``: named first (the summary counts them: "most" is the target); ``two``:
both found; ``outside``: nothing misnamed (nothing added, or the listed acceptable name);
``confounded``: a bit viscous torque under a constant top speed, -c_v v = c_v (Omega - v) - c_v Omega,
is exactly a string damping plus a constant torque that the restart state absorbs into the twist:
the calibrated damping ratio takes it (docs/loop.md); nothing else may be named; ``calibration``: a
torque load cell reading 1.15 T + 0.15 N m (``sensor_gain``'s defaults), named first with the fitted
scale within :data:`SCALE_TOLERANCE` of 1.15 (the baseline's law absorbs most of a gain: the E ratio
is no measure of it). In every case each step is listed with its validation E before and after it,
and a step that raises E fails the case (issue 29).

    PYTHONPATH=python python3 benchmarks/loop_validation.py              # the whole table (~5 min)
    PYTHONPATH=python python3 benchmarks/loop_validation.py --markdown   # as the table of docs/loop.md
    PYTHONPATH=python python3 benchmarks/loop_validation.py --only fast  # the cases the tests run
    PYTHONPATH=python python3 benchmarks/loop_validation.py --only half,two --markdown --no-header  # part
    PYTHONPATH=python python3 benchmarks/loop_validation.py --only single --truth-model   # the floor of E
    PYTHONPATH=python python3 benchmarks/loop_validation.py --seed 18 --declared-gj truth  # GJ known exactly
    PYTHONPATH=python python3 benchmarks/loop_validation.py --only fast --scheme exact_modal  # the exact scheme

``--truth-model`` runs no loop: it scores the case's truth itself through the loop's predictor (its
law, damping, effects and stiffness, reduced to the declared model's one mode at the loop's engine
step), once with the truth's GJ and once with the declared GJ (the draw inside the geometry's
tolerance undone): the short-horizon error a perfect calibration of the declared structure reaches.
"""
from __future__ import annotations

import argparse
import sys
import time
from dataclasses import dataclass

from drillpy.loop import LoopOptions, run_loop
from drillpy.loop.effects import CATALOGUE
from drillpy.loop.effects.string_stiffness import EFFECT as STRING_STIFFNESS
from drillpy.loop.synthetic import declared_config, synthetic_record, truth_config

#: The loop's catalogue before this validation's additions: the "outside" cases search only these.
ORIGINAL_SIX = ("bit_hysteresis", "wob_coupling", "top_drive_dynamics", "sensor_lag", "torque_fluctuation",
                "viscous_damping")
#: Record length [s], rate [Hz] and engine step of the loop [s].
DURATION_S, RATE_HZ, LOOP_DT_S = 40.0, 500.0, 2e-4
#: The loop's scheme and its long runs' torque (``LoopOptions.scheme``, ``long_run_fluctuation``; ``--scheme``,
#: ``--long-run-fluctuation``)
OPTIONS = {"scheme": "modified_euler", "long_run_fluctuation": "none", "channel_timing": "auto"}


@dataclass
class Case:
    kind: str
    effects: dict
    seed: int
    noise: float = 1.0
    search: tuple | None = None   #: the loop's candidates (None: the whole catalogue)
    acceptable: tuple = ()        #: names that are a correct reading besides the truth's (documented)
    fast: bool = False            #: run by the tests

    @property
    def label(self) -> str:
        eff = "; ".join(f"{k} ({', '.join(f'{a} {b:g}' for a, b in v.items()) or 'defaults'})"
                        for k, v in self.effects.items()) or "none"
        return eff + (f", noise x{self.noise:g}" if self.noise != 1 else "") + (
            ", catalogue without it" if self.search else "")


CASES = [
    Case("clean", {}, 1, fast=True), Case("clean", {}, 2), Case("clean", {}, 3),
    Case("single", {"bit_hysteresis": {}}, 11),
    Case("single", {"wob_coupling": {}}, 12),
    Case("single", {"top_drive_dynamics": {}}, 13, fast=True),
    Case("single", {"sensor_lag": {}}, 14),
    Case("single", {"torque_fluctuation": {}}, 15),
    Case("confounded", {"viscous_damping": {}}, 16, acceptable=("viscous_damping",)),
    Case("single", {"string_stiffness": {}}, 17, fast=True),
    Case("single", {"static_friction": {}}, 18, fast=True),
    Case("single", {"string_friction": {}}, 19),
    Case("half", {"bit_hysteresis": {"beta1": 0.1}}, 21),
    Case("half", {"wob_coupling": {"gain": 0.5}}, 22),
    Case("half", {"top_drive_dynamics": {"slope_nms_rad": 0.5}}, 23),
    Case("half", {"sensor_lag": {"lowpass_hz": 20.0}}, 24),
    Case("confounded", {"viscous_damping": {"bit_viscous_nms": 0.015}}, 26, acceptable=("viscous_damping",)),
    Case("half", {"static_friction": {"static_torque_nm": 3.6}}, 28),
    Case("half", {"string_stiffness": {"gj_factor": 0.925}}, 27),
    Case("half", {"string_friction": {"string_friction_nm": 0.15}}, 29),
    Case("two", {"top_drive_dynamics": {}, "wob_coupling": {}}, 31, fast=True),
    Case("two", {"sensor_lag": {}, "bit_hysteresis": {}}, 32),
    Case("two", {"static_friction": {}, "wob_coupling": {}}, 33),
    Case("two", {"string_stiffness": {}, "top_drive_dynamics": {}}, 34),
    Case("outside", {"string_stiffness": {}}, 41, search=ORIGINAL_SIX, fast=True),
    Case("outside", {"string_friction": {}}, 42, search=ORIGINAL_SIX),
    Case("outside", {"top_speed_ramp": {}}, 43, acceptable=("top_drive_dynamics",)),
    Case("noise", {"top_drive_dynamics": {}}, 51, noise=3.0),
    Case("noise", {"bit_hysteresis": {}}, 52, noise=3.0),
    Case("calibration", {"sensor_gain": {}}, 61),
]
#: ``calibration`` cases: the fitted scale within this of the truth's load cell (``sensor_gain.MARGIN``)
SCALE_TOLERANCE = 0.03

_DONE: dict = {}


def run_case(case: Case, truth_gj: bool = False) -> dict:
    """Generate the record of a case, run the loop, summarize (cached: a case runs once).
    ``truth_gj``: declare the truth's GJ (its draw inside the geometry's tolerance) instead of the
    nominal one."""
    key = (case.kind, repr(case.effects), case.seed, case.noise, case.search, truth_gj, OPTIONS["scheme"],
           OPTIONS["long_run_fluctuation"], OPTIONS["channel_timing"])
    if key not in _DONE:
        _DONE[key] = _run(case, truth_gj)
    return _DONE[key]


def _run(case: Case, truth_gj: bool) -> dict:
    rec = synthetic_record(case.effects, duration_s=DURATION_S, seed=case.seed, fs_hz=RATE_HZ, noise=case.noise)
    opt = LoopOptions(rate_hz=RATE_HZ, dt_s=LOOP_DT_S, scheme=OPTIONS["scheme"],
                      long_run_fluctuation=OPTIONS["long_run_fluctuation"], channel_timing=OPTIONS["channel_timing"],
                      **({"effects": case.search} if case.search else {}))
    declared = declared_config()
    if truth_gj:
        STRING_STIFFNESS.configure(declared, {"gj_factor": truth_config(case.seed)[1]["gj_factor"]}, None)
    res = run_loop(rec, declared, opt, log=lambda *a: None)
    added = [s.effect for s in res.steps if s.action == "add"]
    first = next((s for s in res.steps if s.action == "add"), None)
    truth = set(case.effects)
    if case.kind == "clean":
        ok = not added
    elif case.kind in ("single", "noise"):
        named = first is not None and (first.effect in truth or first.effect in case.acceptable)
        ok = named and first.error_after <= 0.6 * res.baseline.E_test
    elif case.kind == "half":
        ok = first is not None and (first.effect in truth or first.effect in case.acceptable)
    elif case.kind == "two":
        ok = truth <= set(added)
    elif case.kind == "calibration":
        (name,) = case.effects
        true_s = case.effects[name].get("torque_scale", CATALOGUE[name].defaults["torque_scale"])
        s = float(res.final.model.effects.get(name, {}).get("torque_scale", 1.0))
        ok = first is not None and first.effect == name and abs(s / true_s - 1.0) <= SCALE_TOLERANCE
    else:  # outside the catalogue, or confounded with the calibrated damping: nothing misnamed
        ok = set(added) <= set(case.acceptable)
    lr_b, lr_f = res.baseline_long_run, (res.steps[-1].long_run if res.steps else res.baseline_long_run)
    # every step with its validation E before and after; a step that raises E is a failure of the case
    steps = [({"add": "+", "remove": "-"}.get(st.action, "~") + st.effect,
              float(st.error_before), float(st.error_after)) for st in res.steps]
    raised = [name for name, e0, e1 in steps if e1 > e0]
    ok = ok and not raised
    return {"case": case, "found": added, "steps": steps, "raised": raised, "removed": res.removed, "baseline": res.baseline.E_test,
            "first_after": first.error_after if first else res.baseline.E_test, "final": res.final.E_test,
            "params": {s.effect: s.evidence.parameters or {} for s in res.steps if s.action == "add"},
            "long_run": {"measured": (lr_b or {}).get("measured"), "baseline": (lr_b or {}).get("model"),
                         "final": (lr_f or {}).get("after", (lr_f or {}).get("model"))},
            "unexplained": res.unexplained_fraction, "adequate": res.adequacy["adequate"],
            "terms": [t["name"] for t in res.discovery.get("terms", [])], "truth": rec.provenance["synthetic"]["truth"],
            "ok": ok}


#: Effects the truth's configuration carries (the others are input series or a measurement chain).
IN_CONFIG = {"bit_hysteresis", "viscous_damping", "string_stiffness", "static_friction", "string_friction"}


def truth_model_errors(case: Case) -> dict:
    """(E_train, E_val) of the case's truth scored by the loop's predictor with one mode at the loop's
    engine step: with the truth's GJ ("truth") and with the declared GJ ("declared_gj")."""
    import copy
    from drillpy.model.config import normalize
    from drillpy.loop.data import prepare
    from drillpy.loop.effects import declared_effects, stripped
    from drillpy.loop.model import LoopModel, evaluate
    from drillpy.loop.run import analysis_config
    rec = synthetic_record(case.effects, duration_s=DURATION_S, seed=case.seed, fs_hz=RATE_HZ, noise=case.noise)
    data = prepare(rec, normalize(declared_config()), LoopOptions(rate_hz=RATE_HZ, dt_s=LOOP_DT_S, scheme=OPTIONS["scheme"]))
    info = rec.provenance["synthetic"]
    out = {}
    for key, gj in (("truth", 1.0), ("declared_gj", info["truth"]["gj_factor"])):
        c = copy.deepcopy(info["config"])
        c["rom"]["modes"] = 1
        c["damping"]["ratios"] = c["damping"]["ratios"][:1]
        for sec in c["string"]["sections"]:
            sec["youngs_modulus_pa"] /= gj
        c["simulation"]["scheme"] = OPTIONS["scheme"]
        c = analysis_config(normalize(c), data.dt, LOOP_DT_S)
        base = stripped(c)
        m = LoopModel(base, dict(base["law"]), float(c["operation"]["top_speed_rad_s"]), float(c["operation"]["wob_n"]),
                      declared_effects(c))
        ev = evaluate(m, data)
        out[key] = (ev.E_train, ev.E_test)
    return out


def _lr(x) -> str:
    if not x:
        return "n/a"
    f = x.get("cycle_frequency_hz")
    return f"{x['ss']:.2f} / {x['stick_fraction']:.2f} / " + (f"{f:.2f}" if f is not None else "-")


def _params(p: dict) -> str:
    out = []
    for k, v in p.items():
        val = v["value"] if isinstance(v, dict) else v
        if isinstance(val, float):
            out.append(f"{k} {val:.3g}")
    return ", ".join(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--markdown", action="store_true")
    ap.add_argument("--only", help="run only these kinds, comma-separated (clean, single, confounded, half, two, "
                                   "outside, noise), or 'fast' (the cases the tests run)")
    ap.add_argument("--no-header", action="store_true", help="Markdown rows only (to join the outputs of several runs)")
    ap.add_argument("--truth-model", action="store_true", help="score each case's truth (one mode, the loop's step) "
                                                                "with the loop's predictor instead of running the loop")
    ap.add_argument("--seed", type=int, action="append", help="run only the cases of this seed (repeatable)")
    ap.add_argument("--declared-gj", choices=("nominal", "truth"), default="nominal",
                    help="declare the nominal GJ (default) or the truth's own (its draw inside the tolerance)")
    ap.add_argument("--scheme", choices=("modified_euler", "exact_modal"), default="modified_euler",
                    help="the loop's scheme (at the table's step, 2e-4 s)")
    ap.add_argument("--long-run-fluctuation", choices=("none", "record"), default="none",
                    help="the long runs' bit-rock torque (LoopOptions.long_run_fluctuation)")
    ap.add_argument("--channel-timing", choices=("none", "auto"), default="auto",
                    help="the channels' timing the loop reads each record at (LoopOptions.channel_timing)")
    a = ap.parse_args(argv)
    OPTIONS["scheme"] = a.scheme
    OPTIONS["long_run_fluctuation"] = a.long_run_fluctuation
    OPTIONS["channel_timing"] = a.channel_timing
    kinds = None if a.only is None else set(a.only.split(","))
    cases = [c for c in CASES if (kinds is None or c.kind in kinds or ("fast" in kinds and c.fast))
             and (a.seed is None or c.seed in a.seed)]
    if a.truth_model:
        for c in cases:
            if not set(c.effects) <= IN_CONFIG:
                print(f"{c.kind:<8} {c.label:<60} seed {c.seed}: skipped (the truth's effect is an input series or a "
                      "measurement chain, not in its configuration)")
                continue
            r = truth_model_errors(c)
            print(f"{c.kind:<8} {c.label:<60} seed {c.seed}: truth E {r['truth'][0]:.4f} / {r['truth'][1]:.4f}, with the "
                  f"declared GJ {r['declared_gj'][0]:.4f} / {r['declared_gj'][1]:.4f} (calibration / validation)")
            sys.stdout.flush()
        return 0
    if a.markdown and not a.no_header:
        print("| kind | truth (injected) | seed | answer (added, in order) | loop steps (E before -> after) | E before | "
              "E after step 1 | E final | SS / stick / Hz: record, baseline, final | unexplained | fitted | pass |")
        print("|---|---|---:|---|---|---:|---:|---:|---|---:|---|---|")
    tally: dict = {}
    for c in cases:
        t = time.time()
        r = run_case(c, a.declared_gj == "truth")
        tally.setdefault(c.kind, []).append(r["ok"])
        lr = r["long_run"]
        un = f"{100 * r['unexplained']:.0f} %" if r["unexplained"] is not None else "n/a"
        ans = ", ".join(r["found"]) or "none"
        steps = ", ".join(f"{n} ({e0:.3f}->{e1:.3f})" for n, e0, e1 in r["steps"]) or "none"
        if r["raised"]:
            steps += f"; RAISES E: {', '.join(r['raised'])}"
        if a.markdown:
            print(f"| {c.kind} | {c.label} | {c.seed} | {ans} | {steps} | {r['baseline']:.3f} | {r['first_after']:.3f} | "
                  f"{r['final']:.3f} | {_lr(lr['measured'])}; {_lr(lr['baseline'])}; {_lr(lr['final'])} | {un} | "
                  f"{'; '.join(f'{k}: {_params(v)}' for k, v in r['params'].items()) or '-'} | "
                  f"{'yes' if r['ok'] else 'NO'} |")
        else:
            print(f"{c.kind:<8} {c.label:<70} seed {c.seed}: {steps:<60} E {r['baseline']:.3f} -> {r['first_after']:.3f} "
                  f"-> {r['final']:.3f}  long run {_lr(lr['measured'])} | {_lr(lr['baseline'])} | {_lr(lr['final'])}  "
                  f"unexplained {un}  {'ok' if r['ok'] else 'FAIL'}  [{time.time() - t:.1f} s]")
        sys.stdout.flush()
    summary = ", ".join(f"{k} {sum(v)}/{len(v)}" for k, v in tally.items())
    total = sum(sum(v) for v in tally.values()), sum(len(v) for v in tally.values())
    raised = [f"{r['case'].kind} seed {r['case'].seed}: {r['raised']}" for r in _DONE.values() if r["raised"]]
    print(f"\npassed: {summary}; total {total[0]}/{total[1]}; steps that raise E: {'; '.join(raised) or 'none'}")
    return 0 if total[0] == total[1] else 1


if __name__ == "__main__":
    sys.exit(main())
