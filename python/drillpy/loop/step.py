"""One step of the loop (:class:`Step`): an effect added, removed, or the calibration replaced by
a recalibration, with the validation error before and after, its evidence and long runs."""
from __future__ import annotations

from dataclasses import dataclass

from .evidence import Evidence
from .model import Evaluation

#: The step's fields written to ``loop.json`` -> ``steps`` (the evaluations stay in memory).
JSON_FIELDS = ("action", "effect", "error_before", "error_after", "evidence", "long_run")


@dataclass
class Step:
    """A step of :func:`drillpy.loop.run_loop` (:attr:`drillpy.loop.LoopResult.steps`).

    Attributes
    ----------
    action : str
        ``"add"`` (an effect of the catalogue added), ``"remove"`` (a declared or added effect
        removed by a backward step) or ``"recalibrate"`` (the calibration replaced by a
        ``string_stiffness`` fit inside the GJ tolerance, proposed by the calibration error and
        accepted when it lowers the validation error).
    effect : str
        The effect's catalogue name.
    error_before, error_after : float
        E on the validation part [-] of the model before and after the step.
    evidence : Evidence
        The evidence (:class:`drillpy.loop.evidence.Evidence`, with the step's ``parameters``,
        ``rivals``, ``confusable`` or ``direct`` where they apply).
    long_run : dict or None
        The long runs measured / before / after (:func:`drillpy.loop.longrun.long_run`); None when
        switched off.
    before, candidate, after : Evaluation
        The model before the step, the candidate as fitted, and the model after it.
    after_long_run : dict or None
        The long run of ``after`` (a recalibration's, which the loop continues from).
    """
    action: str
    effect: str
    error_before: float
    error_after: float
    evidence: Evidence
    long_run: dict | None
    before: Evaluation
    candidate: Evaluation
    after: Evaluation
    after_long_run: dict | None = None

    @property
    def accepted(self) -> bool:
        """Whether the evidence accepted the step (a refused recalibration is recorded, not taken)."""
        return bool(self.evidence.accepted)

    def to_json(self) -> dict:
        """The step as written to ``loop.json`` -> ``steps`` (:data:`JSON_FIELDS`).

        Returns
        -------
        dict
            ``action``, ``effect``, ``error_before``, ``error_after``, ``evidence``, ``long_run``.
        """
        return {k: self.evidence.to_json() if k == "evidence" else getattr(self, k) for k in JSON_FIELDS}
