"""Verdicts under declared uncertainty: sampling, robust classes, binomial intervals.

* :mod:`.settings`: the ``[uncertainty]`` settings (what is uncertain, and how much);
* :mod:`.sampling`: common random numbers and the sampled blocks and amplitude factors;
* :mod:`.robust`: Wilson intervals, the robustness classes and the sequential stopping rule;
* :mod:`.scenes`: the probability of overturning of one scene (batched kernel runs).
"""

from .robust import Robustness, wilson_interval
from .settings import UncertaintyConfig

__all__ = ["Robustness", "UncertaintyConfig", "wilson_interval"]
