"""The ``drillpy`` command.

  drillpy report   --preset thesis-field --out DIR      main job: frequencies, SS sweep, maps
  drillpy modes    --preset thesis-field --elements 100 -n 5 --json
  drillpy simulate --preset thesis-field --top-speed 16 --out DIR
  drillpy sweep    --preset thesis-field --law hysteretic --beta1 0.14 --speeds 6:27:22 --json
  drillpy map      --preset thesis-field --beta1 0.56 --speeds-rpm 50:160:23 --wobs-kn 22:267:12
  drillpy convergence --preset thesis-field            FE and time-step convergence orders
  drillpy analyze  ../shared/data/testrig/sample175_0-40s.mat --out DIR   measured record: report
  drillpy analyze  REC1 REC2 ... (or a folder, or REC@T0:T1) --out DIR   section 5.3 across samples
  drillpy frf      --preset thesis-ch6 --model SM_CB2 --case 4 --samples 2500 --json
  drillpy frf-report --preset thesis-ch6 --out DIR          chapter 6 and appendix C figures
  drillpy robust-ss --preset thesis-ch6 --samples 40 --speeds 6:27:8 --out DIR
  drillpy mc       --preset thesis-field --samples 500 --speeds 6:27:22 --seed 1 --json
  drillpy mc-merge CHUNK_DIR1 CHUNK_DIR2 ... --out DIR   chunks run with mc --first-sample --out
  drillpy loop     RECORD --preset thesis-rig --out DIR      residual -> missing effect -> corrected model
  drillpy predict  MODEL.json RECORD --out DIR --json       a calibrated rig model on a record it never saw
  drillpy control  --preset thesis-field --drive-inertia 2000 --torque-limit 50000 --out DIR   robust tuning

Every error prints one line ``drillpy: error: ...`` and exits with status 2.
"""
# Layout: this module holds main(), the parser assembly and what several commands share (the model
# options, grids, typed option values); each command group lives in its own module, which registers
# its subcommands' arguments next to their handlers in its ``SUBCOMMANDS`` (name -> the function that
# adds the subparser), and GROUPS lists the modules in the order of ``drillpy --help``:
#   cli/model.py        report, modes, simulate, sweep, map, convergence
#   cli/uncertainty.py  frf, frf-report, robust-ss, mc, mc-merge
#   cli/reproduce.py    reproduce
#   cli/records.py      analyze, predict, loop, calibrate, posterior-map
#   cli/control.py      control
# Adding a command: its ``_add_*`` and ``cmd_*`` in a group module and its entry in that module's
# SUBCOMMANDS (a new group: its module and its name in GROUPS).
# A handler parses its arguments, calls the library and prints; files are written by the library.
from __future__ import annotations

import argparse
import contextlib
import os
import re
import shutil
import sys
from pathlib import Path
from typing import Callable

import numpy as np

from drillpy.model.config import load_config, with_overrides
from drillpy.model.configuration import Configuration


class OptionError(Exception):
    """A command-line value a typed option refuses.

    Deliberately not a ``ValueError``: argparse turns those raised by a ``type=`` function into its
    multi-line usage error, whereas :func:`main` prints this one as ``drillpy: error: ...`` (status 2)
    like every error of the library.
    """


class _Parser(argparse.ArgumentParser):
    """argparse with drillpy's errors: one line ``drillpy: error: ...`` (status 2) naming the
    subcommand's help instead of a usage dump; a value starting with ``-`` and a digit, a dot,
    ``inf`` or ``nan`` is a (negative) number, not an option, so ``--speeds -10,-5`` and
    ``--t0 -1e3`` are values."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = re.compile(r"^-(\.?\d|inf|nan)", re.IGNORECASE)

    def error(self, message: str):
        """Print ``drillpy: error: <message> (see <prog> --help)`` on stderr and exit with status 2."""
        self.exit(2, f"drillpy: error: {message} (see {self.prog} --help)\n")


#: Most points a grid option may ask for (a sweep over more would run for days).
MAX_GRID_POINTS = 100_000


def parse_grid(text: str, name: str, quantity: str | None = None, default_unit: str | None = None,
               to: str | None = None) -> np.ndarray:
    """Parse a grid option: ``start:stop:num`` (inclusive linspace) or a comma-separated list,
    with an optional trailing unit for a physical quantity (``"50:160:23rpm"``, ``"20,45klbf"``).

    Parameters
    ----------
    text : str
        The option's value, e.g. ``"6:27:22"`` or ``"8,14,20"``.
    name : str
        Option named in the error message, e.g. ``"--speeds"``.
    quantity : str, optional
        A quantity of :data:`drillpy.units.UNITS` (``"speed"``, ``"force"``): the grid is returned in SI.
    default_unit : str, optional
        Unit of a grid typed without one (default the SI unit).
    to : str, optional
        Unit of the result (default the SI unit).

    Returns
    -------
    ndarray
        The grid values (float; SI, or ``to``, when ``quantity`` is given).

    Raises
    ------
    ValueError
        ``"<name> = '<text>': use start:stop:num or a comma-separated list"``; also for a value
        that is not finite or more than :data:`MAX_GRID_POINTS` points.
    """
    bad = f"{name} = {text!r}: use start:stop:num or a comma-separated list"
    if quantity is not None:
        from drillpy import units
        number, unit = units.split_unit(text, quantity)
        return units.grid_in_si(parse_grid(number, name), unit, quantity, default_unit, to)
    try:
        if ":" in text:
            a, b, n = text.split(":")
            a, b, n = float(a), float(b), int(n)
            vals = [a, b]
        else:
            vals = [float(x) for x in text.split(",") if x.strip()]
            n = len(vals)
    except ValueError:
        raise ValueError(bad) from None
    if n < 1:
        raise ValueError(bad)
    if n > MAX_GRID_POINTS:
        raise ValueError(f"{name} = {text!r}: at most {MAX_GRID_POINTS} points")
    if not np.all(np.isfinite(vals)):
        raise ValueError(f"{name} = {text!r}: the values must be finite numbers")
    return np.linspace(a, b, n) if ":" in text else np.asarray(vals)


def print_json(result) -> None:
    """Print ``result`` as one line of JSON, NaN and inf as ``null`` (:func:`drillpy.jsonio.dumps`).

    Parameters
    ----------
    result : object
        What a ``--json`` command prints (dicts, lists, numbers, NumPy values).
    """
    from drillpy.jsonio import dumps
    print(dumps(result, indent=None))


def integer(name: str) -> Callable[[str], int]:
    """A ``type=`` function for an integer option whose bad value is a one-line ``drillpy`` error.

    Parameters
    ----------
    name : str
        Field named in the error message, e.g. ``"samples"``.

    Returns
    -------
    callable
        ``convert(text) -> int``; raises :class:`OptionError`
        ``"<name> = '<text>': must be an integer"`` when ``text`` is not one. Ranges (e.g. samples >= 1)
        are checked by the library, which names the field the same way.
    """
    def convert(text: str) -> int:
        try:
            return int(text)
        except ValueError:
            raise OptionError(f"{name} = {text!r}: must be an integer") from None
    convert.__name__ = name  # argparse names the type in its own messages
    return convert


def quantity(name: str, kind: str, default_unit: str | None = None) -> Callable[[str], float]:
    """A ``type=`` function for a physical value with an optional unit suffix (``120rpm``, ``45klbf``).

    Parameters
    ----------
    name : str
        Option named in the error message, e.g. ``"--top-speed"``.
    kind : str
        A quantity of :data:`drillpy.units.UNITS` (``"speed"``, ``"force"``, ``"torque"``).
    default_unit : str, optional
        Unit of a plain number (default the SI unit: rad/s, N, N m).

    Returns
    -------
    callable
        ``convert(text) -> float`` in SI; raises :class:`OptionError` naming the option and the value.
    """
    from drillpy import units

    def convert(text: str) -> float:
        try:
            return units.parse_quantity(text, kind, name, default_unit)
        except ValueError as e:
            raise OptionError(str(e)) from None
    convert.__name__ = name
    return convert


def renamed(new: str, why: str) -> type:
    """An argparse action for a removed option: using it is an error naming its replacement.

    Parameters
    ----------
    new : str
        The option to use instead.
    why : str
        What the replacement means.

    Returns
    -------
    type
        An ``argparse.Action`` subclass raising :class:`OptionError`.
    """
    class Renamed(argparse.Action):
        def __call__(self, parser, namespace, values, option_string=None):
            raise OptionError(f"{option_string} = {values}: renamed {new} ({why})")
    return Renamed


def add_figure_units_arg(p: argparse.ArgumentParser) -> None:
    """Add ``--figure-units si|field``: the units of the figure's axes (the files stay SI).

    Parameters
    ----------
    p : argparse.ArgumentParser
        A command that writes a figure with ``--out``.
    """
    p.add_argument("--figure-units", choices=("si", "field"), default="si",
                   help="axes of the figures: si (rad/s, kN, N m; maps in RPM and kN; records in RPM, N, N m) or "
                        "field (RPM, klbf, kft-lbf; records in RPM, lbf, ft-lbf); the written data stay SI")


def add_wob_arg(p: argparse.ArgumentParser) -> None:
    """Add ``--wob``: the weight on bit of every run, with an optional unit (``200kN``, ``45klbf``; plain: N).

    Parameters
    ----------
    p : argparse.ArgumentParser
        A simulation command's parser; :func:`model_config` applies it (``operation.wob_n``).
    """
    p.add_argument("--wob", type=quantity("--wob", "force"),
                   help="weight on bit of the runs: a number in N or with a unit (200kN, 45klbf, 10000lbf); "
                        "default the configuration's operation.wob_n")


#: Most OpenMP threads ``--threads`` takes.
MAX_THREADS = 1024


def threads_option(text: str) -> int:
    """The ``type=`` function of ``--threads``: an integer in [0, :data:`MAX_THREADS`] (0: the OpenMP default).

    Parameters
    ----------
    text : str
        The option's value.

    Returns
    -------
    int
        The thread count.

    Raises
    ------
    OptionError
        ``"threads = '<text>': must be an integer between 0 and 1024 (0: the OpenMP default)"``.
    """
    try:
        n = int(text)
    except ValueError:
        n = -1
    if not 0 <= n <= MAX_THREADS:
        raise OptionError(f"threads = {text!r}: must be an integer between 0 and {MAX_THREADS} (0: the OpenMP "
                          "default)")
    return n


def add_model_args(p: argparse.ArgumentParser) -> None:
    """Add the options every simulation command shares: the model source and its overrides.

    Parameters
    ----------
    p : argparse.ArgumentParser
        A subcommand's parser; receives ``--preset``/``--config`` (one required), the overrides of
        :func:`drillpy.model.config.with_overrides` (``--dt``, ``--duration``, ``--transient`` in s),
        ``--threads``, ``--start`` and ``--no-progress``.
    """
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--preset", help="built-in configuration (thesis-field, thesis-ch4, thesis-rig, thesis-ch6)")
    src.add_argument("--config", help="JSON configuration file")
    p.add_argument("--elements", type=int, help="total elements, split in proportion to section lengths")
    p.add_argument("--modes", type=int, help="elastic modes kept in the reduced-order model")
    p.add_argument("--law", choices=["hysteretic", "tucker_wang"], help="thesis bit-rock law parameter set")
    p.add_argument("--beta1", type=float, help="hysteresis amplitude of Eq. (3.3)")
    p.add_argument("--law-speed-unit", choices=["rad_s", "rpm"],
                   help="unit in which the bit-rock law's parameters (b0..b5, c0, alpha) read speeds; not the unit "
                        "of the speeds you type (give those a suffix: --top-speed 120rpm)")
    p.add_argument("--speed-unit", action=renamed("--law-speed-unit", "it sets the unit of the law's parameters, "
                                                  "not of the speeds typed: give a speed its unit, e.g. "
                                                  "--top-speed 120rpm"), help=argparse.SUPPRESS)
    p.add_argument("--scheme", choices=["modified_euler", "bdf2", "exact_modal"], help="time integration scheme")
    p.add_argument("--acceleration", choices=["implicit", "lagged"],
                   help="bit acceleration in Eq. (3.3): the step's own (implicit, default) or the last "
                        "step's backward difference (lagged, modified Euler only)")
    p.add_argument("--dt", type=float, help="time step [s]")
    p.add_argument("--duration", type=float, help="simulated time [s]")
    p.add_argument("--transient", type=float, help="time discarded before metrics [s]")
    p.add_argument("--threads", type=threads_option, default=0, help="OpenMP threads (0: default)")
    p.add_argument("--start", choices=["rest", "rigid", "steady"],
                   help="initial state: bit at rest (Eq. 2.10), string turning rigidly with the top "
                        "(Eq. 2.3) or steady drilling (default: the configuration's simulation.start, "
                        "rest unless set); saved in the configuration")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    c = p.add_argument_group("controlled top drive (docs/control.md)")
    c.add_argument("--controller", choices=["stiff", "pi", "soft_speed", "z_torque"],
                   help="a top drive with inertia driven by this speed controller (tuned from the string's "
                        "properties unless --kp/--ki are given; pi: the stiff drive's pole placement) instead of "
                        "the configuration's top drive")
    c.add_argument("--drive-inertia", type=float, metavar="J",
                   help="rotor and gearbox inertia of the controlled top drive [kg m^2] (needed with --controller "
                        "unless the configuration's drive has one)")
    c.add_argument("--kp", type=float, help="proportional gain [N m s/rad] (overrides the tuning)")
    c.add_argument("--ki", type=float, help="integral gain [N m/rad] (overrides the tuning)")
    c.add_argument("--torque-limit", type=quantity("--torque-limit", "torque"),
                   help="motor torque limit: N m or with a unit (50kNm, 36900ft-lbf)")
    c.add_argument("--sample-time", type=float, help="controller sample time [s] (zero-order hold; default continuous)")


def controlled_drive(a: argparse.Namespace, base: dict) -> dict | None:
    """The ``top_drive`` block of ``--controller`` and its options (None without ``--controller``).

    Parameters
    ----------
    a : argparse.Namespace
        ``--controller``, ``--drive-inertia``, ``--kp``, ``--ki``, ``--torque-limit``, ``--sample-time``.
    base : dict
        The configuration before the override (its drive's inertia is kept when none is given).

    Returns
    -------
    dict or None
        ``{"type": "controlled", "inertia_kg_m2": J, "controller": {...}}``; the engine validates it.

    Raises
    ------
    ValueError
        A controller option without ``--controller``, or no inertia known.
    """
    extra = {"--drive-inertia": a.drive_inertia, "--kp": a.kp, "--ki": a.ki, "--torque-limit": a.torque_limit,
             "--sample-time": a.sample_time}
    if a.controller is None:
        given = [k for k, v in extra.items() if v is not None]
        if given:
            raise ValueError(f"{given[0]} = {extra[given[0]]}: needs --controller")
        return None
    inertia = a.drive_inertia if a.drive_inertia is not None else Configuration.of(base).top_drive.get("inertia_kg_m2")
    if inertia is None:
        raise ValueError(f"--controller = {a.controller}: give --drive-inertia, the top drive's inertia [kg m^2] "
                         "(the configuration's drive has none)")
    from drillpy.control.tuning import controlled_drive as drive
    from drillpy.control.tuning import nominal_pi_gains
    keys = {"kp_nms_rad": a.kp, "ki_nm_rad": a.ki, "sample_time_s": a.sample_time}
    given = {k: v for k, v in keys.items() if v is not None}
    if a.controller == "pi":  # the tuning the help promises for the gains not given
        given = {**nominal_pi_gains(base, inertia), **given}
    return drive(a.controller, inertia, a.torque_limit, given)


def add_study_args(p: argparse.ArgumentParser) -> None:
    """Add the options of a stored, distributable study (:mod:`drillpy.study`): ``--scheduler`` and ``--chunk``.

    Parameters
    ----------
    p : argparse.ArgumentParser
        The parser of ``sweep``, ``map`` or ``mc``.
    """
    p.add_argument("--scheduler", default="local",
                   help="where the runs go: local (OpenMP in this process, default), local:N (a Dask LocalCluster "
                        "of N workers) or tcp://HOST:PORT (a running Dask scheduler); with --out the study is "
                        "stored in OUT/study.zarr and a repeated command computes only what is missing")
    p.add_argument("--chunk", type=integer("chunk"),
                   help="runs per task along the study's task axis (default: sweep 4 speeds, map 1 WOB, mc 50 "
                        "samples); a stored study keeps its own")


def study_severity(study: Callable, a: argparse.Namespace, direct: Callable[[], np.ndarray]) -> np.ndarray:
    """SS of a study: ``direct()`` (today's in-process path) unless ``--out`` stores it or ``--scheduler``
    distributes it, then :func:`drillpy.study.run_study` (the same bits either way).

    Parameters
    ----------
    study : callable
        Returns the :class:`drillpy.study.Study` (built only when needed, so that the in-process path
        keeps the engine's own messages for bad grids).
    a : argparse.Namespace
        ``--out``, ``--scheduler``, ``--chunk``, ``--threads``, ``--no-progress``.
    direct : callable
        Computes the SS array in this process without a store.

    Returns
    -------
    numpy.ndarray
        SS [-] in the study's dimensions.
    """
    if not a.out and a.scheduler == "local":
        return direct()
    from drillpy.study import run_study
    return run_study(study(), a.out, scheduler=a.scheduler, chunk=a.chunk, threads=a.threads,
                     progress=not a.no_progress)["severity"].values


def model_config(a: argparse.Namespace) -> dict:
    """The configuration selected by the options of :func:`add_model_args`.

    Parameters
    ----------
    a : argparse.Namespace
        Parsed arguments of a command registered with :func:`add_model_args`.

    Returns
    -------
    dict
        The preset or JSON file with the given overrides applied (validated by the library),
        ``--start`` included (``simulation.start``) and ``--wob`` (``operation.wob_n``) for the commands
        that have it (:func:`add_wob_arg`).
    """
    base = load_config(preset=a.preset) if a.preset else load_config(path=a.config)
    return with_overrides(base, elements=a.elements, modes=a.modes, law=a.law, beta1=a.beta1,
                          speed_unit=a.law_speed_unit, wob=getattr(a, "wob", None), scheme=a.scheme, acceleration=a.acceleration, dt=a.dt,
                          duration=a.duration, transient=a.transient, start=a.start,
                          top_drive=controlled_drive(a, base))


def check_output_folder(out: str) -> None:
    """Refuse an output folder that cannot be one, before any work is done.

    Parameters
    ----------
    out : str
        The ``--out`` value.

    Raises
    ------
    ValueError
        ``"--out = '<out>': is a file, not a folder"`` (or names the file on its path).
    """
    p = Path(out)
    for q in (p, *p.parents):
        if q.exists():
            if not q.is_dir():
                where = "is a file" if q == p else f"{str(q)!r} on its path is a file"
                raise ValueError(f"--out = {out!r}: {where}, not a folder")
            return


def removed_on_failure(out):
    """Context manager: if its block raises, remove the first folder of ``out`` that did not exist
    on entry (with what this run wrote in it); a folder that existed before is never removed, nor one
    interrupted (Ctrl-C) with a study store in it (``study.zarr``: its finished blocks are kept and the
    same command resumes them).

    Parameters
    ----------
    out : str or Path or None
        The output folder (None: none, the guard does nothing).

    Returns
    -------
    contextlib.AbstractContextManager
        The guard.
    """
    if out is None:  # nothing written (posterior-map without --out): nothing to remove
        return contextlib.nullcontext()
    p, first_new = Path(os.path.abspath(out)), None
    while not p.exists() and p != p.parent:
        first_new, p = p, p.parent

    @contextlib.contextmanager
    def guard():
        try:
            yield
        except KeyboardInterrupt:
            if first_new is not None and first_new.is_dir():
                from drillpy.study.store import STORE_NAME
                if any(first_new.rglob(STORE_NAME)):
                    print(f"drillpy: the finished blocks are kept in {out}: the same command resumes them",
                          file=sys.stderr)
                else:
                    shutil.rmtree(first_new, ignore_errors=True)
            raise
        except BaseException as e:
            from drillpy.outputs import FolderBusy
            if first_new is not None and first_new.is_dir() and not isinstance(e, FolderBusy):  # busy: not ours
                shutil.rmtree(first_new, ignore_errors=True)
            raise
    return guard()



@contextlib.contextmanager
def plausibility_lines():
    """Context manager: each distinct plausibility warning of a configuration
    (:class:`drillpy.model.plausibility.ImplausibleConfiguration`) printed once on stderr as
    ``drillpy: warning: <field> = <value> <unit>: outside the plausible <range> (<source>)...``; other
    warnings as Python shows them.

    Returns
    -------
    contextlib.AbstractContextManager
        The context.
    """
    import warnings

    from drillpy.model.plausibility import ImplausibleConfiguration
    seen: set = set()
    with warnings.catch_warnings():
        warnings.simplefilter("always", ImplausibleConfiguration)
        shown = warnings.showwarning

        def show(message, category, filename, lineno, file=None, line=None):
            if not issubclass(category, ImplausibleConfiguration):
                return shown(message, category, filename, lineno, file, line)
            if str(message) not in seen:
                seen.add(str(message))
                from tqdm import tqdm
                tqdm.write(f"drillpy: warning: {message}", file=sys.stderr)
        warnings.showwarning = show
        yield


#: The command groups (modules of ``drillpy.cli``), in the order of ``drillpy --help``.
GROUPS = ("model", "uncertainty", "reproduce", "records", "control")


def registry() -> dict:
    """Every subcommand: name -> the function that adds its parser, group by group (:data:`GROUPS`)
    in each group's ``SUBCOMMANDS`` order.

    Returns
    -------
    dict
        Command name -> ``_add_*(subparsers)``.
    """
    import importlib
    out = {}
    for g in GROUPS:
        for name, add in importlib.import_module(f"drillpy.cli.{g}").SUBCOMMANDS.items():
            if name in out:
                raise RuntimeError(f"drillpy.cli.{g}: the command {name!r} is registered twice")
            out[name] = add
    return out


def __getattr__(name: str):
    """``COMMANDS``: every command's name in the order of ``drillpy --help`` (from :func:`registry`)."""
    if name == "COMMANDS":
        return tuple(registry())
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def build_parser() -> argparse.ArgumentParser:
    """The ``drillpy`` argument parser with every subcommand.

    Returns
    -------
    argparse.ArgumentParser
        Each subcommand's parsed namespace carries its handler as ``func``.
    """
    commands = registry()
    p = _Parser(prog="drillpy", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    from drillpy import __version__
    p.add_argument("--version", action="version", version=f"drillpy {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    for add in commands.values():
        add(sub)
    return p


def main(argv: list[str] | None = None) -> int:
    """Run the ``drillpy`` command.

    Parameters
    ----------
    argv : list of str, optional
        Arguments without the program name (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        Exit status: 0 on success, 2 after a one-line ``drillpy: error: ...`` on stderr (bad input,
        failed run, unreadable file), 130 when interrupted. argparse's own usage errors exit with 2
        after one line too (:class:`_Parser`). A ``--out`` that cannot be a folder (or is empty) is
        refused before any work, a failed command removes the output folder it created
        (:func:`removed_on_failure`), and a folder another command is writing into is refused
        (:func:`drillpy.outputs.folder_lock`).
    """
    from drillpy.provenance import running_command
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        args = parser.parse_args(argv)
        out = getattr(args, "out", None)
        out = out if isinstance(out, str) else None
        if out is not None:
            if not out.strip():
                raise ValueError(f"--out = {out!r}: an empty folder name (give a folder, e.g. --out results/run1)")
            check_output_folder(out)
        from drillpy.outputs import folder_lock
        # the command line recorded in every output; a failed command leaves no folder it created; one
        # command at a time writes into a folder; each plausibility warning printed once
        with contextlib.ExitStack() as stack:
            stack.enter_context(running_command(argv))
            stack.enter_context(plausibility_lines())
            if out:
                stack.enter_context(removed_on_failure(out))
                stack.enter_context(folder_lock(out))
            return args.func(args)
    except (OptionError, ValueError, RuntimeError, OSError) as e:
        print(f"drillpy: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("drillpy: interrupted", file=sys.stderr)
        return 130
