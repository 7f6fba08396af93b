"""Artifact detection and repair for measured records.

:func:`clean` puts a record on a uniform time grid and flags, per channel and per sample
(:class:`drillpy.records.io.Flag`):

* rows logged out of time order (e.g. two swapped rows): a row whose stamp lies on the sampling
  grid, on a slot no other row holds and within ``MAX_RESTAMP`` rows of its place in the file is
  sorted into place by its time stamp (an ``order`` artifact, flagged TIME);
* other time stamps that go backwards, repeat or fall off the sampling grid (repaired from the
  acquisition order when the neighbours agree; an error when they cannot be placed);
* a channel without a single finite value: an error naming the channel and the source;
* gaps in the time grid (samples inserted);
* non-finite values (NaN, empty cells, inf);
* isolated spikes (encoder artifacts: short excursions far from the running median);
* artifact stretches: clusters of spikes, like the top-speed channel of sample 175 oscillating
  between about -200 and +50 RPM while the bit is stuck (around 28-30 s);
* held values (flatlines): a channel that repeats one value exactly for ``flatline_min_s`` or
  longer (a frozen encoder, a saturated load cell, a logger holding its last sample). The rig's
  channels carry noise through a 10 Hz filter and never repeat a value more than twice in sample
  175, so a hold is no motion. Not flagged: a speed held at or below the stick threshold (a stuck
  bit, as a noise-free simulation writes it), a torque held while the bit is stuck (a noise-free
  stall: the string at rest against a drive that cannot turn it), a channel held over most of its
  length (a set point, e.g. an ideal drive's top speed) and a quantized channel (one whose
  consecutive samples repeat often outside the holds).

Repairs, all reported and flagged REPAIRED:

* gaps and non-finite runs up to ``max_fill_s`` long: linear interpolation between the finite
  neighbours (the rig's channels are low-passed at 10 Hz, so 50 ms is a fraction of the
  filter's own memory);
* isolated spikes: linear interpolation across the spike;
* an artifact stretch of the top speed while the bit is stuck: replaced by the bit speed. A stuck
  bit with a torque on bit that stays nearly constant means the string is not winding up, so the
  top drive is at rest too (the report gives the torque change over the stretch as evidence).

What cannot be repaired soundly (longer gaps, stretches where the bit moves, wide excursions) is
flagged UNRELIABLE and left as measured (NaN where nothing was measured): analyses exclude those
samples and the cycles that touch them. Nothing is dropped silently: exact duplicate rows are the
only samples removed, and they are counted.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np
from scipy import ndimage

from drillpy.records.io import Flag, Record
from drillpy import validate
from drillpy.records.stick import STICK_FRACTION, stick_threshold

KINDS = ("time", "order", "duplicate", "gap", "nonfinite", "spike", "oscillation", "flatline")
MAX_RESTAMP = 10  #: anchors re-stamped on each side of a run of bad time stamps, at most
#: The time grid may hold at most MAX_GRID_FACTOR x rows + MAX_GRID_EXTRA samples (gaps inserted):
#: beyond that the stamps are refused rather than a grid of invented samples built (e.g. one stamp
#: of 1e12 s in a 1 kHz record would ask for 10^15 samples).
MAX_GRID_FACTOR, MAX_GRID_EXTRA = 10, 10**6


@dataclass
class CleaningOptions:
    """Thresholds of :func:`clean` (times in seconds).

    Attributes
    ----------
    max_fill_s : float
        Longest run of missing or non-finite samples repaired by linear interpolation [s].
    grid_tolerance : float
        A time stamp is on the sampling grid when within this fraction of the interval.
    spike_window_s : float
        Width of the running median the spikes are measured against [s].
    spike_sigmas : float
        Detection threshold in robust standard deviations of (signal - running median).
    spike_min_fraction : float
        ... and at least this fraction of the 1-99 % range of the running median (so that smooth
        signals with a tiny median residual do not flag their own curvature).
    spike_max_width_s : float
        A flagged excursion wider than this is not a spike: it is flagged UNRELIABLE unrepaired.
    spike_pad_s : float
        Samples this close to a spike are taken with it (the filtered tails of the spike).
    stretch_gap_s : float
        Spikes closer than this (end to start) belong to one artifact stretch.
    stretch_min_spikes : int
        Number of spikes that make a cluster an artifact stretch.
    stick_threshold_rad_s : float or None
        Bit speed at or below which the bit counts as stuck [rad/s]; default 5 % of the median
        top speed (of the bit speed's 95th percentile without a top-speed channel).
    stuck_fraction : float
        Fraction of a stretch the bit must be stuck for the top-speed repair.
    spike_channels : tuple or None
        Channels searched for spikes and artifact stretches (None: all). ``drillpy loop`` searches
        the encoder channels only: a load cell's torque drops sharply, and genuinely, when the bit
        nearly sticks for a few milliseconds.
    flatline_min_s : float
        A value repeated exactly for this long or longer is a held value (every channel is
        searched) [s]; 0 switches the search off.
    flatline_quantized_fraction : float
        A channel whose consecutive samples, outside the holds, repeat exactly more often than this
        fraction is quantized (an encoder's counts, a logger's coarse steps): its holds may be
        motion and are not flagged.
    """
    max_fill_s: float = 0.05
    grid_tolerance: float = 0.1
    spike_window_s: float = 0.051
    spike_sigmas: float = 8.0
    spike_min_fraction: float = 0.5
    spike_max_width_s: float = 0.06
    spike_pad_s: float = 0.003
    stretch_gap_s: float = 0.1
    stretch_min_spikes: int = 3
    stick_threshold_rad_s: float | None = None
    stuck_fraction: float = 0.9
    spike_channels: tuple | None = None
    flatline_min_s: float = 0.1
    flatline_quantized_fraction: float = 0.05

    def validate(self) -> None:
        """Check the thresholds (called by :func:`clean`).

        Raises
        ------
        ValueError
            If a duration, factor or fraction is negative, ``grid_tolerance`` is not strictly
            between 0 and 0.5, ``stretch_min_spikes`` is below 2 or ``stick_threshold_rad_s`` is
            negative.
        """
        for name in ("max_fill_s", "spike_window_s", "spike_sigmas", "spike_min_fraction",
                     "spike_max_width_s", "spike_pad_s", "stretch_gap_s", "stuck_fraction",
                     "flatline_min_s", "flatline_quantized_fraction"):
            validate.non_negative(f"cleaning.{name}", getattr(self, name))
        validate.number("cleaning.grid_tolerance", self.grid_tolerance, lo=0.0, hi=0.5,
                        lo_closed=False, hi_closed=False)
        validate.integer("cleaning.stretch_min_spikes", self.stretch_min_spikes, 2)
        if self.stick_threshold_rad_s is not None:
            validate.non_negative("cleaning.stick_threshold_rad_s", self.stick_threshold_rad_s, "rad/s")


@dataclass
class Artifact:
    """One detected artifact: a contiguous run of samples of one channel.

    Attributes
    ----------
    kind : str
        One of :data:`KINDS`: ``time`` (bad time stamps re-stamped), ``order`` (rows sorted into
        time order), ``duplicate`` (exact duplicate rows removed), ``gap`` (samples inserted on the
        time grid), ``nonfinite`` (NaN/empty/inf values), ``spike`` (isolated encoder spike) or
        ``oscillation`` (artifact stretch, a cluster of spikes) or ``flatline`` (a held value).
    channel : str
        Channel name, or ``"time"`` for the time-grid artifacts.
    start_s, end_s : float
        Time of the first and of the last affected sample [s].
    samples : int
        Number of affected samples.
    repair : str
        How it was repaired, or ``"none: flagged UNRELIABLE (excluded; <why>)"``.
    """
    kind: str        #: one of KINDS
    channel: str     #: channel name, or "time"
    start_s: float   #: time of the first affected sample [s]
    end_s: float     #: time of the last affected sample [s]
    samples: int     #: number of affected samples
    repair: str      #: how it was repaired, or "none: flagged UNRELIABLE (excluded)"

    @property
    def repaired(self) -> bool:
        """True unless the samples were left as measured and flagged UNRELIABLE."""
        return not self.repair.startswith("none")


@dataclass
class CleaningReport:
    """What :func:`clean` found and did.

    Attributes
    ----------
    artifacts : list of Artifact
        Every artifact found, sorted by start time and channel.
    n_input : int
        Number of samples (rows) of the record as read.
    n_output : int
        Number of samples on the uniform time grid after cleaning (inserted gap samples count,
        removed duplicates do not).
    dt_s : float
        Sampling interval of the grid [s]: median of the increasing time steps.
    stick_threshold_rad_s : float
        Bit speed at or below which the bit counted as stuck for the top-speed repair [rad/s].
    notes : list of str
        Explanations of the less obvious repairs (rows sorted into time order, artifact
        stretches replaced by the bit speed and the evidence for it).
    """
    artifacts: list = field(default_factory=list)
    n_input: int = 0
    n_output: int = 0
    dt_s: float = 0.0
    stick_threshold_rad_s: float = float("nan")
    notes: list = field(default_factory=list)

    def counts(self) -> dict:
        """Per kind: events, affected samples, repaired samples and excluded samples."""
        out = {}
        for k in KINDS:
            arts = [a for a in self.artifacts if a.kind == k]
            out[k] = {"events": len(arts), "samples": int(sum(a.samples for a in arts)),
                      "repaired_samples": int(sum(a.samples for a in arts if a.repaired)),
                      "excluded_samples": int(sum(a.samples for a in arts if not a.repaired))}
        return out

    def by_channel(self) -> dict:
        """Per channel and kind: number of events."""
        out: dict = {}
        for a in self.artifacts:
            out.setdefault(a.channel, {}).setdefault(a.kind, 0)
            out[a.channel][a.kind] += 1
        return out

    def summary(self) -> dict:
        """The report as a JSON-ready dict (stored in ``provenance["cleaning"]``).

        Returns
        -------
        dict
            ``n_input_samples``, ``n_output_samples``, ``dt_s``, ``stick_threshold_rad_s``,
            ``counts`` (:meth:`counts`), ``by_channel`` (:meth:`by_channel`), ``notes`` and
            ``artifacts`` (one dict per :class:`Artifact`).
        """
        return {"n_input_samples": self.n_input, "n_output_samples": self.n_output,
                "dt_s": self.dt_s, "stick_threshold_rad_s": self.stick_threshold_rad_s,
                "counts": self.counts(), "by_channel": self.by_channel(), "notes": list(self.notes),
                "artifacts": [asdict(a) for a in self.artifacts]}

    def lines(self) -> list:
        """Human-readable summary, one line per artifact kind that occurred."""
        out = []
        for k, c in self.counts().items():
            if c["events"]:
                out.append(f"{k}: {c['events']} event(s), {c['samples']} sample(s) "
                           f"({c['repaired_samples']} repaired, {c['excluded_samples']} excluded)")
        return out or ["no artifact found"]


def clean(record: Record, options: CleaningOptions | None = None) -> tuple[Record, CleaningReport]:
    """Detect, flag and (where sound) repair the artifacts of a record.

    Parameters
    ----------
    record : Record
        As read (any time stamps, NaNs allowed). Its arrays are not modified.
    options : CleaningOptions, optional
        Thresholds; default :class:`CleaningOptions` (the values tuned on the rig's 1 kHz
        records).

    Returns
    -------
    cleaned : Record
        On a uniform time grid, with per-sample flags; ``provenance["cleaning"]`` holds the report
        summary.
    report : CleaningReport
        Every artifact found, how it was repaired or excluded, and the counts.

    Raises
    ------
    ValueError
        If the time stamps cannot be placed on a uniform grid (e.g. a file made of concatenated
        pieces that overlap in time), there are fewer than 3 finite time stamps, the stamps span
        far more sampling intervals than the record has rows (:data:`MAX_GRID_FACTOR`), or a
        channel has no finite value at all (the error names it, and the record's source file when
        known).
    """
    opt = options or CleaningOptions()
    opt.validate()
    for name in record.channels:
        if not np.isfinite(getattr(record, name)).any():
            src = record.provenance.get("source", "record")
            col = record.provenance.get("variables", {}).get(name) or name
            raise ValueError(f"record = {src!r}: channel {name!r} ({col}) has no finite value (all "
                             f"{len(record)} samples NaN or missing); nothing to clean or analyse")
    rep = CleaningReport(n_input=len(record))
    # values near the float limit (1e308) overflow in differences and medians: the results are inf
    # and NaN, which the thresholds and flags handle, not warnings
    with np.errstate(over="ignore", invalid="ignore"):
        try:
            rec = _regrid(record, opt, rep)
        except ValueError as e:  # time stamps that cannot be placed: name the record they come from
            src = record.provenance.get("source")
            if src is None:
                raise
            raise ValueError(f"record = {src!r}: {e}") from None
        for name in rec.channels:
            _fill_missing(rec, name, opt, rep)
        rep.stick_threshold_rad_s = _stick_threshold(rec, opt)
        for name in rec.channels:
            _flatlines(rec, name, opt, rep)
        for name in rec.channels:
            if opt.spike_channels is None or name in opt.spike_channels:
                _spikes(rec, name, opt, rep)
    rep.n_output = len(rec)
    rep.artifacts.sort(key=lambda a: (a.start_s, a.channel))
    rec.provenance = dict(rec.provenance, cleaning=rep.summary())
    return rec, rep


# ------------------------------------------------------------------------------ time grid
def _regrid(record: Record, opt: CleaningOptions, rep: CleaningReport) -> Record:
    t = record.time_s
    fin = np.isfinite(t)
    if fin.sum() < 3:
        raise ValueError(f"time_s: only {int(fin.sum())} finite time stamp(s); need at least 3")
    d = np.diff(t[fin])
    pos = d[d > 0]
    if pos.size == 0:
        raise ValueError("time_s: the time stamps never increase")
    dt = float(f"{np.median(pos):.12g}")  # drop the rounding noise of the stamps
    rep.dt_s = dt
    lo, hi = float(np.min(t[fin])), float(np.max(t[fin]))
    steps = (hi - lo) / dt
    if not steps <= MAX_GRID_FACTOR * t.size + MAX_GRID_EXTRA:  # mostly invented samples (and memory)
        raise ValueError(f"time_s: the time stamps span {lo:g} to {hi:g} s, {steps:.3g} sampling intervals of "
                         f"{dt:g} s for {t.size} rows: a stamp far off the others, or pieces recorded far apart "
                         "(fix the stamps, or split the file)")
    t0 = float(t[fin][0])
    k = np.full(t.size, -1, dtype=np.int64)
    k[fin] = np.rint((t[fin] - t0) / dt).astype(np.int64)
    on_grid = fin & (np.abs(t - (t0 + k * dt)) <= opt.grid_tolerance * dt)
    rows = np.arange(t.size)
    data = {c: getattr(record, c) for c in record.channels}
    restamped = np.zeros(t.size, bool)
    # exact duplicates of the previous row (same stamp, same values) are removed and counted
    dup = np.r_[False, t[1:] == t[:-1]]
    for x in data.values():
        dup &= np.r_[False, (x[1:] == x[:-1]) | (np.isnan(x[1:]) & np.isnan(x[:-1]))]
    keep = ~dup
    for run in _runs(dup):
        rep.artifacts.append(Artifact("duplicate", "time", float(t[run[0]]), float(t[run[-1]]),
                                      len(run), "removed (exact duplicate of the previous row)"))

    good = on_grid & keep
    increasing = np.all(np.diff(k[good]) > 0) if good.sum() > 1 else True
    if good.sum() == keep.sum() and increasing:
        anchors = rows[keep]
    else:
        # Consistent rows: longest strictly increasing subsequence of the grid index among the
        # on-grid rows; every other kept row has a bad stamp.
        cand = rows[good]
        anchors = cand[_lis(k[cand])]
        is_anchor = np.zeros(t.size, bool)
        is_anchor[anchors] = True
        bad = rows[~is_anchor & keep]
        # rows logged out of order (e.g. two swapped rows): a stamp on the grid, on a slot no other
        # row holds and at most MAX_RESTAMP rows from where the acquisition order puts it, is
        # trusted: the row is sorted into its place by time (reported as an "order" artifact)
        taken = set(k[anchors].tolist())
        moved = []
        for b in bad:
            if not good[b] or int(k[b]) in taken:
                continue
            shift = np.searchsorted(k[anchors], k[b]) - np.searchsorted(anchors, b)
            if abs(shift) <= MAX_RESTAMP:
                taken.add(int(k[b]))
                moved.append(b)
        bad = np.setdiff1d(bad, moved)
        # place each run of bad stamps between its anchors, in acquisition order; when the anchors
        # leave too few grid slots (e.g. two swapped stamps), the neighbouring anchors are re-stamped
        # too, up to MAX_RESTAMP of them on each side
        kept_rows = rows[keep]
        for run in _split_consecutive(bad, keep):
            first, last = run[0], run[-1]
            for _ in range(MAX_RESTAMP + 1):
                lo = anchors[anchors < first]
                hi = anchors[anchors > last]
                if not (lo.size and hi.size):
                    break
                seg = kept_rows[(kept_rows >= first) & (kept_rows <= last)]
                if k[hi[0]] - k[lo[-1]] - 1 >= seg.size:
                    break
                first, last = lo[-1], hi[0]
            run = kept_rows[(kept_rows >= first) & (kept_rows <= last)]
            n = len(run)
            if lo.size and hi.size:
                klo, khi = k[lo[-1]], k[hi[0]]
                if khi - klo - 1 < n:
                    raise ValueError(
                        f"time_s: {n} sample(s) from row {run[0]} (t = {float(t[run[0]])!r} s) cannot be placed "
                        f"between t = {t[lo[-1]]:g} s and t = {t[hi[0]]:g} s: the time stamps go "
                        "backwards or repeat with different values (sort or fix the file)")
                k[run] = klo + 1 + np.arange(n)
            elif lo.size:
                k[run] = k[lo[-1]] + 1 + np.arange(n)
            elif hi.size:
                k[run] = k[hi[0]] - n + np.arange(n)
            else:  # re-stamping the neighbours swallowed every anchor: nothing left to place the rows by
                raise ValueError(
                    f"time_s: {n} sample(s) from row {run[0]} (t = {float(t[run[0]])!r} s) to row {run[-1]} cannot be "
                    "placed: the time stamps go backwards or repeat throughout (sort or fix the file)")
            restamped[run] = True
            rep.artifacts.append(Artifact(
                "time", "time", float(t0 + k[run[0]] * dt), float(t0 + k[run[-1]] * dt), n,
                "time stamp replaced by its place on the sampling grid (acquisition order kept)"))
    src_rows = rows[keep][np.argsort(k[keep], kind="stable")]
    ks = k[src_rows]
    if np.any(np.diff(ks) <= 0):  # the placement above leaves no repeat; guard against surprises
        raise ValueError(f"time_s: the time stamps cannot be placed on a uniform grid of {dt:g} s: off the grid by "
                         f"more than grid_tolerance = {opt.grid_tolerance:g} interval, or out of order (sort or fix "
                         "the file)")
    # rows whose place in time differs from their place in the file (sorted by time stamp above)
    out_of_order = src_rows != np.sort(src_rows)
    for run in _runs(out_of_order):
        lo, hi = int(src_rows[run].min()), int(src_rows[run].max())
        rep.artifacts.append(Artifact(
            "order", "time", float(t0 + ks[run[0]] * dt), float(t0 + ks[run[-1]] * dt), len(run),
            f"rows sorted by time stamp (file rows {lo}-{hi} were logged out of time order; stamps kept)"))
        rep.notes.append(f"time_s: file rows {lo}-{hi} were out of time order "
                         f"(t = {float(t0 + ks[run[0]] * dt):.6g}-{float(t0 + ks[run[-1]] * dt):.6g} s); "
                         "sorted by their time stamps")
        restamped[src_rows[run]] = True
    t0 += ks[0] * dt
    ks = ks - ks[0]
    n = int(ks[-1]) + 1
    grid = t0 + np.arange(n) * dt
    out = {}
    flags = {}
    for c, x in data.items():
        y = np.full(n, np.nan)
        y[ks] = x[src_rows]
        out[c] = y
        f = np.zeros(n, np.uint16)
        f[ks] = np.where(np.isfinite(x[src_rows]), 0, int(Flag.NONFINITE))
        flags[c] = f
    ft = np.full(n, int(Flag.GAP), np.uint16)
    ft[ks] = 0
    ft[ks[restamped[src_rows]]] |= int(Flag.TIME)
    flags["time"] = ft
    inserted = (ft & Flag.GAP) != 0
    for c in out:
        flags[c][inserted] |= int(Flag.GAP)
    nmax = _max_fill(opt, dt)
    for run in _runs(inserted):
        if run.size <= nmax and run[0] > 0 and run[-1] < n - 1:
            how = "samples inserted on the time grid; values linearly interpolated in every channel"
        else:
            how = ("none: samples inserted on the time grid and flagged UNRELIABLE (excluded; longer than "
                   f"max_fill_s = {opt.max_fill_s:g} s)")
        rep.artifacts.append(Artifact("gap", "time", float(grid[run[0]]), float(grid[run[-1]]), len(run), how))
    return Record(time_s=grid, **out, units=dict(record.units), provenance=dict(record.provenance),
                  flags=flags)


def _lis(x: np.ndarray) -> np.ndarray:
    """Indices of a longest strictly increasing subsequence of x (patience sorting)."""
    import bisect
    tails, tails_idx, prev = [], [], np.full(x.size, -1)
    for i, v in enumerate(x):
        j = bisect.bisect_left(tails, v)
        if j == len(tails):
            tails.append(v)
            tails_idx.append(i)
        else:
            tails[j] = v
            tails_idx[j] = i
        prev[i] = tails_idx[j - 1] if j > 0 else -1
    out = []
    i = tails_idx[-1] if tails_idx else -1
    while i >= 0:
        out.append(i)
        i = prev[i]
    return np.asarray(out[::-1], dtype=np.int64)


def _runs(mask: np.ndarray) -> list:
    """Index arrays of the runs of True in a boolean mask."""
    m = np.asarray(mask, bool)
    if not m.any():
        return []
    edges = np.flatnonzero(np.diff(np.r_[0, m.astype(np.int8), 0]))
    return [np.arange(a, b) for a, b in zip(edges[::2], edges[1::2])]


def _split_consecutive(idx: np.ndarray, keep: np.ndarray) -> list:
    """Split sorted row indices into runs of consecutive kept rows."""
    if idx.size == 0:
        return []
    kept_pos = np.cumsum(keep) - 1  # position among kept rows
    pos = kept_pos[idx]
    cuts = np.flatnonzero(np.diff(pos) != 1) + 1
    return [r for r in np.split(idx, cuts) if r.size]


# ------------------------------------------------------------------------------ missing values
def _fill_missing(rec: Record, name: str, opt: CleaningOptions, rep: CleaningReport) -> None:
    x = getattr(rec, name)
    fl = rec.flags[name]
    t = rec.time_s
    nmax = _max_fill(opt, rep.dt_s)
    for run in _runs(~np.isfinite(x)):
        a, b = run[0], run[-1]
        only_gap = bool(np.all(fl[run] & Flag.GAP))  # reported once, on the time channel
        inside = a > 0 and b < x.size - 1
        if inside and run.size <= nmax:
            x[run] = np.interp(t[run], [t[a - 1], t[b + 1]], [x[a - 1], x[b + 1]])
            fl[run] |= int(Flag.REPAIRED)
            how = "linear interpolation between the finite neighbours"
        else:
            fl[run] |= int(Flag.UNRELIABLE)
            why = "at the record's edge" if not inside else f"longer than max_fill_s = {opt.max_fill_s:g} s"
            how = f"none: flagged UNRELIABLE (excluded; {why})"
        if not only_gap:
            rep.artifacts.append(Artifact("nonfinite", name, float(t[a]), float(t[b]), run.size, how))


def _max_fill(opt: CleaningOptions, dt: float) -> int:
    return int(min(np.floor(opt.max_fill_s / dt + 1e-9), 2**62))  # bounded at a vanishing dt


def _stick_threshold(rec: Record, opt: CleaningOptions) -> float:
    if opt.stick_threshold_rad_s is not None:
        return float(opt.stick_threshold_rad_s)
    if rec.top_speed is not None and np.isfinite(rec.top_speed).any():
        return stick_threshold(rec.top_speed)
    if rec.bit_speed is not None and np.isfinite(rec.bit_speed).any():
        return STICK_FRACTION * float(np.nanpercentile(np.abs(rec.bit_speed), 95))
    return float("nan")


# ------------------------------------------------------------------------------ held values
def _flatlines(rec: Record, name: str, opt: CleaningOptions, rep: CleaningReport) -> None:
    """Flag UNRELIABLE the runs of one value held exactly for ``flatline_min_s`` or longer."""
    x = getattr(rec, name)
    nmin = max(int(np.ceil(opt.flatline_min_s / rep.dt_s - 1e-9)), 3) if opt.flatline_min_s > 0 else 0
    if nmin == 0 or x.size < nmin:
        return
    fl = rec.flags[name]
    same = np.isfinite(x[1:]) & (x[1:] == x[:-1])  # sample i+1 repeats sample i
    holds = [np.r_[r[0], r + 1] for r in _runs(same) if r.size + 1 >= nmin]
    if not holds:
        return
    held = np.zeros(x.size, bool)
    for h in holds:
        held[h] = True
    if held.mean() > 0.5:  # a set point (an ideal drive's speed, a constant WOB), not an artifact
        return
    outside = same & ~held[1:] & ~held[:-1]
    pairs = int(np.count_nonzero(~held[1:] & ~held[:-1] & np.isfinite(x[1:]) & np.isfinite(x[:-1])))
    if pairs and np.count_nonzero(outside) > opt.flatline_quantized_fraction * pairs:
        return  # quantized: holds happen in motion
    speed = name in ("bit_speed", "top_speed")
    thr = rep.stick_threshold_rad_s
    t = rec.time_s
    vb = rec.bit_speed
    for h in holds:
        v = float(x[h[0]])
        if speed and np.isfinite(thr) and abs(v) <= thr:
            continue  # a stuck bit (or a top at rest) held at zero: motion, not an artifact
        if name == "torque_on_bit" and vb is not None and np.isfinite(thr) \
                and np.mean(np.abs(vb[h]) <= thr) >= opt.stuck_fraction:
            continue  # a bit stuck under a stalled drive holds its torque (a noise-free simulation's stall)
        fl[h] |= int(Flag.FLATLINE | Flag.UNRELIABLE)
        rep.artifacts.append(Artifact(
            "flatline", name, float(t[h[0]]), float(t[h[-1]]), h.size,
            f"none: flagged UNRELIABLE (excluded; the value {v:.6g} held for {h.size} samples, "
            f"{h.size * rep.dt_s:.3g} s: a frozen, saturated or dropped-out sensor)"))


# ------------------------------------------------------------------------------ spikes
def spike_regions(x: np.ndarray, dt: float, opt: CleaningOptions | None = None) -> list:
    """Runs of samples (index arrays) that deviate from the running median like a spike.

    A core sample deviates by more than max(spike_sigmas x robust sigma, spike_min_fraction x
    1-99 % range) from the median over spike_window_s; each core is grown to the neighbouring
    samples deviating by more than a quarter of that threshold, then padded by ``spike_pad_s`` on
    each side (the rig's 10 Hz filter smears a spike). NaNs are ignored (interpolated for the
    median only). Only detects: :func:`clean` decides what is a spike and what an artifact stretch.

    Parameters
    ----------
    x : ndarray
        One channel on a uniform time grid (SI units; the thresholds are relative, so any unit).
    dt : float
        Sampling interval [s].
    opt : CleaningOptions, optional
        Uses ``spike_window_s``, ``spike_sigmas``, ``spike_min_fraction`` and ``spike_pad_s``;
        default :class:`CleaningOptions`.

    Returns
    -------
    list of ndarray
        Index arrays of the runs, in time order; empty when fewer than 3 samples are finite or
        nothing deviates.
    """
    opt = opt or CleaningOptions()
    x = np.asarray(x, float)
    fin = np.isfinite(x)
    if fin.sum() < 3:
        return []
    idx = np.arange(x.size)
    xf = np.where(fin, x, np.interp(idx, idx[fin], x[fin]))
    # a window (or pad) longer than the record is the record: bounds the cost at a vanishing dt
    w = max(3, int(round(min(opt.spike_window_s / dt, 2 * x.size + 1))) | 1)
    r = xf - ndimage.median_filter(xf, size=w, mode="nearest")
    sigma = 1.4826 * np.median(np.abs(r[fin]))
    lo, hi = np.percentile((xf - r)[fin], [1, 99])  # range of the running median: spikes do not widen it
    thr = max(opt.spike_sigmas * sigma, opt.spike_min_fraction * (hi - lo))
    if not thr > 0:
        return []
    core = (np.abs(r) > thr) & fin
    if not core.any():
        return []
    grown, _ = ndimage.label(np.abs(r) > 0.25 * thr)
    keep_labels = np.unique(grown[core])
    region = np.isin(grown, keep_labels[keep_labels > 0])
    # the acquisition filter smears a spike: take its tails too
    pad = int(round(min(opt.spike_pad_s / dt, x.size)))
    if pad:
        region = ndimage.binary_dilation(region, iterations=pad)
    return _runs(region)


def _spikes(rec: Record, name: str, opt: CleaningOptions, rep: CleaningReport) -> None:
    x = getattr(rec, name)
    fl = rec.flags[name]
    t = rec.time_s
    dt = rep.dt_s
    regions = spike_regions(x, dt, opt)
    if not regions:
        return
    # group spikes into clusters (artifact stretches)
    clusters, cur = [], [regions[0]]
    for r in regions[1:]:
        if (r[0] - cur[-1][-1]) * dt < opt.stretch_gap_s:
            cur.append(r)
        else:
            clusters.append(cur)
            cur = [r]
    clusters.append(cur)
    for cl in clusters:
        if len(cl) >= opt.stretch_min_spikes:
            _repair_stretch(rec, name, np.arange(cl[0][0], cl[-1][-1] + 1), len(cl), opt, rep)
            continue
        for r in cl:
            a, b = r[0], r[-1]
            fl[r] |= int(Flag.SPIKE)
            wide = r.size * dt > opt.spike_max_width_s
            edge = a == 0 or b == x.size - 1
            if wide or edge or not (np.isfinite(x[a - 1]) and np.isfinite(x[b + 1])):
                fl[r] |= int(Flag.UNRELIABLE)
                why = (f"wider than spike_max_width_s = {opt.spike_max_width_s:g} s" if wide
                       else "no finite neighbour on both sides")
                how = f"none: flagged UNRELIABLE (excluded; {why})"
            else:
                x[r] = np.interp(t[r], [t[a - 1], t[b + 1]], [x[a - 1], x[b + 1]])
                fl[r] |= int(Flag.REPAIRED)
                how = "linear interpolation across the spike"
            rep.artifacts.append(Artifact("spike", name, float(t[a]), float(t[b]), r.size, how))


def _repair_stretch(rec: Record, name: str, span: np.ndarray, nspikes: int, opt: CleaningOptions,
                    rep: CleaningReport) -> None:
    x = getattr(rec, name)
    fl = rec.flags[name]
    t = rec.time_s
    fl[span] |= int(Flag.OSCILLATION)
    thr = rep.stick_threshold_rad_s
    how = None
    if name == "top_speed" and rec.bit_speed is not None and np.isfinite(thr):
        vb = rec.bit_speed[span]
        ok = np.isfinite(vb) & ((rec.flags["bit_speed"][span] & Flag.UNRELIABLE) == 0)
        stuck = np.mean(ok & (np.abs(vb) <= thr))
        if stuck >= opt.stuck_fraction:
            x[span] = np.where(ok, vb, 0.0)
            fl[span] |= int(Flag.REPAIRED)
            how = (f"replaced by the bit speed: the bit is stuck over {100 * stuck:.0f} % of the stretch")
            if rec.torque_on_bit is not None:
                tq = rec.torque_on_bit[span]
                if np.isfinite(tq).any():
                    how += (f" and the torque on bit changes by only {np.nanmax(tq) - np.nanmin(tq):.3g} N m "
                            f"(mean {np.nanmean(tq):.3g} N m), so the string does not wind up and the "
                            "top drive is at rest")
            rep.notes.append(f"{name} artifact stretch {t[span[0]]:.3f}-{t[span[-1]]:.3f} s "
                             f"({nspikes} spikes): {how}")
    if how is None:
        fl[span] |= int(Flag.UNRELIABLE)
        how = "none: flagged UNRELIABLE (excluded; the bit is not stuck, the true value is unknown)"
    rep.artifacts.append(Artifact("oscillation", name, float(t[span[0]]), float(t[span[-1]]),
                                  span.size, how + f" [{nspikes} spikes]"))
