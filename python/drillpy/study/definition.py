"""What a study is: a grid of independent tasks over named dimensions, and how one block is computed.

A study (:class:`Study`) is one of the engine's parameter studies:

========== ============================================ ========= ==============================================
kind       variables (dimensions)                       task axis one task
========== ============================================ ========= ==============================================
sweep      severity (top_speed)                         top_speed SS (Eq. 3.4) of one run at one top speed
map        severity (wob, top_speed)                    wob       the runs of one WOB row (Figs. 3.11-3.12)
mc         severity (sample, top_speed)                 sample    one realization of eta at every speed
                                                                  (Algorithm 1)
structural severity (sample, top_speed)                 sample    one random structure (SM_CB2, chapter 6), with
                                                                  or without eta, at every speed (robust-ss)
frf        frf_db (sample, point, frequency) float32,   sample    the acceleration FRF of one random structure
           energy (sample, point)                                 (Eqs. 6.5, 6.15) and its band energy (Eq. C.2)
========== ============================================ ========= ==============================================

The task axis is cut into blocks (:func:`compute_block` computes one). Every value depends only on
its own coordinates, and a Monte Carlo sample i only on (seed, i) (the counter-based streams of
``drill/rng.hpp``), so a study's numbers are bit-identical whatever the blocks, their order, the
worker that computed them or the thread count (tests/python/test_study.py).
"""
from __future__ import annotations

import functools
import json
from dataclasses import dataclass, field

import numpy as np

from drillpy import _core, validate

KINDS = ("sweep", "map", "mc", "structural", "frf")
#: Dimension along which each kind's tasks are cut into blocks.
TASK_DIM = {"sweep": "top_speed", "map": "wob", "mc": "sample", "structural": "sample", "frf": "sample"}
#: Units of the coordinates and variables (attributes of the stored Dataset).
UNITS = {"top_speed": "rad/s", "wob": "N", "sample": "1", "severity": "1", "frequency": "Hz", "point": "FE node",
         "frf_db": "dB re 1 rad/s^2 per N m", "energy": "(rad/s^2 / (N m))^2 rad/s"}
#: Long names of the variables.
LONG_NAMES = {"severity": "stick-slip severity SS (Eq. 3.4)",
              "frf_db": "acceleration FRF 20 log10 |a| for a unit torque at the bit (Eqs. 6.5, 6.15)",
              "energy": "band energy of the FRF, the integrand of Conv2 (Eq. C.2)"}
#: Default block length along the task axis: a block must outweigh its scheduling and, for mc, the
#: deterministic warm start every block repeats (100 s per speed against 60 s per sample and speed).
DEFAULT_CHUNK = {"sweep": 4, "map": 1, "mc": 50, "structural": 10, "frf": 100}


@dataclass(frozen=True)
class Study:
    """One parameter study of the engine (module docstring), described so that any process can
    compute any block of it.

    Attributes
    ----------
    kind : str
        ``"sweep"``, ``"map"``, ``"mc"``, ``"structural"`` or ``"frf"``.
    config : dict
        The configuration of every run (:func:`drillpy.model.config.load_config`; for mc, with the
        study's duration and transient already applied).
    top_speeds : tuple of float
        Top-drive speeds [rad/s] (frf: empty).
    wobs : tuple of float
        Weights on bit [N] (map only; empty otherwise).
    samples : int
        Number of Monte Carlo samples (mc, structural, frf; 0 otherwise).
    seed : int
        Seed of the random streams (mc, structural, frf).
    options : dict
        What else decides the numbers, JSON-ready: for mc ``psd`` (the PSD's ``as_dict``), ``eta_dt_s``,
        ``warmup_s``; for sweep and map ``start`` (None: the configuration's); for structural ``model``,
        ``delta``, ``case``, ``structural``, ``psd`` (None: no eta), ``eta_dt_s``; for frf ``model``,
        ``delta``, ``case``, ``freq_hz`` and ``nodes``.
    """
    kind: str
    config: dict = field(repr=False)
    top_speeds: tuple
    wobs: tuple = ()
    samples: int = 0
    seed: int = 0
    options: dict = field(default_factory=dict)

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"kind = {self.kind!r}: unknown study (use {', '.join(KINDS)})")
        sp = np.asarray(self.top_speeds, dtype=float)
        if self.kind != "frf" and (sp.ndim != 1 or sp.size == 0 or not np.all(np.isfinite(sp)) or np.any(sp <= 0)):
            raise ValueError(f"top_speeds = {list(self.top_speeds)!r}: must be positive finite numbers [rad/s]")
        if self.kind == "map" and len(self.wobs) == 0:
            raise ValueError("wobs = (): a map needs at least one weight on bit [N]")
        if TASK_DIM[self.kind] == "sample":
            validate.integer("samples", self.samples, 1, 10_000_000)
            validate.seed(self.seed)

    @property
    def task_dim(self) -> str:
        """The dimension cut into blocks (``TASK_DIM``)."""
        return TASK_DIM[self.kind]

    @property
    def task_size(self) -> int:
        """Length of the task dimension."""
        return {"sweep": len(self.top_speeds), "map": len(self.wobs)}.get(self.kind, self.samples)

    def variables(self) -> dict:
        """Each stored variable's dimensions (task dimension first) and dtype.

        Returns
        -------
        dict
            name -> (dims, numpy dtype).
        """
        if self.kind == "frf":
            return {"frf_db": (("sample", "point", "frequency"), np.float32), "energy": (("sample", "point"), np.float64)}
        dims = {"sweep": ("top_speed",), "map": ("wob", "top_speed")}.get(self.kind, ("sample", "top_speed"))
        return {"severity": (dims, np.float64)}

    def coords(self) -> dict:
        """Coordinates other than the task dimension's samples: name -> values.

        Returns
        -------
        dict
            ``top_speed`` [rad/s], ``wob`` [N], ``frequency`` [Hz] and ``point`` (FE node) as they apply.
        """
        if self.kind == "frf":
            return {"point": np.asarray(self.options["nodes"], dtype=np.int64),
                    "frequency": np.asarray(self.options["freq_hz"], dtype=float)}
        c = {"top_speed": np.asarray(self.top_speeds, dtype=float)}
        if self.kind == "map":
            c["wob"] = np.asarray(self.wobs, dtype=float)
        return c

    def identity(self) -> dict:
        """Everything but the length of the task dimension of an mc study: two studies with the same
        identity hold the same numbers at the same coordinates (a store is resumed or extended only
        by a study of its identity).

        Returns
        -------
        dict
            JSON-ready ``kind``, ``config``, ``top_speeds``, ``wobs``, ``seed``, ``options``.
        """
        return json.loads(json.dumps({"kind": self.kind, "config": self.config, "top_speeds": list(self.top_speeds),
                                      "wobs": list(self.wobs), "seed": self.seed, "options": self.options}))

    def key(self) -> str:
        """:meth:`identity` as canonical JSON text (a cache key)."""
        return json.dumps(self.identity(), sort_keys=True)


@functools.lru_cache(maxsize=4)
def _engine(key: str):
    """The engine of a sweep, map or mc study, built once per process (a worker keeps it between blocks)."""
    d = json.loads(key)
    if d["kind"] != "mc":
        from drillpy.model.config import engine_config
        return _core.Simulation(engine_config(d["config"]))
    from drillpy.uncertainty.montecarlo import study_engine
    from drillpy.uncertainty.process import psd_from_dict
    o = d["options"]
    return study_engine(d["config"], psd_from_dict(o["psd"]), o["eta_dt_s"], int(d["seed"]), o["warmup_s"])


def mc_study(cfg: dict, speeds, samples: int, seed: int, *, psd=None, eta_dt: float | None = None,
             warmup: float | None = None, duration: float | None = None, transient: float | None = None) -> Study:
    """The study of :func:`drillpy.uncertainty.montecarlo.stochastic_study` (samples 0 .. samples - 1) as
    an ``"mc"`` :class:`Study`, to run on a backend and store (``drillpy mc --out``/``--scheduler``).

    Parameters
    ----------
    cfg, speeds, samples, seed, psd, eta_dt, warmup, duration, transient
        As for :func:`~drillpy.uncertainty.montecarlo.stochastic_study` (None: its defaults); ``psd``
        must be a :class:`~drillpy.uncertainty.process.PsdModel` or
        :class:`~drillpy.uncertainty.process.PsdTable` (a stored study cannot hold a Python callable).

    Returns
    -------
    Study
        An ``"mc"`` study.

    Raises
    ------
    ValueError
        For a PSD given as a callable, and as ``stochastic_study`` for bad values.
    """
    from drillpy.uncertainty import montecarlo as mcm
    psd = mcm.THESIS_PSD if psd is None else psd
    eta_dt = mcm.ETA_DT_S if eta_dt is None else eta_dt
    warmup = mcm.default_warmup(cfg) if warmup is None else warmup
    if not hasattr(psd, "as_dict"):
        raise ValueError("psd: a Python callable cannot be stored in a study (give a PsdModel or a PsdTable)")
    c = mcm.study_config(cfg, mcm.DURATION_S if duration is None else duration,
                         mcm.TRANSIENT_S if transient is None else transient)
    validate.non_negative("warmup_s", warmup, "s")
    return Study("mc", c, tuple(mcm.speed_grid(speeds).tolist()), samples=samples, seed=validate.seed(seed),
                 options={"psd": psd.as_dict(), "eta_dt_s": validate.positive("eta_dt_s", eta_dt, "s"),
                          "warmup_s": float(warmup)})


def compute_block(study: Study, lo: int, hi: int, threads: int = 0) -> dict:
    """The results of tasks ``range(lo, hi)`` of a study (along its task dimension).

    Parameters
    ----------
    study : Study
        The study.
    lo, hi : int
        Task range (0 <= lo < hi <= ``study.task_size``).
    threads : int
        Engine threads (OpenMP; 0: all cores).

    Returns
    -------
    dict
        Variable name -> array of shape (hi - lo, ...) in the order of :meth:`Study.variables`.
    """
    o = study.options
    if study.kind == "frf":
        from drillpy.uncertainty.frf import frf_samples
        db, energy = frf_samples(study.config, o["model"], o["delta"], o["case"], samples=hi - lo, seed=study.seed,
                                 first_sample=lo, freq_hz=o["freq_hz"], nodes=o["nodes"], progress=False,
                                 threads=threads)
        return {"frf_db": np.asarray(db), "energy": np.asarray(energy)}
    if study.kind == "structural":
        from drillpy.uncertainty.process import psd_from_dict
        from drillpy.uncertainty.structural import severity_study
        st = severity_study(study.config, list(study.top_speeds), hi - lo, model=o["model"], delta=o["delta"],
                            case=o["case"], structural=o["structural"],
                            eta_psd=None if o["psd"] is None else psd_from_dict(o["psd"]), eta_dt=o["eta_dt_s"],
                            seed=study.seed, first_sample=lo, progress=False, threads=threads)
        return {"severity": np.asarray(st.ss)}
    eng = _engine(study.key())
    sp = list(study.top_speeds)
    if study.kind == "sweep":
        ss = np.asarray(eng.sweep(sp[lo:hi], [], None, int(threads), o.get("start")))[0]
    elif study.kind == "map":
        ss = np.asarray(eng.sweep(sp, list(study.wobs)[lo:hi], None, int(threads), o.get("start")))
    else:
        ss = np.asarray(eng.severity(sp, int(lo), int(hi - lo), None, int(threads)))
    return {"severity": ss}


def deterministic_curve(study: Study, threads: int = 0) -> np.ndarray:
    """SS with eta = 0 per top speed of an mc study (Fig. 4.8), the same durations and warm start
    (:func:`drillpy.uncertainty.montecarlo.deterministic_severity`).

    Parameters
    ----------
    study : Study
        An mc study.
    threads : int
        Engine threads (0: all cores).

    Returns
    -------
    numpy.ndarray
        SS [-], shape (n_speeds,).
    """
    from drillpy.uncertainty.montecarlo import deterministic_severity
    o = study.options
    return deterministic_severity(study.config, study.top_speeds, o["eta_dt_s"], study.seed, o["warmup_s"], threads)
