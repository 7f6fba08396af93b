"""The loop itself (:func:`run_loop`): calibrate the declared model, check it against trivial
predictors, question its declared effects, add the catalogue's effects one at a time against a
null candidate, check every corrected model's limit cycle, and regress what is left on a library
of terms (docs/loop.md)."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path

from drillpy.model.config import normalize
from drillpy.model.configuration import Configuration
from drillpy.model.plausibility import fitted_values
from drillpy.records import bit_balance
from drillpy.records.io import read_record
from drillpy.records.plausibility import check_record, emit
from .damping_hold import hold_damping
from .data import LoopData, prepare
from .discovery import discover, library, residual_structure
from .effects import CATALOGUE
from .evidence import Evidence, adequacy, evidence, law_evidence
from .fitting import RESTART_GAIN, calibrate, declared_model, e_train, fit_round, null_candidate, parameter_evidence, refit
from .longrun import cycle_damage, long_run, missed_cycle, stick_collapse
from .model import STIFFNESS, Evaluation, LoopModel, equation_residual, evaluate
from .options import LoopOptions
from .rivals import confusable_note, rivals
from .step import Step
from .time_step import at_step, choose_step, step_difference


@dataclass
class LoopResult:
    """Everything a loop run computed (:func:`run_loop`): the data, the baseline and final
    evaluations, every step and round with its evidence; :mod:`drillpy.reports.loop` writes it.

    Attributes
    ----------
    data : LoopData
        The record on the analysis grid, its horizons and split.
    baseline : Evaluation
        The calibrated declared model (damping held by the limit cycle when needed).
    final : Evaluation
        The model after the last step (the baseline when nothing was added or removed).
    steps : list of Step
        Every step in order (:class:`drillpy.loop.step.Step`: an effect added or removed, or a
        recalibration, with E before and after, evidence, long runs and evaluations).
    rounds : list of list
        Every round's candidates: ``{"effect": name, **evidence}``.
    options : LoopOptions
        The options of the run.
    config : dict
        Declared configuration (normalized, modified Euler, engine step dividing the analysis
        interval).
    notes : list of str
        Remarks for the report (modes kept, damping held, inadequate baseline...).
    declared : list of str
        Effects of the declared model.
    adequacy : dict
        The baseline against trivial predictors (:func:`drillpy.loop.evidence.adequacy`).
    baseline_long_run : dict
        The baseline's long run (:func:`drillpy.loop.longrun.long_run`; {} when switched off).
    discovery : dict
        The discovery step's output (:func:`drillpy.loop.discovery.discover` with ``structure``,
        ``equation``, ``balanced`` and possibly ``warning``; ``skipped`` without a top speed).
    last_round : dict
        Candidate name -> Evaluation of the last round (for the signature figure).
    warnings : list of PlausibilityWarning
        The record checked against the declared model (:func:`drillpy.records.plausibility.check_record`).
    time_step : dict
        The step rule's record (:mod:`drillpy.loop.time_step`): ``declared_s``, ``used_s`` [s],
        ``tolerance``, the differences [-] of the declared model (``declared_model_difference``, and
        every step ``tried``), of the baseline and of the final model; {} when the step was given.
    """
    data: LoopData
    baseline: Evaluation
    final: Evaluation
    steps: list        #: Step records, in order
    rounds: list       #: every round's candidates with their evidence
    options: LoopOptions
    config: dict       #: declared configuration (normalized, analysis time step)
    notes: list
    declared: list = field(default_factory=list)        #: effects of the declared model
    adequacy: dict = field(default_factory=dict)        #: the baseline against trivial predictors
    baseline_long_run: dict = field(default_factory=dict)
    discovery: dict = field(default_factory=dict)       #: the discovery step's output
    last_round: dict = field(default_factory=dict)      #: candidate -> Evaluation of the last round
    warnings: list = field(default_factory=list)        #: plausibility warnings of the record
    time_step: dict = field(default_factory=dict)       #: the step rule's record ({}: the step was given)

    def metric(self) -> str:
        """The definition of the error E of this run, in words and numbers (``loop.json`` ->
        ``metric``): the formula with its two or three channels, the validation part's start [s],
        sd(v) [rad/s] and sd(T) [N m], and the restart interval [s]."""
        d = self.data
        top = (" + (top_pred - top)^2 / sd(v)^2" if d.has_top else "")
        n = 3 if d.has_top else 2
        return (f"normalized short-horizon prediction error E = sqrt(((v_pred - v)^2 / sd(v)^2 + (T_pred - T)^2 / "
                f"sd(T)^2{top}) / {n}), averaged over every sample of the validation part (t >= {d.t_split:.3f} s); "
                f"v bit speed, T torque on bit" + (", top top speed (where it is a measurement)" if d.has_top else "")
                + f" as recorded, sd over the calibration part (sd(v) = {d.sigma_v:.4g} rad/s, sd(T) = "
                f"{d.sigma_T:.4g} N m); predictions restarted every {self.options.horizon_s:g} s from the measured "
                "state")

    def decision(self) -> dict:
        """Which data fitted the models, which decided the steps, and which the final error is
        measured on (``loop.json`` -> ``decision``; docs/loop.md, "Which data decide").

        Returns
        -------
        dict
            ``fitted_on``, ``decided_on``, ``final_error_on``: one sentence each, with the parts'
            time ranges [s] and horizon counts.
        """
        d, o = self.data, self.options
        cal = f"calibration part (t < {d.t_split:.3f} s, {int((~d.is_test).sum())} horizons)"
        val = f"validation part (t >= {d.t_split:.3f} s, {int(d.is_test.sum())} horizons)"
        return {
            "fitted_on": f"{cal}: every model's parameters, the null candidate's and the candidates'; nothing is "
                         "fitted on the validation part",
            "decided_on": f"{val}: an effect is added only if, refitted, it lowers E there by min_gain "
                          f"({100 * o.min_gain:g} %) against the current model (and passes the guard against the null "
                          "candidate); a direct measurement only proposes a candidate; a recalibration (proposed by a "
                          "lower calibration error) must lower E there; a declared or added effect is removed when it "
                          f"does not lower E there by {100 * o.min_gain:g} % and its removal does not raise E there (no "
                          "step raises E)",
            "final_error_on": f"{val}, the data that decided the steps: the final E is the selected model's error on "
                              "its selection data, an optimistic estimate of its error elsewhere; an out-of-sample "
                              "error is the model's on data the loop never saw (drillpy predict model.json OTHER_RECORD)",
        }

    @property
    def removed(self) -> list:
        """Effects removed by a backward step, in order."""
        return [s.effect for s in self.steps if s.action == "remove"]

    @property
    def confusable(self) -> list:
        """The added effects the record cannot tell from a rival (:mod:`.rivals`): per such step
        ``{"named": effect, "or": [rivals], "note": ...}``, in order."""
        return [{"named": s.effect, "or": [r["effect"] for r in s.evidence.rivals if r["verdict"] == "confusable"],
                 "note": s.evidence.confusable} for s in self.steps if s.evidence.confusable]

    @property
    def unexplained_fraction(self) -> float | None:
        """Fraction of the final model's equation residual the discovery step leaves unexplained
        [-] (None when the step did not run; where the bit's equation does not balance on the
        record, ``discovery["balanced"]`` is False and the residual is not a model mismatch)."""
        return self.discovery.get("unexplained_fraction")

    def loop_json(self) -> dict:
        """The content of ``loop.json`` (docs/loop.md): metric, decision data, baseline error and adequacy,
        the WOB input and the channels' timing (None: as recorded), the step rule, declared and removed effects, long runs, steps, final error and effects, unexplained
        fraction, discovered terms, the final model's parameters and the plausibility ``warnings``.

        Returns
        -------
        dict
            JSON-ready apart from NumPy scalars and non-finite numbers (:func:`drillpy.jsonio.dumps` handles them).
        """
        return {"metric": self.metric(), "decision": self.decision(), "baseline_error": self.baseline.E_test,
                "adequacy": self.adequacy, "wob_input": self.data.wob_response, "channel_timing": self.data.channel_timing,
                "time_step": self.time_step,
                "declared": self.declared, "removed": self.removed, "baseline_long_run": self.baseline_long_run,
                "steps": [s.to_json() for s in self.steps],
                "final_error": self.final.E_test, "final_effects": list(self.final.model.effects),
                "confusable": self.confusable,
                "unexplained_fraction": self.unexplained_fraction,
                "discovered_terms": self.discovery.get("terms", []), "parameters": self.final.model.parameters(),
                "warnings": [w.as_dict() for w in self.warnings]}


def analysis_config(cfg: dict, dt: float, dt_engine: float | None = None) -> dict:
    """The declared configuration with an engine step (``dt_engine`` or its own) that divides the
    analysis interval ``dt``.

    The step is ``dt`` / k with k the smallest integer for which it is at most the requested step;
    the duration is at least two analysis intervals and the transient at most half the duration.

    Parameters
    ----------
    cfg : dict or Configuration
        Engine configuration (normalized); not modified.
    dt : float
        Analysis sampling interval [s].
    dt_engine : float, optional
        Requested engine step [s] (default: ``cfg.simulation.dt_s``).

    Returns
    -------
    dict
        A normalized copy with the new ``simulation.dt_s`` [s].
    """
    c = Configuration.of(cfg)
    sim = c.simulation
    k = max(1, math.ceil(dt / (dt_engine or sim.dt_s) - 1e-9))
    duration = max(sim.duration_s, 2 * dt)
    return normalize(c.replace({"simulation.dt_s": dt / k, "simulation.duration_s": duration,
                                "simulation.transient_s": min(sim.transient_s, 0.5 * duration)}))


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


def _backward(cur: Evaluation, cur_lr: dict, data: LoopData, opt: LoopOptions, keep, log, done: int) -> tuple:
    """Remove, one at a time, the effects (other than ``keep``) the guard does not defend against
    their removal (the cheapest removal first), after ``done`` steps, unless the removal would raise
    the validation error (no step of the loop does, issue 29) or break the record's limit cycle.
    Returns (model, its long run, the removal steps)."""
    steps = []
    while True:
        trials = []
        for name in [e for e in cur.model.effects if e not in keep]:
            try:
                red = evaluate(null_candidate(_without(cur.model, name), data, opt)[0], data, opt.threads)
            except (ValueError, RuntimeError):
                continue
            e = evidence(red, cur, data, len(cur.model.effects), opt)
            lr = _long(opt, red.model, data)
            kept = (cycle_damage(cur_lr, lr) or stick_collapse(cur_lr, lr)) if opt.long_run else None
            if not kept and red.E_test > cur.E_test:  # no step of the loop raises the validation error (issue 29)
                kept = f"the validation error would rise ({cur.E_test:.4f} -> {red.E_test:.4f})"
            log(f"  remove {name:<20} E_val {red.E_test:.4f} (the effect's gain {100 * e.relative_gain:+.1f} %)"
                + ("" if e.accepted else f"  <- kept: without it {kept}" if kept else
                   "  <- not defended: removed"))
            if not e.accepted and not kept:
                trials.append((red.E_test, name, red, e, lr))
        if not trials:
            return cur, cur_lr, steps
        _, name, red, e, lr = min(trials, key=lambda r: r[0])
        steps.append(Step("remove", name, cur.E_test, red.E_test,
                          dataclasses.replace(e, accepted=True,
                                              reasons=[f"the guard does not defend {name}: " + "; ".join(e.reasons)]),
                          _pair(cur_lr, lr), cur, red, red))
        log(f"step {done + len(steps)}: remove {name}: validation error {cur.E_test:.4f} -> {red.E_test:.4f}")
        cur, cur_lr = red, lr


def _direct(effect, cur: Evaluation, e: Evidence, data: LoopData) -> None:
    """An effect measured directly on the record (its ``direct`` hook, e.g. the break-away torques
    of the stick phases) is *proposed* by that measurement: the candidate is started from the
    measured value (:func:`.fitting.fit_candidate`), and the measurement is recorded in its evidence
    (``e.direct``). It never replaces the validation test (issue 29): a candidate the guard
    refuses stays refused, with the measurement named among the reasons."""
    d = effect.direct(cur.model, data)
    if not d or not d["significant"]:
        return
    e.direct = d["detail"]
    if not e.accepted:
        e.refuse(f"proposed by its direct measurement ({d['detail']}), but a direct measurement does not replace "
                 "the validation test")


def step_gate(before: float, after: float, margin: float) -> str | None:
    """The test every model-changing step of the loop must pass on the data that decide it, the
    validation part (docs/loop.md, "Which data decide"): the step's model must lower E from
    ``before`` to ``after`` <= (1 - ``margin``) ``before``. Returns None when it does, else the
    reason it does not.

    Parameters
    ----------
    before, after : float
        E on the validation part of the current model and of the model after the step [-].
    margin : float
        The relative decrease asked [-]: ``min_gain`` for an added effect, :data:`RECALIBRATION_GAIN`
        for a recalibration.

    Returns
    -------
    str or None
        None: the step lowers E by the margin; else why it is refused.
    """
    if math.isfinite(after) and after <= (1.0 - margin) * before and (margin > 0 or after < before):
        return None
    return (f"the step's model does not lower the validation error by {100 * margin:g} % "
            f"({before:.4f} -> {after:.4f}" + (f", {100 * (1 - after / before):+.1f} %)" if before > 0 else ")"))


#: An addition whose stick phases vanish (:func:`.longrun.stick_collapse`) is still made, and flagged,
#: when it lowers the validation error by at least this share (sample 175's motor, ``--scalar``:
#: 7.0 %; validation case 13's, the truth: 72 %).
COLLAPSE_GAIN = 0.25

#: An added effect whose validation gain is below this multiple of ``min_gain`` is reported as a
#: marginal decision: the rounding of another integrator path or another seed of the same truth can
#: tip it (validation case 26's fast torque_fluctuation passed at 6.2 % before it was flagged).
MARGIN_FACTOR = 2.0


def marginal(name: str, e: dict, opt: LoopOptions) -> str | None:
    """The note on an added effect whose evidence sits near the threshold, or None.

    Parameters
    ----------
    name : str
        The effect.
    e : Evidence
        Its evidence (:func:`drillpy.loop.evidence.evidence`: ``relative_gain``).
    opt : LoopOptions
        The loop's options (``min_gain``).

    Returns
    -------
    str or None
        "marginal: ..." when the validation gain is below :data:`MARGIN_FACTOR` x ``min_gain``, else
        None. (No effect is added below ``min_gain``: a direct measurement no longer stands in for
        the validation test, :func:`step_gate`.)
    """
    g = float(e.relative_gain or 0.0)
    if g >= MARGIN_FACTOR * opt.min_gain:
        return None
    why = f"the {100 * opt.min_gain:.0f} % asked is passed by little"
    return (f"marginal: {name} lowers the validation error by {100 * g:.1f} % ({why}; below "
            f"{100 * MARGIN_FACTOR * opt.min_gain:.0f} % a decision can tip with the rounding or the record)")


#: At most this many recalibrations from a ``string_stiffness`` fit inside the GJ tolerance (:func:`_null_class`).
RECALIBRATIONS = 2

#: The validation margin a recalibration must pass (:func:`step_gate`; 0: it must lower E, by any
#: amount). A recalibration adds no parameter: it is the same model at another optimum of the
#: calibration, proposed by the calibration part (E_cal lower by :data:`~.fitting.RESTART_GAIN`); the
#: validation part must agree that it predicts better. The guard's ``min_gain`` protects against
#: an added parameter fitting noise, which a recalibration cannot do (docs/loop.md).
RECALIBRATION_GAIN = 0.0


def _null_class(fit, null_m: LoopModel, cur_lr: dict, data: LoopData, opt: LoopOptions, log):
    """A ``string_stiffness`` candidate whose factor lies inside the declared GJ tolerance is a
    model of the null class: the GJ calibrated within its tolerance, from the effect's own starts
    (factors 0.8-1.25) instead of the current value. The calibration can stop in a local minimum of
    the GJ (a baseline that took the GJ to its bound to stand in for a missing effect keeps it
    there once the effect is added); when that fit calibrates better than the null candidate, by
    :data:`~.fitting.RESTART_GAIN` at least, and keeps the record's limit cycle, it is returned as
    (model with the factor as its calibrated GJ, its long run, note, {calibration errors before and
    after, factor}), else None. The loop records it as a step with ``"action": "recalibrate"``."""
    if fit is None or isinstance(fit, Exception) or not null_m.gj_tolerance:
        return None
    m = fit[0]
    f = float(m.effects[STIFFNESS]["gj_factor"])
    if abs(f - 1.0) > null_m.gj_tolerance:
        return None
    alt = m.copy()
    del alt.effects[STIFFNESS]
    alt.gj_factor = f
    e_alt, e_null = e_train(alt, data, opt.threads), e_train(null_m, data, opt.threads)
    if not e_alt < (1.0 - RESTART_GAIN) * e_null:
        return None
    lr = _long(opt, alt, data)
    if opt.long_run and (not lr or "error" in lr):
        return None
    if opt.long_run and cur_lr and "error" not in cur_lr and (cycle_damage(cur_lr, lr) or stick_collapse(cur_lr, lr)):
        return None
    note = (f"recalibrated: the string_stiffness fit lies inside the declared GJ tolerance (x {f:.4f}) and calibrates "
            f"better than the null candidate (E_cal {e_null:.4f} -> {e_alt:.4f}): a model of the null class from "
            "other starts, its calibration replaces the current one and the round is fitted again from it")
    log(f"  proposed by the calibration part: {note}")
    return alt, lr, note, {"calibration_error_before": e_null, "calibration_error_after": e_alt, "gj_factor": f}


def _recalibration(fit, null: Evaluation, cur: Evaluation, cur_lr: dict, data: LoopData, opt: LoopOptions,
                   log) -> Step | None:
    """The step ``"action": "recalibrate"`` of a round whose ``string_stiffness`` fit is a better
    model of the null class (:func:`_null_class`), or None. Its evidence is taken against the null
    candidate, with the calibration errors and the factor; like the Evaluations ``before``,
    ``candidate`` and ``after``, ``after_long_run`` (the recalibrated model's whole long run) stays
    out of ``loop.json``. The calibration part proposes it; it is accepted (``evidence.accepted``)
    only when it also lowers the validation error (:func:`step_gate` at :data:`RECALIBRATION_GAIN`),
    else the returned step is refused (``accepted`` False, with the reason) and the loop records it
    in the round's evidence instead of taking it."""
    better = _null_class(fit, null.model, cur_lr, data, opt, log)
    if better is None:
        return None
    alt, lr, note, cal = better
    new = evaluate(alt, data, opt.threads)
    veto = step_gate(cur.E_test, new.E_test, RECALIBRATION_GAIN)
    reasons = [note] + ([f"refused: {veto}"] if veto else [])
    e = dataclasses.replace(evidence(null, new, data, 1, opt), accepted=veto is None, reasons=reasons, **cal,
                            parameters={"gj_factor": {"value": cal["gj_factor"], "ci95": None, "at_bound": False,
                                                      "unit": "-"}})
    if veto:
        log(f"  the recalibration is refused by the validation part: {veto}")
    return Step("recalibrate", STIFFNESS, cur.E_test, new.E_test, e, _pair(cur_lr, lr), cur, new, new, lr)


#: A steel string's (bar's) modal damping ratio above this is implausible: the final model is flagged
#: (a structural damping of a few per cent; the whole-rig model's range, ``rigsim.RIG_PARAMETERS``).
PLAUSIBLE_DAMPING = 0.1
def _discovery(model: LoopModel, data: LoopData, log) -> dict:
    eq = equation_residual(model, data)
    if eq is None:
        return {"skipped": "no top-speed channel: the twist of the bit's equation is unknown"}
    r, chans, coeffs = eq
    terms = library(chans, dt=data.dt)
    out = discover(r, terms, dt=data.dt)
    out["structure"] = residual_structure(r, chans, data.dt)
    out["equation"] = coeffs
    # terms of the equation itself: a relative change beyond 50 % is not a mismatch but an equation
    # that does not balance on this record (e.g. a twist integrated from unreliable encoders)
    nominal = {"T": 1.0, "twist": coeffs["k_nm_rad"], "a": coeffs["J_kg_m2"]}
    off = [f"{t['name']} ({t['coefficient'] / nominal[t['name']]:+.0%} of its own coefficient)"
           for t in out["terms"] if t["name"] in nominal and abs(t["coefficient"]) > 0.5 * nominal[t["name"]]]
    out["balanced"] = not off
    names = ", ".join(f"{t['name']} ({t['coefficient']:.3g} {t['unit']})" for t in out["terms"]) or "none"
    if off:
        out["warning"] = ("the bit's equation does not balance on this record: " + ", ".join(off) + "; the twist "
                          "integrated from the top and bit encoders does not follow the measured torque, so the "
                          "terms found are not a model mismatch and the unexplained fraction is not meaningful")
        log("discovery: " + out["warning"])
    log(f"discovery: terms {names}; unexplained: {100 * out['unexplained_fraction']:.0f} % of the final model's "
        "equation residual" + (" (which does not balance: not a model mismatch)" if off else ""))
    return out


def run_loop(record, cfg: dict, options: LoopOptions | None = None, log=print) -> LoopResult:
    """Run the loop on a record (path or :class:`Record`) from the declared configuration ``cfg``.

    Calibrate the declared model, check it against trivial predictors, question its declared
    effects, add the catalogue's effects one at a time against a null candidate (with the long-run
    check), and regress what is left (docs/loop.md). The loop integrates with the modified Euler
    scheme at an engine step dividing the analysis interval.

    Parameters
    ----------
    record : Record, str or Path
        The measured record or its file (bit speed and torque on bit; top speed and WOB optional).
    cfg : dict
        The declared configuration (normalized here).
    options : LoopOptions, optional
        The loop's options (default :class:`LoopOptions`); validated.
    log : callable
        Called with each progress line (default :func:`print`).

    Returns
    -------
    LoopResult
        Everything the run computed.

    Raises
    ------
    ValueError
        Invalid options, or a record the loop cannot use (:func:`drillpy.loop.data.prepare`).

    Notes
    -----
    The optimizer's linear algebra (SVDs of tall Jacobians) runs on ``options.blas_threads`` BLAS
    threads (:func:`threadpoolctl.threadpool_limits`; one by default): OpenBLAS's threads gain
    nothing on those matrices, and while they spin after each call they take the cores from the
    engine's OpenMP threads (``benchmarks/loop_sample175.py``).
    """
    opt = options or LoopOptions()
    opt.validate()
    cfg = normalize(cfg)  # the declared configuration's plausibility warnings, once
    with fitted_values():  # the candidates are judged by their bounds and flags (docs/loop.md, "The evidence")
        if not opt.blas_threads:
            return _run_loop(record, cfg, opt, log)
        from threadpoolctl import threadpool_limits
        with threadpool_limits(limits=opt.blas_threads, user_api="blas"):
            return _run_loop(record, cfg, opt, log)


def _run_loop(record, cfg: dict, opt: LoopOptions, log) -> LoopResult:
    """:func:`run_loop` with validated options: its stages in order."""
    cfg = normalize(cfg)
    data, warns, notes = _read(record, cfg, opt, log)
    cfg = _analysis(cfg, data, opt, notes)
    declared_cfg, cfg, step = _time_step(cfg, data, opt, log)
    base, base_lr, adeq = _baseline(cfg, data, opt, notes, log)
    if step and not _step_holds(step, base.model, data, opt, log):
        cfg = declared_cfg
        base, base_lr, adeq = _baseline(cfg, data, opt, notes, log)
    st = _State(data, opt, log, base, base_lr, notes)
    if adeq["adequate"]:
        _search(st)
    else:
        notes.append("the declared model predicts no better than a trivial predictor (mean or hold-last): no effect "
                     "is attributed")
        log("the declared model is not better than a trivial predictor: nothing is attributed")
    _final_flags(st)
    if step and step["used_s"] != step["declared_s"]:
        step["final_difference"] = step_difference(at_step(st.cur.model, step["declared_s"]), data, step["used_s"],
                                                   threads=opt.threads)
        if step["final_difference"] > opt.step_tolerance:
            notes.append(f"the final model's predictions at the loop's step {step['used_s']:.3g} s differ from the "
                         f"declared step's by {step['final_difference']:.4f} of the spreads, above the step rule's "
                         f"{opt.step_tolerance:g}: rerun with --dt {step['declared_s']:.3g} to check its decisions")
    disc = _discovery(st.cur.model, data, log) if opt.discovery else {}
    return LoopResult(data, base, st.cur, st.steps, st.rounds, opt, cfg, notes, list(base.model.effects), adeq,
                      base_lr, disc, st.last, warns, step)


@dataclass
class _State:
    """What the loop's stages share and change: the record, the options, the current model and its
    long run, the steps and rounds so far, the last round's candidate evaluations, the notes, the
    effects already tried and the recalibrations taken."""
    data: LoopData
    opt: LoopOptions
    log: object
    cur: Evaluation
    cur_lr: dict
    notes: list
    steps: list = field(default_factory=list)
    rounds: list = field(default_factory=list)
    last: dict = field(default_factory=dict)
    tried: set = field(default_factory=set)
    recalibrated: int = 0

    def backward(self, added: tuple) -> None:
        """Try to remove every other effect after ``added`` (:func:`_backward`)."""
        if self.opt.backward:
            self.cur, self.cur_lr, rem = _backward(self.cur, self.cur_lr, self.data, self.opt, added, self.log,
                                                   len(self.steps))
            self.steps += rem


def _read(record, cfg: dict, opt: LoopOptions, log) -> tuple:
    """Stage 1, the record: read, checked against the configuration and brought to the analysis
    grid; (data, plausibility warnings, notes on the horizons set apart and on the WOB's role)."""
    raw = read_record(record) if isinstance(record, (str, Path)) else record
    warns = check_record(raw, cfg)  # before prepare: a record it refuses (a time unit off) is explained
    emit(warns)
    data = prepare(raw, cfg, opt)
    notes = []
    if data.set_apart:
        count = {r: sum(v == r for v in data.set_apart.values()) for r in sorted(set(data.set_apart.values()))}
        why = {"stall": "they overlap " + ", ".join(f"the stall at {a:.2f} s ({n:.2f} s)" for a, n in data.stalls)
                        + ": the bit stuck at a torque the motor cannot overcome until the WOB is relieved, no part "
                          "of the regular cycle",
               "top-speed artifact at the restart": "their restart's top speed is an artifact, not a measurement, "
                                                    "and is never fed in"}
        note = "horizons set apart from E: " + "; ".join(f"{n} ({r}): {why[r]}" for r, n in count.items())
        notes.append(note)
        log(note)
    wr = data.wob_response
    if wr is not None and wr["input"] == "trend" and wr["correlation"] is None:
        note = ("the law takes the recorded WOB's trend below 0.5 Hz (--wob-input trend): the record is too short "
                "(under 10 s) to test whether the WOB is a response of the rotation")
        notes.append(note)
        log(note)
    elif wr is not None and wr["input"] == "trend":
        note = (f"the recorded WOB is a response of the rotation, not an input: its part above 0.5 Hz follows the "
                f"bit's angle deficit (correlation {wr['correlation']:.2f} at a lag of {1e3 * wr['lag_s']:.0f} ms, "
                f"{wr['gain_n_rad']:.0f} N/rad); the law takes its trend below 0.5 Hz, the WOB known beforehand "
                "(--wob-input measured feeds the recorded one: a diagnosis, not a prediction)")
        notes.append(note)
        log(note)
    return data, warns, notes


def _analysis(cfg: dict, data: LoopData, opt: LoopOptions, notes: list) -> dict:
    """Stage 2, the engine configuration of the analysis: the options' scheme (``LoopOptions.scheme``)
    at a step dividing the analysis interval (:func:`analysis_config`), with notes on what that
    changes."""
    c = Configuration.of(cfg)
    if c.rom.modes > 1:
        notes.append(f"the model keeps {c.rom.modes} modes: the restart state puts the first mode in "
                     "motion and the others in quasi-static equilibrium (exact only with one mode)")
    if c.simulation.scheme != opt.scheme:
        cfg = normalize(c.replace({"simulation.scheme": opt.scheme}))
        notes.append(f"the loop integrates with the {opt.scheme} scheme (its option scheme), not the declared "
                     f"{c.simulation.scheme}")
    return analysis_config(cfg, data.dt, opt.dt_s)


def _time_step(cfg: dict, data: LoopData, opt: LoopOptions, log) -> tuple:
    """Stage 2b, the step rule (:mod:`.time_step`; only without ``opt.dt_s``): (the configuration at
    the declared step, at the step the loop takes, the rule's record for ``loop.json``; {} when it
    does not run)."""
    if opt.dt_s is not None or not opt.step_tolerance:
        return cfg, cfg, {}
    m = declared_model(cfg, data, opt)
    h0 = float(m.cfg["simulation"]["dt_s"])
    h, d, tried = choose_step(m, data, opt.step_tolerance, opt.threads)
    step = {"declared_s": h0, "used_s": h, "tolerance": opt.step_tolerance, "declared_model_difference": d,
            "tried": [{"dt_s": x, "difference": y} for x, y in tried]}
    log(f"engine step: {h:.3g} s (declared {h0:.3g} s; the declared model's horizon predictions differ by "
        + ", ".join(f"{y:.4f} at {x:.3g} s" for x, y in tried) + f" of the spreads, tolerance {opt.step_tolerance:g})")
    return cfg, (analysis_config(cfg, data.dt, h) if h != h0 else cfg), step


def _step_holds(step: dict, model: LoopModel, data: LoopData, opt: LoopOptions, log) -> bool:
    """The step rule confirmed on the calibrated baseline ``model``: its predictions at the loop's step
    within the tolerance of the declared step's (recorded in ``step``); False sends the loop back to
    the declared step."""
    if step["used_s"] == step["declared_s"]:
        return True
    d = step_difference(at_step(model, step["declared_s"]), data, step["used_s"], threads=opt.threads)
    step["baseline_difference"] = d
    if d <= opt.step_tolerance:
        return True
    log(f"engine step: the calibrated baseline's predictions at {step['used_s']:.3g} s differ by {d:.4f} of the "
        f"spreads (tolerance {opt.step_tolerance:g}): back to the declared {step['declared_s']:.3g} s")
    step["used_s"] = step["declared_s"]
    return False


def _baseline(cfg: dict, data: LoopData, opt: LoopOptions, notes: list, log) -> tuple:
    """Stage 3, the baseline: the declared model calibrated (its damping held by the limit cycle when
    the short horizons over-damp it), evaluated and compared with trivial predictors; (evaluation,
    long run, adequacy)."""
    log(f"record: {data.source}; {data.t.size} samples at {1 / data.dt:.0f} Hz; calibration t < {data.t_split:.2f} s "
        f"({int((~data.is_test).sum())} horizons), validation ({int(data.is_test.sum())} horizons of {opt.horizon_s:g} s)")
    if data.channel_timing:
        log(bit_balance.timing_line(data.channel_timing))
    m0, _ = calibrate(cfg, data, opt)
    base_lr = _long(opt, m0, data)
    m0, base_lr, note = hold_damping(m0, base_lr, data, opt, log)
    if note:
        notes.append(note)
    base = evaluate(m0, data, opt.threads)
    adeq = adequacy(base, data)
    gj = f", GJ x {m0.gj_factor:.4f} (within the declared +-{100 * m0.gj_tolerance:g} %)" if m0.gj_free else ""
    log(f"baseline (declared model calibrated: damping {m0.damping_ratios}{gj}, effects {list(m0.effects) or 'none'}): "
        f"validation error E = {base.E_test:.4f} (calibration {base.E_train:.4f}); mean predictor "
        f"{adeq['mean_predictor_error']:.4f}, hold-last predictor {adeq['hold_last_predictor_error']:.4f}")
    return base, base_lr, adeq


def _search(st: _State) -> None:
    """Stage 4, the search: the declared effects questioned, then rounds of candidates against a
    null candidate until none passes (each round: a recalibration the calibration part proposes, or
    the candidates scored, the best that survives its refit, gate and long run added)."""
    if st.cur.model.effects:
        st.backward(())
    st.tried = set(st.cur.model.effects) | {s.effect for s in st.steps}
    for _ in range(st.opt.max_steps + RECALIBRATIONS):
        cands = _candidates(st)
        if not cands or sum(s.action == "add" for s in st.steps) >= st.opt.max_steps:
            break
        null_m, fits = fit_round(st.cur.model, st.data, cands, st.opt)
        null = evaluate(null_m, st.data, st.opt.threads)
        st.log(f"  null candidate (no effect, recalibrated) E_val {null.E_test:.4f}")
        recal, refused_recal = _round_recalibration(st, fits, null)
        if recal:
            continue  # the candidates refitted from the recalibrated model
        results = _score(st, cands, fits, null, refused_recal)
        st.rounds.append([{"effect": n, **e.to_json()} for n, _, e in results])
        st.last = {n: ev for n, ev, _ in results if ev is not None}
        chosen = _choose(st, results)
        # the round's record with the refusals after the refit (the gate, the long run) in it
        st.rounds[-1] = [{"effect": n, **e.to_json()} for n, _, e in results]
        if chosen is None:
            st.log("no candidate beats the null candidate with significant, physical parameters: stop")
            break
        _add(st, chosen, results, null)


def _candidates(st: _State) -> list:
    """The round's candidates: untried effects whose channels the record has, applicable to it, and
    not confounded with a damping the limit cycle holds."""
    return [e for e in st.opt.effects if e not in st.tried and all(c in st.data.channels() for c in CATALOGUE[e].needs)
            and CATALOGUE[e].applicable(st.data)
            and not (st.cur.model.damping_held and "damping" in CATALOGUE[e].confounded_with)]


def _round_recalibration(st: _State, fits: dict, null: Evaluation) -> tuple:
    """A recalibration the round's ``string_stiffness`` fit proposes (:func:`_recalibration`): taken
    when the validation part agrees (True, None), kept in the round's evidence when it refuses
    (False, the refused step's errors and evidence), or none (False, None)."""
    step = _recalibration(fits.get(STIFFNESS), null, st.cur, st.cur_lr, st.data, st.opt, st.log) \
        if st.recalibrated < RECALIBRATIONS else None
    if step is None:
        return False, None
    if not step.accepted:
        # proposed by the calibration part, refused by the validation part: kept in the round's evidence
        return False, {"error_before": step.error_before, "error_after": step.error_after, "evidence": step.evidence.to_json()}
    st.recalibrated += 1
    st.steps.append(step)
    st.log(f"step {len(st.steps)}: recalibrate (GJ x {step.evidence.gj_factor:.4f}): validation error "
           f"{st.cur.E_test:.4f} -> {step.error_after:.4f}")
    st.notes.append(step.evidence.reasons[0])
    st.cur, st.cur_lr = step.after, step.after_long_run
    return True, None


def _score(st: _State, cands: list, fits: dict, null: Evaluation, refused_recal) -> list:
    """Every candidate's evidence against the null candidate (validation gain, paired test, BIC, its
    parameters' intervals and bounds, the law's fit, a direct measurement); [(name, evaluation or
    None, evidence)]."""
    results = []
    for name in cands:
        try:
            if isinstance(fits[name], Exception):
                raise fits[name]
            cm, ci = fits[name]
            ev = evaluate(cm, st.data, st.opt.threads)
            e = evidence(null, ev, st.data, len(cands), st.opt)
            e.parameters, why = parameter_evidence(cm, name, ci, st.data)
            lb, la, lwhy = law_evidence(CATALOGUE[name], null.model, st.data, st.opt)
            if lb is not None:
                e.law_fit_rmse_before_nm, e.law_fit_rmse_after_nm = lb, la
            why += lwhy
            if why:
                e.refuse(*why)
            else:
                _direct(CATALOGUE[name], st.cur, e, st.data)
            if name == STIFFNESS and refused_recal is not None:
                e.recalibration = refused_recal
        except (ValueError, RuntimeError) as err:  # a candidate the engine refuses is not evidence
            ev, e = None, Evidence.failed(f"fit failed: {err}")
        results.append((name, ev, e))
        st.log(f"  candidate {name:<20} " + (
            f"E_val {e.error_test_after:.4f} (gain {100 * e.relative_gain:+.1f} %), p {e.p_value:.2g}, "
            f"dBIC {e.delta_bic:.1f}" if ev is not None else "") + (
            "  <- passes" if e.accepted else f"  ({'; '.join(e.reasons)})"))
    return results


def _choose(st: _State, results: list):
    """The best accepted candidate (lowest validation E) that survives its refit: the step gate on the
    refitted model, the damping re-held when the limit cycle sets it, and the long-run check (a
    correction that destroys the measured cycle, or makes the stick collapse for a small gain, is
    refused); (name, evaluation, evidence, refitted evaluation, long run, damping note) or None.
    Refusals are written into the candidates' evidence."""
    opt, data, cur, cur_lr = st.opt, st.data, st.cur, st.cur_lr
    for name, ev, e in sorted([r for r in results if r[2].accepted], key=lambda r: r[1].E_test):
        nm, ci = refit(ev.model, data, opt)
        _, why = parameter_evidence(nm, name, ci, data)
        if why:  # refitted, the effect must still be there: a gain whose effect went back to its
            # no-effect value is the other parameters' new optimum, not the effect's (issue 33)
            e.refuse(*(f"refitted: {w}" for w in why))
            st.log(f"  {name}: rejected, refitted {'; '.join(why)}")
            continue
        new = evaluate(nm, data, opt.threads)
        lr = _long(opt, nm, data)
        held = None
        if nm.damping_held:  # the limit cycle sets the damping: re-held with the new effect
            m2, lr2, held = hold_damping(nm, lr, data, opt, st.log)
            if held:
                new, lr = evaluate(m2, data, opt.threads), lr2
        gate = step_gate(cur.E_test, new.E_test, opt.min_gain)
        if gate:  # the refitted step must itself lower E by the guard's margin (issue 29)
            e.refuse(f"refitted: {gate}")
            st.log(f"  {name}: rejected, refitted {gate}")
            continue
        damage = cycle_damage(cur_lr, lr) if opt.long_run else None
        collapse = stick_collapse(cur_lr, lr) if opt.long_run and not damage else None
        gain = (cur.E_test - new.E_test) / cur.E_test
        if collapse and gain < COLLAPSE_GAIN:
            damage = f"{collapse}, with a validation gain of {100 * gain:.1f} % (below {100 * COLLAPSE_GAIN:.0f} %)"
        elif collapse:
            e = dataclasses.replace(e, long_run_flag=collapse)
            st.notes.append(f"{name} added although {collapse}: its validation gain of {100 * gain:.1f} % is "
                            f"above {100 * COLLAPSE_GAIN:.0f} %; read the corrected model's limit cycle with care")
            st.log(f"  {name}: flagged, {collapse} (validation gain {100 * gain:.1f} %)")
        if damage:
            e.refuse(damage)
            st.log(f"  {name}: rejected, {damage}")
            continue
        return name, ev, e, new, lr, held
    return None


def _add(st: _State, chosen: tuple, results: list, null: Evaluation) -> None:
    """Stage 4's step: the chosen effect added with its evidence (the marginal note, the damping
    re-held, its rivals and a confusable pair), then the others questioned (:meth:`_State.backward`)."""
    name, ev, e, new, lr, held = chosen
    e = dataclasses.replace(e, error_test_refit=new.E_test, error_test_null=null.E_test, candidates=st.rounds[-1])
    margin = marginal(name, e, st.opt)
    if margin:
        e.marginal = margin
        st.notes.append(margin)
        st.log(f"  {margin}")
    if held:
        e.damping = held
    rv = rivals(name, results, new, st.data, st.opt, st.opt.threads, st.log)
    if rv:
        e.rivals = rv
        note = confusable_note(name, rv)
        if note:
            e.confusable = note
            st.notes.append(note)
            st.log(f"  {note}")
            st.tried.update(r["effect"] for r in rv if r["verdict"] == "confusable")
    st.steps.append(Step("add", name, st.cur.E_test, new.E_test, e, _pair(st.cur_lr, lr), st.cur, ev, new))
    st.log(f"step {len(st.steps)}: add {name}: validation error {st.cur.E_test:.4f} -> {new.E_test:.4f}")
    st.tried.add(name)
    st.cur, st.cur_lr = new, lr
    st.backward((name,))


def _final_flags(st: _State) -> None:
    """Stage 5, the final model's flags: damping ratios no steel string has, and a long run that
    misses the record's cycle."""
    high = [z for z in (st.cur.model.damping_ratios or []) if z > PLAUSIBLE_DAMPING]
    if high:
        note = (f"the final model's damping ratios {[round(z, 3) for z in high]} exceed the {PLAUSIBLE_DAMPING:g} a steel "
                "string's modal damping can reach: an element the catalogue lacks (or one refused) stands in for them, "
                "not a property of the string" + "".join(
                    "; " + e.confounded_note for n, e in CATALOGUE.items()
                    if "damping" in e.confounded_with and n not in st.cur.model.effects))
        st.notes.append(note)
        st.log(note)
    miss = missed_cycle(st.cur_lr)
    if miss:
        st.notes.append(miss)
        st.log(miss)
