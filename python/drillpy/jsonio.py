"""JSON of results: one encoding for every output drillpy writes.

NumPy scalars and arrays become plain numbers and lists, and a number that is not finite (NaN,
inf: "no crossing in range", "no stick phase") becomes ``null``, so every file is valid JSON
(``allow_nan=False`` refuses anything that slipped through).
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from drillpy.outputs import write_text

__all__ = ["jsonable", "dumps", "write_json"]


def jsonable(o):
    """A copy of ``o`` made of JSON types only.

    Parameters
    ----------
    o : object
        Nested dicts, lists, tuples, NumPy arrays and scalars, numbers, strings, None.

    Returns
    -------
    object
        The same structure with string keys, NumPy values converted, and non-finite floats
        replaced by None.
    """
    if isinstance(o, dict):
        return {str(k): jsonable(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [jsonable(v) for v in o]
    if isinstance(o, np.ndarray):
        return jsonable(o.tolist())
    if isinstance(o, np.integer):
        return int(o)
    if isinstance(o, (float, np.floating)):
        return float(o) if math.isfinite(float(o)) else None
    if isinstance(o, np.bool_):
        return bool(o)
    return o


def dumps(o, indent: int | None = 2) -> str:
    """JSON text of :func:`jsonable` (o).

    Parameters
    ----------
    o : object
        The result to encode (see :func:`jsonable`).
    indent : int or None
        Indentation (default 2); ``None`` for one line.

    Returns
    -------
    str
        Valid JSON (NaN and inf written as ``null``).
    """
    return json.dumps(jsonable(o), indent=indent, allow_nan=False)


def write_json(path, o, indent: int | None = 2) -> Path:
    """Write :func:`dumps` (o) to ``path``.

    Parameters
    ----------
    path : str or pathlib.Path
        File to write (replaced if it exists; its directory must exist).
    o : object
        The result to encode (see :func:`jsonable`).
    indent : int or None
        Indentation (default 2); ``None`` for one line.

    Returns
    -------
    pathlib.Path
        The path written.
    """
    p = Path(path)
    write_text(p, dumps(o, indent))
    return p
