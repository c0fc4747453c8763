"""Settings of the simulator (the ``[simulation]`` section of a configuration).

The simulator owns this dataclass; :mod:`pipeline.config` maps a TOML file onto it.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum


class ScannedModel(str, Enum):
    """The model a body given by its scan is judged by (``[simulation] scanned_model``): in each vertical plane, or
    in 3D."""

    rolling = "rolling"         # on the pivots of its convex hull's outline in turn (pipeline.rocking.scanned.rolling)
    two_sided = "two_sided"     # on one pivot per side, the footprint's extremes (pipeline.rocking.scanned.two_sided)
    contact3d = "contact3d"     # in 3D on its hull, every contact mode (pipeline.rocking.scanned.hull3d; not in planes)


@dataclass(frozen=True)
class SimulationConfig:
    """The rocking and sliding simulator (:mod:`pipeline.rocking`)."""

    #: Relative tolerance of the Runge-Kutta error control [-].
    rtol: float = 1e-7
    #: Absolute tolerance as a fraction of alpha (theta) and p alpha (omega) [-].
    atol: float = 1e-9
    #: An impact whose rebound is below rest_ratio * p * alpha puts the block to rest [-].
    rest_ratio: float = 1e-6
    #: True (default): the small flights of an impact cascade near rest are taken in closed form
    #: (:mod:`pipeline.rocking.planar.chatter`) wherever the term it drops is within ``rtol``; False: every flight is
    #: stepped by Runge-Kutta and every impact located by Newton iterations (the ``reference`` tier does this;
    #: ``screen bench`` measures the difference).
    closed_form_chatter: bool = True
    #: Largest integration step as a fraction of 1/p [-].
    max_step_p: float = 0.05
    #: Cap on impacts plus uplifts per scene (chatter guard; the scene is flagged) [-].
    max_events: int = 200000
    #: 0 (default): the vertical is simulated whenever the record has one. A positive value is an
    #: approximation that drops a vertical whose peak stays at or below this fraction of g from the
    #: simulation (never from the at-rest decision); ``screen bench`` measures its effect [-].
    vertical_fraction: float = 0.0
    #: True (default): where pure rocking stops holding (the pivot's friction demand exceeds mu, the
    #: pivot lifts off, the ground falls faster than gravity) the general contact model (slide, slide-rock,
    #: free flight) continues the scene and decides its verdict. False: the pure-rocking verdict is kept
    #: and flagged (slide_rock), and free flight has no verdict (what ``screen bench`` compares with).
    contact_model: bool = True
    #: True (default): a cylinder's or a box's 3D scene whose exact model stops where its base would slide, twist
    #: or lift off, or follows a fall past alpha with its contact held, is decided by the 3D contact model
    #: (:mod:`pipeline.rocking.solids.contact3d`) over the whole record (physics ``contact3d``), in the
    #: probabilities and margins too (0.005 s per such run, median on the bundled run; docs/validation.md). False:
    #: a stopped scene has no verdict (unknown), a held fall keeps the exact model's overturning (held_past_alpha).
    contact3d: bool = True
    #: True (default): in the draws and the margin scan (which keep only the verdict), a box or a cylinder the
    #: contact model follows is handed back to its exact model wherever it turns on its base without slipping again
    #: (:mod:`pipeline.rocking.solids.alternate`; on the bundled run 97.8 % of its box verdicts and 97.0 % of its
    #: cylinder verdicts are the contact model's alone, which agrees with itself at half its step in 98.4 % and
    #: 99.3 %: docs/validation.md). False: the contact model follows it to the end alone.
    handback: bool = True
    #: A block with a blank azimuth (or any block on a record of unknown absolute azimuth) is
    #: simulated in every rocking plane k * orientation_step_deg that moves it (worst plane) [deg].
    orientation_step_deg: float = 5.0
    #: When no grid plane overturns the block, the planes within one grid step of the worst plane
    #: are also simulated every orientation_refine_deg (0: no refinement) [deg].
    orientation_refine_deg: float = 1.0
    #: Amplitude step of upward threshold scans, as a fraction of the uplift acceleration [-]
    #: (scans never bisect: overturning is not monotonic in amplitude).
    scan_step: float = 0.005
    #: Scans stop at this multiple of the uplift acceleration (or at the sliding line mu g) [-].
    scan_max_factor: float = 20.0
    #: A body given by its scan (inventory column ``mesh``) rolls on its convex hull ("rolling", the default: the
    #: model scored on the granite shake-table tests) or rocks on the footprint's extreme points within 2 mm of the
    #: base ("two_sided"); docs/validation.md measures both.
    scanned_model: str = ScannedModel.rolling
    #: Margin ``overturn_scale``: the factor on the governing record grows by this fraction per
    #: step, from the factor that first lifts the block (upward scan, no bisection) [-].
    margin_step: float = 0.01
    #: The margin scan stops at this factor on the record (reported as "more than this") [-].
    margin_max_factor: float = 10.0
    #: ... in steps of ``margin_step`` up to this factor (the largest margin that changes a recommendation, the
    #: report's 'restrain' bound), then in steps doubling from ``margin_step`` up to
    #: ``margin_coarse_step``, a factor there that overturns bisected back to ``margin_step`` [-].
    margin_fine_to: float = 1.5
    margin_coarse_step: float = 0.1
