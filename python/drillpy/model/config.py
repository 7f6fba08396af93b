"""Configurations: the JSON schema shared with ``drillsim`` (parsed and validated by the engine).

A configuration is a plain ``dict``; :func:`load_config` returns it normalized (every default
made explicit) so that what a run used can always be written back next to its results.
:func:`engine_config` parses it once into the engine's ``_core.Config``, which ``Simulation``,
``StochasticModel``, ``MonteCarlo`` and the functions of :mod:`drillpy.model.simulation` take as is.
"""
from __future__ import annotations

import copy
import json
import math
from pathlib import Path

from drillpy import _core, validate


def preset_names() -> list[str]:
    """Names of the built-in presets (``thesis-field``, ``thesis-rig``, ``thesis-ch6``)."""
    return list(_core.preset_names())


def as_dict(config) -> dict:
    """The dict of a configuration given as a dict or as a typed
    :class:`~drillpy.model.configuration.Configuration` (its ``to_dict()``), at the JSON edge.

    Parameters
    ----------
    config : dict or Configuration
        A configuration; a dict (or an engine ``_core.Config``) is returned as is.

    Returns
    -------
    dict or _core.Config
    """
    if isinstance(config, (dict, _core.Config)) or not hasattr(config, "to_dict"):
        return config
    return config.to_dict()


def to_json_text(config: dict) -> str:
    """JSON text of a configuration for the engine.

    Non-finite numbers, which JSON cannot carry, are refused here with the path of the field.

    Parameters
    ----------
    config : dict or Configuration
        A configuration (the JSON schema shared with drillsim, docs/presets.md).

    Returns
    -------
    str
        Compact JSON text.

    Raises
    ------
    ValueError
        ``"string.sections[0].length_m = nan: must be a finite number"`` for a NaN or inf anywhere.
    """
    def walk(x, path):
        if isinstance(x, dict):
            for k, v in x.items():
                walk(v, f"{path}.{k}" if path else str(k))
        elif isinstance(x, (list, tuple)):
            for i, v in enumerate(x):
                walk(v, f"{path}[{i}]")
        elif isinstance(x, float) and not math.isfinite(x):
            raise ValueError(f"{path} = {x}: must be a finite number")
    config = as_dict(config)
    walk(config, "")
    return json.dumps(config, allow_nan=False)


def engine_config(config) -> "_core.Config":
    """The engine's parsed and validated configuration (``_core.Config``) of a dict.

    Build it once and reuse it: it crosses into the engine once, and ``Simulation``,
    ``StochasticModel``, ``MonteCarlo`` and :func:`drillpy.model.simulation.simulate` take it as is.

    Parameters
    ----------
    config : dict, Configuration or _core.Config
        A configuration (the JSON schema shared with drillsim); a ``_core.Config`` is returned as is.
        A dict is checked for implausible values first
        (:func:`drillpy.model.plausibility.warn_config`: warnings, not errors).

    Returns
    -------
    _core.Config
        The validated configuration, every default explicit (``to_dict()`` gives the normalized dict).

    Raises
    ------
    ValueError
        Naming the field and the value when the configuration is invalid.
    """
    config = as_dict(config)
    if isinstance(config, _core.Config):
        return config
    from drillpy.model import plausibility
    plausibility.warn_config(config)  # values the engine accepts but no string has (a unit mix-up, usually)
    return _core.Config(to_json_text(config))


def normalize(config: dict) -> dict:
    """Validate a configuration in the engine and return it with all defaults explicit.

    Parameters
    ----------
    config : dict or Configuration
        A configuration, possibly partial (missing fields take the engine's defaults).

    Returns
    -------
    dict
        The normalized configuration: what a run with it uses, every field explicit.

    Raises
    ------
    ValueError
        Naming the field and the value when the configuration is invalid.
    """
    return engine_config(config).to_dict()


#: Deepest nesting of arrays and objects a JSON file may have (the engine's ``max_json_depth``,
#: ``drill/config.hpp``): a configuration nests 4 levels, so deeper text is not one.
MAX_JSON_DEPTH = 64


def _nesting_depth(value, limit: int) -> int:
    """Levels of lists and dicts in ``value`` (a scalar: 0), counted without recursion; stops at
    the first level past ``limit``."""
    deepest, stack = 0, [(value, 1)]
    while stack:
        v, d = stack.pop()
        if isinstance(v, (dict, list)):
            deepest = max(deepest, d)
            if d > limit:
                break
            stack.extend((c, d + 1) for c in (v.values() if isinstance(v, dict) else v))
    return deepest


def read_json(path, field: str):
    """The JSON content of a file.

    Parameters
    ----------
    path : str or Path
        The file.
    field : str
        What the file is, for the message (e.g. ``"config"``, ``"model"``).

    Returns
    -------
    object
        The parsed JSON.

    Raises
    ------
    ValueError
        ``"<field> = '<path>': no such file"``, ``"...: malformed JSON: ..."`` or
        ``"...: duplicate key 'k' in a JSON object"`` (plain JSON parsing would keep the last value silently),
        or ``"...: JSON nested too deep: more than 64 levels ..."`` (:data:`MAX_JSON_DEPTH`, as the engine).
    """
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"{field} = {str(p)!r}: no such file")

    def unique(pairs):
        out = {}
        for k, v in pairs:
            if k in out:
                raise ValueError(f"{field} = {str(p)!r}: duplicate key {k!r} in a JSON object")
            out[k] = v
        return out
    too_deep = (f"{field} = {str(p)!r}: JSON nested too deep: more than {MAX_JSON_DEPTH} levels of arrays and "
                f"objects" + (" (a configuration has 4)" if field == "config" else ""))
    try:
        data = json.loads(p.read_text(), object_pairs_hook=unique)
    except json.JSONDecodeError as e:
        raise ValueError(f"{field} = {str(p)!r}: malformed JSON: {e}") from None
    except RecursionError:  # e.g. 200 000 nested arrays: Python's parser gives up at once
        raise ValueError(too_deep) from None
    if _nesting_depth(data, MAX_JSON_DEPTH) > MAX_JSON_DEPTH:
        raise ValueError(too_deep)
    return data


def load_config(preset: str | None = None, path: str | Path | None = None,
                config: dict | None = None) -> dict:
    """A configuration from exactly one of a preset name, a JSON file or a dict, validated and
    normalized.

    Parameters
    ----------
    preset : str, optional
        A built-in preset (:func:`preset_names`: ``thesis-field`` the chapter-2/3 field string of
        Table 3.1, ``thesis-ch4`` its chapter-4 reading, ``thesis-rig`` the test rig of chapter 5,
        ``thesis-ch6`` the chapter-6 string).
    path : str or Path, optional
        A JSON configuration file.
    config : dict, optional
        A configuration dict (copied, never modified).

    Returns
    -------
    dict
        The normalized configuration (:func:`normalize`).

    Raises
    ------
    ValueError
        When not exactly one source is given, or the configuration is invalid (naming the field).
    """
    given = [x is not None for x in (preset, path, config)]
    if sum(given) != 1:
        raise ValueError("load_config: give exactly one of preset, path or config")
    if preset is not None:
        return _core.Config(_core.preset_json(preset)).to_dict()
    if path is not None:
        return normalize(read_json(path, "config"))
    return normalize(copy.deepcopy(config))


def thesis_law(name: str, beta1: float | None = None) -> dict:
    """A bit-rock law with the thesis's parameters.

    Parameters
    ----------
    name : str
        ``tucker_wang``: the reversible law of section 3.1 (Eq. 3.1, speeds in rad/s);
        ``hysteretic``: the law of section 3.2 (Eqs. 3.2-3.3, speeds in RPM), the ``thesis-field``
        preset's.
    beta1 : float, optional
        Hysteresis amplitude of Eq. (3.3) [dimensionless] for ``hysteretic``: 0, 0.14 and 0.56
        are the thesis's models 1-3.

    Returns
    -------
    dict
        The ``law`` section of a configuration (units in docs/units.md).

    Raises
    ------
    ValueError
        For an unknown name.
    """
    if name == "tucker_wang":
        return {"type": "tucker_wang", "speed_unit": "rad_s", "wob_ref_n": 245e3, "c0": 4700.0,
                "alpha0": 1.67e4, "alpha1": 5.30, "alpha2": 3.45}
    if name == "hysteretic":
        law = json.loads(_core.preset_json("thesis-field"))["law"]
        if beta1 is not None:
            law["beta1"] = float(beta1)
        return law
    raise ValueError(f"law = {name!r}: no thesis parameter set (use tucker_wang or hysteretic)")


#: Largest count the engine takes (a C int): larger ones are refused, never wrapped.
_INT_MAX = 2**31 - 1


def with_overrides(cfg: dict, *, elements: int | None = None, modes: int | None = None,
                   law: str | None = None, beta1: float | None = None,
                   speed_unit: str | None = None, scheme: str | None = None,
                   acceleration: str | None = None, dt: float | None = None, duration: float | None = None,
                   transient: float | None = None, top_speed: float | None = None,
                   wob: float | None = None, start: str | None = None, top_drive: dict | None = None) -> dict:
    """A normalized copy of ``cfg`` with command-line style overrides applied.

    Parameters
    ----------
    cfg : dict or Configuration
        The configuration (not modified).
    elements : int, optional
        Re-mesh the string with this many finite elements, split in proportion to the section
        lengths (100 on Table 3.1 gives 91 DP + 9 BHA).
    modes : int, optional
        Modes kept by the reduced-order model (``rom.modes``, Eq. 2.9).
    law : str, optional
        A thesis parameter set (:func:`thesis_law`).
    beta1 : float, optional
        Hysteresis amplitude of Eq. (3.3) [dimensionless]; refused for a law without hysteresis.
    speed_unit : str, optional
        Speed unit of the law's parameters (``rad_s`` or ``rpm``).
    scheme : str, optional
        Time integrator (``modified_euler``, ``bdf2`` or ``exact_modal``).
    acceleration : str, optional
        Bit acceleration in Eq. (3.3): ``implicit`` or ``lagged`` (``drill/integrator.hpp``).
    dt : float, optional
        Time step [s].
    duration : float, optional
        Simulated time [s]; the transient becomes half of it when it would not fit.
    transient : float, optional
        Initial time left out of the metrics [s].
    top_speed : float, optional
        Top-drive speed [rad/s].
    wob : float, optional
        Weight on bit [N].
    start : str, optional
        Initial state of runs and sweeps (``simulation.start``): ``"rest"`` (Eq. 2.10), ``"rigid"``
        (Eq. 2.3) or ``"steady"``.
    top_drive : dict, optional
        The ``top_drive`` block (e.g. a controlled drive, docs/control.md), validated by the engine.

    Returns
    -------
    dict
        The normalized configuration.

    Raises
    ------
    ValueError
        Naming the field and the value for an invalid override.
    """
    for name, value in (("beta1", beta1), ("dt", dt), ("duration", duration), ("transient", transient),
                        ("top_speed", top_speed), ("wob", wob)):
        if value is not None:  # the type here; the ranges are the configuration's (C++) checks
            validate.number(name, value)
    c = copy.deepcopy(as_dict(cfg))
    if elements is not None:
        validate.integer("elements", elements, 1, _INT_MAX)
        c = _core.with_total_elements(engine_config(c), int(elements)).to_dict()
    if modes is not None:
        validate.integer("modes", modes, 1, _INT_MAX)
        c["rom"]["modes"] = int(modes)
    if law is not None:
        c["law"] = thesis_law(law)
    for name, value in (("beta1", beta1), ("speed_unit", speed_unit)):
        if value is not None and "law" not in c:  # axial.type = rgd: the bit law is axial.bit
            raise ValueError(f"{name} = {value!r}: the configuration has no law block (axial.type = rgd: the bit law "
                             "is axial.bit)")
    if beta1 is not None:
        if "beta1" not in c["law"]:
            raise ValueError(f"beta1 = {beta1}: the law {c['law']['type']!r} has no hysteresis")
        c["law"]["beta1"] = float(beta1)
    if speed_unit is not None:
        c["law"]["speed_unit"] = speed_unit
    sim = c.setdefault("simulation", {})
    for key, val in (("scheme", scheme), ("acceleration", acceleration), ("dt_s", dt), ("duration_s", duration),
                     ("transient_s", transient), ("start", start)):
        if val is not None:
            sim[key] = float(val) if key.endswith("_s") else val
    if duration is not None and transient is None and sim.get("transient_s", 0) >= duration:
        sim["transient_s"] = 0.5 * duration
    op = c.setdefault("operation", {})
    if top_speed is not None:
        op["top_speed_rad_s"] = float(top_speed)
    if wob is not None:
        op["wob_n"] = float(wob)
    if top_drive is not None:
        c["top_drive"] = copy.deepcopy(top_drive)
    return normalize(c)
