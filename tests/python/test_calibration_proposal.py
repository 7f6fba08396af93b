"""The ABC-SMC's model proposal: the share spread evenly over the families (``calibration.family_share``,
docs/calibration.md "Keeping every family explored")."""
from __future__ import annotations

import math

import numpy as np
import pytest
from test_calibration import _config, _posterior_json, _truth_record

from drillpy.calibration import abcsmc
from drillpy.calibration.posterior import calibrate_record
from drillpy.calibration.priors import prior_spec


def _offset_simulator(offsets):
    """Model m's one statistic is its one parameter plus ``offsets[m]`` (observed 0, scale 1): the
    distance is |z + offset|."""
    def simulate(m, Z):
        return Z[:, :1] + offsets[m]
    return simulate


def _hand_weights(prev, cur, share, M):
    """The importance weights of ``cur``'s particles computed from their definition, one at a time:
    w = pi(m) pi(z | m) / [q(m) q(z | m)], pi(m) = 1 / M, pi(z | m) = 1 on [0, 1], q(m) = (1 - s) P(m)
    + s / M, q(z | m) the mixture over the previous population's particles of model m (weights W_j
    renormalized in it) of Gaussians of variance 2 var_W + 0.01^2 (0.1^2 below 3 effective
    particles), or 1 (the prior) for a model with fewer than 2 particles; normalized."""
    P = [sum(w for w, mm in zip(prev.weight, prev.model) if mm == m) / sum(prev.weight) for m in range(M)]
    out = []
    for m, z in zip(cur.model, cur.z):
        qm = (1 - share) * P[m] + share / M
        zs = [float(zz[0]) for zz, mm in zip(prev.z, prev.model) if mm == m]
        ws = [float(w) for w, mm in zip(prev.weight, prev.model) if mm == m]
        if len(zs) < 2:
            qz = 1.0
        else:
            ws = [w / sum(ws) for w in ws]
            mu = sum(w * x for w, x in zip(ws, zs))
            var = (2 * sum(w * (x - mu) ** 2 for w, x in zip(ws, zs)) + 0.01 ** 2
                   if 1 / sum(w * w for w in ws) >= 3 else 0.1 ** 2)
            qz = sum(w * math.exp(-0.5 * (float(z[0]) - x) ** 2 / var) / math.sqrt(2 * math.pi * var)
                     for w, x in zip(ws, zs))
        out.append((1.0 / M) / (qm * qz))
    return np.array(out) / sum(out)


def test_the_weights_are_prior_over_the_proposal_computed_by_hand_on_a_tiny_population():
    """Two models, one parameter each, 6 particles, share 0.6: every generation's weights equal the
    hand computation, in a run where a model proposed from its prior (fewer than 2 particles) and
    a model proposed by its kernel both have accepted particles."""
    share, M = 0.6, 2
    res = abcsmc.run(_offset_simulator([0.0, 0.3]), [1, 1], np.zeros(1), np.ones(1), population=6,
                     max_simulations=400, max_generations=4, seed=0, family_share=share, min_acceptance=0.0)
    branches = set()
    for prev, cur in zip(res.populations, res.populations[1:]):
        np.testing.assert_allclose(cur.weight, _hand_weights(prev, cur, share, M), rtol=1e-12)
        for m in set(cur.model.tolist()):
            branches.add("prior" if np.sum(prev.model == m) < 2 else "kernel")
    assert branches == {"prior", "kernel"}, branches


def _weak_model_run(share, seed):
    """Model 1's statistic is 8 times its parameter (model 0's is the parameter): near the observed 0
    it has 1/8 of model 0's prior mass, P(1) = 1/9 at a small tolerance."""
    def simulate(m, Z):
        return Z[:, :1] * (8.0 if m else 1.0)
    return abcsmc.run(simulate, [1, 1], np.zeros(1), np.ones(1), population=20, max_simulations=1500,
                      max_generations=6, seed=seed, family_share=share, min_acceptance=0.0)


def test_the_share_keeps_a_family_the_population_is_losing_proposed_and_alive():
    """With the old 10 % the weak model (P 1/9) is proposed about 5 % of the time once it falls behind
    and ends without particles (seeds 0-5, 20 particles, 6 generations); proposed equally often
    (share 1) it keeps at least 40 % of every generation's proposals and ends with particles."""
    for seed in range(6):
        old, new = _weak_model_run(0.1, seed), _weak_model_run(1.0, seed)
        assert old.history[-1]["model_ess"][1] == 0 and old.history[-1]["model_proposals"][1] \
            < 0.15 * old.history[-1]["proposals"], old.history[-1]
        assert all(h["model_proposals"][1] >= 0.4 * h["proposals"] for h in new.history[1:]), new.history
        assert new.history[-1]["model_ess"][1] >= 3, new.history[-1]


def test_the_share_is_read_from_the_configuration_same_seed_same_numbers_on_any_thread_count():
    rec = _truth_record(duration=6.0)
    fams = ["polynomial_hysteretic", "polynomial", "tucker_wang", "hysteretic"]
    kw = dict(population=8, max_simulations=60, predictive_draws=2, seed=11)
    a = calibrate_record(rec, config=_config(families=fams, family_share=0.8), threads=1, **kw)
    b = calibrate_record(rec, config=_config(families=fams, family_share=0.8), threads=2, **kw)
    c = calibrate_record(rec, config=_config(families=fams), threads=1, **kw)
    assert _posterior_json(a) == _posterior_json(b)
    assert a.run["family_share"] == 0.8 and c.run["family_share"] == 0.1
    assert a.run["history"] != c.run["history"]  # the share changed the proposals
    assert all(len(h["model_ess"]) == 4 for h in a.run["history"])


@pytest.mark.parametrize("value", [0, -0.1, 1.5, math.nan, "0.5", True])
def test_a_bad_share_is_one_error_naming_the_field_and_the_value(value):
    with pytest.raises(ValueError, match=r"calibration\.family_share = .*: a number in \(0, 1\]"):
        prior_spec({"family_share": value})
    with pytest.raises(ValueError, match=r"calibration\.family_share = "):
        calibrate_record("never-read.mat", config=_config(family_share=value), population=4,
                         max_simulations=8)  # refused before the record is read
    with pytest.raises(ValueError, match=r"family_share = "):
        abcsmc.run(_offset_simulator([0.0]), [1], np.zeros(1), np.ones(1), population=4, max_simulations=8,
                   family_share=value)
