"""``drillpy loop``: residual -> missing effect -> corrected model, with the error before and after.

Starting from a declared model (a preset or a JSON configuration), :func:`run_loop`

1. **calibrates what the declared model leaves uncertain** on the first part of a record (the
   *calibration part*; the rest, the *validation part*, is never used to fit anything): the law's
   parameters (on the law residual, then jointly), the modal damping ratios, the parameters of the
   effects it declares, the string's GJ within the declared geometry's tolerance (+-3 %) and the
   operating point, to convergence. A stiffness mismatch beyond that tolerance is an effect to be
   found (``string_stiffness``), not absorbed (:mod:`.fitting`);
2. checks that the calibrated model predicts better than two **trivial predictors** (the channel
   means and the value held from each restart); if it does not, nothing is attributed
   (:func:`.evidence.adequacy`);
3. **questions the declared effects** (backward step): an effect whose removal the guard does not
   refuse is removed (:func:`.run._backward`);
4. fits every effect of the catalogue (:mod:`.effects`, one module per effect) that the model
   lacks and the **null candidate** (the model recalibrated with no effect, same budget and start).
   An effect is added when it beats the null candidate: a relative validation gain of at least
   ``min_gain``, a one-sided paired test over the validation horizons significant at ``alpha`` /
   (number of candidates), a BIC improvement above ``min_delta_bic``, parameters inside their
   physical bounds with 95 % intervals excluding their no-effect values, and no implausibility flag
   (:mod:`.evidence`, :func:`.fitting.parameter_evidence`). The best such candidate whose corrected
   model still stick-slips when the record does (:mod:`.longrun`) is added; the backward step runs
   again; rounds repeat until no candidate passes;
5. regresses the final model's residual (of the bit's equation of motion) on a library of terms
   by sparse regression and reports the terms found and the **unexplained fraction**
   (:mod:`.discovery`).

**Metric** (the number ``loop.json`` reports): the normalized short-horizon prediction error

    E = sqrt( 1/3 [ mean (v_pred - v)^2 / s_v^2 + mean (T_pred - T)^2 / s_T^2 + mean (top_pred - top)^2 / s_v^2 ] )

over all samples of the horizons of a part (v bit speed [rad/s], T torque on bit [N m], top top
speed [rad/s], as recorded; s_v, s_T the standard deviations of bit speed and torque over the
calibration part, fixed for the whole loop; the top-speed term counts zero where the recorded top
speed is not a measurement, and without a top-speed channel the sum has two terms, over 2:
:func:`.model.score`); every ``horizon_s`` the
model restarts from the state that reproduces the measured bit speed, acceleration, torque on bit
and top speed (``Integrator::state_from_bit``) and the engine integrates the horizon
(``drill/horizons.hpp``). E = 0 is a perfect prediction; E = 1 is as far off, on average, as the
channels' own spread. ``error_before``, ``error_after``, ``baseline_error`` and ``final_error`` are E
on the validation part.
"""
from __future__ import annotations

from .data import LoopData, measured, prepare
from .effects import CATALOGUE, NAMES
from .evidence import Evidence, adequacy, evidence, trivial_predictors
from .fitting import calibrate, fit_candidate, null_candidate, refit
from .longrun import long_run
from .model import Evaluation, LoopModel, evaluate, predict
from .options import LoopOptions
from .run import LoopResult, run_loop
from .step import Step

__all__ = ["CATALOGUE", "NAMES", "Evaluation", "Evidence", "LoopData", "LoopModel", "LoopOptions", "LoopResult", "adequacy",
           "calibrate", "evaluate", "evidence", "fit_candidate", "long_run", "measured",
           "null_candidate", "predict", "prepare", "refit", "run_loop", "Step", "trivial_predictors"]
