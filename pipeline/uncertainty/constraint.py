"""The constraint that standing fragile rocks put on a hazard model's logic tree.

Per end branch b of the tree and rock i (Purvance et al. 2008; Baker et al. 2013; Rood et al. 2020):

* the annual rate of toppling, the fragility integrated over the branch's hazard curve,
  lambda_ib = integral P(topple | im) |d lambda_b / d im| d im (:func:`.hazard.annual_rates`: the integral of
  ``screen fragility``, for many fragility draws on many branches at once);
* the probability that the rock stood through its age T_i, averaged over the age's uncertainty and over the
  fragility's draws (the fragility's own uncertainty, carried as draws rather than a point):
  L_ib = mean_d E_T[exp(-lambda_ib(d) T_i)] (:func:`survival_likelihood`);
* the likelihood of the branch given every rock (:func:`combine`): the product over the rocks (rocks
  toppled independently of one another), or, the conservative choice where the same earthquakes shake every
  rock of a site, the likelihood of the most constraining rock alone (the one whose survival the prior
  predicts least: the smallest sum_b w_b L_ib);
* the posterior weight w'_b = w_b L_b / sum_b w_b L_b (Bayes' rule; :func:`posterior_weights`).

References
----------
Anderson, J. G. & Brune, J. N. (1999). Methodology for using precarious rocks in Nevada to test seismic hazard
models. BSSA 89(2), 456-467. Purvance, M. D., Brune, J. N., Abrahamson, N. A. & Anderson, J. G. (2008).
Consistency of precariously balanced rocks with probabilistic seismic hazard estimates in southern California.
BSSA 98(6), 2629-2640. Baker, J. W., Whitney, J. W., Hanks, T. C., Abrahamson, N. A. & Board, M. P. (2013). Use
of fragile geologic structures as indicators of unexceeded ground motions and direct constraints on probabilistic
seismic hazard analysis. BSSA 103(3), 1898-1911. Rood, A. H., Rood, D. H., Stirling, M. W. et al. (2020).
Earthquake hazard uncertainties improved using precariously balanced rocks. AGU Advances 1(4), e2020AV000182.
"""

from __future__ import annotations

from enum import Enum
from typing import NamedTuple

import numpy as np

from ..errors import ConstraintError
from .ages import Age

#: A rock contradicts the hazard model where even its most favourable branch gives it less than this probability
#: of having stood through its age [-] (the best possible is 1: a branch under which it surely stands).
CONTRADICTION_LIKELIHOOD = 1e-3


class Combine(Enum):
    """How the rocks of one site combine into one likelihood per branch."""

    #: the most constraining rock alone (conservative where the same earthquakes shake every rock)
    strongest = "strongest"
    #: the product over the rocks (rocks toppled independently of one another: overstates the constraint
    #: where the same earthquakes shake them)
    independent = "independent"


class FragilityDraws(NamedTuple):
    """A rock's lognormal fragility: its fit and draws of it [IM in SI units]."""

    theta: float
    beta: float
    #: draws of the median (inf: nothing overturned in that draw; 0: everything did) and of the dispersion
    theta_draws: np.ndarray
    beta_draws: np.ndarray
    #: the largest IM level at which the fragility was tested (inf: not known)
    top_level: float


def survival_likelihood(rates: np.ndarray, age: Age) -> np.ndarray:
    """P(the rock stood through its age | branch): E over the draws (last axis) and the age of exp(-rate T) [-].

    Parameters
    ----------
    rates : ndarray, shape (..., draws)
        Toppling rates [1/yr] of each branch and fragility draw.
    """
    return np.mean(age.survival(rates), axis=-1)


def survival_error(rates: np.ndarray, age: Age) -> np.ndarray:
    """The Monte Carlo standard error of :func:`survival_likelihood` over the fragility's draws (last axis of
    ``rates``): the draws' standard deviation of E_T[exp(-rate T)] over the square root of their number [-]."""
    survival = age.survival(rates)
    n = survival.shape[-1]
    return np.std(survival, axis=-1, ddof=1) / np.sqrt(n) if n > 1 else np.zeros(survival.shape[:-1])


def combine(likelihoods: np.ndarray, prior: np.ndarray, rule: Combine) -> tuple[np.ndarray, int]:
    """One likelihood per branch from every rock's (``likelihoods``: rocks x branches).

    Returns
    -------
    likelihood : ndarray, shape (branches,)
    chosen : int
        The most constraining rock's index (``strongest``), -1 for ``independent``.
    """
    lik = np.asarray(likelihoods, dtype=float)
    if rule is Combine.independent:
        return np.prod(lik, axis=0), -1
    predicted = lik @ np.asarray(prior, dtype=float)          # each rock's prior probability of standing
    chosen = int(np.argmin(predicted))
    return lik[chosen], chosen


def posterior_weights(prior: np.ndarray, likelihood: np.ndarray) -> np.ndarray:
    """Bayes' rule over the end branches: w_b L_b / sum w_b L_b [-].

    Raises
    ------
    ConstraintError
        When every branch makes the rocks' survival impossible (sum w_b L_b = 0).
    """
    joint = np.asarray(prior, dtype=float) * np.asarray(likelihood, dtype=float)
    total = float(joint.sum())
    if not total > 0:
        raise ConstraintError("under every branch the rocks could not have stood through their ages (likelihood 0): "
                              "the rocks, their fragility or their ages contradict the whole hazard model; check the "
                              "ages' units (years) and the fragility's IM and component")
    return joint / total


def contradicting(likelihoods: np.ndarray) -> np.ndarray:
    """The rocks (rows of ``likelihoods``: rocks x branches) whose largest likelihood over the branches is below
    :data:`CONTRADICTION_LIKELIHOOD`: under every branch they could hardly have stood through their ages, so that
    the posterior would rest on whichever branch is least impossible, not on the rock's evidence. Their indices."""
    best = np.max(np.asarray(likelihoods, dtype=float), axis=1)
    return np.flatnonzero(~(best >= CONTRADICTION_LIKELIHOOD))
