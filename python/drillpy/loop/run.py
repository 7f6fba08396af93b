"""The loop itself (:func:`run_loop`): calibrate the declared model, check it against trivial
predictors, question its declared effects, add the catalogue's effects one at a time against a
null candidate, check every corrected model's limit cycle, and regress what is left on a library
of terms (docs/loop.md)."""
from __future__ import annotations

import copy
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

from ..config import normalize
from .data import LoopData, prepare
from .discovery import discover, library, residual_structure
from .effects import CATALOGUE
from .evidence import adequacy, evidence
from .fitting import calibrate, fit_candidate, null_candidate, parameter_evidence, refit
from .longrun import destroys_cycle, long_run
from .model import Evaluation, LoopModel, equation_residual, evaluate
from .options import LoopOptions


@dataclass
class LoopResult:
    data: LoopData
    baseline: Evaluation
    final: Evaluation
    steps: list        #: dicts: action, effect, error_before, error_after, evidence, long_run (+ evaluations)
    rounds: list       #: every round's candidates with their evidence
    options: LoopOptions
    config: dict       #: declared configuration (normalized, analysis time step)
    notes: list
    declared: list = field(default_factory=list)        #: effects of the declared model
    adequacy: dict = field(default_factory=dict)        #: the baseline against trivial predictors
    baseline_long_run: dict = field(default_factory=dict)
    discovery: dict = field(default_factory=dict)       #: the discovery step's output
    last_round: dict = field(default_factory=dict)      #: candidate -> Evaluation of the last round

    def metric(self) -> str:
        d = self.data
        return (f"normalized short-horizon prediction error E = sqrt(((v_pred - v)^2 / sd(v)^2 + (T_pred - T)^2 / "
                f"sd(T)^2) / 2), averaged over every sample of the validation part (t >= {d.t_split:.3f} s); "
                f"v bit speed, T torque on bit as recorded, sd over the calibration part (sd(v) = {d.sigma_v:.4g} "
                f"rad/s, sd(T) = {d.sigma_T:.4g} N m); predictions restarted every {self.options.horizon_s:g} s "
                f"from the measured state")

    @property
    def removed(self) -> list:
        return [s["effect"] for s in self.steps if s["action"] == "remove"]

    @property
    def unexplained_fraction(self) -> float | None:
        return self.discovery.get("unexplained_fraction")

    def loop_json(self) -> dict:
        keys = ("action", "effect", "error_before", "error_after", "evidence", "long_run")
        return {"metric": self.metric(), "baseline_error": self.baseline.E_test, "adequacy": self.adequacy,
                "declared": self.declared, "removed": self.removed, "baseline_long_run": self.baseline_long_run,
                "steps": [{k: s[k] for k in keys} for s in self.steps],
                "final_error": self.final.E_test, "final_effects": list(self.final.model.effects),
                "unexplained_fraction": self.unexplained_fraction,
                "discovered_terms": self.discovery.get("terms", []), "parameters": self.final.model.parameters()}


def analysis_config(cfg: dict, dt: float, dt_engine: float | None = None) -> dict:
    """The declared configuration with an engine step (``dt_engine`` or its own) that divides the
    analysis interval ``dt``."""
    c = copy.deepcopy(cfg)
    k = max(1, math.ceil(dt / (dt_engine or c["simulation"]["dt_s"]) - 1e-9))
    c["simulation"]["dt_s"] = dt / k
    c["simulation"]["duration_s"] = max(c["simulation"]["duration_s"], 2 * dt)
    c["simulation"]["transient_s"] = min(c["simulation"]["transient_s"], 0.5 * c["simulation"]["duration_s"])
    return normalize(c)


def _without(model: LoopModel, name: str) -> LoopModel:
    m = model.copy()
    del m.effects[name]
    holder = {"law": m.law, "operation": {}, "string": {"sections": []}}
    CATALOGUE[name].strip(holder)  # a law-level effect leaves the law
    return m


def _long(opt: LoopOptions, model: LoopModel, data: LoopData) -> dict:
    return long_run(model, data) if opt.long_run else {}


def _pair(before: dict, after: dict) -> dict:
    if not before or not after:
        return {}
    return {"measured": after.get("measured", before.get("measured")), "before": before.get("model"),
            "after": after.get("model"), "error": after.get("error")}


def _backward(cur: Evaluation, cur_lr: dict, data: LoopData, opt: LoopOptions, keep, log) -> tuple:
    """Remove, one at a time, the effects (other than ``keep``) the guard does not defend against
    their removal (the cheapest removal first). Returns (model, its long run, the removal steps)."""
    steps = []
    while True:
        trials = []
        for name in [e for e in cur.model.effects if e not in keep]:
            try:
                red = evaluate(null_candidate(_without(cur.model, name), data, opt)[0], data, opt.threads)
            except (ValueError, RuntimeError):
                continue
            e = evidence(red, cur, data, len(cur.model.effects), opt)
            log(f"  remove {name:<20} E_val {red.E_test:.4f} (the effect's gain {100 * e['relative_gain']:+.1f} %)"
                + ("" if e["accepted"] else "  <- not defended: removed"))
            if not e["accepted"]:
                trials.append((red.E_test, name, red, e))
        if not trials:
            return cur, cur_lr, steps
        _, name, red, e = min(trials, key=lambda r: r[0])
        lr = _long(opt, red.model, data)
        steps.append({"action": "remove", "effect": name, "error_before": cur.E_test, "error_after": red.E_test,
                      "evidence": {**e, "accepted": True, "reasons": [f"the guard does not defend {name}: " +
                                                                      "; ".join(e["reasons"])]},
                      "long_run": _pair(cur_lr, lr), "before": cur, "candidate": red, "after": red})
        log(f"step: remove {name}: validation error {cur.E_test:.4f} -> {red.E_test:.4f}")
        cur, cur_lr = red, lr


def _discovery(model: LoopModel, data: LoopData, log) -> dict:
    eq = equation_residual(model, data)
    if eq is None:
        return {"skipped": "no top-speed channel: the twist of the bit's equation is unknown"}
    r, chans, coeffs = eq
    terms = library(chans, dt=data.dt)
    out = discover(r, terms, dt=data.dt)
    out["structure"] = residual_structure(r, chans, data.dt)
    out["equation"] = coeffs
    names = ", ".join(f"{t['name']} ({t['coefficient']:.3g} {t['unit']})" for t in out["terms"]) or "none"
    log(f"discovery: terms {names}; unexplained: {100 * out['unexplained_fraction']:.0f} % of the final model's "
        f"equation residual")
    return out


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
    cfg = analysis_config(cfg, data.dt, opt.dt_s)
    th = opt.threads
    log(f"record: {data.source}; {data.t.size} samples at {1 / data.dt:.0f} Hz; calibration t < {data.t_split:.2f} s "
        f"({int((~data.is_test).sum())} horizons), validation ({int(data.is_test.sum())} horizons of {opt.horizon_s:g} s)")
    m0, _ = calibrate(cfg, data, opt)
    base = evaluate(m0, data, th)
    adeq = adequacy(base, data)
    base_lr = _long(opt, m0, data)
    declared = list(m0.effects)
    log(f"baseline (declared model calibrated: damping {m0.damping_ratios}, effects {declared or 'none'}): validation "
        f"error E = {base.E_test:.4f} (calibration {base.E_train:.4f}); mean predictor {adeq['mean_predictor_error']:.4f}, "
        f"hold-last predictor {adeq['hold_last_predictor_error']:.4f}")
    cur, cur_lr, steps, rounds, last = base, base_lr, [], [], {}
    if not adeq["adequate"]:
        notes.append("the declared model predicts no better than a trivial predictor (mean or hold-last): no effect "
                     "is attributed")
        log("the declared model is not better than a trivial predictor: nothing is attributed")
    else:
        if opt.backward and cur.model.effects:
            cur, cur_lr, rem = _backward(cur, cur_lr, data, opt, (), log)
            steps += rem
        tried = set(cur.model.effects) | {s["effect"] for s in steps}
        for _ in range(opt.max_steps):
            cands = [e for e in opt.effects if e not in tried and all(c in data.channels() for c in CATALOGUE[e].needs)]
            if not cands:
                break
            null_m, _ = null_candidate(cur.model, data, opt)
            null = evaluate(null_m, data, th)
            log(f"  null candidate (no effect, recalibrated) E_val {null.E_test:.4f}")
            results = []
            for name in cands:
                try:
                    cm, ci = fit_candidate(cur.model, data, name, opt)
                    ev = evaluate(cm, data, th)
                    e = evidence(null, ev, data, len(cands), opt)
                    e["parameters"], why = parameter_evidence(cm, name, ci, data)
                    if why:
                        e["accepted"] = False
                        e["reasons"] = e["reasons"] + why
                except (ValueError, RuntimeError) as err:  # a candidate the engine refuses is not evidence
                    ev, e = None, {"accepted": False, "reasons": [f"fit failed: {err}"]}
                results.append((name, ev, e))
                log(f"  candidate {name:<20} " + (
                    f"E_val {e['error_test_after']:.4f} (gain {100 * e['relative_gain']:+.1f} %), p {e['p_value']:.2g}, "
                    f"dBIC {e['delta_bic']:.1f}" if ev is not None else "") + (
                    "  <- passes" if e["accepted"] else f"  ({'; '.join(e['reasons'])})"))
            rounds.append([{"effect": n, **e} for n, _, e in results])
            last = {n: ev for n, ev, _ in results if ev is not None}
            chosen = None
            for name, ev, e in sorted([r for r in results if r[2]["accepted"]], key=lambda r: r[1].E_test):
                nm, ci = refit(ev.model, data, opt)
                new = evaluate(nm, data, th)
                lr = _long(opt, nm, data)
                if opt.long_run and destroys_cycle(cur_lr, lr):
                    e["accepted"] = False
                    e["reasons"] = e["reasons"] + ["the corrected model no longer stick-slips while the record does"]
                    log(f"  {name}: rejected, the corrected model's limit cycle has no stick-slip")
                    continue
                chosen = (name, ev, e, new, lr)
                break
            if chosen is None:
                log("no candidate beats the null candidate with significant, physical parameters: stop")
                break
            name, ev, e, new, lr = chosen
            e = dict(e, error_test_refit=new.E_test, error_test_null=null.E_test, candidates=rounds[-1])
            steps.append({"action": "add", "effect": name, "error_before": cur.E_test, "error_after": new.E_test,
                          "evidence": e, "long_run": _pair(cur_lr, lr), "before": cur, "candidate": ev, "after": new})
            log(f"step {len(steps)}: add {name}: validation error {cur.E_test:.4f} -> {new.E_test:.4f}")
            tried.add(name)
            cur, cur_lr = new, lr
            if opt.backward:
                cur, cur_lr, rem = _backward(cur, cur_lr, data, opt, (name,), log)
                steps += rem
    disc = _discovery(cur.model, data, log) if opt.discovery else {}
    return LoopResult(data, base, cur, steps, rounds, opt, cfg, notes, declared, adeq, base_lr, disc, last)


def loop_record(record, out_dir, *, preset: str | None = None, config_path: str | None = None,
                config: dict | None = None, options: LoopOptions | None = None, log=print) -> dict:
    """``drillpy loop``: run the loop and write ``loop.json``, ``evidence.json``, ``predictions.csv``,
    ``model.json``, ``report.md`` and the figures to ``out_dir``. Returns the content of loop.json."""
    from ..config import load_config
    from .report import write_outputs
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
