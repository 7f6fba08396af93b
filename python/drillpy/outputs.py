"""Outputs that survive: every file a command writes appears whole or not at all, and one command
at a time writes into an output folder.

* :func:`write_text` and :func:`replacing` write to a temporary file beside the target and move it
  into place with :func:`os.replace` (atomic on POSIX): a reader, a crash or Ctrl-C never sees half
  a file, and a file from an earlier run stays whole until the new one replaces it.
* :func:`folder_lock` holds an exclusive advisory lock (``fcntl.flock``) on ``OUT/.drillpy.lock``
  while a command writes into ``OUT``: a second command on the same folder stops at once with one
  error naming the folder and the process holding it.
"""
from __future__ import annotations

import contextlib
import fcntl
import os
import tempfile
from pathlib import Path

LOCK_NAME = ".drillpy.lock"


class FolderBusy(ValueError):
    """Another process holds the output folder's lock (the folder is theirs: never clean it up)."""


@contextlib.contextmanager
def replacing(path):
    """Context manager yielding a temporary path beside ``path``, moved onto ``path`` when the block
    ends without an exception (removed otherwise).

    Parameters
    ----------
    path : str or Path
        The file to write.

    Yields
    ------
    Path
        The temporary file to write to (same folder and suffix, so writers that infer the format from
        the suffix still do).
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=f".tmp{path.suffix}", dir=path.parent)
    os.close(fd)
    try:
        yield Path(tmp)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def write_text(path, text: str) -> Path:
    """Write ``text`` to ``path`` atomically (:func:`replacing`).

    Parameters
    ----------
    path : str or Path
        The file.
    text : str
        Its whole content.

    Returns
    -------
    Path
        ``path``.
    """
    with replacing(path) as tmp:
        tmp.write_text(text)
    return Path(path)


@contextlib.contextmanager
def folder_lock(out):
    """Context manager: hold the exclusive lock of the output folder ``out`` (created if missing).

    Parameters
    ----------
    out : str or Path
        The output folder.

    Raises
    ------
    FolderBusy
        ``"--out = '<out>': another drillpy command (pid N) is writing into this folder; ..."`` when
        another process holds it (a ``ValueError``).
    """
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    lock = folder / LOCK_NAME
    while True:
        fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.read(fd, 32).decode(errors="replace").strip() or "?"
            os.close(fd)
            raise FolderBusy(f"--out = {str(out)!r}: another drillpy command (pid {holder}) is writing into this "
                             "folder; wait for it to finish or give another --out") from None
        try:  # the holder may have removed the file between our open and our lock: lock the current one
            same = os.path.samestat(os.fstat(fd), os.stat(lock))
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)
    try:
        os.ftruncate(fd, 0)
        os.write(fd, str(os.getpid()).encode())
        yield folder
    finally:
        with contextlib.suppress(OSError):
            os.unlink(lock)
        os.close(fd)
