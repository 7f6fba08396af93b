"""A study on disk: a labelled Zarr store that records which tasks are done.

``DIR/study.zarr`` is a Zarr (format 3) group that ``xarray.open_zarr`` reads as a labelled
``xarray.Dataset`` (each array names its dimensions):

* the study's variables (:meth:`drillpy.study.definition.Study.variables`): ``severity``, SS (Eq. 3.4)
  [-] with the named dimensions ``top_speed`` [rad/s], ``wob`` [N], ``sample``; for frf ``frf_db``
  (sample, point, frequency [Hz]) and ``energy`` (sample, point); NaN where not computed yet;
* ``done``: one flag per task (along the task dimension), set only after the task's values are
  written, so a store interrupted at any moment (Ctrl-C, a lost worker) is consistent: what is
  flagged is final, the rest is computed again by the next run;
* mc studies: ``deterministic_severity`` (top_speed) and the ``eta_std`` attribute;
* attributes: ``study`` (the identity JSON: kind, configuration, speeds, WOBs, seed, options),
  ``chunk`` (block length along the task dimension), ``provenance`` (JSON: drillpy version,
  command line, time) and ``units`` per variable.

Running the same study on an existing store computes only the tasks not done; an mc study with
more samples than the store extends it (the first samples unchanged); a store of another study
is refused naming the first field that differs.

The store is written and read with ``zarr`` alone (:class:`StudyData`); xarray labels it only when a
Dataset is asked for (:meth:`StudyData.dataset`, :func:`open_study`), so a command that stores a study
and summarises its numbers does not import xarray (issue 33: ``mc``'s serial start).
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from drillpy.study.definition import LONG_NAMES, UNITS, Study

STORE_NAME = "study.zarr"


@dataclass
class StudyData:
    """A study's numbers with their labels, without xarray.

    Attributes
    ----------
    variables : dict
        Data variable name -> ``(dims, numpy.ndarray, attrs)`` (the study's variables, ``done``, and
        for mc ``deterministic_severity``).
    coords : dict
        Coordinate name -> ``(dims, numpy.ndarray, attrs)``.
    attrs : dict
        The study's attributes (``study``, ``chunk``, ``provenance``, mc's ``eta_std``).
    """

    variables: dict
    coords: dict
    attrs: dict

    def __getitem__(self, name: str) -> np.ndarray:
        """The values of a variable or a coordinate."""
        return {**self.coords, **self.variables}[name][1]

    def dataset(self):
        """The same numbers as an ``xarray.Dataset`` (what ``xarray.open_zarr`` gives of the store).

        Returns
        -------
        xarray.Dataset
            Variables with named dimensions and units, coordinates, the study's attributes.
        """
        import xarray as xr
        return xr.Dataset(self.variables, coords=self.coords, attrs=self.attrs)


def _coords(study: Study, lo: int, hi: int) -> dict:
    c = {k: ((k,), np.asarray(v), {"units": UNITS[k]}) for k, v in study.coords().items()}
    if study.task_dim == "sample":
        c["sample"] = (("sample",), np.arange(lo, hi, dtype=np.int64), {"units": UNITS["sample"]})
    return c


def _attrs(study: Study, chunk: int, extra: dict) -> dict:
    from drillpy.provenance import provenance
    return {"study": json.dumps(study.identity(), sort_keys=True), "chunk": int(chunk),
            "provenance": json.dumps(provenance(seed=study.seed, samples=study.samples)), **extra}


def empty(study: Study, chunk: int, init: dict | None = None) -> StudyData:
    """NaN-filled variables and unset ``done`` for every task of ``study``.

    Parameters
    ----------
    study : Study
        The study.
    chunk : int
        Block length along the task dimension (the ``chunk`` attribute).
    init : dict, optional
        mc's ``{"deterministic_severity": array, "eta_std": float}``: arrays become variables
        along ``top_speed``, scalars attributes.

    Returns
    -------
    StudyData
        The study before any task is computed.
    """
    init = init or {}
    return _empty(study, 0, study.task_size, chunk, init)


def _empty(study: Study, lo: int, hi: int, chunk: int, init: dict) -> StudyData:
    sizes = {k: len(v) for k, v in study.coords().items()}
    data = {}
    for name, (dims, dtype) in study.variables().items():
        shape = [hi - lo] + [sizes[d] for d in dims[1:]]
        data[name] = (dims, np.full(shape, np.nan, dtype=dtype), {"units": UNITS[name], "long_name": LONG_NAMES[name]})
    data["done"] = ((study.task_dim,), np.zeros(hi - lo, dtype=bool), {"long_name": "task computed and written"})
    for k, v in init.items():
        if not np.isscalar(v):
            data[k] = (("top_speed",), np.asarray(v, dtype=float), {"units": UNITS["severity"]})
    extra = {k: v for k, v in init.items() if np.isscalar(v)}
    return StudyData(data, _coords(study, lo, hi), _attrs(study, chunk, extra))


def _differs(a: dict, b: dict, prefix: str = "") -> str | None:
    """The first path at which two JSON values differ (None when equal)."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                return prefix + k
            d = _differs(a[k], b[k], prefix + k + ".")
            if d is not None:
                return d
        return None
    return None if a == b else prefix.rstrip(".")


def _group(path: Path, group: str | None, mode: str):
    import zarr
    root = zarr.open_group(str(path), mode=mode, zarr_format=3)
    if group is None:
        return root
    return root.require_group(group) if mode != "r" else root[group]


def _create(data: StudyData, path: Path, group: str | None, task_dim: str, chunk: int) -> None:
    g = _group(path, group, "w" if group is None else "a")
    g.attrs.update(data.attrs)
    for name, (dims, values, attrs) in {**data.coords, **data.variables}.items():
        chunks = tuple(chunk if d == task_dim else n for d, n in zip(dims, values.shape))
        fill = np.nan if values.dtype.kind == "f" else values.dtype.type(0)
        a = g.create_array(name, shape=values.shape, dtype=values.dtype, chunks=chunks, fill_value=fill,
                           attributes=attrs, dimension_names=list(dims))
        a[...] = values


def prepare(study: Study, path, chunk: int, init: dict | None = None, group: str | None = None) -> tuple[np.ndarray, int]:
    """Open the store at ``path`` for ``study`` (created if missing, extended if the mc study is longer).

    Parameters
    ----------
    study : Study
        The study to run.
    path : str or Path
        The ``.zarr`` folder.
    chunk : int
        Block length along the task dimension for a new store (an existing store keeps its own).
    init : dict, optional
        Extra content of a new store: ``{"deterministic_severity": array, "eta_std": float}`` for mc.
    group : str, optional
        Zarr group of the study inside the store (one store holding several studies: robust-ss).

    Returns
    -------
    (numpy.ndarray, int)
        The ``done`` flags along the task dimension and the store's chunk.

    Raises
    ------
    ValueError
        When the store holds another study (naming the first differing field) or more samples than
        asked for.
    """
    p = Path(path)
    if not has_group(p, group):
        _create(empty(study, chunk, init), p, group, study.task_dim, chunk)
        return np.zeros(study.task_size, dtype=bool), chunk
    g = _group(p, group, "r+")
    if "study" not in g.attrs:
        raise ValueError(f"store = '{p}': not a drillpy study store (no study attribute)")
    d = _differs(json.loads(g.attrs["study"]), study.identity())
    if d is not None:
        raise ValueError(f"store = '{p}': holds another study ({d} differs); use another --out or delete it")
    chunk = int(g.attrs["chunk"])
    done = np.asarray(g["done"][...], dtype=bool)
    n = done.size
    if n > study.task_size:
        raise ValueError(f"samples = {study.samples}: the store '{p}' already holds {n} samples (ask for {n} or more)")
    if n < study.task_size:  # extend an mc study: the first n samples stay as they are
        more = _empty(study, n, study.task_size, chunk, {})
        for name, (dims, values, _) in {**more.coords, **more.variables}.items():
            if dims[0] == study.task_dim:
                a = g[name]
                a.resize((study.task_size,) + tuple(a.shape[1:]))
                a[n:] = values
        done = np.concatenate([done, np.zeros(study.task_size - n, dtype=bool)])
    return done, chunk


def has_group(path: Path, group: str | None) -> bool:
    """Whether the store at ``path`` holds a study (in ``group`` when given).

    Parameters
    ----------
    path : Path
        The ``.zarr`` folder.
    group : str or None
        Zarr group of the study inside the store.

    Returns
    -------
    bool
        True when the store (or its group) exists.
    """
    return Path(path).exists() if group is None else (Path(path) / group).exists()


def write_block(study: Study, path, lo: int, values: dict, group: str | None = None) -> None:
    """Write the results of tasks ``range(lo, lo + n)``, then flag them done.

    Parameters
    ----------
    study : Study
        The study of the store.
    path : str or Path
        The ``.zarr`` folder.
    lo : int
        First task of the block.
    values : dict
        Variable -> array (:func:`drillpy.study.definition.compute_block`).
    group : str, optional
        Zarr group of the study inside the store.
    """
    g = _group(Path(path), group, "r+")
    n = next(iter(values.values())).shape[0]
    for k, v in values.items():
        g[k][lo:lo + n] = v
    g["done"][lo:lo + n] = True


def read(path, group: str | None = None) -> StudyData:
    """A stored study's numbers and labels, read with zarr alone.

    Parameters
    ----------
    path : str or Path
        ``study.zarr`` or the output folder holding it.
    group : str, optional
        Zarr group of the study (robust-ss stores one per source of uncertainty).

    Returns
    -------
    StudyData
        Every array of the store with its dimensions and attributes, the study's attributes.

    Raises
    ------
    ValueError
        When there is no store at ``path``.
    """
    p = Path(path)
    if p.is_dir() and (p / STORE_NAME).exists():
        p = p / STORE_NAME
    if not p.exists():
        raise ValueError(f"store = '{path}': no {STORE_NAME} there")
    g = _group(p, group, "r")
    variables, coords = {}, {}
    for name, a in g.arrays():
        dims = tuple(a.metadata.dimension_names)
        entry = (dims, np.asarray(a[...]), {k: v for k, v in a.attrs.items() if not k.startswith("_")})
        (coords if dims == (name,) else variables)[name] = entry
    return StudyData(variables, coords, dict(g.attrs))


def open_study(path, group: str | None = None):
    """A stored study as an ``xarray.Dataset`` (numpy-backed; ``xarray.open_zarr`` gives the same lazily).

    Parameters
    ----------
    path : str or Path
        ``study.zarr`` or the output folder holding it.
    group : str, optional
        Zarr group of the study (robust-ss stores one per source of uncertainty).

    Returns
    -------
    xarray.Dataset
        The study's variables, ``done``, coordinates with units, the study's attributes.
    """
    return read(path, group).dataset()
