"""What a study is: a grid of independent tasks over named dimensions, and how one block is computed.

A study (:class:`Study`) is one of the engine's parameter studies:

========== ========================= ============ ==================================================
kind       dimensions of ``severity`` task axis    one task
========== ========================= ============ ==================================================
sweep      (top_speed,)              top_speed    SS (Eq. 3.4) of one run at one top speed
map        (wob, top_speed)          wob          the runs of one WOB row (Figs. 3.11-3.12)
mc         (sample, top_speed)       sample       one realization of eta at every speed (Algorithm 1)
========== ========================= ============ ==================================================

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

KINDS = ("sweep", "map", "mc")
#: Dimension along which each kind's tasks are cut into blocks.
TASK_DIM = {"sweep": "top_speed", "map": "wob", "mc": "sample"}
#: Units of the coordinates (attributes of the stored Dataset).
UNITS = {"top_speed": "rad/s", "wob": "N", "sample": "1", "severity": "1"}
#: Default block length along the task axis: a block must outweigh its scheduling and, for mc, the
#: deterministic warm start every block repeats (100 s per speed against 60 s per sample and speed).
DEFAULT_CHUNK = {"sweep": 4, "map": 1, "mc": 50}


@dataclass(frozen=True)
class Study:
    """One parameter study of the engine (module docstring), described so that any process can
    compute any block of it.

    Attributes
    ----------
    kind : str
        ``"sweep"``, ``"map"`` or ``"mc"``.
    config : dict
        The configuration of every run (:func:`drillpy.model.config.load_config`; for mc, with the
        study's duration and transient already applied).
    top_speeds : tuple of float
        Top-drive speeds [rad/s].
    wobs : tuple of float
        Weights on bit [N] (map only; empty otherwise).
    samples : int
        Number of Monte Carlo samples (mc only; 0 otherwise).
    seed : int
        Seed of the random streams (mc only).
    options : dict
        What else decides the numbers, JSON-ready: for mc ``psd`` (the PSD's ``as_dict``), ``eta_dt_s``,
        ``warmup_s``; for sweep and map ``start`` (None: the configuration's).
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
        if sp.ndim != 1 or sp.size == 0 or not np.all(np.isfinite(sp)) or np.any(sp <= 0):
            raise ValueError(f"top_speeds = {list(self.top_speeds)!r}: must be positive finite numbers [rad/s]")
        if self.kind == "map" and len(self.wobs) == 0:
            raise ValueError("wobs = (): a map needs at least one weight on bit [N]")
        if self.kind == "mc":
            validate.integer("samples", self.samples, 1, 10_000_000)
            validate.seed(self.seed)

    @property
    def task_dim(self) -> str:
        """The dimension cut into blocks (``TASK_DIM``)."""
        return TASK_DIM[self.kind]

    @property
    def task_size(self) -> int:
        """Length of the task dimension."""
        return {"sweep": len(self.top_speeds), "map": len(self.wobs), "mc": self.samples}[self.kind]

    def dims(self) -> tuple:
        """Dimensions of the ``severity`` array, task dimension first."""
        return {"sweep": ("top_speed",), "map": ("wob", "top_speed"), "mc": ("sample", "top_speed")}[self.kind]

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
    """The engine of a study, built once per process (a worker keeps it between blocks)."""
    from drillpy.model.config import engine_config
    from drillpy.uncertainty.process import psd_from_dict, psd_on_grid
    d = json.loads(key)
    cfg = engine_config(d["config"])
    if d["kind"] != "mc":
        return _core.Simulation(cfg)
    o = d["options"]
    _, S = psd_on_grid(psd_from_dict(o["psd"]), o["eta_dt_s"], d["config"]["simulation"]["duration_s"])
    return _core.MonteCarlo(cfg, S, float(o["eta_dt_s"]), int(d["seed"]), float(o["warmup_s"]))


def compute_block(study: Study, lo: int, hi: int, threads: int = 0) -> np.ndarray:
    """SS of the tasks ``lo .. hi - 1`` of a study (along its task dimension).

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
    numpy.ndarray
        SS [-], shape (hi - lo, ...) in the order of :meth:`Study.dims`.
    """
    eng = _engine(study.key())
    sp = list(study.top_speeds)
    start = study.options.get("start")
    if study.kind == "sweep":
        return np.asarray(eng.sweep(sp[lo:hi], [], None, int(threads), start))[0]
    if study.kind == "map":
        return np.asarray(eng.sweep(sp, list(study.wobs)[lo:hi], None, int(threads), start))
    return np.asarray(eng.severity(sp, int(lo), int(hi - lo), None, int(threads)))


def deterministic_curve(study: Study, threads: int = 0) -> np.ndarray:
    """SS with eta = 0 per top speed of an mc study (Fig. 4.8), the same durations and warm start.

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
    from drillpy.model.config import engine_config
    from drillpy.uncertainty.process import psd_from_dict, psd_on_grid
    o = study.options
    f, _ = psd_on_grid(psd_from_dict(o["psd"]), o["eta_dt_s"], study.config["simulation"]["duration_s"])
    zero = _core.MonteCarlo(engine_config(study.config), np.zeros_like(f), float(o["eta_dt_s"]), int(study.seed),
                            float(o["warmup_s"]))
    return np.asarray(zero.severity(list(study.top_speeds), 0, 1, None, int(threads)))[0]
