"""Settings of the uncertainty sampling (the ``[uncertainty]`` section of a configuration).

Every spread is the coefficient of variation of a lognormal factor whose *median* is 1, so
the nominal block and record are the median sample (ln X ~ N(0, s^2), s = sqrt(ln(1 + cov^2))).
The defaults are declared, not measured; docs/user-guide.md says where each comes from.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class UncertaintyConfig:
    """What is uncertain in a scene, and how the probability of overturning is estimated."""

    #: Largest number of samples per scene; 0: nominal verdicts only (no probability) [-].
    samples: int = 40
    #: Samples drawn before the first stopping test, and between two tests [-].
    batch: int = 5
    #: Lognormal factor on the whole record (horizontals and vertical together) [-, cov].
    amplitude_cov: float = 0.05
    #: Lognormal factor on the restitution (capped at 1) [-, cov].
    restitution_cov: float = 0.05
    #: Lognormal factor on the friction coefficient [-, cov].
    friction_cov: float = 0.10
    #: Independent lognormal factors on the height and on the width [-, cov].
    size_cov: float = 0.02
    #: Normal scatter of a given azimuth [deg] (blank azimuths are scanned, not sampled).
    azimuth_sd_deg: float = 5.0
    #: Seed of the common random numbers (the same draws for every record and block) [-].
    seed: int = 20261123
    #: A scene is robust_stand when the interval's upper bound is below this probability [-].
    robust_below: float = 0.1
    #: A scene is robust_overturn when the interval's lower bound is above this probability [-].
    robust_above: float = 0.9
    #: Confidence of the two-sided Wilson interval on p_overturn [-].
    confidence: float = 0.90
    #: Precision target of a sensitive scene's p_overturn: sampling goes on until half the interval's width is
    #: at most this, or ``samples`` is reached (0.5 or more: stop as soon as the class is decided) [-].
    #: At p = 0.5 the 40 default samples give a 90 % half-width of 0.13; 0.1 needs about 65 samples.
    p_halfwidth: float = 0.1
    #: Grid of the rocking planes a block of blank azimuth is sampled in [deg]: the per-orientation probabilities
    #: are taken on it, plus the pulse axis and the nominal scan's governing plane; 0: the nominal scan's grid
    #: (``simulation.orientation_step_deg``). 10 deg took 16.3 s against 26.2 s on the bundled records and
    #: lowered the worst orientation's p by more than 0.1 in 4 of 188 scenes (docs/validation.md).
    orientation_step_deg: float = 0.0
    #: A block of unknown orientation: the probability for a uniformly random orientation is estimated on draws
    #: of one grid plane each (random permutations of the grid, the same for every scene), until half its 90 %
    #: interval (Wilson's, or the stratified mean's over the planes where narrower) is at most
    #: ``orientation_average_halfwidth`` or this many draws are in [-].
    orientation_average_samples: int = 120
    #: ... the precision target of that average [-] (0.10 gave rare errors of 0.28; 0.07 none over 0.2,
    #: docs/validation.md).
    orientation_average_halfwidth: float = 0.07
    #: Samples whose margin scan is run on each block's governing record (``overturn_scale_median``);
    #: 0 (the default) or ``samples`` = 0: off. Each costs a whole margin scan per block: about 50
    #: simulations, up to 230 for a block that stands up to ``simulation.margin_max_factor`` [-].
    margin_samples: int = 0
