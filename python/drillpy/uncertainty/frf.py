"""Uncertain structure in the frequency domain (thesis chapter 6, appendix C).

Craig-Bampton substructuring (Eqs. 6.6-6.18), the stochastic models SM_full (Eq. 6.4), SM_CB1
(Eqs. 6.19-6.20) and SM_CB2 (Eqs. 6.21-6.23) built on Soize's SE+ / SE+0 random matrices
(Eqs. 6.1-6.3, 6.24-6.25), and Monte Carlo envelopes of the acceleration FRF for a unit torque at
the bit (section 6.6) with the convergence function Conv2 (Eq. C.2). The numerics run in the C++
engine; this module shapes inputs and results.

Dispersions are arrays ``delta[k, a, s]``: substructure k (DP = 0, BHA = 1), matrix a (M, D, K),
side s (inner DOFs, interface DOFs). SM_full has one "substructure" and SM_full / SM_CB1 use the
inner column only.
"""
from __future__ import annotations

import copy
import json
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import trapezoid

from drillpy import _core, validate
from drillpy.progress import progress_bar

MODELS = ("SM_full", "SM_CB1", "SM_CB2")
POINT_LABELS = ("P_obs,1 (first free DP node)", "P_obs,2 (DP/BHA interface)", "P_obs,3 (bit)")
CASE_TITLES = {1: "mass uncertainty (Table 6.1)", 2: "damping uncertainty (Table 6.2)",
               3: "stiffness uncertainty (Table 6.3)", 4: "DP uncertainty (Table 6.4)",
               5: "BHA uncertainty (Table 6.5)", 6: "inner-DOF uncertainty (Table 6.6)",
               7: "interface-DOF uncertainty (Table 6.7)"}


def default_frequencies(n: int = 1000, f_min_hz: float = 0.01, f_max_hz: float = 10.0) -> np.ndarray:
    """The frequency grid of the envelope studies [Hz]: n points from 0.01 to 10 Hz."""
    return np.linspace(f_min_hz, f_max_hz, int(n))


def n_substructures(cfg: dict) -> int:
    return len(cfg["string"]["sections"])


def dispersions(cfg: dict, model: str = "SM_CB2", delta=None, case: int | None = None) -> np.ndarray:
    """Dispersion array (substructures, 3, 2) for ``model``.

    ``case`` (1-7) takes Tables 6.1-6.7 (SM_CB2 on DP + BHA); otherwise ``delta`` is a scalar
    (every dispersion), a dict ``{"M": x, "D": y, "K": z}``, or an array of shape (3,) for
    SM_full, (substructures, 3) for SM_CB1 or (substructures, 3, 2) for SM_CB2.
    """
    if model not in MODELS:
        raise ValueError(f"model = {model!r}: unknown stochastic model (use {', '.join(MODELS)})")
    ns = 1 if model == "SM_full" else n_substructures(cfg)
    if case is not None:
        if delta is not None:
            raise ValueError("give either case or delta, not both")
        if model != "SM_CB2":
            raise ValueError(f"case = {case}: the case studies (Tables 6.1-6.7) are SM_CB2 models")
        if ns != 2:
            raise ValueError(f"case = {case}: the case studies need two substructures (DP + BHA), not {ns}")
        return np.asarray(_core.thesis_case_dispersions(int(case), 0.1))
    if delta is None:
        delta = 0.1
    if isinstance(delta, dict):
        unknown = set(delta) - {"M", "D", "K"}
        if unknown:
            raise ValueError(f"delta = {delta!r}: keys must be M, D, K")
        delta = [float(delta.get(a, 0.0)) for a in ("M", "D", "K")]
    d = np.asarray(delta, dtype=float)
    if d.ndim == 0:
        d = np.full((ns, 3), float(d))
    elif d.shape == (3,):
        d = np.broadcast_to(d, (ns, 3))
    if d.shape == (ns, 3):
        d = np.repeat(d[:, :, None], 2, axis=2)  # the same dispersion for inner and interface
    expected = {"SM_full": "(3,)", "SM_CB1": f"(3,) or ({ns}, 3)",
                "SM_CB2": f"(3,), ({ns}, 3) or ({ns}, 3, 2)"}[model]
    if d.shape != (ns, 3, 2) or (model == "SM_CB1" and not np.array_equal(d[:, :, 0], d[:, :, 1])):
        raise ValueError(f"delta shape {np.shape(delta)}: expected a scalar, a dict or shape {expected} "
                         f"for {model}")
    return np.ascontiguousarray(d)


def with_cb_modes(cfg: dict, modes) -> dict:
    """A copy of ``cfg`` with ``craig_bampton.modes`` replaced (one count per section)."""
    c = copy.deepcopy(cfg)
    c["craig_bampton"] = {"modes": [int(m) for m in modes]}
    return c


def stochastic_model(cfg: dict, model: str = "SM_CB2", delta=None, case: int | None = None):
    """The engine's stochastic model (``_core.StochasticModel``) of a configuration."""
    d = dispersions(cfg, model, delta, case)
    return _core.StochasticModel(json.dumps(cfg), model, d)


def observation_nodes(cfg: dict) -> list[int]:
    """Nodes of P_obs,1 (first free DP node), P_obs,2 (DP/BHA interface), P_obs,3 (bit)."""
    return list(_core.observation_nodes(json.dumps(cfg)))


@dataclass
class FRFEnvelope:
    """Monte Carlo statistics of the acceleration FRF, 20 log10 |a| [dB re 1 rad/s^2 per N m].

    Arrays ``nominal_db`` (mean model), ``mean_db`` (sample mean of the dB response),
    ``lower_db`` / ``upper_db`` (quantiles (1 -+ probability)/2) have shape (n_freq, n_points).
    ``energy[i, p]`` is the integral over the band of |a_i(omega)|^2 d omega for sample i
    (the integrand of Conv2, Eq. C.2).
    """
    freq_hz: np.ndarray
    nodes: list
    nominal_db: np.ndarray
    mean_db: np.ndarray
    lower_db: np.ndarray
    upper_db: np.ndarray
    energy: np.ndarray
    model: str
    delta: np.ndarray
    samples: int
    seed: int
    probability: float
    labels: list = field(default_factory=lambda: list(POINT_LABELS))

    @property
    def width_db(self) -> np.ndarray:
        """Envelope width upper - lower [dB], shape (n_freq, n_points)."""
        return self.upper_db - self.lower_db

    def conv2(self) -> np.ndarray:
        """Conv2(n_s) of Eq. (C.2) for n_s = 1..samples: shape (samples, n_points)."""
        n = np.arange(1, self.energy.shape[0] + 1)[:, None]
        return np.sqrt(np.cumsum(self.energy, axis=0) / n)

    def to_json(self) -> dict:
        return {
            "model": self.model, "samples": self.samples, "seed": self.seed,
            "probability": self.probability, "delta": self.delta.tolist(),
            "freq_hz": self.freq_hz.tolist(),
            "points": [{"label": lab, "node": int(nd), "nominal_db": self.nominal_db[:, p].tolist(),
                        "mean_db": self.mean_db[:, p].tolist(), "lower_db": self.lower_db[:, p].tolist(),
                        "upper_db": self.upper_db[:, p].tolist()}
                       for p, (lab, nd) in enumerate(zip(self.labels, self.nodes))],
        }


def frf_envelope(cfg: dict, model: str = "SM_CB2", delta=None, case: int | None = None, *,
                 samples: int = 2500, seed: int = 1, freq_hz=None, probability: float = 0.95,
                 nodes=None, progress: bool = True, threads: int = 0) -> FRFEnvelope:
    """Statistical envelope of the acceleration FRF for a unit torque at the bit (section 6.6).

    ``samples`` realizations of ``model`` (sample i from (seed, i) only), frequencies ``freq_hz``
    [Hz] (default :func:`default_frequencies`), observation ``nodes`` (default P_obs,1-3).
    Ctrl-C stops the study (KeyboardInterrupt).
    """
    validate.integer("samples", samples, 1)
    validate.seed(seed)
    f = default_frequencies() if freq_hz is None else np.asarray(freq_hz, dtype=float)
    sm = stochastic_model(cfg, model, delta, case)
    nd = observation_nodes(cfg) if nodes is None else [int(x) for x in nodes]
    with progress_bar(int(samples) + f.size, f"FRF envelope {model}", progress) as cb:
        r = sm.envelope(np.ascontiguousarray(f), nd, int(samples), int(seed), float(probability), cb, threads)
    labels = list(POINT_LABELS) if nodes is None else [f"node {x}" for x in nd]
    return FRFEnvelope(freq_hz=r.freq_hz, nodes=list(r.nodes), nominal_db=r.nominal_db,
                       mean_db=r.mean_db, lower_db=r.lower_db, upper_db=r.upper_db,
                       energy=r.energy, model=model, delta=np.asarray(sm.delta), samples=r.samples,
                       seed=int(seed), probability=float(probability), labels=labels)


def cb_frequencies(cfg: dict, n: int, modes=None) -> np.ndarray:
    """First n natural frequencies [Hz] of the assembled Craig-Bampton model (optionally with
    ``modes`` fixed-interface modes per substructure)."""
    c = cfg if modes is None else with_cb_modes(cfg, modes)
    return np.asarray(_core.cb_frequencies(json.dumps(c), int(n)))


def band_widths(env: FRFEnvelope, bands_hz) -> np.ndarray:
    """Mean envelope width [dB] over each band (integral of the width over the band divided by
    its length, trapezoid rule): shape (n_bands, n_points)."""
    out = []
    for lo, hi in bands_hz:
        sel = (env.freq_hz >= lo) & (env.freq_hz <= hi)
        if sel.sum() < 2:
            raise ValueError(f"band [{lo}, {hi}] Hz holds fewer than two grid frequencies")
        fr = env.freq_hz[sel]
        out.append(trapezoid(env.width_db[sel], fr, axis=0) / (fr[-1] - fr[0]))
    return np.asarray(out)


def conv2_vs_modes(cfg: dict, substructure: int, modes, model: str = "SM_CB2", delta=None,
                   case: int | None = None, *, samples: int = 500, seed: int = 1, freq_hz=None,
                   progress: bool = True, threads: int = 0) -> np.ndarray:
    """Conv2 (Eq. C.2) with ``samples`` samples versus the number of fixed-interface modes of one
    substructure (the others keep the configuration's count): shape (len(modes), n_points)."""
    base = list(cfg["craig_bampton"]["modes"])
    if not 0 <= substructure < len(base):
        raise ValueError(f"substructure = {substructure}: must be between 0 and {len(base) - 1}")
    out = []
    for m in modes:
        counts = list(base)
        counts[substructure] = int(m)
        env = frf_envelope(with_cb_modes(cfg, counts), model, delta, case, samples=samples, seed=seed,
                           freq_hz=freq_hz, progress=progress, threads=threads)
        out.append(env.conv2()[-1])
    return np.asarray(out)

