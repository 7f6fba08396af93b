"""Run a study on a backend: today's OpenMP path in this process, or Dask distributed.

* ``local`` (default): the blocks run one after another in this process, each on all the engine's
  OpenMP threads; no dependency beyond the engine (and xarray/zarr when the study is stored).
* ``dask``: the blocks are submitted to a Dask ``distributed`` cluster: ``local:N`` starts a
  ``LocalCluster`` of N single-threaded worker processes (its dashboard address is printed),
  ``tcp://HOST:PORT`` joins a running scheduler whose workers have drillpy installed; from Python,
  ``run_study(study, client=client)``. Each worker builds the engine once and keeps it. The option
  and the client: :mod:`drillpy.study.cluster`.

Results stream to the store block by block as they complete (the driver is the only writer), so no
process holds more than a block; the numbers do not depend on the backend, the number of workers,
the chunk size or the order of completion (:mod:`drillpy.study.definition`).
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from drillpy import validate
from drillpy.progress import progress_bar
from drillpy.study import store as st
from drillpy.study.cluster import completed, open_client, parse_scheduler
from drillpy.study.definition import DEFAULT_CHUNK, Study, compute_block, deterministic_curve


def _blocks(done: np.ndarray, chunk: int) -> list:
    """(lo, hi) of every store chunk with a task not done."""
    return [(lo, min(lo + chunk, done.size)) for lo in range(0, done.size, chunk) if not done[lo:lo + chunk].all()]


def run_study(study: Study, out=None, *, client=None, scheduler=None, chunk: int | None = None, threads: int = 0,
              progress: bool = True, log=None, group: str | None = None):
    """Compute a study (the missing part of it when ``out`` holds it already) and return it labelled.

    Parameters
    ----------
    study : Study
        What to compute.
    out : str or Path, optional
        Folder of the Zarr store (``out/study.zarr``); without it the study runs in memory.
    client : dask.distributed.Client, optional
        Run the blocks on this cluster.
    scheduler : str, optional
        ``--scheduler``: ``local`` (default), ``local:N`` or ``tcp://HOST:PORT``
        (:func:`drillpy.study.cluster.parse_scheduler`); ignored when ``client`` is given.
    chunk : int, optional
        Tasks per block along the task dimension (default ``DEFAULT_CHUNK[kind]``; an existing store
        keeps its own).
    threads : int
        Engine threads per block on the local backend (0: all cores); Dask workers use one each.
    progress : bool
        One progress bar over the study's tasks.
    log : callable, optional
        Receives status lines (default: stderr).
    group : str, optional
        Zarr group of the study inside ``out/study.zarr`` (a command storing several studies).

    Returns
    -------
    xarray.Dataset
        The study's variables with named dimensions and units, ``done``, the study's attributes (and
        for mc ``deterministic_severity`` and ``eta_std``): :func:`compute_study`'s numbers, labelled.

    Raises
    ------
    ValueError
        For a bad chunk or scheduler, or a store holding another study.
    KeyboardInterrupt
        On Ctrl-C; the store keeps every block finished before it.
    """
    return compute_study(study, out, client=client, scheduler=scheduler, chunk=chunk, threads=threads,
                         progress=progress, log=log, group=group).dataset()


def compute_study(study: Study, out=None, *, client=None, scheduler=None, chunk: int | None = None, threads: int = 0,
                  progress: bool = True, log=None, group: str | None = None) -> st.StudyData:
    """:func:`run_study` without xarray: the same numbers and labels as a :class:`~drillpy.study.store.StudyData`.

    Parameters
    ----------
    study : Study
        What to compute.
    out, client, scheduler, chunk, threads, progress, log, group
        As for :func:`run_study`.

    Returns
    -------
    StudyData
        The study's variables, ``done``, coordinates and attributes as numpy arrays and dicts.

    Raises
    ------
    ValueError
        For a bad chunk or scheduler, or a store holding another study.
    KeyboardInterrupt
        On Ctrl-C; the store keeps every block finished before it.
    """
    log = log or (lambda m: print(m, file=sys.stderr))
    chunk = validate.integer("chunk", DEFAULT_CHUNK[study.kind] if chunk is None else chunk, 1, 2**31 - 1)
    sched = None if client is not None else parse_scheduler(scheduler)
    init = {}
    path = None if out is None else Path(out) / st.STORE_NAME
    if study.kind == "mc" and (path is None or not st.has_group(path, group)):
        init = {"deterministic_severity": deterministic_curve(study, threads), "eta_std": _eta_std(study)}
    if path is None:
        data = st.empty(study, chunk, init)
        done = data.variables["done"][1]
    else:
        Path(out).mkdir(parents=True, exist_ok=True)
        done, chunk = st.prepare(study, path, chunk, init, group)
    blocks = _blocks(done, chunk)
    own = None
    if client is None and sched is not None and blocks:
        client, own = open_client(sched, log)
    try:
        with progress_bar(int(sum(hi - lo for lo, hi in blocks)), f"{study.kind} study", progress) as cb:
            finished = 0
            for lo, values in _compute(study, blocks, client, threads):
                n = next(iter(values.values())).shape[0]
                if path is not None:
                    st.write_block(study, path, lo, values, group)
                else:
                    for name, v in values.items():
                        data.variables[name][1][lo:lo + n] = v
                    done[lo:lo + n] = True
                finished += n
                if cb is not None:
                    cb(finished, 0)
    finally:
        if own is not None:
            client.close()
            own.close()
    return data if path is None else st.read(path, group)


def _compute(study: Study, blocks: list, client, threads: int):
    """Yield (lo, values) per block as blocks complete."""
    if client is None:
        for lo, hi in blocks:
            yield lo, compute_block(study, lo, hi, threads)
        return
    futures = {client.submit(compute_block, study, lo, hi, 1, pure=False): lo for lo, hi in blocks}
    try:
        for fut in completed(client, futures):
            yield futures[fut], fut.result()
    finally:
        for fut in futures:
            fut.cancel()


def _eta_std(study: Study) -> float:
    from drillpy.study.definition import _engine
    return float(np.sqrt(_engine(study.key()).eta_variance))
