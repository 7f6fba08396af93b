"""The protocol every effect of the loop's catalogue follows (one module per effect).

An effect is a named change of the declared model with its own parameters. Its module defines one
:class:`Effect` subclass instance that says

* what it is: ``level`` (``"law"``: fitted with the bit-rock law on the law residual first;
  ``"dynamic"``: fitted on the short-horizon predictions), its parameters (:class:`Param`: unit,
  physical bounds, the value at which the effect is absent), the model change, the signature it
  leaves in the residual of a model without it and its physical reading on the test rig;
* how it is fitted: :meth:`Effect.starts` (starting parameter sets);
* how it changes the engine configuration: :meth:`Effect.configure`; how a declared configuration
  carries it: :meth:`Effect.declared` and :meth:`Effect.strip`;
* how it changes a prediction restarted from the record (only the effects that act through the
  record's inputs or the sensors override these): :meth:`Effect.delay_s`, :meth:`Effect.undo`,
  :meth:`Effect.top_state`, :meth:`Effect.wob_input`, :meth:`Effect.eta`, :meth:`Effect.restart_torque`;
* what is physically implausible about a fit: :meth:`Effect.flags`;
* how the synthetic generator puts it into a record: :meth:`Effect.inject`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Param:
    """A parameter of an effect: physical bounds of the fit, the value at which the effect is
    absent (``null``; None when no finite value removes it), the margin around it within which a
    value is no effect (``margin``: the declared model's own tolerance, e.g. a bar's GJ from its
    nominal dimensions), and whether it is fitted on the short horizons (``scale``: ``"lin"`` or
    ``"log"``, the latter fitted in ln) or estimated otherwise (``fitted`` False: reported only)."""
    name: str
    unit: str
    meaning: str
    lower: float = -math.inf
    upper: float = math.inf
    scale: str = "lin"
    null: float | None = None
    fitted: bool = True
    margin: float = 0.0
    binding: bool = True  #: a fit at a bound means the effect is not identified (False: a shape parameter, flagged only)


class Effect:
    """Base class of the catalogue's effects; see the module docstring for the protocol."""
    name: str = ""
    level: str = "dynamic"
    params: tuple = ()
    change: str = ""
    signature: str = ""
    reading: str = ""
    needs: tuple = ()
    confounded_with: tuple = ()  #: effects it cannot be told from in some conditions (documented per effect)
    #: the effect rewrites part of the law (e.g. its static branch): a candidate is started from the
    #: law refitted on the law residual with it as well as from the current law (which, without the
    #: effect, may have bent to mimic it)
    reshapes_law: bool = False

    # ------------------------------------------------------------------ parameters and fits
    def free(self, p: dict) -> tuple:
        """The parameters fitted on the short horizons for these values (default: every fitted one)."""
        return tuple(q for q in self.params if q.fitted) if self.level == "dynamic" else ()

    def count(self, p: dict) -> int:
        """Number of calibrated parameters the effect adds (for the information criterion)."""
        return len(self.free(p))

    def bounds(self, q: Param, model) -> tuple:
        """(lower, upper) of a parameter's fit for this model (default: the parameter's own)."""
        return q.lower, q.upper

    def starts(self, model, data) -> list:
        """Starting parameter sets of the fit (the best on the calibration horizons is refined)."""
        raise NotImplementedError(self.name)

    def direct(self, model, data) -> dict | None:
        """A direct measurement of the effect from the record's calibration part, independent of
        the short-horizon fit: {"params": {...}, "ci95": {...}, "significant": bool, "detail": str},
        or None when the effect has none (default)."""
        return None

    def flags(self, p: dict, data) -> list:
        """Reasons why fitted values are physically implausible (an empty list: plausible)."""
        return []

    # --------------------------------------------------------------- engine configuration
    def declared(self, cfg: dict) -> dict | None:
        """The effect's parameters if a declared configuration already has it, else None."""
        return None

    def strip(self, cfg: dict) -> None:
        """Remove the effect from a configuration (in place): the value that makes it absent."""

    def configure(self, cfg: dict, p: dict, model) -> None:
        """Put the effect with parameters ``p`` into the engine configuration ``cfg`` (in place)."""

    # ------------------------------------------------------- predictions from the record
    def delay_s(self, p: dict) -> float:
        """Delay of the recorded channels behind the model's state [s] (sensors)."""
        return 0.0

    def undo(self, p: dict) -> tuple:
        """(c1, c2) of a second-order measurement chain undone as x = y + c1 y' + c2 y''."""
        return 0.0, 0.0

    def top_state(self, p: dict, model, chs: dict, idx):
        """(top speed, its rate, top-speed series driving the top or None) at the restarts, or None
        when the effect does not change the top boundary."""
        return None

    def wob_input(self, p: dict, model, w):
        """The law's WOB input from the recorded WOB ``w`` (None: the effect does not change it)."""
        return None

    def eta(self, p: dict, model, data, chs: dict, idx, leads):
        """Forecast of the relative torque fluctuation at the restarts (rows) and leads [s] (columns)."""
        return None

    def restart_torque(self, p: dict, model, data, chs: dict, idx):
        """Correction [N m] of the total torque on the bit at the restarts ``idx`` (added to the
        measured torque on bit of the restart state, after the engine's own T_sf sign(v) and c_v v),
        or None: for effects whose share of the torque on a bit near rest the measured speed does not
        determine."""
        return None

    def measure(self, p: dict, chans: dict, fs: float) -> dict:
        """The recorded channels of a simulation (dict name -> array at ``fs`` Hz) after the effect's
        measurement chain (default: unchanged)."""
        return chans

    # ------------------------------------------------------------------------ synthetic truth
    def inject(self, truth, p: dict) -> None:
        """Switch the effect on in a synthetic truth (:class:`drillpy.records.synthetic.Truth`)."""
        raise NotImplementedError(self.name)

    defaults: dict = {}  #: parameters of the synthetic truth when switched on without values

