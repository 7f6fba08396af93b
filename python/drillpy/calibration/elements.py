"""The rig elements a model of the comparison may leave out: models over law families and elements.

A model of the calibration's comparison is a law family (:data:`drillpy.calibration.families.FAMILIES`)
of the whole rig model, or that model with some of its elements taken out, named
``"FAMILY without ELEMENT[, ELEMENT]"`` in ``calibration.families``::

    "calibration": {"families": ["polynomial", "polynomial without jack", "polynomial without coupling"]}

so that the model probabilities answer which elements the record supports beside which law (issue 35,
item 2: the residual loop's catalogue of effects, ``drillpy.loop.effects``, names the same elements:
``axial_jack`` the jack, ``top_drive_dynamics`` the motor with its shaft coupling; the thesis names the
motor, section 5.3.2: "top drive speed decreases between 40 % and 60 % during drilling"). An element left
out is not calibrated: its parameter is held where the model has no such element.

The elements (:data:`ELEMENTS`), each with the parameter held in the model without it:

* ``jack`` (``jack_gain_n_rad`` = 0): the WOB is the record's slow trend (the jack's set force), the
  law's input, alone: no WOB state driven by the rotation (``drill/axial.hpp``).
* ``coupling`` (``coupling_stiffness_nm_rad`` = None): the motor's rotor turns the bar's top rigidly
  (no shaft coupling, :func:`drillpy.records.rigsim.with_coupling`).
* ``motor`` (``motor_slope_nms_rad`` = None): an ideal drive turns the top (or the coupling) at the
  command: the thesis's constant top speed, where the rig's open-loop motor gives way.
"""
from __future__ import annotations

from dataclasses import dataclass

from drillpy.calibration.families import FAMILIES

#: The separator of a model's name between its family and the elements it leaves out.
WITHOUT = " without "


@dataclass(frozen=True)
class Element:
    """A rig element a model may leave out.

    Attributes
    ----------
    parameter : str
        Its calibrated parameter (:data:`drillpy.calibration.priors.PARAMETERS`).
    held : float or None
        The parameter's value in a model without the element.
    """
    parameter: str
    held: float | None


#: The elements: name -> :class:`Element` (module docstring).
ELEMENTS = {
    "jack": Element("jack_gain_n_rad", 0.0),
    "coupling": Element("coupling_stiffness_nm_rad", None),
    "motor": Element("motor_slope_nms_rad", None),
}


def parse_model(name, where: str | None = None) -> tuple:
    """A model's law family and the elements it leaves out.

    Parameters
    ----------
    name : str
        ``"FAMILY"`` or ``"FAMILY without ELEMENT[, ELEMENT]"`` (module docstring).
    where : str, optional
        What an error starts with (default ``calibration.families = [<name>]``).

    Returns
    -------
    (str, tuple of str)
        The family and the elements left out, in :data:`ELEMENTS`' order.

    Raises
    ------
    ValueError
        ``<where>: ...`` naming the unknown family or element.
    """
    where = where or f"calibration.families = [{name!r}]"
    if not isinstance(name, str):
        raise ValueError(f"{where}: model {name!r}: a name 'FAMILY' or 'FAMILY without ELEMENT'")
    family, sep, rest = name.partition(WITHOUT)
    if family not in FAMILIES:
        raise ValueError(f"{where}: unknown family {family!r} "
                         f"(use {', '.join(FAMILIES)}, optionally followed by '{WITHOUT.strip()} ELEMENT')")
    if not sep:
        return family, ()
    out = [e.strip() for e in rest.split(",")]
    for e in out:
        if e not in ELEMENTS:
            raise ValueError(f"{where}: model {name!r}: unknown element {e!r} "
                             f"(use {', '.join(ELEMENTS)})")
    if len(set(out)) != len(out):
        raise ValueError(f"{where}: model {name!r}: an element named twice")
    return family, tuple(e for e in ELEMENTS if e in out)


def left_out(name: str) -> dict:
    """The parameters a model holds for the elements it leaves out: parameter -> held value.

    Parameters
    ----------
    name : str
        A model's name (:func:`parse_model`).

    Returns
    -------
    dict
    """
    return {ELEMENTS[e].parameter: ELEMENTS[e].held for e in parse_model(name)[1]}


def model_equation(name: str) -> str:
    """The model's law equation and the elements it leaves out, for the posterior's ``equations``.

    Parameters
    ----------
    name : str
        A model's name (:func:`parse_model`).

    Returns
    -------
    str
    """
    family, out = parse_model(name)
    eq = FAMILIES[family].equation
    return eq + "".join(f", no {e} (held {ELEMENTS[e].parameter} = {ELEMENTS[e].held})" for e in out)
