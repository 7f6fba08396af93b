"""A study on disk: a labelled Zarr store that records which tasks are done.

``DIR/study.zarr`` holds an ``xarray.Dataset`` readable with ``xarray.open_zarr``:

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
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from drillpy.study.definition import LONG_NAMES, UNITS, Study

STORE_NAME = "study.zarr"
_ZARR = {"consolidated": False}


def _xr():
    import xarray as xr
    return xr


def _coords(study: Study, lo: int, hi: int) -> dict:
    c = {k: (k, v, {"units": UNITS[k]}) for k, v in study.coords().items()}
    if study.task_dim == "sample":
        c["sample"] = ("sample", np.arange(lo, hi, dtype=np.int64), {"units": UNITS["sample"]})
    return c


def _attrs(study: Study, chunk: int, extra: dict) -> dict:
    from drillpy.provenance import provenance
    return {"study": json.dumps(study.identity(), sort_keys=True), "chunk": int(chunk),
            "provenance": json.dumps(provenance(seed=study.seed, samples=study.samples)), **extra}


def _empty(study: Study, lo: int, hi: int, chunk: int, extra: dict):
    """NaN-filled variables and unset ``done`` for tasks lo .. hi - 1."""
    xr = _xr()
    sizes = {k: len(v) for k, v in study.coords().items()}
    data = {}
    for name, (dims, dtype) in study.variables().items():
        shape = [hi - lo] + [sizes[d] for d in dims[1:]]
        data[name] = (dims, np.full(shape, np.nan, dtype=dtype), {"units": UNITS[name], "long_name": LONG_NAMES[name]})
    data["done"] = ((study.task_dim,), np.zeros(hi - lo, dtype=bool), {"long_name": "task computed and written"})
    return xr.Dataset(data, coords=_coords(study, lo, hi), attrs=_attrs(study, chunk, extra))


def _encoding(study: Study, chunk: int) -> dict:
    sizes = {k: len(v) for k, v in study.coords().items()}
    enc = {name: {"chunks": (chunk,) + tuple(sizes[d] for d in dims[1:])}
           for name, (dims, _) in study.variables().items()}
    enc["done"] = {"chunks": (chunk,)}
    return enc


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
    xr = _xr()
    p = Path(path)
    init = init or {}
    if not _has_group(p, group):
        extra = {k: v for k, v in init.items() if np.isscalar(v)}
        ds = _empty(study, 0, study.task_size, chunk, extra)
        for k, v in init.items():
            if not np.isscalar(v):
                ds[k] = ("top_speed", np.asarray(v, dtype=float), {"units": UNITS["severity"]})
        ds.to_zarr(p, mode="w" if group is None else "a", group=group, encoding=_encoding(study, chunk), **_ZARR)
        return np.zeros(study.task_size, dtype=bool), chunk
    ds = xr.open_zarr(p, chunks=None, group=group, **_ZARR)
    if "study" not in ds.attrs:
        raise ValueError(f"store = '{p}': not a drillpy study store (no study attribute)")
    stored = json.loads(ds.attrs["study"])
    d = _differs(stored, study.identity())
    if d is not None:
        raise ValueError(f"store = '{p}': holds another study ({d} differs); use another --out or delete it")
    chunk = int(ds.attrs["chunk"])
    n = ds.sizes[study.task_dim]
    if n > study.task_size:
        raise ValueError(f"samples = {study.samples}: the store '{p}' already holds {n} samples (ask for {n} or more)")
    done = np.asarray(ds["done"].values, dtype=bool)
    if n < study.task_size:  # extend an mc study: the first n samples stay as they are
        extra = {k: ds.attrs[k] for k in ds.attrs if k not in ("study", "chunk", "provenance")}
        _empty(study, n, study.task_size, chunk, extra).to_zarr(p, append_dim=study.task_dim, group=group, **_ZARR)
        done = np.concatenate([done, np.zeros(study.task_size - n, dtype=bool)])
    return done, chunk


def _has_group(path: Path, group: str | None) -> bool:
    if group is None:
        return path.exists()
    return (path / group).exists()


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
    xr = _xr()
    variables = study.variables()
    n = next(iter(values.values())).shape[0]
    region = {study.task_dim: slice(lo, lo + n)}
    xr.Dataset({k: (variables[k][0], v) for k, v in values.items()}).to_zarr(
        path, region=region, safe_chunks=False, group=group, **_ZARR)
    xr.Dataset({"done": ((study.task_dim,), np.ones(n, dtype=bool))}).to_zarr(
        path, region=region, safe_chunks=False, group=group, **_ZARR)


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
    p = Path(path)
    if p.is_dir() and (p / STORE_NAME).exists():
        p = p / STORE_NAME
    if not p.exists():
        raise ValueError(f"store = '{path}': no {STORE_NAME} there")
    return _xr().open_zarr(p, chunks=None, group=group, **_ZARR).load()
