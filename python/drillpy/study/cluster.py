"""The ``--scheduler`` option: where independent runs go, and the Dask client that takes them there.

* ``local`` (or none): this process (the caller's OpenMP or thread pool); no Dask needed;
* ``local:N``: a Dask ``LocalCluster`` of N single-threaded worker processes, started here and
  closed with the client (its dashboard address goes to the log);
* ``tcp://HOST:PORT`` (any ``scheme://address``): a running Dask scheduler whose workers have drillpy
  installed; a scheduler that does not answer within :data:`CONNECT_TIMEOUT_S` is an error.

Used by the studies (:mod:`drillpy.study.run`), the robust speeds (``drillpy robust-ss``) and the
calibration's sampler (:mod:`drillpy.calibration.sampler`).
"""
from __future__ import annotations

#: Seconds a ``tcp://`` scheduler has to answer before the option is refused.
CONNECT_TIMEOUT_S = 10.0
#: Seconds a cluster may go without a single worker while results are awaited: past that its workers
#: are lost (a worker process killed or crashed) and :func:`completed` raises instead of waiting forever.
WORKERLESS_S = 60.0
#: Seconds between two looks at the pending results (and the cluster's workers).
POLL_S = 0.5


def parse_scheduler(text: str | None, option: str = "scheduler"):
    """``--scheduler``: None or ``local`` -> None (this process); ``local:N`` -> N workers;
    ``tcp://HOST:PORT`` (or any address with ``://``) -> the address.

    Parameters
    ----------
    text : str or None
        The option's value.
    option : str
        The option's name in the error.

    Returns
    -------
    None, int or str
        The backend.

    Raises
    ------
    ValueError
        ``scheduler = '<text>': use local, local:N or tcp://HOST:PORT``.
    """
    if text is None or text == "local":
        return None
    if isinstance(text, str) and text.startswith("local:"):
        try:
            n = int(text[6:])
        except ValueError:
            n = 0
        if n >= 1:
            return n
    elif isinstance(text, str) and "://" in text and text.split("://", 1)[1]:
        return text
    raise ValueError(f"{option} = {text!r}: use local, local:N (N >= 1 Dask workers) or tcp://HOST:PORT")


def open_client(scheduler, log, timeout_s: float = CONNECT_TIMEOUT_S, option: str = "scheduler"):
    """A Dask client for a backend of :func:`parse_scheduler`: ``N`` starts a LocalCluster of N
    single-threaded workers (its dashboard address goes to ``log``), an address joins that scheduler.

    Parameters
    ----------
    scheduler : None, int or str
        What :func:`parse_scheduler` returned.
    log : callable
        Receives the dashboard line.
    timeout_s : float
        Seconds an address has to answer.
    option : str
        The option's name in the errors.

    Returns
    -------
    (Client or None, LocalCluster or None)
        ``(None, None)`` for the local backend; close both when done.

    Raises
    ------
    ValueError
        When Dask is not installed, or the address is malformed or does not answer within ``timeout_s``.
    """
    if scheduler is None:
        return None, None
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise ValueError(f"{option} = {scheduler!r}: needs Dask (pip install 'drillpy[distributed]')") from None
    if isinstance(scheduler, int):
        cluster = LocalCluster(n_workers=scheduler, threads_per_worker=1, processes=True, dashboard_address=":0")
        log(f"Dask LocalCluster: {scheduler} workers, dashboard {cluster.dashboard_link}")
        return Client(cluster), cluster
    try:
        return Client(scheduler, timeout=timeout_s), None
    except (OSError, ValueError, TypeError) as e:
        raise ValueError(f"{option} = {scheduler!r}: no Dask scheduler reached within {timeout_s:g} s ({e})") from None


def completed(client, futures, workerless_s: float = WORKERLESS_S):
    """Yield ``futures`` as they complete (each once), as ``dask.distributed.as_completed`` does, but
    raise when the cluster has had no worker for ``workerless_s`` seconds: a study or a calibration
    whose workers died is one error naming the scheduler, not a hang.

    Parameters
    ----------
    client : dask.distributed.Client
        The client the futures belong to.
    futures : iterable of Future
        The pending results.
    workerless_s : float
        Seconds without a worker before giving up [s].

    Yields
    ------
    Future
        A finished future (its ``result()`` raises a task's own error).

    Raises
    ------
    RuntimeError
        ``scheduler <address>: no Dask worker for <s> s ...``.
    """
    import time
    from dask.distributed import as_completed
    ac = as_completed(futures)
    since = None
    while not ac.is_empty():
        batch = ac.next_batch(block=False)
        if batch:
            since = None
            yield from batch
            continue
        time.sleep(POLL_S)
        if client.scheduler_info().get("workers"):
            since = None
        elif since is None:
            since = time.monotonic()
        elif time.monotonic() - since > workerless_s:
            raise RuntimeError(f"scheduler {client.scheduler.address}: no Dask worker for {workerless_s:g} s while "
                               f"{ac.count()} result(s) were awaited: the workers were lost (killed or crashed); "
                               "run again, or on local")
