"""Statistics across samples, section 5.3 of the thesis (``drillpy analyze`` given several records).

Every sample (a record, or a window of one) goes through the single-record pipeline of
:func:`drillpy.records.analysis.compute_analysis` up to the identification: read
(:func:`drillpy.records.io.read_record`) -> clean (:func:`drillpy.records.cleaning.clean`) -> stick-slip
cycles, per-cycle statistics and the mean cycle (:mod:`drillpy.records.signals`) -> the laws fitted to
that sample alone (:func:`drillpy.records.identification.fit_laws`). Across samples it gives

* **Table 5.2**: per sample the mean, standard deviation (ddof = 1) and CV = std / mean of the
  measured torque on bit, and Var[MSE] of Eq. (5.2) between the sample's mean cycle (Eq. 4.3) and
  the regularized law Eq. (3.1) (``tucker_wang``) and the non-regularized law Eq. (5.1)
  (``polynomial``) fitted to the sample (:func:`drillpy.records.identification.mean_cycle_var_mse`);
* **Fig. 5.4**: a box plot of the per-cycle stick-slip severity SS (Eq. 3.4 over each cycle,
  :func:`drillpy.records.signals.cycle_statistics`), one box per sample. The per-cycle SS uses the
  reliable top-speed samples only: a cycle whose top speed was excluded by the cleaning or is an
  artifact stretch replaced by the bit speed (a stall, e.g. 28-29.6 s of sample 175) has no SS and
  is counted apart (isolated spikes interpolated by the cleaning are kept);
* **the acceptance criterion** of section 5.3.3 (:class:`Acceptance`);
* **the law parameters per sample** and their spread across samples (mean, std, CV of every
  fitted parameter; fixed parameters and parameters at a bound are named).

The acceptance criterion, as the thesis states it (section 5.3.3): "An acceptance criteria to
evaluate the samples, it can be spanned by the blend of CV average and the variation of concrete
properties. [...] an acceptance criteria of quality related to variation of concrete resistance is
10%. CV average of samples according to table 5.2 is 0.329 can be used, that means an acceptance
criteria equal to 43% of variation. Considering 39% of variation over the torque on bit values, an
acceptable value for Var[MSE] of regularized model is 47.93 and 0.26 for non-regularized model.
That means, the samples 14, 15, 16, 17, 18, 19 and 20 are acceptable for regularized and
non-regularized models. Therefore, 8 among 10 samples are acceptable [...], which is enough to
validate the test-rig results (bigger than 70%)".

What is implemented: a sample is accepted when its Var[MSE] is at or below the threshold of every
law (defaults 47.93 for Eq. 3.1 and 0.26 for Eq. 5.1; parameters); the set of samples validates
the rig when more than 70 % are accepted. The variation limit (CV average + concrete variation,
0.329 + 0.10 = 43 %) is reported, and each sample's CV is compared with it, but it does not decide
(``require_cv=True`` makes it decide): the thesis accepts samples 15 and 18 whose CVs are 0.66 and
0.59. The text does not say how 47.93 and 0.26 follow from the 39 %; they are taken as given.
Two inconsistencies of the thesis's own numbers, reproduced by :func:`thesis_table_5_2`: the
thresholds accept samples 13-20 (8 of 10, as the conclusion says), while the list names 14-20
(sample 13 has 20.86 and 0.0017, below both); and the CV average of Table 5.2 as printed is 0.411,
not 0.329 (sample 19's CV 0.3222 does not match its std/mean 0.2140/1.5059 = 0.142 either). The
default variation limit uses the thesis's stated 0.329.

Var[MSE] is in (N m)^4 of this record's torque; the thesis's thresholds come from its samples 11-20
(torques of 0.7-2.2 N m mean) and are only meaningful on comparable records.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from drillpy.records import identification as ident
from drillpy.records import signals as sig
from drillpy.records.cleaning import CleaningOptions, clean
from drillpy.records.io import RPM, Record, read_record
from drillpy.records.rigsim import reliable_top_speed, stick_threshold
from drillpy import validate
from drillpy.records.stick import STICK_FRACTION

#: Laws of Table 5.2: the regularized Eq. (3.1) and the non-regularized Eq. (5.1).
TABLE_LAWS = {"tucker_wang": "regularized (Eq. 3.1)", "polynomial": "non-regularized (Eq. 5.1)"}
#: Record files a folder argument is searched for.
RECORD_SUFFIXES = (".mat", ".csv")

#: Thesis Table 5.2 (samples 11-20): Var[MSE] regularized, Var[MSE] non-regularized, mean, std, CV.
THESIS_TABLE_5_2 = {
    11: (52.9938, 0.2725, 1.3812, 0.6430, 0.4656), 12: (58.0845, 1.8469, 0.7390, 0.5208, 0.7048),
    13: (20.8601, 0.0017, 1.8502, 0.5266, 0.2846), 14: (9.1219, 0.0072, 2.2292, 0.5144, 0.2307),
    15: (17.7767, 0.0109, 1.4754, 0.9759, 0.6615), 16: (0.0302, 0.0075, 1.9774, 0.5903, 0.2985),
    17: (8.2123, 0.0302, 1.6453, 0.5441, 0.3307), 18: (43.1178, 0.2388, 0.9307, 0.5450, 0.5856),
    19: (37.7625, 0.2410, 1.5059, 0.2140, 0.3222), 20: (27.8216, 0.0264, 1.9485, 0.4453, 0.2285),
}


@dataclass
class Acceptance:
    """The acceptance criterion of section 5.3.3 (defaults: the thesis's values).

    Attributes
    ----------
    max_var_mse : dict
        Law -> largest acceptable Var[MSE] (Eq. 5.2): 47.93 for the regularized Eq. (3.1), 0.26
        for the non-regularized Eq. (5.1).
    cv_reference : float or None
        CV average the variation limit starts from (thesis: 0.329 for its samples 11-20; None:
        the CV average of the samples analysed).
    concrete_variation : float
        Quality variation of the concrete resistance added to it (thesis: 10 %).
    min_accepted_fraction : float
        The samples validate the rig when more than this fraction is accepted (thesis: 70 %).
    require_cv : bool
        Also require CV <= the variation limit per sample (the thesis does not).
    """
    max_var_mse: dict = field(default_factory=lambda: {"tucker_wang": 47.93, "polynomial": 0.26})
    cv_reference: float | None = 0.329
    concrete_variation: float = 0.10
    min_accepted_fraction: float = 0.70
    require_cv: bool = False

    def validate(self) -> None:
        """Check the criterion (called by :meth:`evaluate` and :func:`analyze_samples`).

        Raises
        ------
        ValueError
            If ``max_var_mse`` is empty, names an unknown law or holds a non-positive threshold,
            a fraction lies outside [0, 1], or ``cv_reference`` is negative.
        """
        if not self.max_var_mse:
            raise ValueError("acceptance.max_var_mse: give at least one law's threshold")
        for law, v in self.max_var_mse.items():
            if law not in ident.LAWS:
                raise ValueError(f"acceptance.max_var_mse: unknown law {law!r} (use {', '.join(ident.LAWS)})")
            validate.positive(f"acceptance.max_var_mse[{law!r}]", v)
        for name in ("concrete_variation", "min_accepted_fraction"):
            validate.fraction(f"acceptance.{name}", getattr(self, name))
        if self.cv_reference is not None:
            validate.non_negative("acceptance.cv_reference", self.cv_reference)

    def evaluate(self, rows: list) -> dict:
        """Apply the criterion to Table 5.2 rows; returns the per-sample verdicts and the overall one.

        Parameters
        ----------
        rows : list of dict
            One per sample, with ``sample`` (name), ``cv`` (std / mean of the torque on bit) and
            ``var_mse`` (law -> Var[MSE] of Eq. 5.2 [(N m)^4]); a law missing from a row fails its
            threshold.

        Returns
        -------
        dict
            ``per_sample`` (``sample``, ``passes`` per law, ``cv_within_variation_limit``,
            ``accepted``), ``accepted`` and ``rejected`` (sample names), ``accepted_fraction``,
            ``validates`` (more than ``min_accepted_fraction`` accepted), the thresholds used
            (``max_var_mse``, ``cv_reference`` and its source, ``concrete_variation``,
            ``variation_limit``), ``cv_average`` of the rows, ``require_cv``,
            ``min_accepted_fraction`` and the ``rule`` in words.
        """
        self.validate()
        cvs = np.array([r["cv"] for r in rows], float)
        cv_avg = float(np.nanmean(cvs)) if np.isfinite(cvs).any() else float("nan")
        ref = cv_avg if self.cv_reference is None else float(self.cv_reference)
        limit = ref + self.concrete_variation
        per = []
        for r in rows:
            laws = {}
            for law, thr in self.max_var_mse.items():
                v = r["var_mse"].get(law, float("nan"))
                laws[law] = bool(np.isfinite(v) and v <= thr)
            cv_ok = bool(np.isfinite(r["cv"]) and r["cv"] <= limit)
            ok = all(laws.values()) and (cv_ok or not self.require_cv)
            per.append({"sample": r["sample"], "passes": laws, "cv_within_variation_limit": cv_ok, "accepted": ok})
        acc = [p["sample"] for p in per if p["accepted"]]
        frac = len(acc) / len(per) if per else float("nan")
        return {"max_var_mse": dict(self.max_var_mse), "cv_reference": ref,
                "cv_reference_source": "thesis Table 5.2 (as stated in the text)" if self.cv_reference is not None
                else "the CV average of these samples",
                "concrete_variation": self.concrete_variation, "variation_limit": limit,
                "cv_average": cv_avg, "require_cv": self.require_cv, "per_sample": per, "accepted": acc,
                "rejected": [p["sample"] for p in per if not p["accepted"]], "accepted_fraction": frac,
                "min_accepted_fraction": self.min_accepted_fraction,
                "validates": bool(per) and frac > self.min_accepted_fraction,
                "rule": ("a sample is accepted when Var[MSE] (Eq. 5.2) <= the threshold for every law"
                         + (" and its CV <= the variation limit" if self.require_cv else
                            "; its CV is compared with the variation limit (CV average + concrete variation) "
                            "but does not decide, as in the thesis")
                         + f"; the samples validate the rig when more than {100 * self.min_accepted_fraction:.0f} % "
                           "are accepted (section 5.3.3)")}


def thesis_table_5_2() -> list:
    """The thesis's Table 5.2 as rows for :meth:`Acceptance.evaluate`."""
    return [{"sample": str(k), "var_mse": {"tucker_wang": v[0], "polynomial": v[1]}, "mean": v[2], "std": v[3],
             "cv": v[4]} for k, v in THESIS_TABLE_5_2.items()]


@dataclass
class SampleOptions:
    """Choices of :func:`analyze_samples` (as :class:`drillpy.records.analysis.AnalysisOptions`).

    Attributes
    ----------
    t0, t1 : float, optional
        Window analysed in every record [s].
    stick_fraction : float
        The bit is stuck at or below this fraction of the median reliable top speed.
    laws : tuple
        Laws fitted to each sample; Table 5.2 uses ``tucker_wang`` and ``polynomial``.
    folds : int
        Cross-validation folds over cycles (0: none; Table 5.2 does not need them).
    fit_rate_hz : float
        Samples used by the fits per second.
    speed_unit : str
        Unit the law parameters refer to (``rpm`` or ``rad_s``).
    acceptance : Acceptance
        The criterion of section 5.3.3.
    """
    t0: float | None = None
    t1: float | None = None
    stick_fraction: float = STICK_FRACTION
    laws: tuple = tuple(TABLE_LAWS)
    folds: int = 0
    fit_rate_hz: float = 100.0
    speed_unit: str = "rpm"
    acceptance: Acceptance = field(default_factory=Acceptance)


def parse_window(text: str, name: str = "window") -> tuple:
    """'T0:T1' [s] -> (t0, t1) with t0 < t1 (a sample's window ``FILE@T0:T1``, an option such as
    ``--calibrate T0:T1``).

    Parameters
    ----------
    text : str
        The window, e.g. ``"0:10"`` (the part after ``@`` in ``sample.mat@0:10``).
    name : str
        What the error names, e.g. ``"--calibrate"``.

    Returns
    -------
    tuple of float
        ``(t0, t1)`` [s].

    Raises
    ------
    ValueError
        ``"<name> = '<text>': use T0:T1 [s] ..."`` if the text is not two numbers separated by ``:``,
        ``"...: needs finite T0 < T1 [s]"`` if they are not finite with T0 < T1.
    """
    try:
        a, b = (float(x) for x in text.split(":"))
    except ValueError:
        raise ValueError(f"{name} = {text!r}: use T0:T1 [s], e.g. 0:10" + (" (or sample.mat@0:10)" if name == "window" else
                                                                           "")) from None
    if not (math.isfinite(a) and math.isfinite(b) and a < b):
        raise ValueError(f"{name} = {text!r}: needs finite T0 < T1 [s]")
    return a, b


def find_records(paths) -> list:
    """Expand the arguments into samples ``(name, path, window)``.

    A file is one sample; a folder gives its .mat/.csv files (sorted by name); ``FILE@T0:T1`` is
    the window T0 <= t < T1 [s] of a file (so ``rec.mat@0:10 rec.mat@10:20`` share no sample).
    A path that exists as written is never split at ``@``.

    Parameters
    ----------
    paths : iterable of str or Path
        Files, folders or ``FILE@T0:T1`` windows (the command-line arguments).

    Returns
    -------
    list of tuple
        ``(name, path, window)``: the file stem (``stem@T0-T1s`` for a window), the
        :class:`~pathlib.Path`, and ``(t0, t1)`` [s] or None.

    Raises
    ------
    ValueError
        For a missing path, a bad window, a window on a folder or a folder without records.
    """
    out = []
    for a in paths:
        a = str(a)
        window = None
        if "@" in a and not Path(a).exists():
            a, w = a.rsplit("@", 1)
            window = parse_window(w)
        p = Path(a)
        if p.is_dir():
            if window is not None:
                raise ValueError(f"record = {a!r}: a window applies to a file, not a folder")
            found = sorted(q for q in p.iterdir() if q.is_file() and q.suffix.lower() in RECORD_SUFFIXES)
            if not found:
                raise ValueError(f"record folder = {str(p)!r}: holds no .mat or .csv file")
            out += [(q.stem, q, None) for q in found]
        elif p.is_file():
            name = p.stem if window is None else f"{p.stem}@{window[0]:g}-{window[1]:g}s"
            out.append((name, p, window))
        else:
            raise ValueError(f"record = {str(p)!r}: no such file or folder")
    return out


def _unique(names) -> list:
    """Names suffixed with #k when repeated."""
    out, seen = [], {}
    for b in names:
        seen[b] = seen.get(b, 0) + 1
        out.append(b if names.count(b) == 1 else f"{b}#{seen[b]}")
    return out


def analyze_sample(record: Record | str | Path, name: str, options: SampleOptions | None = None,
                   window: tuple | None = None) -> dict:
    """The per-sample part: Table 5.2 row, per-cycle SS and the fitted laws of one record.

    Read (if a path), window, clean, segment the stick-slip cycles (stick threshold:
    ``options.stick_fraction`` of the median reliable top speed, or the cleaning's threshold
    without a reliable top speed), mean cycle, fit ``options.laws`` on the slip samples at
    ``options.fit_rate_hz`` and compute Var[MSE] (Eq. 5.2) on the mean cycle above the stick
    threshold.

    Parameters
    ----------
    record : Record, str or Path
        The record or its file; it needs bit speed and torque on bit.
    name : str
        Sample name used in the tables and messages.
    options : SampleOptions, optional
        Default :class:`SampleOptions`.
    window : tuple of float, optional
        ``(t0, t1)`` [s]: the samples t0 <= t < t1; None: ``options.t0``/``t1``, both inclusive
        (or the whole record).

    Returns
    -------
    dict
        ``sample``, ``source``, ``window_s``, ``n_samples``, ``sample_rate_hz``, ``cleaning``,
        ``stick_threshold_rpm``, ``torque`` (:func:`drillpy.records.signals.sample_statistics` of
        the torque on bit [N m]) with its ``mean``/``std``/``cv`` repeated at top level, ``var_mse``
        (law -> [(N m)^4]), ``cycles`` (counts, median period [s], per-cycle ``ss`` over cycles
        with a reliable top speed, their median and mean), ``mean_top_speed_rpm``,
        ``mean_bit_speed_rpm``, ``stick_fraction`` and ``fits`` (per law: ``equation``,
        ``parameters``, ``ci95``, ``fixed``, ``at_bound``, ``rmse_nm``, ``r2``, ``n``, ``n_cycles``,
        ``engine_law``).

    Raises
    ------
    ValueError
        If a needed channel is missing, the window holds no sample, or no valid stick-slip cycle
        is found (and for the errors of reading, cleaning and fitting).
    """
    opt = options or SampleOptions()
    raw = read_record(record) if isinstance(record, (str, Path)) else record
    src = raw.provenance.get("source", name)
    for need in ("bit_speed", "torque_on_bit"):
        raw.channel(need)
    if window is not None:
        idx = np.flatnonzero((raw.time_s >= window[0]) & (raw.time_s < window[1]))
        if idx.size == 0:
            raise ValueError(f"window {window[0]:g}:{window[1]:g} s: no sample (the record spans "
                             f"{np.nanmin(raw.time_s):g} to {np.nanmax(raw.time_s):g} s)")
        raw = raw.take(idx)
    elif opt.t0 is not None or opt.t1 is not None:
        raw = raw.select(opt.t0, opt.t1)
    rec, rep = clean(raw, CleaningOptions())
    top_ok = None  # reliable top-speed samples: not excluded, not an artifact stretch replaced by the bit speed
    if rec.top_speed is not None:
        top_ok = reliable_top_speed(rec)
    if top_ok is not None and top_ok.any():
        thr = stick_threshold(rec, opt.stick_fraction)
    else:
        thr = rep.stick_threshold_rad_s
    v, tq = rec.bit_speed, rec.torque_on_bit
    ok = rec.valid("bit_speed", "torque_on_bit")
    cyc = sig.segment_cycles(v, rec.dt, thr, valid=ok)
    if not cyc.valid.any():
        raise ValueError(f"sample {name!r} ({src}): no valid stick-slip cycle (no bit-speed peak with a "
                         "prominence of 25 % of its range, or excluded samples everywhere)")
    acc = sig.derivative(np.where(np.isfinite(v), v, 0.0), rec.dt)
    lab = cyc.branch_labels(len(rec))
    cid = cyc.cycle_id(len(rec))
    # per-cycle SS on reliable top-speed samples only (repaired ones -> NaN -> no SS for that cycle)
    top_rel = None if top_ok is None else np.where(top_ok, rec.top_speed, np.nan)
    cst = sig.cycle_statistics(cyc, v, top_rel, tq, rec.wob)
    ss = cst.get("ss", np.zeros(0))
    ss_ok = ss[np.isfinite(ss)]
    stats = sig.sample_statistics(tq[ok])
    mc = sig.mean_cycle(v, tq, acc, lab)
    every = max(1, int(round(rec.sample_rate_hz / opt.fit_rate_hz)))
    data = ident.FitData.from_arrays(v, acc, tq, lab, cid, wob=rec.wob, use_wob=False, every=every, cycles=cyc)
    fits = ident.fit_laws(data, opt.laws, mc=mc, folds=opt.folds, speed_unit=opt.speed_unit, stick_threshold=thr)
    var = {}
    for f in fits:
        vm = f.var_mse
        if not (isinstance(vm, float) and math.isfinite(vm)):
            vm = ident.mean_cycle_var_mse(f, mc, thr)
        var[f.name] = float(vm)
    top_mean = float(np.mean(rec.top_speed[top_ok & ok])) if top_rel is not None and (top_ok & ok).any() \
        else float("nan")
    return {
        "sample": name, "source": src, "window_s": [float(rec.time_s[0]), float(rec.time_s[-1])],
        "n_samples": len(rec), "sample_rate_hz": rec.sample_rate_hz,
        "cleaning": {"lines": rep.lines(), "counts": rep.counts()},
        "stick_threshold_rpm": thr * RPM,
        "torque": stats, "mean": stats["mean"], "std": stats["std"], "cv": stats["cv"], "var_mse": var,
        "cycles": {"n_found": len(cyc), "n_valid": int(cyc.valid.sum()), "n_with_ss": int(ss_ok.size),
                   "n_without_reliable_top_speed": int(ss.size - ss_ok.size),
                   "period_s_median": float(np.median(cst["period_s"])),
                   "ss": ss_ok.tolist(),
                   "ss_median": float(np.median(ss_ok)) if ss_ok.size else float("nan"),
                   "ss_mean": float(np.mean(ss_ok)) if ss_ok.size else float("nan")},
        "mean_top_speed_rpm": top_mean * RPM,
        "mean_bit_speed_rpm": float(np.mean(v[ok])) * RPM,
        "stick_fraction": float(np.mean(v[ok] <= thr)),
        "fits": {f.name: {"equation": ident.EQUATIONS[f.name],
                          "parameters": {n: float(x) for n, x in zip(f.names, f.values)},
                          "ci95": {n: [float(lo), float(hi)] for n, lo, hi in zip(f.names, f.ci_low, f.ci_high)},
                          "fixed": dict(f.fixed), "at_bound": list(f.at_bound), "rmse_nm": f.rmse, "r2": f.r2,
                          "n": f.n, "n_cycles": f.n_clusters, "engine_law": f.law} for f in fits},
    }


def parameter_spread(samples: list) -> dict:
    """Per law and parameter: the value in each sample and the mean, std (ddof = 1) and CV across
    samples; parameters at a bound in some sample and fixed parameters are named.

    Parameters
    ----------
    samples : list of dict
        :func:`analyze_sample` results, all with the same laws (the first sample's laws and
        parameter names are used).

    Returns
    -------
    dict
        Law -> ``equation``, ``fixed`` (the first sample's fixed parameters) and ``parameters``
        (name -> ``unit``, ``values`` per sample, ``mean``, ``std``, ``cv`` = std / |mean| and
        ``at_bound_in``: the samples where it ended on a bound). Empty for no sample.
    """
    out = {}
    laws = [law for law in samples[0]["fits"]] if samples else []
    for law in laws:
        names = list(samples[0]["fits"][law]["parameters"])
        block = {"equation": ident.EQUATIONS[law], "fixed": samples[0]["fits"][law]["fixed"], "parameters": {}}
        for nm in names:
            x = np.array([s["fits"][law]["parameters"][nm] for s in samples], float)
            m = float(np.mean(x))
            sd = float(np.std(x, ddof=1)) if x.size > 1 else float("nan")
            block["parameters"][nm] = {
                "unit": ident.PARAM_UNITS.get(nm, ""), "values": x.tolist(), "mean": m, "std": sd,
                "cv": sd / abs(m) if m != 0 and math.isfinite(sd) else float("nan"),
                "at_bound_in": [s["sample"] for s in samples if nm in s["fits"][law]["at_bound"]]}
        out[law] = block
    return out


def compute_samples(records, options: SampleOptions | None = None, log=print) -> dict:
    """Section 5.3 across samples, computed (nothing drawn or written; :func:`drillpy.reports.samples.analyze_samples`
    writes ``samples.json``, ``samples.md`` and ``fig5_4_boxplot.png``).

    Parameters
    ----------
    records : list
        Paths (files, folders of .mat/.csv records, or ``FILE@T0:T1`` windows, see
        :func:`find_records`), :class:`Record` objects, or ``(name, record)`` pairs; at least two
        samples.
    options : SampleOptions, optional
        Window, stick fraction, laws, folds, fit rate, speed unit and acceptance criterion;
        default :class:`SampleOptions` (the thesis's Table 5.2 laws and thresholds).
    log : callable
        Progress lines (``print`` by default).

    Returns
    -------
    dict
        The content of ``samples.json`` but for ``figures``.

    Raises
    ------
    ValueError
        With fewer than two samples, an acceptance threshold for a law that is not fitted, an
        invalid criterion, or a sample that cannot be analysed (the message names it).
    """
    opt = options or SampleOptions()
    opt.acceptance.validate()
    items = []  # (name, path or Record, window)
    for r in records:
        if isinstance(r, (str, Path)):
            items += find_records([r])
        elif isinstance(r, Record):
            items.append((Path(str(r.provenance.get("source", "record"))).stem or "record", r, None))
        elif isinstance(r, tuple) and len(r) == 2 and isinstance(r[1], (Record, str, Path)):
            items.append((str(r[0]), r[1], None))
        else:
            raise ValueError(f"records: {type(r).__name__} is not a path, a Record or a (name, record) pair")
    if len(items) < 2:
        raise ValueError(f"analyze_samples: {len(items)} record(s); the statistics across samples need at least 2 "
                         "(use drillpy.reports.analysis.analyze_record for one)")
    for law in opt.acceptance.max_var_mse:
        if law not in opt.laws:
            raise ValueError(f"acceptance threshold for law {law!r}, which is not fitted (laws: {', '.join(opt.laws)})")
    names = _unique([it[0] for it in items])
    samples = []
    for name, (_, rec, window) in zip(names, items):
        try:
            s = analyze_sample(rec, name, opt, window=window)
        except ValueError as e:
            raise ValueError(f"sample {name!r}: {e}") from None
        samples.append(s)
        log(f"{name}: torque mean {s['mean']:.4f} N m, std {s['std']:.4f}, CV {s['cv']:.4f}; "
            + ", ".join(f"Var[MSE] {law} {v:.4g}" for law, v in s["var_mse"].items())
            + f"; {s['cycles']['n_with_ss']} cycles with SS, median {s['cycles']['ss_median']:.3f}")
    table = [{"sample": s["sample"], "var_mse": s["var_mse"], "mean": s["mean"], "std": s["std"], "cv": s["cv"],
              "n": s["torque"]["n"], "ss_median": s["cycles"]["ss_median"], "n_cycles_ss": s["cycles"]["n_with_ss"],
              "mean_top_speed_rpm": s["mean_top_speed_rpm"]} for s in samples]
    acc = opt.acceptance.evaluate(table)
    cv = np.array([r["cv"] for r in table])
    mean = np.array([r["mean"] for r in table])
    S = {"n_samples": len(samples), "laws": {k: TABLE_LAWS.get(k, ident.EQUATIONS[k]) for k in opt.laws},
         "window_s": [opt.t0, opt.t1], "speed_unit": opt.speed_unit,
         "table_5_2": table,
         "across_samples": {"torque_mean": _spread(mean), "torque_cv": _spread(cv),
                            "var_mse": {law: _spread([r["var_mse"][law] for r in table]) for law in opt.laws},
                            "ss_median": _spread([r["ss_median"] for r in table])},
         "acceptance": acc, "parameters": parameter_spread(samples), "samples": samples,
         "thesis_table_5_2": {"rows": thesis_table_5_2(),
                              "acceptance_with_these_thresholds": opt.acceptance.evaluate(thesis_table_5_2())},
         "method": ("per sample: read, clean, cycles (stick at "
                    f"{opt.stick_fraction:g} x median reliable top speed), mean cycle, laws fitted on the slip "
                    "samples of that sample's valid cycles (drillpy.records.identification.fit_laws), Var[MSE] Eq. (5.2) "
                    "on its mean cycle; per-cycle SS Eq. (3.4) over cycles with a reliable top speed")}
    return S


def _spread(x) -> dict:
    x = np.asarray(x, float)
    x = x[np.isfinite(x)]
    if x.size == 0:
        return {"n": 0}
    m = float(np.mean(x))
    sd = float(np.std(x, ddof=1)) if x.size > 1 else float("nan")
    return {"n": int(x.size), "mean": m, "std": sd, "cv": sd / abs(m) if m != 0 and math.isfinite(sd) else float("nan"),
            "min": float(np.min(x)), "max": float(np.max(x))}
