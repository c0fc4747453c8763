"""Invariants of the reweighting, over random trees, rates and ages (Hypothesis): the posterior is a distribution;
likelihoods scaled by one factor change nothing; a rock that cannot topple leaves the prior as it was; an older
rock is less likely to have stood; the branch that topples the rocks fastest never gains weight."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from pipeline.uncertainty.ages import normal_age
from pipeline.uncertainty.constraint import Combine, combine, posterior_weights, survival_likelihood

branches = st.integers(min_value=2, max_value=12)
seeds = st.integers(min_value=0, max_value=2**32 - 1)


def _tree(n: int, seed: int):
    rng = np.random.default_rng(seed)
    prior = rng.uniform(0.05, 1.0, n)
    rates = rng.uniform(0.0, 3e-4, (2, n, 20))               # rocks x branches x draws [1/yr]
    return prior / prior.sum(), rates


@settings(max_examples=60, deadline=None)
@given(n=branches, seed=seeds, scale=st.floats(min_value=1e-6, max_value=1e3), rule=st.sampled_from(list(Combine)))
def test_the_posterior_is_a_distribution_and_ignores_a_common_factor(n, seed, scale, rule):
    prior, rates = _tree(n, seed)
    lik = np.array([survival_likelihood(r, normal_age(8_000, 1_000)) for r in rates])
    joint, _ = combine(lik, prior, rule)
    post = posterior_weights(prior, joint)
    assert np.all(post >= 0) and abs(post.sum() - 1) < 1e-12
    assert np.allclose(posterior_weights(prior, joint * scale), post, rtol=1e-10, atol=1e-15)


@settings(max_examples=40, deadline=None)
@given(n=branches, seed=seeds)
def test_a_rock_that_cannot_topple_leaves_the_prior(n, seed):
    prior, _ = _tree(n, seed)
    lik = survival_likelihood(np.zeros((n, 5)), normal_age(20_000, 3_000))
    assert np.allclose(posterior_weights(prior, lik), prior, rtol=1e-12)


@settings(max_examples=40, deadline=None)
@given(seed=seeds, mean=st.floats(min_value=500, max_value=50_000), extra=st.floats(min_value=1, max_value=20_000),
       sd=st.floats(min_value=0, max_value=5_000))
def test_an_older_rock_is_less_likely_to_have_stood(seed, mean, extra, sd):
    rates = np.random.default_rng(seed).uniform(1e-6, 1e-3, 30)
    young = normal_age(mean, sd).survival(rates)
    old = normal_age(mean + extra, sd).survival(rates)
    assert np.all(old <= young * (1 + 1e-12))


@settings(max_examples=60, deadline=None)
@given(n=branches, seed=seeds, rule=st.sampled_from(list(Combine)))
def test_the_fastest_toppling_branch_never_gains_weight(n, seed, rule):
    prior, rates = _tree(n, seed)
    rates[:, 0, :] = rates.max() * 1.5                       # branch 0 topples every rock fastest, in every draw
    lik = np.array([survival_likelihood(r, normal_age(10_000, 2_000)) for r in rates])
    post = posterior_weights(prior, combine(lik, prior, rule)[0])
    assert post[0] <= prior[0] * (1 + 1e-12)
