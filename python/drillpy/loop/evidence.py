"""The evidence of a loop step: is the declared model better than trivial predictors, does a
candidate beat the null candidate (validation gain, paired test over the validation horizons,
information criterion), and are its parameters significant and physical."""
from __future__ import annotations

import math

import numpy as np
from scipy import stats

from .. import identification as ident
from .data import LoopData, measured
from .model import Evaluation, score
from .options import LoopOptions


def _autocorrelation_time(x: np.ndarray) -> float:
    x = np.asarray(x, float)
    if x.size < 3 or np.std(x) == 0:
        return 1.0
    return max(1.0, ident.autocorrelation_time(x))


def evidence(before: Evaluation, after: Evaluation, data: LoopData, n_candidates: int, opt: LoopOptions) -> dict:
    """The evidence for ``after`` against ``before`` (the null candidate of the round, or the model
    with an effect removed): signature, validation improvement and its significance, information
    criterion, and the guard's decision."""
    te, tr = data.is_test, ~data.is_test
    gain = 1.0 - after.E_test / before.E_test
    d = np.log(before.e_h[te] / after.e_h[te])
    tau = _autocorrelation_time(d)
    k_eff = d.size / tau
    sd = float(np.std(d, ddof=1))
    tstat = float(np.mean(d) / (sd / math.sqrt(k_eff))) if sd > 0 else (math.inf if np.mean(d) > 0 else 0.0)
    p = float(stats.t.sf(tstat, max(k_eff - 1.0, 1.0)))
    Yv, YT = measured(data)
    rv = ((Yv - before.v) / data.sigma_v)[tr].ravel()
    rT = ((YT - before.T) / data.sigma_T)[tr].ravel()
    sv = ((after.v - before.v) / data.sigma_v)[tr].ravel()
    sT = ((after.T - before.T) / data.sigma_T)[tr].ravel()
    R, S = np.r_[rv, rT], np.r_[sv, sT]
    explained = float((R @ S) ** 2 / ((R @ R) * (S @ S))) if (S @ S) > 0 and (R @ R) > 0 else 0.0
    tau_r = 0.5 * (_autocorrelation_time(rv) + _autocorrelation_time(rT))
    n_eff = rv.size / tau_r
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
    return {"explained_fraction": explained, "error_train_before": before.E_train, "error_train_after": after.E_train,
            "error_test_before": before.E_test, "error_test_after": after.E_test, "relative_gain": gain,
            "t_statistic": tstat, "p_value": p, "level": level, "validation_horizons": int(d.size),
            "effective_horizons": k_eff, "delta_bic": dbic, "n_eff": n_eff, "added_parameters": dk,
            "law_rmse_train_before_nm": before.law_rmse_train, "law_rmse_train_after_nm": after.law_rmse_train,
            "law_rmse_test_before_nm": before.law_rmse_test, "law_rmse_test_after_nm": after.law_rmse_test,
            "accepted": not reasons, "reasons": reasons}


def trivial_predictors(data: LoopData) -> dict:
    """E (validation part) of two predictors that know no physics: the calibration part's mean of
    each channel, and the value at the restart held over the horizon."""
    tr = data.valid & (data.t < data.t_split)
    L = data.L
    n = data.starts.size
    mean_v, mean_T = float(np.mean(data.v_meas[tr])), float(np.mean(data.T_meas[tr]))
    _, _, e_mean = score(np.full((n, L), mean_v), np.full((n, L), mean_T), data)
    v0, T0 = data.ch["v"][data.starts], data.ch["T"][data.starts]
    _, _, e_hold = score(np.repeat(v0[:, None], L, 1), np.repeat(T0[:, None], L, 1), data)
    return {"mean": e_mean, "hold_last": e_hold}


def adequacy(base: Evaluation, data: LoopData) -> dict:
    """The declared model against the trivial predictors: adequate when its validation error is
    below both."""
    triv = trivial_predictors(data)
    best = min(triv.values())
    return {"baseline_error": base.E_test, "mean_predictor_error": triv["mean"],
            "hold_last_predictor_error": triv["hold_last"], "adequate": bool(base.E_test < best),
            "skill": 1.0 - base.E_test / best}
