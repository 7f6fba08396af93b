"""The loop's independent fits side by side (issue 33): the two starts of a refit, the candidates
of a round and the damping hold's long runs do not depend on each other, so they run on as many
Python threads as the engine has cores, and each engine call takes the cores' share of the tasks
still running (:func:`engine_threads`: a task left alone gets them all).

The engine releases the GIL while it integrates and a horizon's numbers do not depend on the
threads that computed it (docs/numerics.md), so every task returns exactly what it returns alone;
the results come back in the order of the tasks. A task that runs inside another runs its own
tasks one after the other (no nested pools).
"""
from __future__ import annotations

import concurrent.futures
import threading

from drillpy import _core

_worker = threading.local()
_lock = threading.Lock()
_running = [0]  # tasks of task_map running now


def engine_threads(threads: int) -> int:
    """The threads of one engine call: ``threads`` (0: the engine's default) outside
    :func:`task_map`; inside, those cores shared by the tasks still running (at least one).

    Parameters
    ----------
    threads : int
        The loop's engine threads (``LoopOptions.threads``; 0: :func:`drillpy._core.max_threads`).

    Returns
    -------
    int
        Threads for this call (0: the engine's default).
    """
    n = _running[0]
    if n == 0:
        return threads
    return max(1, (threads or _core.max_threads()) // n)


def task_map(fn, items, opt) -> list:
    """``[fn(item, opt) for item in items]``, the tasks on up to as many threads as the engine's
    cores (``opt.threads``; 0: :func:`drillpy._core.max_threads`).

    Parameters
    ----------
    fn : callable
        ``fn(item, options)``; an exception it raises reaches the caller (the first one, in the
        order of ``items``).
    items : iterable
        The tasks' arguments.
    opt : LoopOptions
        The loop's options.

    Returns
    -------
    list
        The results in the order of ``items``.
    """
    items = list(items)
    workers = min(len(items), opt.threads or _core.max_threads())
    if workers < 2 or getattr(_worker, "inside", False):
        return [fn(x, opt) for x in items]

    def run(x):
        _worker.inside = True
        with _lock:
            _running[0] += 1
        try:
            return fn(x, opt)
        finally:
            with _lock:
                _running[0] -= 1
            _worker.inside = False

    with concurrent.futures.ThreadPoolExecutor(workers) as pool:
        return list(pool.map(run, items))
