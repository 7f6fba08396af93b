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

from dataclasses import dataclass, field

import numpy as np

from drillpy import _core, validate
from drillpy.model.config import engine_config
from drillpy.model.configuration import Configuration
from drillpy.progress import progress_bar

MODELS = ("SM_full", "SM_CB1", "SM_CB2")
POINT_LABELS = ("P_obs,1 (first free DP node)", "P_obs,2 (DP/BHA interface)", "P_obs,3 (bit)")
CASE_TITLES = {1: "mass uncertainty (Table 6.1)", 2: "damping uncertainty (Table 6.2)",
               3: "stiffness uncertainty (Table 6.3)", 4: "DP uncertainty (Table 6.4)",
               5: "BHA uncertainty (Table 6.5)", 6: "inner-DOF uncertainty (Table 6.6)",
               7: "interface-DOF uncertainty (Table 6.7)"}


def _trapezoid(*args, **kwargs):
    """scipy.integrate.trapezoid, imported when used (off the import path of `drillpy mc`)."""
    from scipy.integrate import trapezoid

    return trapezoid(*args, **kwargs)


def default_frequencies(n: int = 1000, f_min_hz: float = 0.01, f_max_hz: float = 10.0) -> np.ndarray:
    """The frequency grid of the envelope studies [Hz]: n points from 0.01 to 10 Hz by default.

    Parameters
    ----------
    n : int
        Number of frequencies (default 1000).
    f_min_hz, f_max_hz : float
        First and last frequency [Hz] (default 0.01 and 10 Hz; the first natural frequency of
        thesis-ch6 is 0.313 Hz).

    Returns
    -------
    numpy.ndarray
        Evenly spaced frequencies [Hz], shape (n,).
    """
    return np.linspace(f_min_hz, f_max_hz, int(n))


def n_substructures(cfg: dict) -> int:
    """Number of Craig-Bampton substructures: the sections of the string (DP, BHA, ...).

    Parameters
    ----------
    cfg : dict
        Configuration with ``string.sections``.

    Returns
    -------
    int
        ``len(cfg.string.sections)``.
    """
    return len(Configuration.of(cfg).string.sections)


def dispersions(cfg: dict, model: str = "SM_CB2", delta=None, case: int | None = None) -> np.ndarray:
    """Dispersion array (substructures, 3, 2) for ``model``.

    ``case`` (1-7) takes Tables 6.1-6.7 (SM_CB2 on DP + BHA); otherwise ``delta`` is a scalar
    (every dispersion), a dict ``{"M": x, "D": y, "K": z}``, or an array of shape (3,) for
    SM_full, (substructures, 3) for SM_CB1 or (substructures, 3, 2) for SM_CB2.

    A dispersion delta is that of Soize's SE+ / SE+0 random matrix (Eq. 6.3): the normalized
    standard deviation of the germ [G_A] about the identity; 0 keeps the matrix deterministic.
    Each must lie in [0, sqrt((n+1)/(n+5))) with n the dimension of the randomized block (checked
    by the engine when the model is built).

    Parameters
    ----------
    cfg : dict
        Configuration (its sections are the substructures).
    model : str
        "SM_full" (Eq. 6.4, one random reduced-order model of the whole string), "SM_CB1"
        (Eqs. 6.19-6.20, one random matrix per substructure) or "SM_CB2" (Eqs. 6.21-6.23,
        separate inner and interface random matrices per substructure).
    delta : float, dict or array_like, optional
        Dispersions [-] (default 0.1 for every matrix). For SM_CB1 inner and interface must be
        equal.
    case : int, optional
        Case study 1-7 of section 6.6 (Tables 6.1-6.7, dispersion 0.1 where the table randomizes):
        mass, damping, stiffness, DP, BHA, inner DOFs, interface DOF. Only for SM_CB2 on two
        substructures, and not together with ``delta``.

    Returns
    -------
    numpy.ndarray
        ``delta[k, a, s]`` for substructure k (DP = 0, BHA = 1), matrix a (M, D, K) and side s
        (inner, interface), shape (substructures, 3, 2) (one substructure for SM_full).

    Raises
    ------
    ValueError
        For an unknown model, a shape that does not fit it, or a case outside its scope.
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
    """A copy of ``cfg`` with ``craig_bampton.modes`` replaced (one count per section).

    Parameters
    ----------
    cfg : dict
        Configuration (not modified).
    modes : sequence of int
        Number of fixed-interface normal modes m_k of each substructure (Eq. 6.16).

    Returns
    -------
    dict
        A deep copy with ``craig_bampton = {"modes": [...]}``.
    """
    return Configuration.of(cfg).replace(craig_bampton={"modes": [int(m) for m in modes]}).to_dict()


def stochastic_model(cfg: dict, model: str = "SM_CB2", delta=None, case: int | None = None):
    """The engine's stochastic model (``_core.StochasticModel``) of a configuration.

    The object draws realization i of the random matrices M, D, K from ``(seed, i)`` and runs the
    FRF envelopes (``envelope``) and the time-domain severity samples (``severity_samples``).

    Parameters
    ----------
    cfg : dict
        Configuration (string, Craig-Bampton modes, damping).
    model : str
        "SM_full", "SM_CB1" or "SM_CB2" (see :func:`dispersions`).
    delta : float, dict or array_like, optional
        Dispersions [-] (see :func:`dispersions`; default 0.1).
    case : int, optional
        Case study 1-7 (Tables 6.1-6.7) instead of ``delta``.

    Returns
    -------
    _core.StochasticModel
        The engine object.
    """
    d = dispersions(cfg, model, delta, case)
    return _core.StochasticModel(engine_config(cfg), model, d)


def observation_nodes(cfg: dict) -> list[int]:
    """FE nodes of the observation points of section 6.6.

    Parameters
    ----------
    cfg : dict
        Configuration.

    Returns
    -------
    list of int
        Nodes of P_obs,1 (first free DP node), P_obs,2 (DP/BHA interface), P_obs,3 (bit); on
        thesis-ch6 nodes 1, 100 and 200.
    """
    return list(_core.observation_nodes(engine_config(cfg)))


@dataclass
class FRFEnvelope:
    """Monte Carlo statistics of the acceleration FRF, 20 log10 |a| [dB re 1 rad/s^2 per N m].

    Arrays ``nominal_db`` (mean model), ``mean_db`` (sample mean of the dB response),
    ``lower_db`` / ``upper_db`` (quantiles (1 -+ probability)/2) have shape (n_freq, n_points).
    ``energy[i, p]`` is the integral over the band of |a_i(omega)|^2 d omega for sample i
    (the integrand of Conv2, Eq. C.2).

    Attributes
    ----------
    freq_hz : numpy.ndarray
        Frequencies [Hz], shape (n_freq,).
    nodes : list of int
        FE nodes of the observation points.
    nominal_db : numpy.ndarray
        FRF of the mean (deterministic) model [dB re 1 rad/s^2 per N m], shape (n_freq, n_points).
    mean_db : numpy.ndarray
        Sample mean of the dB response [dB], same shape.
    lower_db, upper_db : numpy.ndarray
        Sample quantiles (1 - probability)/2 and (1 + probability)/2 of the dB response [dB]
        (linear interpolation), same shape.
    energy : numpy.ndarray
        integral_B |a_i(omega)|^2 d omega over the grid (omega in rad/s, trapezoid rule) for each
        sample i and point, [(rad/s^2 / (N m))^2 rad/s], shape (samples, n_points).
    model : str
        "SM_full", "SM_CB1" or "SM_CB2".
    delta : numpy.ndarray
        Dispersions used, ``delta[k, a, s]`` (:func:`dispersions`).
    samples : int
        Number of realizations.
    seed : int
        Random seed.
    probability : float
        Probability level P of the envelope (default 0.95).
    labels : list of str
        One label per observation point (P_obs,1-3 or "node N").
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
        """Conv2(n_s) of Eq. (C.2) for n_s = 1..samples: shape (samples, n_points).

        Conv2(n_s) = sqrt((1/n_s) sum_{i <= n_s} integral_B |a_i(omega)|^2 d omega)
        [rad/s^2 / (N m) sqrt(rad/s)], one column per observation point.
        """
        n = np.arange(1, self.energy.shape[0] + 1)[:, None]
        return np.sqrt(np.cumsum(self.energy, axis=0) / n)

    def to_json(self) -> dict:
        """JSON-ready envelope: model, samples, seed, probability, delta, ``freq_hz`` [Hz] and,
        per observation point, its label, node and the nominal, mean, lower and upper curves [dB]
        (``energy`` is left out)."""
        return {
            "model": self.model, "samples": self.samples, "seed": self.seed,
            "probability": self.probability, "delta": self.delta.tolist(),
            "freq_hz": self.freq_hz.tolist(),
            "points": [{"label": lab, "node": int(nd), "nominal_db": self.nominal_db[:, p].tolist(),
                        "mean_db": self.mean_db[:, p].tolist(), "lower_db": self.lower_db[:, p].tolist(),
                        "upper_db": self.upper_db[:, p].tolist()}
                       for p, (lab, nd) in enumerate(zip(self.labels, self.nodes))],
        }


def _grid(cfg: dict, freq_hz, nodes) -> tuple[np.ndarray, list[int], list[str]]:
    """Frequencies [Hz] (default :func:`default_frequencies`), observation nodes (default P_obs,1-3)
    and their labels."""
    f = default_frequencies() if freq_hz is None else np.ascontiguousarray(freq_hz, dtype=float)
    nd = observation_nodes(cfg) if nodes is None else [int(x) for x in nodes]
    labels = list(POINT_LABELS) if nodes is None else [f"node {x}" for x in nd]
    return f, nd, labels


def _envelope(r, sm, labels: list, seed: int, probability: float) -> FRFEnvelope:
    """The FRFEnvelope of the engine's ``_core.FrfEnvelope`` ``r`` computed with model ``sm``."""
    return FRFEnvelope(freq_hz=r.freq_hz, nodes=list(r.nodes), nominal_db=r.nominal_db,
                       mean_db=r.mean_db, lower_db=r.lower_db, upper_db=r.upper_db,
                       energy=r.energy, model=sm.model, delta=np.asarray(sm.delta), samples=r.samples,
                       seed=int(seed), probability=float(probability), labels=labels)


def frf_envelope(cfg: dict, model: str = "SM_CB2", delta=None, case: int | None = None, *,
                 samples: int = 2500, seed: int = 1, freq_hz=None, probability: float = 0.95,
                 nodes=None, progress: bool = True, threads: int = 0) -> FRFEnvelope:
    """Statistical envelope of the acceleration FRF for a unit torque at the bit (section 6.6).

    ``samples`` realizations of ``model`` (sample i from (seed, i) only), frequencies ``freq_hz``
    [Hz] (default :func:`default_frequencies`), observation ``nodes`` (default P_obs,1-3).
    Ctrl-C stops the study (KeyboardInterrupt). The same as :func:`envelope_from_samples` of
    :func:`frf_samples` (in any chunks of samples), bit for bit.

    The response is the acceleration a = -omega^2 u at each node for a unit harmonic torque at
    the bit (Eqs. 6.5, 6.15), shown as 20 log10 |a| [dB re 1 rad/s^2 per N m].

    Parameters
    ----------
    cfg : dict
        Configuration (e.g. ``load_config(preset="thesis-ch6")``).
    model : str
        "SM_full", "SM_CB1" or "SM_CB2" (default).
    delta : float, dict or array_like, optional
        Dispersions [-] (:func:`dispersions`; default 0.1).
    case : int, optional
        Case study 1-7 (Tables 6.1-6.7) instead of ``delta``.
    samples : int
        Number of realizations n_s (default 2500, thesis; Conv2 Eq. C.2 checks it).
    seed : int
        Random seed.
    freq_hz : array_like, optional
        Frequencies [Hz] (default :func:`default_frequencies`: 1000 points, 0.01-10 Hz).
    probability : float
        Probability level P of the envelope (default 0.95).
    nodes : sequence of int, optional
        FE nodes to observe (default :func:`observation_nodes`).
    progress : bool
        Show a tqdm progress bar.
    threads : int
        OpenMP threads (0: the OpenMP default).

    Returns
    -------
    FRFEnvelope
        Nominal, mean and quantile curves and the Conv2 integrand.
    """
    validate.integer("samples", samples, 1)
    validate.seed(seed)
    f, nd, labels = _grid(cfg, freq_hz, nodes)
    sm = stochastic_model(cfg, model, delta, case)
    with progress_bar(int(samples) + f.size, f"FRF envelope {model}", progress) as cb:
        r = sm.envelope(f, nd, int(samples), int(seed), float(probability), cb, threads)
    return _envelope(r, sm, labels, seed, probability)


def frf_samples(cfg: dict, model: str = "SM_CB2", delta=None, case: int | None = None, *,
                samples: int = 2500, seed: int = 1, first_sample: int = 0, freq_hz=None, nodes=None,
                progress: bool = True, threads: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Per-sample acceleration FRF of samples ``range(first_sample, first_sample + samples)``
    (section 6.6): the inputs of :func:`envelope_from_samples`, computed in chunks.

    Sample i is realization i of ``model`` from (seed, i) only, so chunks stacked in sample order
    equal one run over all samples bit for bit, whatever the chunks and thread counts. The
    response is the acceleration a = -omega^2 u at each node for a unit harmonic torque at the bit
    (Eqs. 6.5, 6.15). Ctrl-C stops the run (KeyboardInterrupt).

    Parameters
    ----------
    cfg : dict
        Configuration (e.g. ``load_config(preset="thesis-ch6")``).
    model : str
        "SM_full", "SM_CB1" or "SM_CB2" (default).
    delta : float, dict or array_like, optional
        Dispersions [-] (:func:`dispersions`; default 0.1).
    case : int, optional
        Case study 1-7 (Tables 6.1-6.7) instead of ``delta``.
    samples : int
        Number of realizations in the chunk (default 2500).
    seed : int
        Random seed.
    first_sample : int
        Index of the first realization; row r is sample ``first_sample + r``.
    freq_hz : array_like, optional
        Frequencies [Hz] (default :func:`default_frequencies`: 1000 points, 0.01-10 Hz).
    nodes : sequence of int, optional
        FE nodes to observe (default :func:`observation_nodes`).
    progress : bool
        Show a tqdm progress bar.
    threads : int
        OpenMP threads (0: the OpenMP default).

    Returns
    -------
    db : numpy.ndarray
        20 log10 |a| [dB re 1 rad/s^2 per N m] as float32 (the precision the envelope keeps),
        shape (samples, n_points, n_freq): ``db[r, p, f]`` for sample ``first_sample + r``, point p
        and frequency ``freq_hz[f]``.
    energy : numpy.ndarray
        integral_B |a_i(omega)|^2 d omega over the grid (omega in rad/s, trapezoid rule; the
        integrand of Conv2, Eq. C.2) [(rad/s^2 / (N m))^2 rad/s], shape (samples, n_points).
    """
    n = validate.integer("samples", samples, 1)
    first = validate.integer("first_sample", first_sample, 0, 2**62)
    seed = validate.seed(seed)
    f, nd, _ = _grid(cfg, freq_hz, nodes)
    sm = stochastic_model(cfg, model, delta, case)
    with progress_bar(n, f"FRF samples {model}", progress) as cb:
        db, energy = sm.frf_samples(f, nd, first, n, seed, cb, threads)
    return db, energy


def envelope_from_samples(cfg: dict, db, energy, model: str = "SM_CB2", delta=None, case: int | None = None, *,
                          seed: int = 1, freq_hz=None, probability: float = 0.95, nodes=None,
                          progress: bool = True, threads: int = 0) -> FRFEnvelope:
    """The envelope of :func:`frf_envelope` from :func:`frf_samples` results (section 6.6).

    ``db`` and ``energy`` are the arrays of all samples stacked in sample order (chunks
    concatenated along axis 0); the nominal curve is the mean model's. With the chunks of samples
    0 .. n_s - 1 the result equals :func:`frf_envelope` with ``samples = n_s`` bit for bit.

    Parameters
    ----------
    cfg : dict
        Configuration the samples were computed with.
    db : array_like
        20 log10 |a| [dB] per sample, point and frequency, shape (n_s, n_points, n_freq) (float32
        from :func:`frf_samples`).
    energy : array_like
        Band energy of each sample and point (Eq. C.2) [(rad/s^2 / (N m))^2 rad/s], shape
        (n_s, n_points).
    model : str
        "SM_full", "SM_CB1" or "SM_CB2" (default), as for the samples.
    delta : float, dict or array_like, optional
        Dispersions [-] of the samples (:func:`dispersions`; default 0.1).
    case : int, optional
        Case study 1-7 (Tables 6.1-6.7) instead of ``delta``.
    seed : int
        Random seed of the samples (recorded in the result).
    freq_hz : array_like, optional
        Frequencies [Hz] of the samples (default :func:`default_frequencies`).
    probability : float
        Probability level P of the envelope (default 0.95).
    nodes : sequence of int, optional
        FE nodes of the samples (default :func:`observation_nodes`).
    progress : bool
        Show a tqdm progress bar (counting frequencies).
    threads : int
        OpenMP threads (0: the OpenMP default).

    Returns
    -------
    FRFEnvelope
        Nominal, mean and quantile curves and the Conv2 integrand of the n_s samples.
    """
    seed = validate.seed(seed)
    f, nd, labels = _grid(cfg, freq_hz, nodes)
    sm = stochastic_model(cfg, model, delta, case)
    with progress_bar(f.size, f"FRF envelope {model}", progress) as cb:
        r = sm.envelope_from_samples(f, nd, np.asarray(db, dtype=np.float32), np.asarray(energy, dtype=float),
                                     float(probability), cb, threads)
    return _envelope(r, sm, labels, seed, probability)


def cb_frequencies(cfg: dict, n: int, modes=None) -> np.ndarray:
    """First n natural frequencies [Hz] of the assembled Craig-Bampton model (optionally with
    ``modes`` fixed-interface modes per substructure).

    Parameters
    ----------
    cfg : dict
        Configuration.
    n : int
        Number of frequencies.
    modes : sequence of int, optional
        Fixed-interface modes per substructure (default: the configuration's
        ``craig_bampton.modes``).

    Returns
    -------
    numpy.ndarray
        The n lowest natural frequencies [Hz].
    """
    c = cfg if modes is None else with_cb_modes(cfg, modes)
    return np.asarray(_core.cb_frequencies(engine_config(c), int(n)))


def band_widths(env: FRFEnvelope, bands_hz) -> np.ndarray:
    """Mean envelope width [dB] over each band (integral of the width over the band divided by
    its length, trapezoid rule): shape (n_bands, n_points).

    Parameters
    ----------
    env : FRFEnvelope
        The envelope.
    bands_hz : sequence of (float, float)
        Frequency bands (low, high) [Hz], each holding at least two grid frequencies (e.g.
        (0.01, 0.25), (0.25, 2), (2, 5), (5, 10)).

    Returns
    -------
    numpy.ndarray
        Mean width upper - lower [dB] per band and observation point.
    """
    out = []
    for lo, hi in bands_hz:
        sel = (env.freq_hz >= lo) & (env.freq_hz <= hi)
        if sel.sum() < 2:
            raise ValueError(f"band [{lo}, {hi}] Hz holds fewer than two grid frequencies")
        fr = env.freq_hz[sel]
        out.append(_trapezoid(env.width_db[sel], fr, axis=0) / (fr[-1] - fr[0]))
    return np.asarray(out)


def conv2_vs_modes(cfg: dict, substructure: int, modes, model: str = "SM_CB2", delta=None,
                   case: int | None = None, *, samples: int = 500, seed: int = 1, freq_hz=None,
                   progress: bool = True, threads: int = 0) -> np.ndarray:
    """Conv2 (Eq. C.2) with ``samples`` samples versus the number of fixed-interface modes of one
    substructure (the others keep the configuration's count): shape (len(modes), n_points).

    One :func:`frf_envelope` study per mode count (Figs. C.3-C.4); each value is Conv2 at its
    last sample.

    Parameters
    ----------
    cfg : dict
        Configuration.
    substructure : int
        Index of the substructure whose mode count varies (0: DP, 1: BHA).
    modes : sequence of int
        Mode counts to try.
    model : str
        "SM_full", "SM_CB1" or "SM_CB2" (default).
    delta : float, dict or array_like, optional
        Dispersions [-] (:func:`dispersions`; default 0.1).
    case : int, optional
        Case study 1-7 instead of ``delta``.
    samples : int
        Realizations per study (default 500).
    seed : int
        Random seed (the same for every mode count).
    freq_hz : array_like, optional
        Frequencies [Hz] (default :func:`default_frequencies`).
    progress : bool
        Show a tqdm progress bar per study.
    threads : int
        OpenMP threads (0: the OpenMP default).

    Returns
    -------
    numpy.ndarray
        Conv2(samples) [rad/s^2 / (N m) sqrt(rad/s)] per mode count and observation point.
    """
    base = list(Configuration.of(cfg).craig_bampton.modes)
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

