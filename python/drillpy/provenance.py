"""Provenance of the files drillpy writes: version, command line, time.

Every JSON output carries ``"provenance": provenance(...)``; every CSV and Markdown report carries
:func:`header` as a comment line, so any result file says which drillpy made it, how and when.

The ``drillpy`` command sets the command line once (:func:`command_line`); a library call outside
the command records the Python command line (``sys.argv``).
"""
from __future__ import annotations

import contextlib
import platform
import shlex
import sys
from datetime import datetime, timezone

__all__ = ["provenance", "header", "markdown_footer", "with_markdown_footer", "command_line", "running_command"]

#: The ``drillpy`` command line being run (set by :func:`running_command`), or None.
_COMMAND: str | None = None


def command_line() -> str:
    """The command line of this run, shell-quoted.

    Returns
    -------
    str
        ``drillpy <arguments>`` inside the ``drillpy`` command, otherwise ``sys.argv`` joined.
    """
    if _COMMAND is not None:
        return _COMMAND
    return shlex.join(sys.argv) if sys.argv and any(sys.argv) else "python"


@contextlib.contextmanager
def running_command(argv: list[str]):
    """Record ``drillpy <argv>`` as the command line for the duration of the ``with`` block.

    Parameters
    ----------
    argv : list of str
        The command's arguments, without the program name.
    """
    global _COMMAND
    previous, _COMMAND = _COMMAND, shlex.join(["drillpy", *argv])
    try:
        yield
    finally:
        _COMMAND = previous


def _version() -> str:
    from drillpy import __version__
    return __version__


def provenance(command: str | None = None, **options) -> dict:
    """Who made an output, how and when.

    Parameters
    ----------
    command : str, optional
        The command line (default: :func:`command_line`).
    **options
        Settings of the run worth recording beside the results (``seed``, ``start``, ``samples``,
        ``delta``...); those that are None are left out.

    Returns
    -------
    dict
        ``drillpy_version``, ``command``, ``timestamp`` (UTC, ISO 8601, seconds), ``python``
        (version) and the options given.
    """
    out = {
        "drillpy_version": _version(),
        "command": command_line() if command is None else command,
        "timestamp": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "python": platform.python_version(),
    }
    out.update({k: v for k, v in options.items() if v is not None})
    return out


def header(prov: dict | None = None, comment: str = "#") -> str:
    """One comment line naming the version, the command and the time (no newline).

    Parameters
    ----------
    prov : dict, optional
        A :func:`provenance` record (default: a new one).
    comment : str
        Comment marker (``"#"`` for CSV).

    Returns
    -------
    str
        ``# drillpy 0.1.0, <command>, <timestamp>``.
    """
    p = provenance() if prov is None else prov
    text = f"drillpy {p['drillpy_version']}, {p['command']}, {p['timestamp']}".replace("\n", " ")
    return f"{comment} {text}" if comment else text


def markdown_footer(prov: dict | None = None) -> str:
    """The last line of a Markdown report: version, command (as code) and time, newline-terminated.

    Parameters
    ----------
    prov : dict, optional
        A :func:`provenance` record (default: a new one).

    Returns
    -------
    str
        A blank line, then ``*drillpy 0.1.0, `<command>`, <timestamp>*`` and a newline (a paragraph of
        its own).
    """
    p = provenance() if prov is None else prov
    cmd = p["command"].replace("\n", " ").replace("`", "'")
    return f"\n*drillpy {p['drillpy_version']}, `{cmd}`, {p['timestamp']}*\n"


def with_markdown_footer(text: str, prov: dict | None = None) -> str:
    """``text`` (a Markdown report) with :func:`markdown_footer` as its last paragraph.

    Parameters
    ----------
    text : str
        The report.
    prov : dict, optional
        A :func:`provenance` record (default: a new one).

    Returns
    -------
    str
        The report, one blank line, the provenance line, a final newline.
    """
    return text.rstrip("\n") + "\n" + markdown_footer(prov)
