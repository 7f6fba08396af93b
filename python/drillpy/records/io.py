"""Measured records: the :class:`Record` type, the rig's MATLAB reader and the CSV format.

A record holds the time and up to four channels, always in SI inside:

============== ========== ==============================================
channel        SI unit    accepted in files
============== ========== ==============================================
time           s          ``s``, ``ms``
bit_speed      rad/s      ``rad_s``, ``rpm``
top_speed      rad/s      ``rad_s``, ``rpm``
torque_on_bit  N m        ``Nm``, ``kNm``
wob            N          ``N``, ``kN``
============== ========== ==============================================

Any of the four channels may be absent (``None``); the time is required. Every channel carries a
per-sample quality bitmask (:class:`Flag`) filled by :mod:`drillpy.records.cleaning`; readers only
record where a value was not a finite number.

CSV format (documented in the README): one header row of ``<quantity>_<unit>`` column names,
canonically ``time_s,bit_speed_rad_s,top_speed_rad_s,torque_on_bit_Nm,wob_N``; lines starting
with ``#`` before the header are comments (the writer puts the provenance there); an empty cell or
``nan`` is a missing value (flagged, never invented); anything else that is not a number is an
error, and so is a column without a single value (the error names the column and the file).
"""
from __future__ import annotations

import csv
import enum
import math
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from drillpy.outputs import write_text

CHANNELS = ("bit_speed", "top_speed", "torque_on_bit", "wob")
SI_UNITS = {"time": "s", "bit_speed": "rad_s", "top_speed": "rad_s", "torque_on_bit": "Nm",
            "wob": "N"}
#: Factor converting a value in the given unit to SI, per quantity.
UNIT_FACTORS = {
    "time": {"s": 1.0, "ms": 1e-3},
    "bit_speed": {"rad_s": 1.0, "rpm": math.pi / 30.0},
    "top_speed": {"rad_s": 1.0, "rpm": math.pi / 30.0},
    "torque_on_bit": {"Nm": 1.0, "kNm": 1e3},
    "wob": {"N": 1.0, "kN": 1e3},
}
RPM = 30.0 / math.pi  #: rad/s -> RPM

#: The rig's MATLAB variable names (sample 175): <prefix>Sample_<n>_complete, unit in the file.
MAT_PREFIXES = {"time": ("Time_", "s"), "bit_speed": ("Bit_Speed_", "rpm"),
                "top_speed": ("Top_Speed_", "rpm"), "torque_on_bit": ("Bit_Torque_", "Nm"),
                "wob": ("WOB_", "N")}


class Flag(enum.IntFlag):
    """Per-sample quality bits of a channel (combine with ``|``; test with ``&``).

    NONFINITE    the source value was NaN, empty or infinite
    GAP          the sample was inserted on the uniform time grid where the source had none
    TIME         the time stamp of the sample was repaired, or the row was sorted into time order
    SPIKE        part of an isolated spike (encoder artifact)
    OSCILLATION  part of an artifact stretch (top speed oscillating while the bit is stuck)
    REPAIRED     the value was replaced (the cleaning report says how)
    UNRELIABLE   the value is not trusted and was not repaired: excluded from every analysis
    FLATLINE     part of a held value (a frozen sensor, a saturated or dropped-out channel)
    """
    NONFINITE = 1
    GAP = 2
    TIME = 4
    SPIKE = 8
    OSCILLATION = 16
    REPAIRED = 32
    UNRELIABLE = 64
    FLATLINE = 128


@dataclass
class Record:
    """A measured (or simulated) drill-string record in SI units.

    Attributes
    ----------
    time_s : ndarray, shape (n,)
        Sample times [s].
    bit_speed, top_speed : ndarray or None
        Bit and top-drive angular speeds [rad/s].
    torque_on_bit : ndarray or None
        Torque on bit [N m].
    wob : ndarray or None
        Weight on bit [N].
    units : dict
        Unit of each quantity in the source file (``{"bit_speed": "rpm", ...}``).
    provenance : dict
        Where the record comes from (``source``, ``format``, ``variables``) and what was done to
        it (``cleaning``).
    flags : dict
        Channel name (and ``"time"``) -> uint16 array of :class:`Flag` bits, one per sample.
    """
    time_s: np.ndarray
    bit_speed: np.ndarray | None = None
    top_speed: np.ndarray | None = None
    torque_on_bit: np.ndarray | None = None
    wob: np.ndarray | None = None
    units: dict = field(default_factory=dict)
    provenance: dict = field(default_factory=dict)
    flags: dict = field(default_factory=dict)

    def __post_init__(self):
        self.time_s = np.asarray(self.time_s, dtype=float)
        if self.time_s.ndim != 1:
            raise ValueError(f"time_s: must be 1-D, got shape {self.time_s.shape}")
        if self.time_s.size == 0:
            raise ValueError("time_s: the record is empty (no samples)")
        n = self.time_s.size
        present = 0
        for name in CHANNELS:
            x = getattr(self, name)
            if x is None:
                continue
            x = np.asarray(x, dtype=float)
            if x.shape != (n,):
                raise ValueError(f"{name}: has {x.size} samples (shape {x.shape}) but time_s has {n}")
            setattr(self, name, x)
            present += 1
        if present == 0:
            raise ValueError("record: no data channel (need at least one of " + ", ".join(CHANNELS) + ")")
        for name in ("time",) + self.channels:
            fl = self.flags.get(name)
            if fl is None:
                x = self.time_s if name == "time" else getattr(self, name)
                fl = np.where(np.isfinite(x), 0, int(Flag.NONFINITE)).astype(np.uint16)
            fl = np.asarray(fl, dtype=np.uint16)
            if fl.shape != (n,):
                raise ValueError(f"flags[{name!r}]: has {fl.size} entries, the record has {n} samples")
            self.flags[name] = fl

    # ------------------------------------------------------------------ queries
    @property
    def channels(self) -> tuple:
        """Names of the channels present, in the canonical order."""
        return tuple(c for c in CHANNELS if getattr(self, c) is not None)

    def __len__(self) -> int:
        return self.time_s.size

    @property
    def dt(self) -> float:
        """Median sampling interval [s] (over finite, increasing steps)."""
        d = np.diff(self.time_s)
        d = d[np.isfinite(d) & (d > 0)]
        if d.size == 0:
            raise ValueError("time_s: no increasing pair of finite time stamps")
        return float(np.median(d))

    @property
    def sample_rate_hz(self) -> float:
        """Sampling rate [Hz] = 1 / median interval."""
        return 1.0 / self.dt

    @property
    def duration_s(self) -> float:
        """Time span of the record [s]: last minus first finite time stamp."""
        return float(np.nanmax(self.time_s) - np.nanmin(self.time_s))

    def channel(self, name: str) -> np.ndarray:
        """The SI array of one channel (the stored array itself, not a copy).

        Parameters
        ----------
        name : str
            One of :data:`CHANNELS`: ``bit_speed`` [rad/s], ``top_speed`` [rad/s],
            ``torque_on_bit`` [N m] or ``wob`` [N].

        Returns
        -------
        ndarray, shape (n,)
            The channel in SI units, NaN where nothing finite was measured.

        Raises
        ------
        ValueError
            If ``name`` is not a channel name, or the channel is absent from this record (the
            message names the source and the channels it has).
        """
        if name not in CHANNELS:
            raise ValueError(f"channel = {name!r}: unknown (known: {', '.join(CHANNELS)})")
        x = getattr(self, name)
        if x is None:
            raise ValueError(f"channel {name!r} is missing from the record "
                             f"({self.provenance.get('source', 'record')} has {', '.join(self.channels)})")
        return x

    def valid(self, *names: str) -> np.ndarray:
        """Mask of the samples usable for analysis.

        A sample is valid when its time stamp and the value of every named channel are finite
        and none of them carries :attr:`Flag.UNRELIABLE`. Repaired samples (interpolated gaps and
        spikes, an artifact stretch of the top speed replaced by the bit speed) count as valid:
        use :meth:`flagged` to tell them apart.

        Parameters
        ----------
        *names : str
            Channels to check (see :meth:`channel`); none given: every channel present.

        Returns
        -------
        ndarray of bool, shape (n,)
        """
        names = names or self.channels
        ok = np.isfinite(self.time_s) & ((self.flags["time"] & Flag.UNRELIABLE) == 0)
        for name in names:
            x = self.channel(name)
            ok &= np.isfinite(x) & ((self.flags[name] & Flag.UNRELIABLE) == 0)
        return ok

    def flagged(self, name: str, flag: Flag) -> np.ndarray:
        """Mask of the samples of one channel that carry a quality flag.

        Parameters
        ----------
        name : str
            Channel name, or ``"time"`` for the flags of the time stamps.
        flag : Flag
            The bit(s) to test; with a combination (``Flag.SPIKE | Flag.OSCILLATION``) a sample
            carrying any of them is marked.

        Returns
        -------
        ndarray of bool, shape (n,)
        """
        return (self.flags[name] & int(flag)) != 0

    def select(self, t0: float | None = None, t1: float | None = None) -> "Record":
        """The samples inside a time window, both ends included (a copy).

        Parameters
        ----------
        t0, t1 : float or None
            Window start and end [s], in the record's own time axis; None leaves that side open.

        Returns
        -------
        Record
            The samples with ``t0 <= t <= t1``, flags, units and provenance carried over.

        Raises
        ------
        ValueError
            If no sample lies in the window (the message gives the span of the record).
        """
        t = self.time_s
        m = np.ones(t.size, bool)
        if t0 is not None:
            m &= t >= t0
        if t1 is not None:
            m &= t <= t1
        if not m.any():
            raise ValueError(f"select: no sample between t0 = {t0} s and t1 = {t1} s "
                             f"(record spans {np.nanmin(t):g} to {np.nanmax(t):g} s)")
        return self.take(np.flatnonzero(m))

    def take(self, index) -> "Record":
        """A new record made of the samples at ``index``.

        Parameters
        ----------
        index : array_like of int or bool
            Sample indices (or a boolean mask) applied to the time, every channel and every flag
            array; units and provenance are copied.

        Returns
        -------
        Record
        """
        kw = {c: (None if getattr(self, c) is None else getattr(self, c)[index]) for c in CHANNELS}
        return replace(self, time_s=self.time_s[index], flags={k: v[index] for k, v in self.flags.items()},
                       provenance=dict(self.provenance), units=dict(self.units), **kw)

    def in_unit(self, name: str, unit: str) -> np.ndarray:
        """A channel converted from SI to another unit, e.g. ``in_unit("bit_speed", "rpm")``.

        Parameters
        ----------
        name : str
            A channel name (see :meth:`channel`) or ``"time"``.
        unit : str
            Target unit, one of :data:`UNIT_FACTORS` for that quantity: ``s``/``ms`` for the time,
            ``rad_s``/``rpm`` for the speeds, ``Nm``/``kNm`` for the torque, ``N``/``kN`` for the
            WOB.

        Returns
        -------
        ndarray, shape (n,)
            A new array in ``unit``; the record is unchanged.

        Raises
        ------
        ValueError
            If the unit is not known for that quantity or the channel is absent.
        """
        q = "time" if name == "time" else name
        x = self.time_s if name == "time" else self.channel(name)
        return x / _factor(q, unit, where=f"{name} unit")


def _factor(quantity: str, unit: str, where: str) -> float:
    try:
        return UNIT_FACTORS[quantity][unit]
    except KeyError:
        known = ", ".join(UNIT_FACTORS.get(quantity, {}))
        raise ValueError(f"{where} = {unit!r}: unknown unit for {quantity} (use {known})") from None


def _require_time_and_data(path: Path, found, time_hint: str, data_hint: str, listing: str) -> None:
    """The error for a file without its time or without any data channel."""
    if "time" not in found:
        raise ValueError(f"record = {str(path)!r}: no time (expected {time_hint}; {listing})")
    if len(found) == 1:
        raise ValueError(f"record = {str(path)!r}: no data channel (expected {data_hint}; {listing})")


# ---------------------------------------------------------------------------------- MATLAB
def read_mat(path: str | Path, variables: dict | None = None) -> Record:
    """Read a test-rig MATLAB (v5/v7) file (the format of the thesis's rig records, chapter 5).

    By default the variables are found by the rig's naming (sample 175):
    ``Time_Sample_<n>_complete`` [s], ``Bit_Speed_...`` [RPM], ``Top_Speed_...`` [RPM],
    ``Bit_Torque_...`` [N m], ``WOB_...`` [N]. Speeds are converted to rad/s; absent channels
    stay ``None``.

    Parameters
    ----------
    path : str or Path
        The ``.mat`` file. MATLAB v7.3 (HDF5) files are not supported.
    variables : dict, optional
        Quantity -> ``(variable_name, unit)`` for files named otherwise, e.g.
        ``{"time": ("t", "s"), "bit_speed": ("wbit", "rad_s")}``; quantities are ``time`` and the
        :data:`CHANNELS`, units those of :data:`UNIT_FACTORS`. When given, only these variables
        are read.

    Returns
    -------
    Record
        SI channels; ``units`` holds each quantity's unit in the file and ``provenance`` the
        source path, ``format = "matlab"`` and the variable read for each quantity.

    Raises
    ------
    ValueError
        If the file is missing, unreadable, lacks the time variable or any data channel, or its
        variables are not numeric vectors of equal length.
    """
    from scipy.io import loadmat

    p = Path(path)
    if not p.is_file():
        raise ValueError(f"record = {str(p)!r}: no such file")
    try:
        data = loadmat(p, squeeze_me=False)
    except NotImplementedError:
        raise ValueError(f"record = {str(p)!r}: MATLAB v7.3 (HDF5) files are not supported; "
                         "save with -v7 or export to CSV") from None
    except Exception as e:  # scipy raises several types for corrupt files
        raise ValueError(f"record = {str(p)!r}: not a readable MATLAB file ({e})") from None
    names = sorted(k for k in data if not k.startswith("__"))
    if not names:
        raise ValueError(f"record = {str(p)!r}: the MATLAB file holds no variables")
    chosen: dict[str, tuple[str, str]] = {}
    if variables:
        for q, spec in variables.items():
            if q not in SI_UNITS:
                raise ValueError(f"variables: unknown quantity {q!r} (known: {', '.join(SI_UNITS)})")
            var, unit = spec
            _factor(q, unit, where=f"variables[{q!r}] unit")
            if var not in data:
                raise ValueError(f"record = {str(p)!r}: no variable {var!r} for {q} "
                                 f"(variables in the file: {', '.join(names)})")
            chosen[q] = (var, unit)
    else:
        for q, (prefix, unit) in MAT_PREFIXES.items():
            hits = [k for k in names if k.startswith(prefix)]
            if len(hits) > 1:
                raise ValueError(f"record = {str(p)!r}: several variables could be {q}: "
                                 f"{', '.join(hits)}; pass variables= to choose")
            if hits:
                chosen[q] = (hits[0], unit)
    _require_time_and_data(p, chosen, "a variable like Time_Sample_<n>_complete",
                           "Bit_Speed_*, Top_Speed_*, Bit_Torque_* or WOB_*", "variables in the file: " + ", ".join(names))
    arrays = {}
    for q, (var, unit) in chosen.items():
        a = data[var]
        if not (isinstance(a, np.ndarray) and a.dtype.kind in "biuf"):
            raise ValueError(f"record = {str(p)!r}: variable {var!r} ({q}) is not numeric "
                             f"(MATLAB class {getattr(a, 'dtype', type(a))})")
        if a.size == 0:
            raise ValueError(f"record = {str(p)!r}: variable {var!r} ({q}) is empty")
        if a.ndim > 2 or (a.ndim == 2 and min(a.shape) != 1):
            raise ValueError(f"record = {str(p)!r}: variable {var!r} ({q}) has shape {a.shape}; "
                             "expected a vector")
        arrays[q] = a.ravel().astype(float) * _factor(q, unit, where=q)
        if not np.isfinite(arrays[q]).any():
            raise ValueError(f"record = {str(p)!r}: variable {var!r} ({q}) has no finite value (all "
                             f"{a.size} NaN or inf)")
    lengths = {chosen[q][0]: v.size for q, v in arrays.items()}
    if len(set(lengths.values())) > 1:
        raise ValueError(f"record = {str(p)!r}: variables have unequal lengths: "
                         + ", ".join(f"{k} {n}" for k, n in lengths.items()))
    return Record(time_s=arrays.pop("time"), **arrays,
                  units={q: u for q, (_, u) in chosen.items()},
                  provenance={"source": str(p), "format": "matlab",
                              "variables": {q: v for q, (v, _) in chosen.items()}})


# ---------------------------------------------------------------------------------- CSV
_COLUMN = re.compile(r"^(time|bit_speed|top_speed|torque_on_bit|wob)_(.+)$")
_MISSING = {"", "nan", "NaN", "NAN", "NA", "na"}


def parse_column(name: str) -> tuple[str, str]:
    """Split a CSV column name into (quantity, unit), e.g. ``bit_speed_rpm`` -> ("bit_speed", "rpm").

    Parameters
    ----------
    name : str
        A header cell ``<quantity>_<unit>``, quantity ``time`` or one of :data:`CHANNELS`, unit one
        of :data:`UNIT_FACTORS` for it (surrounding blanks are ignored).

    Returns
    -------
    tuple of str
        ``(quantity, unit)``.

    Raises
    ------
    ValueError
        If the quantity or the unit is unknown.
    """
    m = _COLUMN.match(name.strip())
    if not m:
        raise ValueError(f"CSV column {name!r}: unknown quantity (columns are <quantity>_<unit> with "
                         f"quantity one of {', '.join(SI_UNITS)})")
    q, unit = m.group(1), m.group(2)
    _factor(q, unit, where=f"CSV column {name!r}: unit")
    return q, unit


def read_csv(path: str | Path) -> Record:
    """Read a record from the drillpy CSV format (see the module docstring and the README).

    Parameters
    ----------
    path : str or Path
        The CSV file (UTF-8, a byte-order mark is accepted). ``#`` lines before the header are kept
        as ``provenance["comments"]``; empty or ``nan`` cells become NaN (flagged NONFINITE).

    Returns
    -------
    Record
        SI channels; ``units`` holds each column's unit in the file and ``provenance`` the source
        path, ``format = "csv"`` and the header.

    Raises
    ------
    ValueError
        Naming the file and, where it applies, the row and column: not UTF-8 text (a binary file),
        not CSV (a NUL byte), empty file, missing time column, no data column, unknown column or
        unit, duplicate column, a row with the wrong number of cells, a cell that is not a number,
        a column without any value.
    """
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"record = {str(p)!r}: no such file")
    try:
        with open(p, newline="", encoding="utf-8-sig") as fh:
            lines = fh.read().splitlines()
    except UnicodeDecodeError as e:  # a binary file, or text in another encoding
        raise ValueError(f"record = {str(p)!r}: not a UTF-8 text file (byte {e.start}: {e.reason}); a CSV "
                         "record is UTF-8 text") from None
    comments, rest = [], []
    for i, line in enumerate(lines, 1):
        if not rest and line.lstrip().startswith("#"):
            comments.append(line.lstrip()[1:].strip())
        elif rest or line.strip():
            rest.append((i, line))
    if not rest:
        raise ValueError(f"record = {str(p)!r}: empty file (no header row)")
    try:
        rows = list(csv.reader([ln for _, ln in rest]))
    except csv.Error as e:  # a NUL byte, a field over the csv module's size limit
        raise ValueError(f"record = {str(p)!r}: not a CSV text file ({e})") from None
    header = [h.strip() for h in rows[0]]
    cols = []
    seen = {}
    for h in header:
        try:
            q, unit = parse_column(h)
        except ValueError as e:
            raise ValueError(f"record = {str(p)!r}: {e}") from None
        if q in seen:
            raise ValueError(f"record = {str(p)!r}: columns {seen[q]!r} and {h!r} are both {q}")
        seen[q] = h
        cols.append((q, unit))
    _require_time_and_data(p, seen, "a column time_s or time_ms", "columns " + ", ".join(
        f"{c}_<unit>" for c in CHANNELS), "header is " + ",".join(header))
    body = [(rest[k][0], r) for k, r in enumerate(rows[1:], 1) if any(c.strip() for c in r)]
    if not body:
        raise ValueError(f"record = {str(p)!r}: no data rows after the header")
    ncol = len(header)
    values = np.empty((len(body), ncol))
    for k, (lineno, r) in enumerate(body):
        if len(r) != ncol:
            raise ValueError(f"record = {str(p)!r}: line {lineno} has {len(r)} cells but the header "
                             f"has {ncol} (unequal column lengths)")
        for j, cell in enumerate(r):
            c = cell.strip()
            if c in _MISSING:
                values[k, j] = np.nan
                continue
            try:
                values[k, j] = float(c)
            except ValueError:
                raise ValueError(f"record = {str(p)!r}: line {lineno}, column {header[j]!r}: "
                                 f"{cell!r} is not a number") from None
    for j, (q, _) in enumerate(cols):
        if not np.isfinite(values[:, j]).any():
            raise ValueError(f"record = {str(p)!r}: column {header[j]!r} ({q}) has no value (all {len(body)} "
                             "cells empty or nan); leave the column out if the channel was not measured")
    arrays = {q: values[:, j] * UNIT_FACTORS[q][unit] for j, (q, unit) in enumerate(cols)}
    prov = {"source": str(p), "format": "csv", "columns": header}
    if comments:
        prov["comments"] = comments
    return Record(time_s=arrays.pop("time"), **arrays, units=dict(cols), provenance=prov)


def write_csv(record: Record, path: str | Path, speed_unit: str = "rad_s",
              comments: list[str] | None = None) -> Path:
    """Write ``record`` in the drillpy CSV format (readable by :func:`read_csv`).

    Speeds are written in ``speed_unit``, the rest in SI (``time_s``, ``torque_on_bit_Nm``,
    ``wob_N``), at full double precision. Non-finite values are written as empty cells. The
    ``comments`` and then the record's source (``# source: ...``) go into ``#`` lines above the
    header. Flags are not written: a record read back has only NONFINITE flags.

    Parameters
    ----------
    record : Record
        The record to write (absent channels are left out of the header).
    path : str or Path
        Output file; its folder is created if needed, an existing file is overwritten.
    speed_unit : str
        ``rad_s`` (default) or ``rpm`` for ``bit_speed`` and ``top_speed``.
    comments : list of str, optional
        Lines written as ``# <line>`` before the header.

    Returns
    -------
    Path
        The file written.
    """
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    cols = [("time_s", record.time_s)]
    for c in record.channels:
        unit = speed_unit if c in ("bit_speed", "top_speed") else SI_UNITS[c]
        cols.append((f"{c}_{unit}", record.in_unit(c, unit)))
    lines = [f"# {c}" for c in (comments or [])]
    src = record.provenance.get("source")
    if src:
        lines.append(f"# source: {src}")
    lines.append(",".join(n for n, _ in cols))
    data = np.column_stack([a for _, a in cols])
    for row in data:
        lines.append(",".join("" if not np.isfinite(x) else repr(float(x)) for x in row))
    write_text(p, "\n".join(lines) + "\n")
    return p


def read_record(path: str | Path) -> Record:
    """Read a record by its extension: ``.mat`` (rig MATLAB file) or ``.csv``/``.txt`` (drillpy CSV).

    Parameters
    ----------
    path : str or Path
        The record file; the suffix (case-insensitive) selects :func:`read_mat` (default variable
        names) or :func:`read_csv`.

    Returns
    -------
    Record
        As read: SI units, NONFINITE flags only; pass it to
        :func:`drillpy.records.cleaning.clean` before analysis.

    Raises
    ------
    ValueError
        For another suffix, and for every error of the reader.
    """
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix == ".mat":
        return read_mat(p)
    if suffix in (".csv", ".txt"):
        return read_csv(p)
    raise ValueError(f"record = {str(p)!r}: unknown format {suffix!r} (use .mat or .csv)")
