"""Progress bars for long engine calls (tqdm), fed by the engine's chunk callbacks."""
from __future__ import annotations

import contextlib
import sys

from tqdm import tqdm


@contextlib.contextmanager
def progress_bar(total: int, desc: str, enabled: bool = True):
    """Yield a callback ``cb(done, total)`` that advances a tqdm bar (or ``None`` if disabled).

    The engine calls it between chunks of work with the GIL held; Ctrl-C raises
    KeyboardInterrupt from the engine at the next chunk boundary.
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
