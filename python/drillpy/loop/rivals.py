"""Rival explanations (issue 29): candidates of one round that the validation part cannot tell
apart from the one the loop is about to add.

Two effects that leave the same signature in the residual (a frequency shift from a softer string
or from the motor's inertia; a tilted slip branch from a viscous torque or from a filter's lag)
can both pass the guard against the null candidate. The loop adds the one with the lowest
validation error, but when that one does not beat the other by the guard's own test, the choice
is not evidence. Each such rival is then tested jointly: fitted on top of the chosen model, it
must lower the validation error by the guard's margin and significantly. When it does, both are
present (the rival stays a candidate of the next round); when it does not, the two explain the
same part of the residual and the step is reported as a confusable pair, with both names and the
numbers, and the rival is not tried again (what it would explain is in the model already).
"""
from __future__ import annotations

from .data import LoopData
from .evidence import evidence
from .fitting import fit_candidate
from .model import Evaluation, evaluate
from .options import LoopOptions

#: At most this many rivals of one chosen effect are tested jointly (each costs a candidate's fit).
MAX_RIVALS = 2


def distinct(chosen: Evaluation, other: Evaluation, data: LoopData, opt: LoopOptions) -> dict:
    """The guard's test of the chosen candidate against another candidate of the same round: does
    the chosen one lower the validation error below the other's by ``min_gain``, with the paired
    t-test over the validation horizons at ``alpha``?

    Parameters
    ----------
    chosen, other : Evaluation
        The two candidates (before the refit), fitted from the same current model.
    data : LoopData
        The record on the analysis grid.
    opt : LoopOptions
        ``min_gain`` and ``alpha``.

    Returns
    -------
    dict
        ``gain`` (1 - E_val(chosen) / E_val(other)), ``p_value`` and ``distinct`` (True: the chosen
        one is better by the guard's test, the other is no rival).
    """
    e = evidence(other, chosen, data, 1, opt)
    gain, p = float(e.relative_gain), float(e.p_value)
    return {"gain": gain, "p_value": p, "distinct": bool(gain >= opt.min_gain and p < opt.alpha)}


def joint(after: Evaluation, name: str, data: LoopData, opt: LoopOptions, threads: int) -> dict:
    """The rival ``name`` fitted on top of the chosen model (``after``, refitted): is it present
    beside the chosen effect?

    Parameters
    ----------
    after : Evaluation
        The model with the chosen effect, refitted.
    name : str
        The rival effect.
    data : LoopData
        The record on the analysis grid.
    opt : LoopOptions
        The loop's options (the guard's ``min_gain``, ``alpha``, ``min_delta_bic``).
    threads : int
        Engine threads.

    Returns
    -------
    dict
        ``error_test_joint`` (E_val of the model with both), ``gain`` against the chosen model alone,
        ``p_value``, ``delta_bic`` and ``present`` (the guard accepts the rival beside the chosen
        effect); ``error`` instead when the joint fit failed (then not present).
    """
    try:
        model, _ = fit_candidate(after.model, data, name, opt)
        both = evaluate(model, data, threads)
    except (ValueError, RuntimeError) as err:  # a joint model the engine refuses is no evidence of presence
        return {"error": str(err), "present": False}
    e = evidence(after, both, data, 1, opt)
    return {"error_test_joint": both.E_test, "gain": float(e.relative_gain), "p_value": float(e.p_value),
            "delta_bic": float(e.delta_bic), "present": bool(e.accepted)}


def rivals(chosen: str, results: list, after: Evaluation, data: LoopData, opt: LoopOptions, threads: int,
           log=print) -> list:
    """The rivals of the chosen effect among the round's candidates that passed the guard, each
    with its test against the chosen one and its joint test.

    Parameters
    ----------
    chosen : str
        The effect the loop is about to add.
    results : list of (str, Evaluation or None, Evidence)
        The round's candidates with their evaluations and evidence (``accepted``: passed the guard
        against the null candidate).
    after : Evaluation
        The model with the chosen effect, refitted.
    data : LoopData
        The record on the analysis grid.
    opt : LoopOptions
        The loop's options.
    threads : int
        Engine threads.
    log : callable
        Progress lines.

    Returns
    -------
    list of dict
        Per rival (the closest first, at most :data:`MAX_RIVALS`): ``effect``, ``error_test`` (its
        own E_val as a candidate), ``against`` (:func:`distinct`), ``joint`` (:func:`joint`) and
        ``verdict``: ``"both"`` (present beside the chosen effect) or ``"confusable"`` (the two
        explain the same residual; the record cannot tell which).
    """
    ev_chosen = next(ev for n, ev, _ in results if n == chosen)
    close = []
    for name, ev, e in results:
        if name == chosen or ev is None or not e.accepted:
            continue
        d = distinct(ev_chosen, ev, data, opt)
        if not d["distinct"]:
            close.append((ev.E_test, name, d))
    out = []
    for err, name, d in sorted(close, key=lambda r: r[0])[:MAX_RIVALS]:
        j = joint(after, name, data, opt, threads)
        verdict = "both" if j["present"] else "confusable"
        log(f"  rival {name}: E_val {err:.4f}, {chosen} better by {100 * d['gain']:+.1f} % (p {d['p_value']:.2g}); "
            + (f"jointly E_val {j['error_test_joint']:.4f} ({100 * j['gain']:+.1f} %, p {j['p_value']:.2g})"
               if "error_test_joint" in j else f"joint fit failed ({j['error']})") + f" -> {verdict}")
        out.append({"effect": name, "error_test": err, "against": d, "joint": j, "verdict": verdict})
    return out


def confusable_note(chosen: str, rv: list) -> str | None:
    """The note of a step whose effect has confusable rivals, or None.

    Parameters
    ----------
    chosen : str
        The effect added.
    rv : list of dict
        Its rivals (:func:`rivals`).

    Returns
    -------
    str or None
        "confusable: ..." naming both effects and the numbers, or None when none is confusable.
    """
    conf = [r for r in rv if r["verdict"] == "confusable"]
    if not conf:
        return None
    parts = [f"{r['effect']} (E_val {r['error_test']:.4f} against {chosen}'s; {chosen} better by "
             f"{100 * r['against']['gain']:+.1f} %, p {r['against']['p_value']:.2g}; added beside it, "
             + (f"{100 * r['joint']['gain']:+.1f} %, p {r['joint']['p_value']:.2g})" if "gain" in r["joint"]
                else "the joint fit failed)") for r in conf]
    return (f"confusable: {chosen} or {' or '.join(r['effect'] for r in conf)}: the record cannot tell them apart "
            f"({'; '.join(parts)}); {chosen} stands in the model for the pair, its name is not a finding")
