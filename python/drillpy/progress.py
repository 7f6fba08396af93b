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
