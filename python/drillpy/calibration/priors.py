"""Priors of the rig model's uncertain parameters: physical ranges written in the configuration.

The priors never come from the record being calibrated: each is a range with its physical source
(:data:`PARAMETERS`; the rig elements' ranges are :data:`drillpy.records.rigsim.RIG_PARAMETERS`),
uniform or log-uniform over it. A configuration file may carry a ``calibration`` section that
replaces any of them, fixes the parameters not calibrated, and names the law families compared::

    "calibration": {
        "priors": {"damping_ratio": {"range": [0.005, 0.1], "scale": "uniform"}, ...},
        "fixed": {"jack_relaxation_s": 0.2, ...},
        "families": ["polynomial_hysteretic", "polynomial", "tucker_wang", "hysteretic"],
        "discrepancy": 2.0,
        "family_share": 0.5,
        "statistics": ["ss", "stick_fraction", ..., "wob_above_trend_std"]
    }

The families (default Eqs. 5.3 and 5.1) and their law parameters' ranges are those of
:mod:`drillpy.calibration.families`; a name may also be a family's rig model without some of its
elements, ``"polynomial without jack"`` (:mod:`drillpy.calibration.elements`). ``discrepancy`` is the model discrepancy's factor
(:func:`discrepancy_factor`). ``family_share`` is the share of the sampler's model proposals spread
evenly over the families (:func:`family_share`). ``statistics`` names the summary statistics of the distance among
:data:`drillpy.calibration.summaries.ALL_NAMES` (default :data:`~drillpy.calibration.summaries.NAMES`). The section is read here and removed before the engine
validates the rest of the configuration.
"""
from __future__ import annotations

import copy
import math
from dataclasses import dataclass

import numpy as np

from drillpy.calibration.elements import left_out, parse_model
from drillpy.calibration.families import DEFAULT_FAMILIES, FAMILIES, FRACTION, LAW_PARAMETERS, POSITIVE
from drillpy.calibration.summaries import ALL_NAMES, NAMES
from drillpy.records.rigsim import RIG_PARAMETERS

#: The calibrated parameters by default: (low, high, unit, scale, the source of the range).
PARAMETERS = {
    "damping_ratio": RIG_PARAMETERS["damping_ratio"][:3] + ("uniform", RIG_PARAMETERS["damping_ratio"][3]),
    "motor_slope_nms_rad": RIG_PARAMETERS["motor_slope_nms_rad"][:3] + ("log-uniform",
                                                                          RIG_PARAMETERS["motor_slope_nms_rad"][3]),
    "command_rad_s": RIG_PARAMETERS["command_rad_s"][:3] + ("uniform", RIG_PARAMETERS["command_rad_s"][3]),
    "coupling_stiffness_nm_rad": RIG_PARAMETERS["coupling_stiffness_nm_rad"][:3]
    + ("log-uniform", RIG_PARAMETERS["coupling_stiffness_nm_rad"][3]),
    "jack_gain_n_rad": RIG_PARAMETERS["jack_gain_n_rad"][:3] + ("uniform", RIG_PARAMETERS["jack_gain_n_rad"][3]),
    "law_scale": (0.6, 1.6, "-", "uniform",
                  "factor on the law's torque (its slip branch a2..a7): the rock's resistance varies between "
                  "samples; the thesis's acceptance criterion (section 5.3.3) allows the torque's CV of 0.33 "
                  "(Table 5.2) plus a 10 % variation of the concrete, and x0.6-x1.6 spans about two such "
                  "spreads either way"),
    "static_torque_nm": (1.0, 6.0, "N m", "uniform",
                         "the static (break-away) torque gain x a0 of Eq. (5.1) at W_ref: above the slip branch's "
                         "low-speed level would be needed for a stick, and below the 8 N m the motor gives at stall "
                         "(section 5.1); a stuck bit above c_m Omega_c stalls the rig"),
    **LAW_PARAMETERS,
}

#: Parameters of each law family (besides the rig's): the families of
#: :data:`drillpy.calibration.families.FAMILIES` (Eqs. 5.3, 5.1, 3.1, 3.2-3.3).
FAMILY_PARAMETERS = {name: fam.parameters for name, fam in FAMILIES.items()}
#: The rig parameters calibrated in every family.
RIG_CALIBRATED = ("damping_ratio", "motor_slope_nms_rad", "command_rad_s", "coupling_stiffness_nm_rad",
                  "jack_gain_n_rad")
#: The rig parameters held (typical values, the start of :func:`drillpy.records.rig_calibration.calibrate_rig`;
#: never fitted to the record).
FIXED = {"motor_inertia_kg_m2": 0.015, "jack_relaxation_s": 0.2, "platform_damping": 0.7,
         "gj_factor": 1.05, "bit_inertia_factor": 1.05}
SCALES = ("uniform", "log-uniform")


@dataclass(frozen=True)
class Prior:
    """A uniform or log-uniform prior over a physical range.

    Attributes
    ----------
    name : str
        Parameter name.
    low, high : float
        The range, in ``unit``.
    unit : str
        Unit of the parameter.
    scale : str
        ``uniform`` or ``log-uniform``.
    source : str
        Where the range comes from.
    """
    name: str
    low: float
    high: float
    unit: str
    scale: str
    source: str

    def __post_init__(self):
        field = f"calibration.priors.{self.name}"
        if self.scale not in SCALES:
            raise ValueError(f"{field}.scale = {self.scale!r}: use 'uniform' or 'log-uniform'")
        for k in ("low", "high"):
            v = getattr(self, k)
            if not (isinstance(v, (int, float)) and math.isfinite(v)):
                raise ValueError(f"{field}.range = [{self.low!r}, {self.high!r}]: {k} must be a finite number")
        if not self.low < self.high:
            raise ValueError(f"{field}.range = [{self.low!r}, {self.high!r}]: low must be below high")
        if self.scale == "log-uniform" and self.low <= 0:
            raise ValueError(f"{field}.range = [{self.low!r}, {self.high!r}]: a log-uniform prior needs low > 0")
        lo, hi = PARAMETERS[self.name][:2] if self.name in PARAMETERS else (-math.inf, math.inf)
        if self.name in ("damping_ratio", "motor_slope_nms_rad", "command_rad_s", "coupling_stiffness_nm_rad",
                         "law_scale", "static_torque_nm") + POSITIVE and self.low <= 0:
            raise ValueError(f"{field}.range = [{self.low!r}, {self.high!r}]: the parameter is positive "
                             f"(default range [{lo:g}, {hi:g}] {self.unit})")
        if self.name in FRACTION and not (0 <= self.low and self.high < 1):
            raise ValueError(f"{field}.range = [{self.low!r}, {self.high!r}]: the parameter lies in [0, 1) "
                             f"(default range [{lo:g}, {hi:g}])")

    def to_unit(self, x):
        """The parameter value(s) ``x`` mapped to [0, 1], where the prior is uniform.

        Parameters
        ----------
        x : array_like
            Values in the parameter's unit.

        Returns
        -------
        ndarray
        """
        x = np.asarray(x, float)
        if self.scale == "log-uniform":
            return (np.log(x) - math.log(self.low)) / (math.log(self.high) - math.log(self.low))
        return (x - self.low) / (self.high - self.low)

    def from_unit(self, z):
        """The parameter value(s) at the unit coordinate(s) ``z`` (inverse of :meth:`to_unit`).

        Parameters
        ----------
        z : array_like
            Unit coordinates in [0, 1].

        Returns
        -------
        ndarray
        """
        z = np.asarray(z, float)
        if self.scale == "log-uniform":
            return np.exp(math.log(self.low) + z * (math.log(self.high) - math.log(self.low)))
        return self.low + z * (self.high - self.low)

    def summary(self) -> dict:
        """JSON-ready description."""
        return {"range": [self.low, self.high], "unit": self.unit, "scale": self.scale, "source": self.source}


@dataclass(frozen=True)
class PriorSpec:
    """The calibration's prior: per law family its parameters' priors, and the held values.

    Attributes
    ----------
    families : dict
        Family name (:data:`FAMILIES`) -> tuple of :class:`Prior` (the rig's, then the law's).
    fixed : dict
        Rig parameter -> held value (:data:`FIXED`).
    statistics : tuple of str
        The summary statistics of the distance (:data:`drillpy.calibration.summaries.ALL_NAMES`).
    """
    families: dict
    fixed: dict
    statistics: tuple = NAMES

    def summary(self) -> dict:
        """JSON-ready description."""
        return {"families": {f: {p.name: p.summary() for p in ps} for f, ps in self.families.items()},
                "fixed": dict(self.fixed), "statistics": list(self.statistics)}


def split_config(cfg: dict) -> tuple:
    """(the configuration without its ``calibration`` section, that section or {}).

    Parameters
    ----------
    cfg : dict
        A configuration.

    Returns
    -------
    tuple of dict
    """
    cfg = copy.deepcopy(cfg)
    sec = cfg.pop("calibration", None)
    if sec is None:
        return cfg, {}
    if not isinstance(sec, dict):
        raise ValueError(f"calibration = {sec!r}: must be an object (priors, fixed, families, discrepancy)")
    return cfg, sec


def prior_spec(section: dict | None = None) -> PriorSpec:
    """The prior from a configuration's ``calibration`` section (module docstring); defaults for
    whatever it does not say.

    Parameters
    ----------
    section : dict, optional
        The ``calibration`` section.

    Returns
    -------
    PriorSpec

    Raises
    ------
    ValueError
        Naming the field and the value of an unknown key, parameter or family, or a bad range.
    """
    sec = dict(section or {})
    unknown = set(sec) - {"priors", "fixed", "families", "discrepancy", "family_share", "statistics"}
    if unknown:
        k = sorted(unknown)[0]
        raise ValueError(f"calibration.{k} = {sec[k]!r}: unknown key (use priors, fixed, families, discrepancy, "
                         "family_share, statistics)")
    stats = sec.get("statistics", list(NAMES))
    if not isinstance(stats, (list, tuple)) or not stats or len(set(stats)) != len(stats) \
            or any(n not in ALL_NAMES for n in stats):
        raise ValueError(f"calibration.statistics = {stats!r}: a non-empty list of distinct statistics of "
                         f"{', '.join(ALL_NAMES)}")
    if "discrepancy" in sec:
        discrepancy_factor(sec["discrepancy"], "calibration.discrepancy")
    family_share(sec.get("family_share"))
    fams = sec.get("families", list(DEFAULT_FAMILIES))
    if not isinstance(fams, (list, tuple)) or not fams:
        raise ValueError(f"calibration.families = {fams!r}: a non-empty list of {', '.join(FAMILIES)} (each "
                         "optionally 'FAMILY without ELEMENT')")
    parsed = [parse_model(f, f"calibration.families = {fams!r}") for f in fams]
    if len(set(parsed)) != len(parsed):
        raise ValueError(f"calibration.families = {fams!r}: a model named twice")
    given = sec.get("priors", {})
    if not isinstance(given, dict):
        raise ValueError(f"calibration.priors = {given!r}: must be an object name -> {{range, scale}}")
    priors = {}
    for name, (lo, hi, unit, scale, source) in PARAMETERS.items():
        g = given.get(name)
        if g is not None:
            if not isinstance(g, dict) or "range" not in g or not isinstance(g["range"], (list, tuple)) \
                    or len(g["range"]) != 2:
                raise ValueError(f"calibration.priors.{name} = {g!r}: give {{\"range\": [low, high]}}")
            lo, hi = g["range"]
            scale = g.get("scale", scale)
            source = g.get("source", "the configuration")
        priors[name] = Prior(name, lo, hi, unit, scale, source)
    for name in given:
        if name not in PARAMETERS:
            raise ValueError(f"calibration.priors.{name} = {given[name]!r}: unknown parameter "
                             f"(use {', '.join(PARAMETERS)})")
    fixed = dict(FIXED)
    for k, v in dict(sec.get("fixed", {})).items():
        if k not in FIXED:
            raise ValueError(f"calibration.fixed.{k} = {v!r}: unknown parameter (use {', '.join(FIXED)})")
        lo, hi = RIG_PARAMETERS[k][:2]
        if not (isinstance(v, (int, float)) and lo <= v <= hi):
            raise ValueError(f"calibration.fixed.{k} = {v!r}: must be a number in its physical range "
                             f"[{lo:g}, {hi:g}] {RIG_PARAMETERS[k][2]}")
        fixed[k] = float(v)
    return PriorSpec({f: tuple(priors[p] for p in model_parameters(f)) for f in fams}, fixed, tuple(stats))


def model_parameters(name: str) -> tuple:
    """The calibrated parameters of a model of the comparison: the rig's (:data:`RIG_CALIBRATED`) but
    those of the elements it leaves out (:mod:`drillpy.calibration.elements`), then its law family's.

    Parameters
    ----------
    name : str
        ``"FAMILY"`` or ``"FAMILY without ELEMENT[, ELEMENT]"``.

    Returns
    -------
    tuple of str
    """
    family, _ = parse_model(name)
    held = left_out(name)
    return tuple(p for p in RIG_CALIBRATED if p not in held) + FAMILY_PARAMETERS[family]


#: The model discrepancy's factor by default (:func:`discrepancy_factor`; docs/calibration.md,
#: "The model discrepancy").
DEFAULT_DISCREPANCY = 3.0
#: Largest discrepancy factor accepted (at that size the statistics say nothing the prior does not).
MAX_DISCREPANCY = 100.0


def discrepancy_factor(value, field: str = "calibration.discrepancy") -> float:
    """The model discrepancy's factor: each statistic's discrepancy standard deviation in units of
    its window-to-window spread on the calibration record (the distance's unit,
    :func:`drillpy.calibration.summaries.noise_scale`); 0 for none.

    Parameters
    ----------
    value : float or None
        The factor (None: :data:`DEFAULT_DISCREPANCY`).
    field : str
        The option's name in the error (``calibration.discrepancy`` or ``--discrepancy``).

    Returns
    -------
    float

    Raises
    ------
    ValueError
        ``<field> = <value>: a number from 0 (no discrepancy) to 100 ...``.
    """
    if value is None:
        return DEFAULT_DISCREPANCY
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) \
            or not (math.isfinite(value) and 0 <= value <= MAX_DISCREPANCY):
        raise ValueError(f"{field} = {value!r}: a number from 0 (no discrepancy) to {MAX_DISCREPANCY:g}, the "
                         "discrepancy's standard deviation of each statistic in units of its window-to-window "
                         "spread on the record")
    return float(value)



#: The share of the model proposals spread evenly over the families by default (:func:`family_share`:
#: 10 %, the sampler's proposal before the option; docs/calibration.md, "Keeping every family explored").
DEFAULT_FAMILY_SHARE = 0.1


def family_share(value) -> float:
    """The share s of the ABC-SMC's model proposals spread evenly over the M families
    (:func:`drillpy.calibration.abcsmc.run`): family m is proposed with probability (1 - s) P(m) + s / M,
    so every family keeps at least s / M of every generation's proposals; 1 proposes every family
    equally often.

    Parameters
    ----------
    value : float or None
        The share, in (0, 1] (None: :data:`DEFAULT_FAMILY_SHARE`).

    Returns
    -------
    float

    Raises
    ------
    ValueError
        ``calibration.family_share = <value>: a number in (0, 1] ...``.
    """
    if value is None:
        return DEFAULT_FAMILY_SHARE
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) \
            or not (math.isfinite(value) and 0 < value <= 1):
        raise ValueError(f"calibration.family_share = {value!r}: a number in (0, 1], the share of the model "
                         "proposals spread evenly over the families (0.1 by default; 1: every family equally often)")
    return float(value)
