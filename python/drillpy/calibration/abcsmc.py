"""ABC-SMC with model choice on a batched simulator (NumPy only).

Population Monte Carlo approximate Bayesian computation (Beaumont et al. 2009, Biometrika 96:983;
with model choice, Toni et al. 2009, J. R. Soc. Interface 6:187 and Toni & Stumpf 2010): a
sequence of populations of N weighted particles (model m, parameters z) whose simulated summary
statistics lie within a shrinking tolerance eps_t of the observed ones.

* Parameters live in unit coordinates z in [0, 1]^d where every prior is uniform
  (:class:`drillpy.calibration.priors.Prior` maps uniform and log-uniform ranges); the model prior
  is uniform over the models.
* Generation 0 draws N particles from the prior, all kept. Generation t >= 1 sets eps_t to the
  weighted median of the previous population's distances and proposes particles in **batches**
  (the simulator runs a whole batch at once) until N have distance <= eps_t: the model from
  q(m) = (1 - s) P_{t-1}(m) + s / M, s the ``family_share`` spread evenly over the models (every model
  is proposed at least s / M of the time, so a model the population is losing keeps proposals,
  though it may end a generation without particles), then with probability rho a fresh prior draw
  (always, for a model with fewer than 2 particles), else a particle of that model
  drawn by weight and moved by a Gaussian kernel of twice the model's weighted covariance
  (Beaumont's choice) plus (:data:`KERNEL_FLOOR`)^2 I, or of :data:`KERNEL_FEW` on every axis when the
  model has fewer effective particles than its dimension + 2 (no covariance can be estimated). A proposal outside the unit cube has prior density 0: it counts as
  rejected without a simulation. Weights are prior / proposal density, w = pi(m) pi(z | m) / q(m, z),
  with q(m, z) = q(m) (rho + (1 - rho) sum_j W_j N(z; z_j, Sigma_m)): the importance weights of an
  exact accept-reject step, so model probabilities stay unbiased for the ABC posterior at eps_t.
* Model probabilities P(m) = sum of the weights of model m's particles; their Monte Carlo standard
  error is the self-normalized importance sampling one, sqrt(sum_i wn_i^2 (1[m_i = m] - P(m))^2), and
  each model's effective sample size is that of its particles' weights (:meth:`Population.model_ess`);
  a model without particles has a rule-of-three upper bound instead (:meth:`Population.upper95`),
  and :func:`model_choice` names the model the population supports or says that it cannot tell.
* Batches are sized to the particles still needed at the acceptance rate expected (the previous
  generation's, times the share of it the new eps keeps, then the rate measured so far), so that few
  simulations run past the N-th acceptance of a generation.
* It stops after ``max_generations``, when the budget ``max_simulations`` runs out in a generation
  (that generation's simulations are spent but not used), when a generation accepts fewer than
  ``min_acceptance`` of its simulations, or, with a model discrepancy, when eps reaches its level.
* A model discrepancy (``discrepancy``: noisy ABC, Wilkinson 2013, "Approximate Bayesian
  computation (ABC) gives exact results under the assumption of model error", Stat. Appl. Genet.
  Mol. Biol. 12(2):129) adds to every simulated statistic a Gaussian draw of the error the model is
  allowed to make: the record is then the model's output plus that error, and the ABC posterior is
  the one of that statement rather than of a model taken as exact. The tolerance is not shrunk
  below the discrepancy's level (:func:`discrepancy_floor`): a smaller eps would only select the
  draws of the error that happened to be small.

The proposals of generation t and batch b come from a generator keyed by (seed, t, b), and the
first N accepted in proposal order are kept: the result depends on the seed only, never on the
threads that run a batch.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


@dataclass
class Population:
    """One generation's accepted particles.

    Attributes
    ----------
    eps : float
        Its tolerance (inf for generation 0).
    model : ndarray of int
        Model index per particle.
    z : list of ndarray
        Unit coordinates per particle (length of the model's dimension).
    weight : ndarray
        Normalized importance weights.
    distance : ndarray
        Distance of each particle's statistics to the observed ones.
    stats : ndarray
        Summary statistics per particle (N x K).
    simulations : int
        Simulations this generation ran.
    proposals : int
        Proposals drawn (with those outside the prior's support).
    model_proposals : ndarray, optional
        Proposals of each model.
    raw_weight_sum : float
        Sum of the accepted particles' weights before normalization (prior / proposal).
    dead_ratio : ndarray, optional
        Per model without particles, an upper bound of its evidence over the surviving models' at this
        tolerance, carried from the generation where it had particles (:func:`dead_ratios`); NaN for a
        model with particles, inf where no bound is known.
    """
    eps: float
    model: np.ndarray
    z: list
    weight: np.ndarray
    distance: np.ndarray
    stats: np.ndarray
    simulations: int
    proposals: int
    model_proposals: np.ndarray | None = None
    raw_weight_sum: float = math.nan
    dead_ratio: np.ndarray | None = None

    def model_probabilities(self, n_models: int) -> tuple:
        """(P(m) per model, its Monte Carlo standard error) from the weights.

        Parameters
        ----------
        n_models : int
            Number of models.

        Returns
        -------
        tuple of ndarray
        """
        w = self.weight / self.weight.sum()
        p = np.array([w[self.model == m].sum() for m in range(n_models)])
        se = np.array([math.sqrt(float(np.sum(w ** 2 * ((self.model == m) - p[m]) ** 2))) for m in range(n_models)])
        return p, se

    def upper95(self, m: int) -> float | None:
        """95 % upper bound of P(m) for a model with no particle (None otherwise), where the
        standard error of :meth:`model_probabilities` (0) says nothing.

        The smaller of two bounds. (1) With no hit among its n_m proposals, the model's acceptance
        rate is below 3 / n_m at 95 % (the rule of three); at that rate its proposals would add at
        most 3 n / (n_m M) to the sum of weights (n proposals in all, a prior proposal's weight 1 /
        (M q(m)); a kernel proposal's is smaller where the kernel's density exceeds the prior's),
        against the population's ``raw_weight_sum`` W: P(m) < B / (W + B), B = 3 n / (n_m M). (2)
        From the generation where it last had particles, :attr:`dead_ratio` r: P(m) < r / (1 + r).
        1 when neither is known.

        Parameters
        ----------
        m : int
            Model index.

        Returns
        -------
        float or None
        """
        if np.any(self.model == m):
            return None
        out = 1.0
        if self.dead_ratio is not None and math.isfinite(self.dead_ratio[m]):
            r = float(self.dead_ratio[m])
            out = r / (1.0 + r)
        if self.model_proposals is None or not math.isfinite(self.raw_weight_sum):
            return out
        n_m = int(self.model_proposals[m])
        if n_m == 0:
            return out
        bound = 3.0 * self.proposals / (n_m * self.model_proposals.size)
        return min(out, float(bound / (self.raw_weight_sum + bound)))

    def difference_se(self, a: int, b: int) -> float:
        """Monte Carlo standard error of P(a) - P(b), the self-normalized importance sampling one
        (:meth:`model_probabilities`) of the indicator difference 1[m = a] - 1[m = b].

        Parameters
        ----------
        a, b : int
            Model indices.

        Returns
        -------
        float
        """
        w = self.weight / self.weight.sum()
        d = (self.model == a).astype(float) - (self.model == b)
        return math.sqrt(float(np.sum(w ** 2 * (d - np.sum(w * d)) ** 2)))

    def model_ess(self, n_models: int) -> np.ndarray:
        """Effective sample size of each model's particles, (sum w)^2 / sum w^2 over them (0 for a
        model without particles).

        Parameters
        ----------
        n_models : int
            Number of models.

        Returns
        -------
        ndarray
        """
        out = np.zeros(n_models)
        for m in range(n_models):
            w = self.weight[self.model == m]
            if w.size:
                out[m] = float(w.sum() ** 2 / np.sum(w ** 2))
        return out

    def ess(self) -> float:
        """Effective sample size of the weights."""
        w = self.weight / self.weight.sum()
        return float(1.0 / np.sum(w ** 2))


@dataclass
class ABCResult:
    """The populations of a run (the last is the posterior) and how it ended.

    Attributes
    ----------
    populations : list of Population
    n_models : int
    simulations : int
        Simulations run in all.
    stopped : str
        Why it stopped.
    history : list of dict
        Per generation: eps, simulations, proposals, acceptance (of its simulations), hit rate (of
        its proposals), ESS, model probabilities and their standard errors, each model's ESS and
        proposals.
    """
    populations: list
    n_models: int
    simulations: int
    stopped: str
    history: list = field(default_factory=list)

    @property
    def posterior(self) -> Population:
        """The last population."""
        return self.populations[-1]


#: Monte Carlo standard errors by which the most probable model must lead every other to be told
#: apart from it (:func:`model_choice`): a lead of 2 s.e. arises from Monte Carlo noise alone in about
#: 2.3 % of runs (one-sided, normal).
RESOLVE_SE = 2.0
#: Smallest Bayes factor of the most probable model over the next that :func:`model_choice` calls a
#: choice (Kass & Raftery 1995, J. Am. Stat. Assoc. 90:773: below 3, "not worth more than a bare
#: mention").
MIN_BAYES_FACTOR = 3.0
#: Smallest effective sample size at which :func:`model_choice` trusts the Monte Carlo standard error:
#: the error is a normal approximation on the ESS effective particles, which for a proportion p wants
#: ESS p (1 - p) of at least 5 or so (ESS 30 serves p from 0.2 to 0.8). One accepted prior draw of a
#: family the proposals seldom try can take most of the weight (docs/calibration.md, sample 175 with
#: four families) and leave an ESS of a few particles whose s.e. says little.
MIN_ESS = 30.0
#: Generations (after the prior's) over which :func:`model_choice` asks the chosen model's probability
#: to have settled as eps fell: ABC model probabilities from summary statistics are those of the
#: statistics at that tolerance (Robert et al. 2011, PNAS 108:15112), and a probability still moving
#: with eps is not the answer yet (docs/calibration.md: an Eq. 5.1 record whose P(Tucker-Wang) fell
#: from 0.93 to 0.81 over the last four generations).
SETTLE_GENERATIONS = 3
#: A change of a probability :func:`model_choice` does not count as a move (the sums of weights round:
#: a model alone in three populations has P 1 +- 0 in each, to the last bits).
SETTLE_ROUNDING = 1e-9


def choice_tolerance(factor: float) -> float:
    """The largest tolerance at which :func:`model_choice` names a model, with a model discrepancy of
    ``factor`` (0: none): twice the distance a right model's run lies at from the record, sqrt(2 +
    factor^2) (each statistic differs by the record's and the run's sampling noise, one unit each in
    the distance's units, and by the discrepancy's draw, ``factor`` units). Above it every accepted run
    is still farther from the record than a right model's runs are, and the model probabilities are
    those of the priors' predictive mass near the record (docs/calibration.md, "Model choice over
    many truths": a wrong family named at eps 9.98, the model without the jack at 3.09 and 3.68).

    Parameters
    ----------
    factor : float
        The model discrepancy's factor.

    Returns
    -------
    float
    """
    return 2.0 * math.sqrt(2.0 + float(factor) ** 2)


def model_choice(pop: Population, names: list, history: list | None = None, resolve_se: float = RESOLVE_SE,
                 min_bayes_factor: float = MIN_BAYES_FACTOR, min_ess: float = MIN_ESS,
                 settle: int = SETTLE_GENERATIONS, max_eps: float | None = None) -> dict:
    """Which model the population supports, or that it cannot tell (equal prior probabilities).

    The most probable model is the choice when its probability leads every other model's by more than
    ``resolve_se`` Monte Carlo standard errors of the difference (:meth:`Population.difference_se`),
    exceeds the 95 % upper bound of every model left without particles (:meth:`Population.upper95`),
    and its Bayes factor over the next (that bound for such a model) is at least
    ``min_bayes_factor``, on a population of at least ``min_ess`` effective particles, and when
    (given the run's ``history``) its probability over the last ``settle`` generations after the
    prior's has moved by no more than ``resolve_se`` standard errors of the difference between its
    highest and lowest values (sqrt(se_a^2 + se_b^2)), and (given ``max_eps``) when the final
    tolerance is at most ``max_eps`` (:func:`choice_tolerance`); otherwise the result cannot
    tell (``family`` None) and ``reason`` says which test failed: the Monte Carlo error (more
    particles or simulations could tell) or the evidence (the record does not tell, at this
    tolerance).

    Parameters
    ----------
    pop : Population
        The final population.
    names : list of str
        Model names, by index.
    history : list of dict, optional
        :attr:`ABCResult.history` (``model_probabilities``, ``model_probability_se`` per generation,
        the last being ``pop``'s); None skips the test that the probability has settled.
    resolve_se : float
        Leads, in standard errors of the difference, that tell two models apart.
    min_bayes_factor : float
        Smallest Bayes factor called a choice.
    min_ess : float
        Smallest effective sample size at which the standard errors are trusted (:data:`MIN_ESS`).
    settle : int
        Generations over which the probability must have settled (:data:`SETTLE_GENERATIONS`).
    max_eps : float, optional
        The largest final tolerance at which a model is named (:func:`choice_tolerance`; None: any).

    Returns
    -------
    dict
        ``family`` (the choice or None), ``most_probable``, ``runner_up``, ``lead`` (P difference),
        ``lead_se``, ``bayes_factor``, ``resolved`` (the lead exceeds ``resolve_se`` s.e. over
        every other model), ``ess``, ``drift`` (the probability at the first and the last of the
        settling generations), ``reason``, ``upper95`` (model without particles -> 95 % upper bound of
        its probability) and the thresholds.
    """
    M = len(names)
    p, _ = pop.model_probabilities(M)
    top = int(np.argmax(p))
    upper = {m: pop.upper95(m) for m in range(M)}
    out = {"most_probable": names[top], "resolve_se": resolve_se, "min_bayes_factor": min_bayes_factor,
           "min_ess": min_ess, "max_eps": max_eps, "ess": pop.ess(), "drift": None, "upper95": {names[m]: u for m, u in upper.items() if u is not None}}
    if M < 2:
        return {**out, "family": names[top], "runner_up": None, "lead": 1.0, "lead_se": 0.0, "bayes_factor": None,
                "resolved": True, "reason": "one model"}
    # a model without particles counts at its 95 % upper bound (its s.e. of 0 says nothing)
    ceiling = [p[m] if upper[m] is None else upper[m] for m in range(M)]
    others = [m for m in range(M) if m != top]
    second = max(others, key=lambda m: ceiling[m])
    resolved = all(p[top] - p[m] > resolve_se * pop.difference_se(top, m) if upper[m] is None
                   else p[top] > upper[m] for m in others)
    bf = float(p[top] / ceiling[second]) if ceiling[second] > 0 else math.inf
    failed = []
    if not resolved:
        failed.append(f"the lead over another model is within {resolve_se:g} Monte Carlo s.e. or below the 95 % "
                      "upper bound of a model left without particles")
    if out["ess"] < min_ess:
        failed.append(f"an effective sample size of {out['ess']:.3g} (below {min_ess:g}) leaves the s.e. unreliable")
    if history is not None:
        last = [h for h in history if h["generation"] > 0][-int(settle):]
        if len(last) < settle:
            failed.append(f"{len(last)} generations after the prior's, fewer than the {settle:g} over which the "
                          "probability must settle")
        else:
            ps = [h["model_probabilities"][top] for h in last]
            hi, lo = int(np.argmax(ps)), int(np.argmin(ps))
            se = math.hypot(last[hi]["model_probability_se"][top], last[lo]["model_probability_se"][top])
            out["drift"] = [float(ps[0]), float(ps[-1])]
            if ps[hi] - ps[lo] > resolve_se * se + SETTLE_ROUNDING:  # P = 1 in each: a rounding is no move
                failed.append(f"P({names[top]}) still moved from {ps[0]:.3f} to {ps[-1]:.3f} over the last {settle} "
                              "generations (more than its Monte Carlo error)")
    if max_eps is not None and pop.eps > max_eps:
        failed.append(f"eps {pop.eps:.3g} above {max_eps:.3g}: every accepted run is still farther from the record than a "
                      "right model's runs are (the probabilities are the priors' mass near the record)")
    if bf < min_bayes_factor:
        failed.append(f"Bayes factor {bf:.3g} over {names[second]} below {min_bayes_factor:g}")
    reason = "cannot tell: " + "; ".join(failed) if failed else "chosen"
    return {**out, "family": names[top] if reason == "chosen" else None, "runner_up": names[second],
            "lead": float(p[top] - p[second]), "lead_se": pop.difference_se(top, second),
            "bayes_factor": bf if math.isfinite(bf) else None, "resolved": bool(resolved), "reason": reason}


#: Smallest kernel standard deviation, in unit coordinates (a share of the prior range).
KERNEL_FLOOR = 0.01
#: Kernel standard deviation of a model with fewer effective particles than its dimension + 2.
KERNEL_FEW = 0.1


def distance(stats: np.ndarray, observed: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """Root mean square of (stats - observed) / scale over the statistics (rows of ``stats``); inf
    where a statistic the observation has is missing (NaN) in a simulation.

    Parameters
    ----------
    stats : ndarray
        Simulated statistics (n x K, or K).
    observed : ndarray
        Observed statistics (K).
    scale : ndarray
        Scale of each statistic (K).

    Returns
    -------
    ndarray
        One distance per row.
    """
    s = np.atleast_2d(stats)
    r = (s - observed) / scale
    d = np.sqrt(np.mean(r ** 2, axis=1))
    d[~np.all(np.isfinite(r), axis=1)] = np.inf
    return d


def discrepancy_floor(discrepancy, scale) -> float:
    """The tolerance at which ABC under a model discrepancy stops: the root mean square of the
    discrepancy's standard deviations in the distance's units, sqrt(mean_k (sd_k / scale_k)^2) (the
    distance a draw of the discrepancy alone puts between a simulation and itself); 0 without one.

    Parameters
    ----------
    discrepancy : array_like
        Standard deviation of each statistic's discrepancy (K).
    scale : array_like
        Scale of each statistic in the distance (K).

    Returns
    -------
    float
    """
    r = np.asarray(discrepancy, float) / np.asarray(scale, float)
    return float(np.sqrt(np.mean(r ** 2))) if r.size else 0.0


def _kernel_density(z, centers, weights, chol_inv, log_norm):
    """sum_j W_j N(z; c_j, Sigma) for each row of z (Sigma given by its inverse Cholesky factor)."""
    diff = (z[:, None, :] - centers[None, :, :]) @ chol_inv.T
    q = np.sum(diff ** 2, axis=2)
    return np.exp(-0.5 * q + log_norm) @ weights


def dead_ratios(prev: Population, models: np.ndarray, eps: float, n_models: int) -> np.ndarray:
    """Upper bounds of the evidence of the models left without particles at the tolerance ``eps``,
    over the surviving models' evidence, from the previous generation ``prev``.

    The ABC evidence Z_m(eps) falls with eps, by the share c_m of model m's ABC posterior at the last
    tolerance whose distance is within the new one (Del Moral, Doucet & Jasra 2012: the weight update
    of a tolerance step), estimated by the weighted share of its particles in ``prev`` within ``eps``,
    with its effective sample size n_m: at most c_m + 2 sqrt(c_m (1 - c_m) / n_m) + 3 / n_m (the last
    term the rule of three where none is within). The surviving models' evidence falls by S = sum_a
    P(a) c_a (``prev``'s probabilities, each c_a at its 2-s.e. lower end). A model that had particles
    in ``prev`` and has none now: r = P(m) c_m,upper / S; one without particles in ``prev`` either:
    its ratio there over S (its evidence cannot grow as eps falls). Both are bounds at about 95 %, as
    the rule of three of :meth:`Population.upper95`'s prior proposals.

    Parameters
    ----------
    prev : Population
        The previous generation (its ``dead_ratio`` for models already without particles).
    models : ndarray of int
        The new generation's model per particle.
    eps : float
        The new tolerance.
    n_models : int
        Number of models.

    Returns
    -------
    ndarray
        Per model: the bound r (inf where none is known), NaN for a model with particles.
    """
    p, _ = prev.model_probabilities(n_models)
    lo, hi = np.zeros(n_models), np.ones(n_models)
    for m in range(n_models):
        sel = prev.model == m
        if not sel.any():
            continue
        w = prev.weight[sel] / prev.weight[sel].sum()
        ess = 1.0 / float(np.sum(w ** 2))
        c = min(1.0, float(np.sum(w[prev.distance[sel] <= eps])))  # a sum of weights may round above 1
        half = 2.0 * math.sqrt(c * (1.0 - c) / ess)
        lo[m], hi[m] = max(c - half, 0.0), min(1.0, c + half + 3.0 / ess)
    alive = np.array([np.any(models == m) for m in range(n_models)])
    survive = float(np.sum(p[alive] * lo[alive]))
    out = np.full(n_models, math.nan)
    for m in np.flatnonzero(~alive):
        if np.any(prev.model == m):
            r = p[m] * hi[m]
        elif prev.dead_ratio is not None:
            r = float(prev.dead_ratio[m])
        else:
            r = math.inf
        out[m] = r / survive if survive > 0 else math.inf
    return out


def run(simulate, dims: list, observed: np.ndarray, scale: np.ndarray, *, population: int = 200,
        max_simulations: int = 20000, max_generations: int = 20, min_acceptance: float = 0.02, seed: int = 0,
        rho: float = 0.0, family_share: float = 0.1, quantile: float = 0.5, discrepancy=None, log=None) -> ABCResult:
    """Run ABC-SMC with model choice.

    Parameters
    ----------
    simulate : callable
        ``simulate(m, Z) -> stats``: the summary statistics (n x K) of model ``m`` at the unit
        coordinates ``Z`` (n x dims[m]); NaN rows for a failed simulation.
    dims : list of int
        Dimension of each model's parameter.
    observed : ndarray
        The observed statistics (K).
    scale : ndarray
        Scale of each statistic in the distance (K, positive).
    population : int
        Particles per generation (at least 4).
    max_simulations : int
        Budget of simulations.
    max_generations : int
        Generations after the prior's.
    min_acceptance : float
        Stop when a generation accepts fewer than this fraction of its simulations.
    seed : int
        Seed of every random draw.
    rho : float
        Share of fresh prior draws among the proposals (a defensive mixture; 0 by default: an accepted
        prior draw far from the kernel's mass takes a weight that swamps the population's). A model
        with fewer than 2 particles is always proposed from its prior.
    family_share : float
        Share of the model proposals spread evenly over the models, in (0, 1]: model m is proposed with
        q(m) = (1 - s) P_{t-1}(m) + s / M, so at least s / M of the time (1: every model equally
        often, whatever its probability). A model with fewer than 2 particles is proposed from its
        prior, else by the kernel around its particles.
    quantile : float
        eps_t is this weighted quantile of the previous population's distances.
    discrepancy : array_like, optional
        Standard deviation of the model discrepancy of each statistic (K, in the statistics' units;
        None or all 0: none). Noisy ABC under model error (Wilkinson 2013, Stat. Appl. Genet. Mol.
        Biol. 12:129): each simulated statistic gets a draw of e ~ N(0, diag(discrepancy^2)) before
        its distance is taken, so that the accepted particles are those whose model *plus an error
        of that size* could have given the observation; the draws come from a generator keyed by
        (seed, t, b, 1), apart from the proposals'. eps_t is then held at the discrepancy's level,
        :func:`discrepancy_floor` (below it the draws of e alone keep most distances out), and the
        run stops after the generation that reaches it (``stopped`` = ``discrepancy``).
    log : callable, optional
        Called with one line per generation.

    Returns
    -------
    ABCResult
    """
    if int(population) < 4:
        raise ValueError(f"population = {population!r}: at least 4 particles")
    if int(max_simulations) < population:
        raise ValueError(f"max_simulations = {max_simulations!r}: at least the population ({population})")
    if isinstance(family_share, bool) or not (isinstance(family_share, (int, float)) and 0 < family_share <= 1):
        raise ValueError(f"family_share = {family_share!r}: a share in (0, 1] of the model proposals spread evenly "
                         "over the models")
    if not 0 < quantile < 1:
        raise ValueError(f"quantile = {quantile!r}: between 0 and 1")
    N, M = int(population), len(dims)
    observed, scale = np.asarray(observed, float), np.asarray(scale, float)
    disc = np.zeros(observed.size) if discrepancy is None else np.asarray(discrepancy, float)
    if disc.shape != observed.shape or not np.all(np.isfinite(disc) & (disc >= 0)):
        raise ValueError(f"discrepancy = {discrepancy!r}: one non-negative standard deviation per statistic")
    floor = discrepancy_floor(disc, scale)

    def noisy(stats, key):
        """The statistics plus their draw of the discrepancy (unchanged without one)."""
        if not disc.any():
            return stats
        e = np.random.default_rng(key + [1]).standard_normal(stats.shape)
        return stats + disc * e

    def sim_all(models, zs):
        K = observed.size
        out = np.full((len(models), K), np.nan)
        for m in range(M):
            idx = [i for i, mm in enumerate(models) if mm == m]
            if idx:
                out[idx] = np.asarray(simulate(m, np.array([zs[i] for i in idx]).reshape(len(idx), dims[m])), float)
        return out

    # generation 0: the prior
    rng = np.random.default_rng([seed, 0, 0])
    models = list(rng.integers(0, M, N))
    zs = [rng.random(dims[m]) for m in models]
    stats = noisy(sim_all(models, zs), [seed, 0, 0])
    d = distance(stats, observed, scale)
    pops = [Population(math.inf, np.array(models), zs, np.full(N, 1.0 / N), d, stats, N, N,
                       np.bincount(models, minlength=M), float(N))]
    total = N
    history = []
    stopped = "max_generations"

    def note(pop, t, hits=None):
        p, se = pop.model_probabilities(M)
        line = {"generation": t, "eps": pop.eps, "simulations": pop.simulations, "proposals": pop.proposals,
                "acceptance": hits / pop.simulations if t else 1.0,
                "hit_rate": hits / pop.proposals if t else 1.0, "ess": pop.ess(),
                "model_probabilities": p.tolist(), "model_probability_se": se.tolist(),
                "model_ess": pop.model_ess(M).tolist(), "model_proposals": pop.model_proposals.tolist()}
        history.append(line)
        if log:
            log(f"generation {t}: eps {pop.eps:.3g}, {pop.simulations} simulations (acceptance "
                f"{line['acceptance']:.2f}), ESS {pop.ess():.0f}, P(model) "
                + ", ".join(f"{a:.3f}+-{b:.3f} (ESS {e:.0f})" for a, b, e in zip(p, se, line["model_ess"])))

    note(pops[0], 0)
    for t in range(1, int(max_generations) + 1):
        prev = pops[-1]
        finite = np.isfinite(prev.distance)
        if not finite.any():
            stopped = "no finite distance in the prior's population"
            break
        order = np.argsort(prev.distance)
        cw = np.cumsum(prev.weight[order]) / prev.weight.sum()
        eps = max(float(prev.distance[order][min(np.searchsorted(cw, quantile), N - 1)]), floor)
        p_prev, _ = prev.model_probabilities(M)
        qm = (1 - family_share) * p_prev + family_share / M
        kern = []
        for m in range(M):
            sel = prev.model == m
            if sel.sum() < 2:
                kern.append(None)
                continue
            Zm = np.array([prev.z[i] for i in np.flatnonzero(sel)])
            Wm = prev.weight[sel] / prev.weight[sel].sum()
            mu = Wm @ Zm
            if 1.0 / np.sum(Wm ** 2) < dims[m] + 2:  # too few effective particles for a covariance
                cov = np.eye(dims[m]) * KERNEL_FEW ** 2
            else:
                cov = 2.0 * ((Zm - mu).T * Wm) @ (Zm - mu) + np.eye(dims[m]) * KERNEL_FLOOR ** 2
            L = np.linalg.cholesky(cov)
            Li = np.linalg.inv(L)
            log_norm = -0.5 * dims[m] * math.log(2 * math.pi) - float(np.sum(np.log(np.diag(L))))
            kern.append((Zm, Wm, L, Li, log_norm))
        acc_m, acc_z, acc_s, acc_d, acc_w = [], [], [], [], []
        sims = props = hits = 0
        n_prop = np.zeros(M, int)
        # proposals per accepted particle: the last generation's rate, times the share of its
        # population the new eps keeps (the quantile); each batch is sized to the particles still
        # needed, so that few simulations run past the N-th acceptance
        rate = (history[-1]["hit_rate"] if t > 1 else 1.0) * quantile
        b = 0
        while len(acc_m) < N:
            need = N - len(acc_m)
            size = int(min(max(math.ceil(need / max(rate, 1e-3)), 16), 8 * N))
            size = int(min(size, max_simulations - total - sims))
            if size <= 0:
                break
            b += 1
            rng = np.random.default_rng([seed, t, b])
            bm = rng.choice(M, size=size, p=qm / qm.sum())
            n_prop += np.bincount(bm, minlength=M)
            bz, inside = [], []
            for m in bm:
                k = kern[m]
                if k is None or rng.random() < rho:
                    z = rng.random(dims[m])
                else:
                    j = rng.choice(len(k[1]), p=k[1])
                    z = k[0][j] + k[2] @ rng.standard_normal(dims[m])
                bz.append(z)
                inside.append(bool(np.all((z >= 0) & (z <= 1))))
            props += size
            keep = [i for i in range(size) if inside[i]]
            st = noisy(sim_all([int(bm[i]) for i in keep], [bz[i] for i in keep]), [seed, t, b])
            sims += len(keep)
            dd = distance(st, observed, scale)
            hits += int(np.sum(dd <= eps))
            for i, si, di in zip(keep, st, dd):
                if di <= eps and len(acc_m) < N:
                    m, z = int(bm[i]), bz[i]
                    k = kern[m]
                    dens = (rho + (1 - rho) * float(_kernel_density(z[None, :], k[0], k[1], k[3], k[4])[0])
                            if k is not None else 1.0)
                    acc_m.append(m)
                    acc_z.append(z)
                    acc_s.append(si)
                    acc_d.append(di)
                    acc_w.append((1.0 / M) / (qm[m] * dens))
            rate = max(hits / props, 1e-3)
        total += sims
        if len(acc_m) < N:
            stopped = "max_simulations"
            break
        w = np.array(acc_w)
        pops.append(Population(eps, np.array(acc_m), acc_z, w / w.sum(), np.array(acc_d), np.array(acc_s), sims,
                               props, n_prop, float(w.sum()), dead_ratios(prev, np.array(acc_m), eps, M)))
        note(pops[-1], t, hits)
        if hits / sims < min_acceptance:
            stopped = "min_acceptance"
            break
        if floor > 0 and eps <= floor:
            stopped = "discrepancy"
            break
    return ABCResult(pops, M, total, stopped, history)
