"""The bound on a model left without particles, from the generation where it last had them
(abcsmc.dead_ratios; issue 35, item 2: a model choice that can name the model that reaches the record)."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from drillpy.calibration import abcsmc


def _sim(m, Z):
    """Model a: y = z; model b: y = 0.5 + 0.3 z (it cannot come below 0.5); noise 0.05."""
    rng = np.random.default_rng(int(1e6 * Z.sum()) % 2 ** 32)
    mu = Z[:, 0] if m == 0 else 0.5 + 0.3 * Z[:, 0]
    return (mu + rng.normal(0, 0.05, len(Z)))[:, None]


def _run(simulations: int):
    return abcsmc.run(_sim, [1, 1], np.array([0.2]), np.array([0.1]), population=200, max_simulations=simulations,
                      seed=2, max_generations=30)


def test_a_model_that_cannot_reach_the_record_is_bounded_from_where_it_died_and_the_other_is_named():
    """Observed 0.2 with a noise scale of 0.1: model b's runs stay about 3 units away. It dies as eps
    falls below that; the prior proposals' rule of three cannot bound it (their bound is about 0.5),
    the share of its last population within the next tolerance can, and the choice names a."""
    r = _run(6000)
    post = r.posterior
    assert not np.any(post.model == 1) and post.eps < 1.0
    c = abcsmc.model_choice(post, ["a", "b"], r.history)
    assert c["family"] == "a" and c["upper95"]["b"] < 0.2, c
    prior_only = dataclasses.replace(post, dead_ratio=None)
    c0 = abcsmc.model_choice(prior_only, ["a", "b"], r.history)
    assert c0["family"] is None and c0["upper95"]["b"] > 0.4, c0
    # once dead, the bound can only grow as eps falls: the survivors' evidence shrinks, b's cannot be
    # known to (its evidence does not grow as eps falls)
    dead = [p.dead_ratio[1] for p in r.populations[1:] if p.dead_ratio is not None and not np.any(p.model == 1)]
    assert len(dead) >= 2 and all(b >= a for a, b in zip(dead, dead[1:])), dead
    # far below b's floor the bound no longer names a (more generations, the same information on b)
    late = _run(20000)
    assert abcsmc.model_choice(late.posterior, ["a", "b"], late.history)["family"] is None


def test_dead_ratios_is_the_share_within_the_new_tolerance_over_the_survivors():
    """By hand: in the previous generation model 0 holds 3 particles of weight 0.6 (two of them within
    the new eps, 2/3 of its weight), model 1 two of 0.4 (none within); model 1 dies."""
    prev = abcsmc.Population(2.0, np.array([0, 0, 0, 1, 1]), [np.zeros(1)] * 5,
                             np.array([0.2, 0.2, 0.2, 0.2, 0.2]), np.array([0.5, 0.8, 1.5, 1.2, 1.9]),
                             np.zeros((5, 1)), 5, 5)
    r = abcsmc.dead_ratios(prev, np.array([0, 0, 0]), 1.0, 2)
    assert math.isnan(r[0])
    c0, ess0, ess1 = 2.0 / 3.0, 3.0, 2.0
    lo0 = c0 - 2.0 * math.sqrt(c0 * (1 - c0) / ess0)
    hi1 = min(1.0, 0.0 + 3.0 / ess1)
    assert r[1] == pytest.approx(0.4 * hi1 / (0.6 * lo0))
    # one generation later, still dead: its ratio over the survivors' share within the next eps
    new = abcsmc.Population(1.0, np.zeros(10, int), [np.zeros(1)] * 10, np.full(10, 0.1),
                            np.linspace(0.1, 1.0, 10), np.zeros((10, 1)), 10, 10, dead_ratio=r)
    r2 = abcsmc.dead_ratios(new, np.zeros(10, int), 0.65, 2)
    c = 0.6  # 6 of the 10 within 0.65
    assert r2[1] == pytest.approx(r[1] / (c - 2.0 * math.sqrt(c * (1 - c) / 10.0)))
