"""Where the calibration's simulations run: threads in this process, or chunks on a Dask cluster.

A batch (one generation's proposals of one family, or the predictive draws) is a list of jobs
``(family, parameter values)`` for :meth:`drillpy.calibration.posterior.RigSimulator.one`:

* **threads** (``scheduler`` None or ``local``): a ``ThreadPoolExecutor`` of ``threads`` workers;
* **Dask** (``local:N`` or ``tcp://HOST:PORT``, :mod:`drillpy.study.cluster`): the simulator (its
  record, priors and law) is sent to every worker once, then the batch is cut into chunks of
  ``chunk`` jobs, one task each, and the rows are put back in the batch's order.

A run draws no random number: every draw (proposals, predictive resampling, noise) is made in the
calling process before the batch goes out or after it is back, so the statistics, and the posterior,
are the same bits whatever the backend, the number of workers, the chunk size or the order in
which the tasks complete (``tests/python/test_calibration.py``).
"""
from __future__ import annotations

import math
import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from drillpy.study.cluster import completed, open_client, parse_scheduler

#: Dask tasks per worker a batch is cut into when no chunk is given.
TASKS_PER_WORKER = 4


def check_backend(scheduler: str | None, chunk: int | None):
    """Check ``scheduler`` and ``chunk`` before any work (nothing is opened).

    Parameters
    ----------
    scheduler : str or None
        ``local`` (or None), ``local:N`` or ``tcp://HOST:PORT``.
    chunk : int or None
        Simulations per Dask task (at least 1).

    Returns
    -------
    None, int or str
        The backend (:func:`drillpy.study.cluster.parse_scheduler`).

    Raises
    ------
    ValueError
        ``scheduler = '<text>': use local, local:N ...`` or ``chunk = <value>: a positive integer ...``.
    """
    if chunk is not None and (isinstance(chunk, bool) or not isinstance(chunk, (int, np.integer)) or chunk < 1):
        raise ValueError(f"chunk = {chunk!r}: a positive integer (simulations per Dask task)")
    return parse_scheduler(scheduler)


def _run_chunk(sim, jobs: list, record) -> list:
    """The statistics of ``jobs`` [(family, values)] on a Dask worker (the simulator and the record
    are the worker's copies)."""
    return [sim.one(family, values, record) for family, values in jobs]


class Sampler:
    """Runs batches of rig simulations on threads or on a Dask cluster (module docstring); a context
    manager that closes the client (and the LocalCluster) it opened.

    Parameters
    ----------
    threads : int
        Simulations at once on the threads backend (0: one per core); unused on Dask (each worker
        runs one at a time).
    scheduler : str, optional
        ``local`` (or None: threads), ``local:N`` or ``tcp://HOST:PORT``
        (:func:`drillpy.study.cluster.parse_scheduler`).
    chunk : int, optional
        Simulations per Dask task (default: each batch in :data:`TASKS_PER_WORKER` tasks per worker).
    log : callable, optional
        Receives the LocalCluster's dashboard line.

    Raises
    ------
    ValueError
        Naming ``scheduler`` or ``chunk`` and the value (a malformed scheduler, one that does not
        answer, Dask missing, a chunk below 1).
    """

    def __init__(self, threads: int = 0, scheduler: str | None = None, chunk: int | None = None, log=None):
        sched = check_backend(scheduler, chunk)
        self.scheduler = None if sched is None else scheduler
        self.threads = threads if threads > 0 else (os.cpu_count() or 1)
        self.chunk = None if chunk is None else int(chunk)
        self._sent = {}
        self.client, self._cluster = open_client(sched, log or (lambda m: None))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self) -> None:
        """Close the client and the cluster this sampler opened (nothing on threads)."""
        self._sent.clear()
        if self.client is not None:
            self.client.close()
        if self._cluster is not None:
            self._cluster.close()
        self.client = self._cluster = None

    def describe(self) -> dict:
        """The backend, for the run's record: ``{"backend": "threads", "threads": n}`` or
        ``{"backend": "dask", "scheduler": ..., "workers": n, "chunk": ...}``."""
        if self.client is None:
            return {"backend": "threads", "threads": self.threads}
        return {"backend": "dask", "scheduler": self.scheduler, "workers": self._workers(), "chunk": self.chunk}

    def _workers(self) -> int:
        return max(1, len(self.client.scheduler_info().get("workers", {})))

    def _remote(self, obj):
        """``obj`` on every worker (sent once per object, kept while this sampler lives)."""
        key = id(obj)
        if key not in self._sent:
            self._sent[key] = (obj, self.client.scatter(obj, broadcast=True, hash=False))
        return self._sent[key][1]

    def map(self, sim, jobs: list, record=None) -> np.ndarray:
        """The statistics of each job, in the order of ``jobs``.

        Parameters
        ----------
        sim : RigSimulator
            Its :meth:`~drillpy.calibration.posterior.RigSimulator.one` runs each job.
        jobs : list
            (family, parameter values) per simulation.
        record : Record, optional
            The window to simulate (default the simulator's calibration window).

        Returns
        -------
        ndarray
            One row of statistics per job.
        """
        if not jobs:
            return np.empty((0, 0))
        if self.client is None:
            with ThreadPoolExecutor(max_workers=self.threads) as pool:
                return np.array(list(pool.map(lambda j: sim.one(j[0], j[1], record), jobs)))
        size = self.chunk or max(1, math.ceil(len(jobs) / (TASKS_PER_WORKER * self._workers())))
        remote_sim = self._remote(sim)
        remote_rec = None if record is None else self._remote(record)
        futures = [self.client.submit(_run_chunk, remote_sim, jobs[i:i + size], remote_rec, pure=False)
                   for i in range(0, len(jobs), size)]
        index = {f: i for i, f in enumerate(futures)}
        parts = [None] * len(futures)
        try:
            for f in completed(self.client, futures):
                parts[index[f]] = f.result()
            rows = [row for part in parts for row in part]
        finally:
            for f in futures:
                f.cancel()
        return np.array(rows)
