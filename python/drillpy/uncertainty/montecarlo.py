"""Monte Carlo analysis of the stochastic drill-string model (thesis section 4.2, appendix C).

One call runs a study in the C++ engine (OpenMP, GIL released, tqdm progress bar, Ctrl-C stops it)
and returns arrays:

* :func:`stochastic_study` -- SS (Eq. 3.4) of ``samples`` realizations of eta at every top speed,
  with the mean, the 5 %-95 % band, P(SS > 0.5), the lowest speed from which P(SS > 0.5) <= 5 %
  (Fig. 4.9), the deterministic curve (Fig. 4.8) and Conv1(n_s) (Eq. C.1, Fig. C.1).
* :func:`merge_studies` -- one study from chunks run apart (``drillpy mc-merge``), bit-identical
  to the study run at once (:func:`study_from_samples` computes the statistics for both).
* :func:`phase_study` -- stick and slip durations over many cycles at one top speed (Fig. 4.7),
  next to the deterministic periodic values (section 4.2.1).

Sample ``i`` depends only on ``(seed, i)``: any thread count and any split of the sample range
(``first_sample``) give bit-identical rows.

Durations. Every run starts from the deterministic state reached after ``warmup`` seconds from
Eq. (2.10) at the same top speed (shared by all samples), then runs ``duration`` seconds with
T_sto = T_hys (1 + eta(t)) (Eq. 4.1), of which the first ``transient`` seconds are discarded.
The defaults (``WARMUP_S``, ``DURATION_S``, ``TRANSIENT_S``) and the evidence that they do not
change the statistics materially are in docs/stochastic.md.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from drillpy import _core, validate
from drillpy.model.config import engine_config, with_overrides
from drillpy.model.configuration import Configuration
from drillpy.uncertainty.process import THESIS_PSD, Psd, psd_on_grid
from drillpy.progress import progress_bar

WARMUP_S = 100.0     #: deterministic start-up shared by all samples [s]
DURATION_S = 60.0    #: stochastic part of every run [s]
TRANSIENT_S = 20.0   #: discarded at the start of the stochastic part [s] (40-s SS window)
ETA_DT_S = 0.05      #: sampling step of eta (Nyquist 10 Hz; S above it < 0.02 % of the variance)
SS_LEVEL = 0.5       #: stick-slip threshold on SS (section 3.3)
P_LEVEL = 0.05       #: probability level of the robust speed (section 4.2.2)
MAX_SAMPLES = 10_000_000


@dataclass
class StochasticStudy:
    """Result of :func:`stochastic_study`: SS (Eq. 3.4) of every sample at every top speed and
    its statistics (Fig. 4.9), the deterministic curve (Fig. 4.8) and Conv1 (Eq. C.1, Fig. C.1).

    Attributes
    ----------
    speeds : numpy.ndarray
        Top speeds [rad/s], in the order given, shape (n_speeds,).
    severity : numpy.ndarray
        SS_i(speed) [-], shape (samples, n_speeds); row r is sample ``first_sample + r``.
    mean : numpy.ndarray
        Mean SS per speed [-].
    q05, q95 : numpy.ndarray
        5 % and 95 % sample quantiles of SS per speed [-] (linear interpolation): the 90 % band.
    p_exceed : numpy.ndarray
        P(SS > 0.5) per speed (fraction of samples; ``SS_LEVEL``).
    p05_speed : float or None
        The robust speed [rad/s]: the lowest speed from which P(SS > 0.5) <= 5 % (where P last
        crosses 0.05 going up in speed, linear interpolation; thesis 20.5 rad/s); None without
        a crossing on the grid.
    deterministic : numpy.ndarray or None
        SS with eta = 0 and the same durations per speed [-] (None with ``deterministic=False``).
    deterministic_threshold : float or None
        Speed [rad/s] where the deterministic SS last crosses 0.5 going up (thesis 16 rad/s);
        None without a crossing or without the deterministic run.
    conv1 : numpy.ndarray
        Conv1(n_s) of Eq. (C.1) for n_s = 1 .. samples [sqrt(rad/s)]; NaN with a single speed.
    seed : int
        Random seed of the study.
    first_sample : int
        Index of the first sample run.
    eta_std : float
        Standard deviation of the generated eta [-] (square root of the process variance on the
        generator's grid).
    settings : dict
        Durations and PSD actually used: ``warmup_s``, ``duration_s``, ``transient_s``, ``dt_s``,
        ``eta_dt_s`` [s], ``psd`` and ``psd_convention``.
    config : dict
        The configuration run (the input one with the study's duration and transient).
    """
    speeds: np.ndarray
    severity: np.ndarray            #: SS_i(speed), shape (samples, speeds)
    mean: np.ndarray
    q05: np.ndarray
    q95: np.ndarray
    p_exceed: np.ndarray            #: P(SS > 0.5) per speed
    p05_speed: float | None         #: lowest speed from which P(SS > 0.5) <= 5 % (None: no crossing)
    deterministic: np.ndarray | None  #: SS with eta = 0 and the same durations
    deterministic_threshold: float | None
    conv1: np.ndarray               #: Conv1(n_s), n_s = 1 .. samples (Eq. C.1)
    seed: int
    first_sample: int
    eta_std: float                  #: standard deviation of the generated eta
    settings: dict = field(default_factory=dict)
    config: dict = field(repr=False, default_factory=dict)

    def summary(self) -> dict:
        """JSON-ready per-speed statistics (what ``drillpy mc --json`` prints).

        Returns
        -------
        dict
            The preset name, sample count, seed, first sample, :attr:`settings`, ``eta_std``,
            one row per speed (``top_speed_rad_s``, ``mean_ss``, ``q05``, ``q95``,
            ``p_ss_gt_0_5`` with its 90 % Wilson interval over the samples ``p_ss_gt_0_5_wilson90`` and,
            if computed, ``deterministic_ss``), ``p05_speed_rad_s``,
            ``deterministic_threshold_rad_s`` and ``conv1_final`` (Conv1 at the last sample).
        """
        from drillpy.uncertainty.binomial import wilson_interval
        low, high = wilson_interval(np.clip(self.p_exceed, 0.0, 1.0), int(self.severity.shape[0]))
        rows = [{"top_speed_rad_s": float(s), "mean_ss": float(m), "q05": float(a), "q95": float(b),
                 "p_ss_gt_0_5": float(p), "p_ss_gt_0_5_wilson90": [float(lo), float(hi)]}
                for s, m, a, b, p, lo, hi in zip(self.speeds, self.mean, self.q05, self.q95, self.p_exceed, low, high)]
        if self.deterministic is not None:
            for r, d in zip(rows, self.deterministic):
                r["deterministic_ss"] = float(d)
        return {"preset": self.config.get("name"), "samples": int(self.severity.shape[0]),
                "seed": self.seed, "first_sample": self.first_sample, **self.settings,
                "eta_std": self.eta_std, "speeds": rows, "p05_speed_rad_s": self.p05_speed,
                "deterministic_threshold_rad_s": self.deterministic_threshold,
                "conv1_final": float(self.conv1[-1])}

    def samples_dict(self) -> dict:
        """Everything needed to rebuild the study exactly (``mc_samples.json``; see :meth:`from_samples_dict`).

        Returns
        -------
        dict
            ``speeds_rad_s``, ``severity`` (one list per sample), ``deterministic_ss``, ``seed``,
            ``first_sample``, ``eta_std``, ``settings`` and ``config``; floats written by ``json``
            round-trip exactly.
        """
        return {"speeds_rad_s": self.speeds.tolist(), "first_sample": self.first_sample, "seed": self.seed,
                "eta_std": self.eta_std, "settings": self.settings, "config": self.config,
                "deterministic_ss": None if self.deterministic is None else self.deterministic.tolist(),
                "severity": self.severity.tolist()}

    @classmethod
    def from_samples_dict(cls, d: dict) -> "StochasticStudy":
        """Rebuild a study from :meth:`samples_dict`, recomputing its statistics.

        Parameters
        ----------
        d : dict
            What :meth:`samples_dict` returned (or ``mc_samples.json`` read back).

        Returns
        -------
        StochasticStudy
            The study, bit-identical to the one written.

        Raises
        ------
        ValueError
            Naming a missing key or a severity table whose shape does not match the speeds.
        """
        keys = ("speeds_rad_s", "first_sample", "seed", "eta_std", "settings", "config", "deterministic_ss",
                "severity")
        missing = [k for k in keys if k not in d]
        if missing:
            raise ValueError(f"{missing[0]}: missing from the samples file (keys: {', '.join(keys)})")
        sp = np.asarray(d["speeds_rad_s"], dtype=float)
        ss = np.asarray(d["severity"], dtype=float)
        if ss.ndim != 2 or ss.shape[1] != sp.size or ss.shape[0] == 0:
            raise ValueError(f"severity: shape {ss.shape} does not match {sp.size} speeds (samples x speeds)")
        return study_from_samples(sp, ss, deterministic=d["deterministic_ss"], seed=d["seed"],
                                  first_sample=d["first_sample"], eta_std=d["eta_std"], settings=d["settings"],
                                  config=d["config"])


@dataclass
class PhaseStudy:
    """Result of :func:`phase_study`: stick and slip durations [s] pooled over samples (Fig. 4.7).

    Attributes
    ----------
    speed : float
        The top speed [rad/s].
    stick, slip : numpy.ndarray
        Durations [s] of every stick and every slip phase after the transient, pooled over the
        samples in index order.
    samples : int
        Number of samples run (a multiple of the batch size).
    severity : numpy.ndarray
        SS (Eq. 3.4) of each sample at ``speed`` [-], shape (samples,).
    deterministic_stick, deterministic_slip : numpy.ndarray
        Stick and slip durations [s] of one period of the deterministic (eta = 0) cycle, or of its
        last three cycles if it is not periodic within the tolerance.
    deterministic_period_cycles : int
        Number of stick-slip cycles in the deterministic period (0: no period found).
    seed : int
        Random seed of the study.
    """
    speed: float
    stick: np.ndarray
    slip: np.ndarray
    samples: int
    severity: np.ndarray
    deterministic_stick: np.ndarray
    deterministic_slip: np.ndarray
    deterministic_period_cycles: int
    seed: int


def study_config(cfg: dict, duration: float, transient: float) -> dict:
    """The configuration of a study's runs: ``cfg`` with the stochastic part's durations.

    Parameters
    ----------
    cfg : dict
        The configuration.
    duration : float
        Stochastic part of every run [s] (> 0).
    transient : float
        Discarded at its start before SS [s].

    Returns
    -------
    dict
        A normalized copy with ``simulation.duration_s`` and ``transient_s`` set.
    """
    return with_overrides(cfg, duration=validate.positive("duration_s", duration),
                          transient=float(transient))


def default_warmup(cfg: dict) -> float:
    """The warm start a study takes when none is given [s]: :data:`WARMUP_S`, or 0 for the
    axial-torsional model (``axial.type = rgd``), whose runs start in RGD's steady drilling (a warm
    start of that model is not implemented: the engine refuses another value).

    Parameters
    ----------
    cfg : dict
        The study's configuration.
    """
    return 0.0 if Configuration.of(cfg).axial.type == "rgd" else WARMUP_S


def study_engine(cfg: dict, psd: Psd, eta_dt: float, seed: int, warmup: float) -> "_core.MonteCarlo":
    """The engine of a chapter-4 study: eta of PSD ``psd`` on the study's grid, the warm start.

    Parameters
    ----------
    cfg : dict
        The study's configuration (:func:`study_config`).
    psd : PsdModel, PsdTable or callable
        One-sided PSD of eta per Hz [1/Hz].
    eta_dt : float
        Sampling step of eta [s].
    seed : int
        Seed of the realizations.
    warmup : float
        Deterministic start-up shared by all samples [s].

    Returns
    -------
    _core.MonteCarlo
        Its ``severity``/``severity_and_bit_speed`` run samples by index (common random numbers).
    """
    _, S = psd_on_grid(psd, eta_dt, Configuration.of(cfg).simulation.duration_s)
    return _core.MonteCarlo(engine_config(cfg), S, float(eta_dt), seed, float(warmup))


def speed_grid(speeds) -> np.ndarray:
    """The top-speed grid of a study, checked.

    Parameters
    ----------
    speeds : array_like
        Top-drive speeds [rad/s].

    Returns
    -------
    numpy.ndarray
        ``speeds`` as a 1-d float array.

    Raises
    ------
    ValueError
        For an empty grid, or a speed that is not a positive finite number.
    """
    a = np.atleast_1d(np.asarray(speeds, dtype=float))
    if a.ndim != 1 or a.size == 0:
        raise ValueError(f"speeds = {speeds!r}: the speed grid is empty (give at least one top speed)")
    if not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise ValueError(f"speeds = {speeds!r}: top speeds must be positive finite numbers [rad/s]")
    return a


def _none_if_nan(x: float) -> float | None:
    return None if x is None or math.isnan(x) else float(x)


def stochastic_study(cfg: dict, speeds, samples: int, seed: int, *, psd: Psd = THESIS_PSD,
                     eta_dt: float = ETA_DT_S, warmup: float | None = None,
                     duration: float = DURATION_S, transient: float = TRANSIENT_S,
                     first_sample: int = 0, deterministic: bool = True, threads: int = 0,
                     progress: bool = True) -> StochasticStudy:
    """SS statistics of the stochastic model over top speeds (Fig. 4.9) with Conv1 (Eq. C.1).

    ``cfg`` is a configuration dict (e.g. ``load_config(preset="thesis-field")``): its model,
    time step and scheme are used; ``warmup``, ``duration`` and ``transient`` [s] replace its
    durations (module docstring). ``psd`` is the one-sided PSD per Hz of eta (default: the
    thesis's Eq. 4.4 calibration). Samples ``first_sample .. first_sample + samples - 1`` run.

    Sample i uses realization i of eta for every speed (common random numbers) and depends only
    on ``(seed, i)``. Each run starts from the deterministic state after ``warmup`` seconds from
    rest (Eq. 2.10) at that speed, then runs ``duration`` seconds with T_sto = T_hys (1 + eta)
    (Eq. 4.1); SS is measured after the first ``transient`` seconds.

    Parameters
    ----------
    cfg : dict
        Configuration (e.g. ``load_config(preset="thesis-field")``).
    speeds : array_like
        Top speeds [rad/s], positive and finite (e.g. the thesis's grid 6 .. 27 rad/s).
    samples : int
        Number of Monte Carlo samples n_s, 1 to ``MAX_SAMPLES`` (thesis: 500, chosen by Conv1).
    seed : int
        Random seed, an integer in [0, 2^64).
    psd : PsdModel, PsdTable or callable
        One-sided PSD of eta per Hz [1/Hz] (default ``THESIS_PSD``, Eq. 4.4).
    eta_dt : float
        Sampling step of eta [s] (default ``ETA_DT_S`` = 0.05 s); the integrator interpolates it
        linearly.
    warmup : float
        Deterministic start-up shared by all samples [s] (default :func:`default_warmup`:
        ``WARMUP_S`` = 100 s, 0 for ``axial.type = rgd``; 0 runs Algorithm 1 literally from rest).
    duration : float
        Stochastic part of every run [s] (default ``DURATION_S`` = 60 s).
    transient : float
        Start of the stochastic part discarded before SS is measured [s] (default
        ``TRANSIENT_S`` = 20 s).
    first_sample : int
        Index of the first sample (to split a study into chunks with identical rows).
    deterministic : bool
        Also run eta = 0 with the same durations (the deterministic curve and threshold).
    threads : int
        OpenMP threads (0: the OpenMP default).
    progress : bool
        Show a tqdm progress bar on stderr (when it is a terminal).

    Returns
    -------
    StochasticStudy
        SS of every sample and speed with its statistics and Conv1.

    Raises
    ------
    KeyboardInterrupt
        When the study is stopped with Ctrl-C.
    """
    sp = speed_grid(speeds)
    n = validate.integer("samples", samples, 1, MAX_SAMPLES)
    first = validate.integer("first_sample", first_sample, 0, 2**62)
    seed = validate.seed(seed)
    c = study_config(cfg, duration, transient)
    warmup = default_warmup(c) if warmup is None else warmup
    mc = study_engine(c, psd, eta_dt, seed, warmup)
    with progress_bar(n, "Monte Carlo samples", progress) as cb:
        ss = mc.severity(list(sp), first, n, cb, int(threads))
    if ss.size == 0:  # cancelled by the callback without an exception
        raise KeyboardInterrupt
    det = deterministic_severity(c, sp, eta_dt, seed, warmup, threads) if deterministic else None
    return study_from_samples(sp, ss, deterministic=det, seed=seed, first_sample=first,
                              eta_std=math.sqrt(mc.eta_variance), settings=_settings(c, psd, eta_dt, warmup), config=c)


def _settings(c: dict, psd: Psd, eta_dt: float, warmup: float) -> dict:
    sim = Configuration.of(c).simulation
    return {"warmup_s": float(warmup), "duration_s": sim.duration_s, "transient_s": sim.transient_s, "dt_s": sim.dt_s,
            "eta_dt_s": float(eta_dt),
            "psd": psd.as_dict() if hasattr(psd, "as_dict") else {"type": "callable"},
            "psd_convention": "one-sided, per Hz: Var[eta] = integral_0^inf S(f) df"}


def from_study_data(data) -> StochasticStudy:
    """The :class:`StochasticStudy` of a stored mc study (:func:`drillpy.study.compute_study`'s numbers):
    the same statistics as :func:`stochastic_study` of the same samples, bit for bit.

    Parameters
    ----------
    data : drillpy.study.store.StudyData or xarray.Dataset
        A finished ``"mc"`` study (``severity`` (sample, top_speed), ``deterministic_severity``,
        ``eta_std`` and ``study`` attributes).

    Returns
    -------
    StochasticStudy
        The study with its statistics.

    Raises
    ------
    ValueError
        When some samples are not computed yet.
    """
    import json
    from drillpy.uncertainty.process import psd_from_dict

    def values(name):
        return np.asarray(data[name])

    done = values("done")
    if not bool(done.all()):
        raise ValueError(f"done: {int((~done).sum())} samples of the study are not computed yet")
    ident = json.loads(data.attrs["study"])
    o = ident["options"]
    c = ident["config"]
    return study_from_samples(values("top_speed"), values("severity"),
                              deterministic=values("deterministic_severity"), seed=ident["seed"], first_sample=0,
                              eta_std=float(data.attrs["eta_std"]),
                              settings=_settings(c, psd_from_dict(o["psd"]), o["eta_dt_s"], o["warmup_s"]), config=c)


def deterministic_severity(c: dict, speeds, eta_dt: float, seed: int, warmup: float, threads: int = 0) -> np.ndarray:
    """SS with eta = 0 at each top speed (Fig. 4.8): the study's runs, durations and warm start without
    the random torque.

    Parameters
    ----------
    c : dict
        The study's configuration (its duration and transient applied).
    speeds : array_like
        Top speeds [rad/s].
    eta_dt : float
        Sampling step of eta [s] (the grid of the zero process).
    seed : int
        Seed of the study (unused by a zero process; kept so the engine is the study's).
    warmup : float
        Deterministic start-up [s].
    threads : int
        OpenMP threads (0: all cores).

    Returns
    -------
    numpy.ndarray
        SS [-], shape (n_speeds,).
    """
    zero = study_engine(c, lambda f: np.zeros_like(f), eta_dt, seed, warmup)
    return np.asarray(zero.severity(list(speeds), 0, 1, None, int(threads)))[0]


def study_from_samples(speeds, severity, *, deterministic, seed: int, first_sample: int, eta_std: float,
                       settings: dict, config: dict) -> StochasticStudy:
    """The statistics of a study (Fig. 4.9, Eq. C.1) computed from its per-sample SS.

    :func:`stochastic_study` and :func:`merge_studies` both end here, so a study run in chunks and
    merged has exactly the numbers of the same study run at once.

    Parameters
    ----------
    speeds : array_like
        Top speeds [rad/s], shape (n_speeds,).
    severity : array_like
        SS (Eq. 3.4) of samples ``first_sample ..`` [-], shape (samples, n_speeds).
    deterministic : array_like or None
        SS with eta = 0 per speed [-], or None.
    seed : int
        Random seed of the study.
    first_sample : int
        Index of the first sample (row 0 of ``severity``).
    eta_std : float
        Standard deviation of eta [-].
    settings : dict
        Durations and PSD of the runs (:attr:`StochasticStudy.settings`).
    config : dict
        The configuration run.

    Returns
    -------
    StochasticStudy
        The study with its mean, band, P(SS > 0.5), 5 % speed, deterministic threshold and Conv1.
    """
    sp = np.asarray(speeds, dtype=float)
    ss = np.asarray(severity, dtype=float)
    st = _core.severity_statistics(ss, list(sp), SS_LEVEL, P_LEVEL, 0.05, 0.95)
    det = det_thr = None
    if deterministic is not None:
        det = np.asarray(deterministic, dtype=float)
        det_thr = _none_if_nan(_core.severity_threshold(list(sp), list(det), SS_LEVEL))
    conv = np.asarray(_core.conv1(ss, list(sp))) if sp.size >= 2 else np.full(ss.shape[0], np.nan)
    return StochasticStudy(
        speeds=sp, severity=ss, mean=st.mean, q05=st.q_low, q95=st.q_high,
        p_exceed=st.p_exceed, p05_speed=_none_if_nan(st.p_speed), deterministic=det,
        deterministic_threshold=det_thr, conv1=conv, seed=int(seed), first_sample=int(first_sample),
        eta_std=float(eta_std), settings=dict(settings), config=config)


def merge_studies(studies) -> StochasticStudy:
    """One study from chunks of the same study run apart (``drillpy mc --first-sample``).

    The chunks must share the configuration, the speeds, the seed, the settings and the
    deterministic curve, and their sample ranges must tile ``first .. first + n - 1`` without gap
    or overlap (in any order). Sample i depends only on (seed, i), so the merged study is
    bit-identical to the same samples run at once.

    Parameters
    ----------
    studies : sequence of StochasticStudy
        The chunks (at least one).

    Returns
    -------
    StochasticStudy
        The merged study, its statistics recomputed from all samples.

    Raises
    ------
    ValueError
        Naming the first field in which two chunks differ, or the gap or overlap of their samples.
    """
    chunks = sorted(studies, key=lambda s: s.first_sample)
    if not chunks:
        raise ValueError("studies: nothing to merge (give at least one chunk)")
    ref = chunks[0]
    for s in chunks[1:]:
        for name, a, b in (("speeds", ref.speeds, s.speeds), ("deterministic", ref.deterministic, s.deterministic)):
            same = (a is None and b is None) or (a is not None and b is not None and np.array_equal(a, b))
            if not same:
                raise ValueError(f"{name}: chunk starting at sample {s.first_sample} differs from the chunk "
                                 f"starting at {ref.first_sample}: {b!r} vs {a!r}")
        for name in ("seed", "eta_std", "settings", "config"):
            if getattr(s, name) != getattr(ref, name):
                raise ValueError(f"{name}: chunk starting at sample {s.first_sample} differs from the chunk "
                                 f"starting at {ref.first_sample} (not the same study)")
    end = ref.first_sample
    for s in chunks:
        if s.first_sample != end:
            what = "overlap" if s.first_sample < end else "gap"
            raise ValueError(f"first_sample = {s.first_sample}: samples {min(end, s.first_sample)}-"
                             f"{max(end, s.first_sample) - 1} {what} between chunks (expected a chunk starting "
                             f"at {end})")
        end += s.severity.shape[0]
    return study_from_samples(ref.speeds, np.vstack([s.severity for s in chunks]), deterministic=ref.deterministic,
                              seed=ref.seed, first_sample=ref.first_sample, eta_std=ref.eta_std,
                              settings=ref.settings, config=ref.config)


def conv1(severity, speeds) -> np.ndarray:
    """Conv1(n_s) of Eq. (C.1) for an SS matrix.

    Conv1(n_s) = sqrt((1/n_s) sum_{i <= n_s} integral_B SS_i(Omega)^2 dOmega), the integral over
    the speed grid B by the trapezoidal rule (speeds sorted by the engine).

    Parameters
    ----------
    severity : array_like
        SS [-], shape (samples, n_speeds): row i is the SS curve of sample i.
    speeds : array_like
        Top speeds [rad/s] of the columns, at least two, positive and finite.

    Returns
    -------
    numpy.ndarray
        Conv1(n_s) for n_s = 1 .. samples [sqrt(rad/s)].
    """
    ss = np.asarray(severity, dtype=float)
    if ss.ndim != 2:
        raise ValueError(f"severity: must be a 2-D array (samples x speeds), got shape {ss.shape}")
    return np.asarray(_core.conv1(ss, list(speed_grid(speeds))))


def phase_study(cfg: dict, speed: float | None = None, *, seed: int, cycles: int = 750,
                psd: Psd = THESIS_PSD, eta_dt: float = ETA_DT_S, warmup: float | None = None,
                duration: float = 200.0, transient: float = TRANSIENT_S, batch: int = 16,
                threads: int = 0, progress: bool = True) -> PhaseStudy:
    """Stick and slip durations at one top speed (default: the configuration's) pooled over
    samples until at least ``cycles`` stick phases are collected (Fig. 4.7; the thesis used 750),
    with the deterministic periodic values from the same configuration (section 4.2.1).

    Samples run in batches of ``batch`` in index order, so the result depends only on the seed.
    If the first 64 batches hold no stick phase (no stick-slip at this speed) the study stops
    with empty durations. The deterministic reference is one run of ``warmup + duration`` seconds
    from rest with eta = 0, of which ``warmup + transient`` seconds are discarded.

    Parameters
    ----------
    cfg : dict
        Configuration (model, time step, scheme, metrics thresholds).
    speed : float, optional
        Top speed [rad/s] (default: the configuration's ``operation.top_speed_rad_s``).
    seed : int
        Random seed, an integer in [0, 2^64).
    cycles : int
        Minimum number of stick phases to collect (thesis: 750).
    psd : PsdModel, PsdTable or callable
        One-sided PSD of eta per Hz [1/Hz] (default ``THESIS_PSD``, Eq. 4.4).
    eta_dt : float
        Sampling step of eta [s].
    warmup : float, optional
        Deterministic start-up before the stochastic part [s] (default :func:`default_warmup`).
    duration : float
        Stochastic part of every run [s] (default 200 s).
    transient : float
        Start of the stochastic part discarded [s].
    batch : int
        Samples per engine call.
    threads : int
        OpenMP threads (0: the OpenMP default).
    progress : bool
        Show a tqdm progress bar (stick phases collected).

    Returns
    -------
    PhaseStudy
        Pooled stick and slip durations with the deterministic values.
    """
    seed = validate.seed(seed)
    ncyc = validate.integer("cycles", cycles, 1, 10**6)
    nb = validate.integer("batch", batch, 1, 100000)
    c = study_config(cfg, duration, transient)
    om = float(Configuration.of(c).operation.top_speed_rad_s if speed is None else speed)
    speed_grid([om])
    warmup = default_warmup(c) if warmup is None else warmup
    mc = study_engine(c, psd, eta_dt, seed, warmup)
    stick, slip, sev = [], [], []
    with progress_bar(ncyc, "stick-slip cycles", progress) as cb:
        first = 0
        while sum(len(s) for s in stick) < ncyc:
            st, sl, ss = mc.phases(om, first, nb, None, int(threads))
            stick += list(st)
            slip += list(sl)
            sev += list(ss)
            first += nb
            if cb:
                cb(min(ncyc, sum(len(s) for s in stick)), ncyc)
            if first >= 64 * nb and not any(len(s) for s in stick):
                break  # no stick-slip at this speed
    det = _core.Simulation(engine_config(with_overrides(c, duration=warmup + duration,
                                                    transient=warmup + transient)))
    d = det.run(top_speed=om, record=False)
    if d.period_cycles:
        dst, dsl = d.period_stick, d.period_slip
    else:  # not periodic within the tolerance: show the last three cycles
        dst, dsl = d.stick_durations[-3:], d.slip_durations[-3:]
    return PhaseStudy(speed=om, stick=np.concatenate(stick) if stick else np.zeros(0),
                      slip=np.concatenate(slip) if slip else np.zeros(0), samples=first,
                      severity=np.asarray(sev), deterministic_stick=np.asarray(dst),
                      deterministic_slip=np.asarray(dsl),
                      deterministic_period_cycles=int(d.period_cycles), seed=seed)


def stochastic_run(cfg: dict, top_speed: float, seed: int, *, sample: int = 0,
                   psd: Psd = THESIS_PSD, eta_dt: float = ETA_DT_S, duration: float = 200.0,
                   transient: float = 100.0):
    """One stochastic run from rest (Eq. 2.10) with eta of ``sample`` over the whole run
    (Algorithm 1; Figs. 4.5-4.6).

    There is no warm-up: eta acts from t = 0 and the configuration's other settings are kept.

    Parameters
    ----------
    cfg : dict
        Configuration.
    top_speed : float
        Top speed [rad/s].
    seed : int
        Random seed, an integer in [0, 2^64).
    sample : int
        Index of the realization of eta (the same eta as Monte Carlo sample ``sample``).
    psd : PsdModel, PsdTable or callable
        One-sided PSD of eta per Hz [1/Hz] (default ``THESIS_PSD``, Eq. 4.4).
    eta_dt : float
        Sampling step of eta [s].
    duration : float
        Simulated time [s] (default 200 s).
    transient : float
        Time discarded before the metrics (SS) are measured [s] (default 100 s).

    Returns
    -------
    result : SimulationResult
        The simulation (:func:`drillpy.model.simulation.simulate`).
    t_eta : numpy.ndarray
        Times of the eta samples [s].
    eta : numpy.ndarray
        The realization of eta used [-].
    """
    from drillpy.uncertainty.process import generate
    from drillpy.model.simulation import simulate
    c = study_config(cfg, duration, transient)
    t, eta = generate(psd, dt=eta_dt, duration=Configuration.of(c).simulation.duration_s, samples=1,
                      seed=seed, first_sample=sample)
    return simulate(c, float(top_speed), eta_series=eta[0], series_dt=eta_dt), t, eta[0]
