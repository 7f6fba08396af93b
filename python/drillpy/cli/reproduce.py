"""``drillpy reproduce``: the thesis's studies chapter by chapter (:mod:`drillpy.reports.reproduce`)."""
from __future__ import annotations

import argparse
from pathlib import Path

from drillpy.cli import print_json, threads_option


def _add_reproduce(sub) -> argparse.ArgumentParser:
    """Register ``drillpy reproduce`` on the subparsers ``sub``; returns its parser."""
    s = sub.add_parser("reproduce", help="the thesis's studies chapter by chapter: figures under the thesis's "
                                         "numbers and a table quantity | thesis | drillpy | tolerance | pass")
    s.add_argument("--chapter", default="all", choices=["3", "4", "5", "6", "all"])
    s.add_argument("--out", required=True, help="folder for the figures, table.md and reproduce.json")
    s.add_argument("--quick", action="store_true", help="reduced studies (tests): not the thesis's settings")
    s.add_argument("--record", help="test-rig record of sample 175 for chapter 5 (default: ../shared/data/testrig)")
    s.add_argument("--seed", type=int, default=1, help="seed of the Monte Carlo studies")
    s.add_argument("--threads", type=threads_option, default=0, help="OpenMP threads (0: default)")
    s.add_argument("--no-progress", action="store_true", help="no progress bar")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_reproduce)
    return s


def cmd_reproduce(a: argparse.Namespace) -> int:
    """Reproduce the thesis's chapters into ``--out`` (:func:`drillpy.reports.reproduce.reproduce`).

    Parameters
    ----------
    a : argparse.Namespace
        Arguments of ``drillpy reproduce``.

    Returns
    -------
    int
        Exit status 0; prints the result as JSON or the table written to ``table.md``.
    """
    from drillpy.reports.reproduce import Options, reproduce
    res = reproduce(a.chapter, a.out, Options(quick=a.quick, threads=a.threads, progress=not a.no_progress,
                                              seed=a.seed), record=a.record)
    if a.json:
        print_json(res.as_dict())
    else:
        print((Path(a.out) / "table.md").read_text(), end="")
        print(f"figures, table.md and reproduce.json written to {a.out}")
    return 0


#: subcommand -> function registering it (``drillpy.cli.build_parser`` orders them)
SUBCOMMANDS = {"reproduce": _add_reproduce}
