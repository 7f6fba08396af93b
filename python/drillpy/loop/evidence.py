"""The evidence of a loop step: is the declared model better than trivial predictors, does a
candidate beat the null candidate (validation gain, paired test over the validation horizons,
information criterion), and are its parameters significant and physical."""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy import stats

from drillpy.records import identification as ident
from .data import LoopData
from .model import Evaluation, channel_errors, score
from .options import LoopOptions


def _autocorrelation_time(x: np.ndarray) -> float:
    x = np.asarray(x, float)
    if x.size < 3 or np.std(x) == 0:
        return 1.0
    return max(1.0, ident.autocorrelation_time(x))


@dataclass
class Evidence:
    """The evidence of a candidate or a step (:func:`evidence`, completed by the loop's stages).

    The first fields are the guard's test of ``after`` against ``before`` (:func:`evidence`); the
    rest are set where they apply and are None (left out of the JSON) otherwise. A candidate whose
    fit failed carries only ``accepted`` (False) and ``reasons`` (:meth:`failed`).

    Attributes
    ----------
    explained_fraction : float
        Share of the calibration residual the prediction change explains [-].
    error_train_before, error_train_after, error_test_before, error_test_after : float
        E on the calibration and validation parts before and after [-].
    relative_gain : float
        1 - E_val(after) / E_val(before) [-].
    t_statistic, p_value, level : float
        The one-sided paired test over the validation horizons and its Bonferroni level.
    validation_horizons : int
        Number of validation horizons.
    effective_horizons, n_eff : float
        Effective sample sizes of the test and of the BIC (n / tau).
    delta_bic : float
        dBIC of the step.
    added_parameters : int
        Parameters the step adds (dk).
    law_rmse_train_before_nm, law_rmse_train_after_nm, law_rmse_test_before_nm, law_rmse_test_after_nm : float
        Law residual RMSEs [N m] before and after, on both parts.
    accepted : bool
        The guard's decision (with every later refusal of the loop).
    reasons : list of str
        Why not (empty when accepted).
    parameters : dict or None
        The candidate's parameters with their 95 % intervals (:func:`drillpy.loop.fitting.parameter_evidence`).
    law_fit_rmse_before_nm, law_fit_rmse_after_nm : float or None
        A law-level effect's law residual RMSE without and with it (:func:`law_evidence`).
    direct : str or None
        The direct measurement that proposed the candidate.
    recalibration : dict or None
        A recalibration of the round proposed and refused (``string_stiffness``'s candidate).
    calibration_error_before, calibration_error_after, gj_factor : float or None
        A recalibration step's calibration errors and GJ factor.
    long_run_flag : str or None
        The long run's warning on an effect added despite it.
    error_test_refit, error_test_null : float or None
        An added effect's E_val refitted and the null candidate's.
    candidates : list or None
        The round's candidates (JSON rows) an added effect was chosen from.
    marginal, confusable : str or None
        Notes on a small gain and on a rival the record cannot tell apart.
    damping : dict or None
        The damping ratios re-held with the added effect.
    rivals : list or None
        The rivals of an added effect (:func:`drillpy.loop.rivals.rivals`).
    """
    explained_fraction: float | None = None
    error_train_before: float | None = None
    error_train_after: float | None = None
    error_test_before: float | None = None
    error_test_after: float | None = None
    relative_gain: float | None = None
    t_statistic: float | None = None
    p_value: float | None = None
    level: float | None = None
    validation_horizons: int | None = None
    effective_horizons: float | None = None
    delta_bic: float | None = None
    n_eff: float | None = None
    added_parameters: int | None = None
    law_rmse_train_before_nm: float | None = None
    law_rmse_train_after_nm: float | None = None
    law_rmse_test_before_nm: float | None = None
    law_rmse_test_after_nm: float | None = None
    accepted: bool = False
    reasons: list = dataclasses.field(default_factory=list)
    parameters: dict | None = None
    law_fit_rmse_before_nm: float | None = None
    law_fit_rmse_after_nm: float | None = None
    direct: str | None = None
    recalibration: dict | None = None
    calibration_error_before: float | None = None
    calibration_error_after: float | None = None
    gj_factor: float | None = None
    long_run_flag: str | None = None
    error_test_refit: float | None = None
    error_test_null: float | None = None
    candidates: list | None = None
    marginal: str | None = None
    damping: dict | None = None
    rivals: list | None = None
    confusable: str | None = None
    fit_failed: bool = False  #: the candidate's fit failed: only ``accepted`` and ``reasons`` hold

    @classmethod
    def failed(cls, reason: str) -> "Evidence":
        """The evidence of a candidate whose fit failed (not evidence of anything).

        Parameters
        ----------
        reason : str
            Why, e.g. ``"fit failed: ..."``.

        Returns
        -------
        Evidence
            Refused, with that reason alone.
        """
        return cls(accepted=False, reasons=[reason], fit_failed=True)

    def refuse(self, *why: str) -> None:
        """Refuse the candidate, adding the reasons (in place).

        Parameters
        ----------
        *why : str
            The reasons, in order.
        """
        self.accepted = False
        self.reasons = self.reasons + list(why)

    def to_json(self) -> dict:
        """The evidence as written to ``loop.json`` and ``evidence.json``: the guard's test (all of
        it, nulls included) and the fields the loop set (those left None are left out); a failed
        fit's ``accepted`` and ``reasons`` alone.

        Returns
        -------
        dict
            Field name -> value.
        """
        out = {}
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if f.name == "fit_failed":
                continue
            if f.name in _TEST_FIELDS and not self.fit_failed or f.name in ("accepted", "reasons") or v is not None:
                out[f.name] = v
        return out


#: The guard's test (:func:`evidence`): always written, nulls included.
_TEST_FIELDS = frozenset(f.name for f in dataclasses.fields(Evidence)[:20])


def evidence(before: Evaluation, after: Evaluation, data: LoopData, n_candidates: int, opt: LoopOptions) -> Evidence:
    """The evidence for ``after`` against ``before`` (the null candidate of the round, or the model
    with an effect removed): signature, validation improvement and its significance, information
    criterion, and the guard's decision.

    The guard (docs/loop.md, "The evidence"): validation gain 1 - E_val(after) / E_val(before) of
    at least ``min_gain``; a one-sided t-test of the per-horizon log error ratios over the
    validation horizons at the effective number n / tau, p below ``alpha`` / ``n_candidates``;
    dBIC = n_eff ln(E_cal(before)^2 / E_cal(after)^2) - dk ln(n_eff) above ``min_delta_bic``.

    Parameters
    ----------
    before : Evaluation
        The reference (the null candidate, or the model with the effect).
    after : Evaluation
        The model questioned (the candidate, or the model without the effect).
    data : LoopData
        The record on the analysis grid.
    n_candidates : int
        Number of candidates in the round (Bonferroni correction of ``alpha``).
    opt : LoopOptions
        ``min_gain``, ``alpha`` and ``min_delta_bic`` are used.

    Returns
    -------
    Evidence
        ``explained_fraction`` (share of the calibration residual the prediction change explains),
        the errors before and after on both parts, ``relative_gain``, ``t_statistic``, ``p_value``,
        ``level``, ``validation_horizons``, ``effective_horizons``, ``delta_bic``, ``n_eff``,
        ``added_parameters``, the law residual RMSEs [N m], ``accepted`` and ``reasons`` (why not).
    """
    te, tr = data.is_test, ~data.is_test
    gain = 1.0 - after.E_test / before.E_test
    d = np.log(before.e_h[te] / after.e_h[te])
    tau = _autocorrelation_time(d)
    k_eff = d.size / tau
    sd = float(np.std(d, ddof=1))
    tstat = float(np.mean(d) / (sd / math.sqrt(k_eff))) if sd > 0 else (math.inf if np.mean(d) > 0 else 0.0)
    p = float(stats.t.sf(tstat, max(k_eff - 1.0, 1.0)))
    eb = channel_errors(before.v, before.T, before.top, data)
    ea = channel_errors(after.v, after.T, after.top, data)
    R = np.concatenate([-r[tr].ravel() for r in eb])  # measured - predicted
    S = np.concatenate([(a - b)[tr].ravel() for a, b in zip(ea, eb)])
    explained = float((R @ S) ** 2 / ((R @ R) * (S @ S))) if (S @ S) > 0 and (R @ R) > 0 else 0.0
    tau_r = float(np.mean([_autocorrelation_time(r[tr].ravel()) for r in eb[:2]]))
    n_eff = eb[0][tr].size / tau_r
    dk = after.model.k - before.model.k
    dbic = float(n_eff * math.log(before.E_train ** 2 / after.E_train ** 2) - dk * math.log(n_eff))
    level = opt.alpha / max(n_candidates, 1)
    reasons = []
    if gain < opt.min_gain:
        reasons.append(f"validation gain {100 * gain:.1f} % < {100 * opt.min_gain:.0f} %")
    if not p < level:
        reasons.append(f"p = {p:.2g} >= {level:.2g}")
    if not dbic > opt.min_delta_bic:
        reasons.append(f"dBIC = {dbic:.1f} <= {opt.min_delta_bic:g}")
    return Evidence(explained, before.E_train, after.E_train, before.E_test, after.E_test, gain, tstat, p, level,
                    int(d.size), k_eff, dbic, n_eff, dk, before.law_rmse_train, after.law_rmse_train,
                    before.law_rmse_test, after.law_rmse_test, accepted=not reasons, reasons=reasons)


def trivial_predictors(data: LoopData) -> dict:
    """E (validation part) of two predictors that know no physics: the calibration part's mean of
    each channel, and the value at the restart held over the horizon.

    Parameters
    ----------
    data : LoopData
        The record on the analysis grid.

    Returns
    -------
    dict
        ``mean`` and ``hold_last``: their E on the validation part [-].
    """
    tr = data.valid & (data.t < data.t_split)
    L = data.L
    n = data.starts.size
    mean_v, mean_T = float(np.mean(data.v_meas[tr])), float(np.mean(data.T_meas[tr]))
    mean_top = np.full((n, L), float(np.mean(data.top_meas[tr & data.top_ok]))) if data.has_top else None
    _, _, e_mean = score(np.full((n, L), mean_v), np.full((n, L), mean_T), data, mean_top)
    v0, T0 = data.ch["v"][data.starts], data.ch["T"][data.starts]
    top0 = np.repeat(data.ch["top"][data.starts][:, None], L, 1) if data.has_top else None
    _, _, e_hold = score(np.repeat(v0[:, None], L, 1), np.repeat(T0[:, None], L, 1), data, top0)
    return {"mean": e_mean, "hold_last": e_hold}


def adequacy(base: Evaluation, data: LoopData) -> dict:
    """The declared model against the trivial predictors: adequate when its validation error is
    below both.

    Parameters
    ----------
    base : Evaluation
        The calibrated declared model.
    data : LoopData
        The record on the analysis grid.

    Returns
    -------
    dict
        ``baseline_error``, ``mean_predictor_error``, ``hold_last_predictor_error`` (E, validation
        part), ``adequate`` and ``skill`` = 1 - E / (the better trivial predictor's E).
    """
    triv = trivial_predictors(data)
    best = min(triv.values())
    return {"baseline_error": base.E_test, "mean_predictor_error": triv["mean"],
            "hold_last_predictor_error": triv["hold_last"], "adequate": bool(base.E_test < best),
            "skill": 1.0 - base.E_test / best}


#: A law-level effect must lower the law residual's RMSE by this fraction at least (on the validation
#: truths the injected law effects lower it by 35-52 %, absent ones by 0-4.3 %:
#: ``PYTHONPATH=python python3 benchmarks/loop_law_evidence.py``).
LAW_EFFECT_SIZE = 0.10


def law_evidence(effect, null_model, data: LoopData, opt: LoopOptions) -> tuple:
    """A law-level effect changes only the torque the law gives for the measured bit speed,
    acceleration and WOB: fitted on the law residual T - T_law(v, a, W) of the calibration part's
    slip samples alone (:func:`.fitting.fit_law`), it must lower that residual by
    :data:`LAW_EFFECT_SIZE` and significantly (an F test of the residual sums of squares at the
    effective sample size n / tau, p < ``alpha``), measured on the record's channels (a measurement
    chain in the model is not undone for this test: that differentiates the noise twice). A
    stiffness or damping mismatch leaves that residual unchanged, however much a law term improves
    the predictions by mimicking it. Returns (RMSE before, after [N m], reasons).

    Parameters
    ----------
    effect : Effect
        The candidate effect (only ``"law"`` effects are tested).
    null_model : LoopModel
        The round's null candidate (its effects, without the measurement chains).
    data : LoopData
        The record on the analysis grid.
    opt : LoopOptions
        ``alpha`` is used.

    Returns
    -------
    tuple
        (law residual RMSE without and with the effect [N m], list of str reasons; empty: the
        evidence holds); (None, None, []) for an effect that is not law-level.
    """
    if effect.level != "law":
        return None, None, []
    from .effects import CATALOGUE
    from .fitting import law_fit_residual
    base = null_model.copy()
    for name in [n for n, p in base.effects.items() if CATALOGUE[n].undo(p) != (0.0, 0.0)]:
        del base.effects[name]  # undoing a measurement chain differentiates the noise twice: tested on the record
    with_it = base.copy()
    with_it.effects[effect.name] = dict(effect.defaults)
    r0, r1 = law_fit_residual(base, data), law_fit_residual(with_it, data)
    rss0, rss1 = float(r0 @ r0), float(r1 @ r1)
    dk = max(effect.count(with_it.effects[effect.name]), 1)
    n_eff = r1.size / _autocorrelation_time(r1)
    dof = max(n_eff - null_model.n_law - dk, 1.0)
    f = ((rss0 - rss1) / dk) / (rss1 / dof) if rss1 > 0 else math.inf
    p = float(stats.f.sf(f, dk, dof)) if f > 0 else 1.0
    before, after = math.sqrt(rss0 / r0.size), math.sqrt(rss1 / r1.size)
    if p < opt.alpha and after <= (1.0 - LAW_EFFECT_SIZE) * before:
        return before, after, []
    return before, after, [f"fitted on the law residual alone it does not lower it by {100 * LAW_EFFECT_SIZE:.0f} % "
                           f"significantly ({before:.4g} -> {after:.4g} N m, F test p = {p:.2g} at n_eff = "
                           f"{n_eff:.0f}): a law-level effect must show in it"]
