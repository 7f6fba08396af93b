"""Progress bars for long engine calls (tqdm), fed by the engine's chunk callbacks."""
from __future__ import annotations

import contextlib
import sys

from tqdm import tqdm


@contextlib.contextmanager
def progress_bar(total: int, desc: str, enabled: bool = True):
    """Yield a callback ``cb(done, total)`` that advances a tqdm bar (or ``None`` if disabled).

    The engine calls it between chunks of work with the GIL held; Ctrl-C raises
    KeyboardInterrupt from the engine at the next chunk boundary. The bar is written to stderr
    and hidden when stderr is not a terminal; it is closed when the block exits.

    Parameters
    ----------
    total : int
        Units of work the bar counts to (runs, samples, cycles).
    desc : str
        Text in front of the bar, e.g. ``"Monte Carlo samples"``.
    enabled : bool
        False: yield ``None`` (no callback, no bar).

    Yields
    ------
    callable or None
        ``cb(done, total)`` with ``done`` the cumulative units finished.
    """
    if not enabled:
        yield None
        return
    bar = tqdm(total=total, desc=desc, unit="run", file=sys.stderr, leave=False,
               disable=None)  # disable=None: no bar when stderr is not a terminal
    state = {"done": 0}

    def callback(done: int, _total: int) -> None:
        bar.update(done - state["done"])
        state["done"] = done

    try:
        yield callback
    finally:
        bar.close()


@contextlib.contextmanager
def log_progress(markers, desc: str, total: int | None = None, enabled: bool = True, echo=print,
                 count: bool = False):
    """Yield a ``log(line)`` callback that echoes a library's progress lines and moves a tqdm bar
    at the lines that mark its stages (the library's outputs are unchanged).

    The bar is written to stderr and hidden when stderr is not a terminal; while it shows, the
    lines are written above it (``tqdm.write``).

    Parameters
    ----------
    markers : sequence of (str, str)
        ``(pattern, label)`` pairs; a line matching ``pattern`` at its start (:func:`re.match`)
        advances the bar and shows ``label``. The pairs are the ordered stages: the bar moves to
        the matched stage's place (1-based), never back; with ``count`` each matching line counts one.
    desc : str
        Text in front of the bar, e.g. ``"analyze"``.
    total : int, optional
        Number of stages or of counted lines; None: a counter without an end.
    enabled : bool
        False: no bar (the lines are still echoed).
    echo : callable or None
        Where the lines go without a bar (``print``); None: they are dropped (e.g. ``--json``).
    count : bool
        Count matching lines instead of moving to ordered stages.

    Yields
    ------
    callable
        ``log(line)`` for the library's ``log`` argument.
    """
    import re
    pats = [(re.compile(p), label) for p, label in markers]
    bar = tqdm(total=total, desc=desc, unit="step", file=sys.stderr, leave=False,
               disable=None if enabled else True)

    def log(line, *rest) -> None:
        text = str(line)
        if echo is not None:
            if bar.disable:
                echo(text, *rest)
            else:
                tqdm.write(" ".join([text, *map(str, rest)]), file=sys.stdout)
        for k, (pat, label) in enumerate(pats):
            if pat.match(text):
                if count:
                    bar.update(1)
                elif k + 1 > bar.n:
                    bar.update(k + 1 - bar.n)
                bar.set_postfix_str(label, refresh=True)
                break

    try:
        yield log
    finally:
        bar.close()
