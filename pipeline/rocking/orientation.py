"""The worst rocking plane of a block whose orientation is not given.

A symmetric block rocks in a vertical plane of azimuth phi (phi and phi + 180
are the same plane). From two orthogonal horizontals a1 (azimuth phi1) and a2
(phi1 + 90 deg) the ground acceleration in that plane is
a(phi, t) = a1 cos(phi - phi1) + a2 sin(phi - phi1).

Overturning is not monotonic in phi, as it is not in amplitude, so no
projection of the record picks the worst plane in advance. The scan here
states what it guarantees:

1. every plane of the grid ``k * step_deg`` (k = 0 .. 180/step - 1), plus the
   planes the caller adds (the pulse axis), is tested for motion by the exact
   uplift / slip test (:func:`pipeline.rocking.planner.demand_ratio`); planes
   where the block provably stays at rest are not integrated;
2. the planes that move are simulated, strongest demand first; the first
   overturning ends the scan (the verdict is then "overturns");
3. when none overturns, the planes within ``step_deg`` of the plane with the
   largest rotation are simulated every ``refine_deg`` (refinement).

Guarantee: the scan's verdict is "overturns" whenever the block overturns in
any plane of the grid (or an added plane), with the same simulator and
settings. Planes between grid points are covered only by the refinement
around the worst standing plane; a narrow overturning window elsewhere
between two grid planes can be missed.

References
----------
docs/validation.md (the scan's grids and the pulse axis alone against each other, ``screen bench``);
Zhang, J. & Makris, N. (2001), J. Eng. Mech. 127(5), 473-483, for the rocking plane of a block under two
horizontal components.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from enum import IntEnum

import numpy as np

from ..constants import G
from ..records.record import project
from .block import Block
from .numerics.ground import QuietTable, quiet_table
from .planner import REST_SCENE, Response, Scene, demand_ratio, motion_threshold, simulate_scene
from .settings import SimulationConfig
from .simulate import FiniteSeries, finite_series

#: Rounding allowance on angles of the orientation grid [deg] (the grid ends short of 180 deg; a span that is a
#: whole number of refinement steps is that many)
GRID_TOL_DEG = 1e-9


class Orientation(IntEnum):
    """How the rocking plane of a scene was chosen."""

    given = 0                 # the block's azimuth, on a record of known azimuth
    scanned = 1               # blank azimuth: the worst plane of the scan
    scanned_relative = 2      # the same, on a record of unknown absolute azimuth (relative orthogonal pair)
    single_component = 3      # one horizontal recorded: its plane only
    axisymmetric = 4          # a cylinder on two horizontals: no plane, the 3D model (the azimuth: where it leant)
    given_3d = 5              # a box with a depth at its azimuth, on two horizontals: the 3D model (where it leant)
    given_certified = 6       # the same box, its other base axis certified never to lift nor slip: the plane of its
    #                           width, whose equation the 3D model then follows


def plane_grid(step_deg: float) -> np.ndarray:
    """Azimuths of the scanned planes, ``k * step_deg`` in [0, 180) [deg]."""
    return np.arange(0.0, 180.0 - GRID_TOL_DEG, step_deg)


class Planes:
    """A record's horizontal motion projected on rocking planes, cached per plane.

    Parameters
    ----------
    horizontal_ms2 : ndarray, shape (n_h, npts)
        One or two horizontals [m s-2]; the second 90 deg clockwise of the first.
    azimuth0_deg : float
        Azimuth of the first horizontal [deg].
    vertical_ms2 : ndarray or None
        Vertical acceleration, up positive [m s-2].
    g_ms2 : float
        Gravity [m s-2].
    """

    def __init__(self, horizontal_ms2: np.ndarray, azimuth0_deg: float, vertical_ms2: np.ndarray | None,
                 *, g_ms2: float = G) -> None:
        self.h = np.atleast_2d(horizontal_ms2)
        for k, h in enumerate(self.h):
            finite_series(f"horizontal component {k + 1}", h)
        self.az0 = float(azimuth0_deg)
        self.vertical = None if vertical_ms2 is None else finite_series("vertical acceleration", vertical_ms2)
        self.g = g_ms2
        self._along: dict[float, np.ndarray] = {}
        self._ratio: dict[float, float] = {}
        self._quiet: dict[float, QuietTable] = {}
        self._vector_ratio: float | None = None
        self._orders: dict[tuple, tuple[list[float], np.ndarray]] = {}

    @staticmethod
    def key(azimuth_deg: float) -> float:
        """The plane of ``azimuth_deg``, in [0, 180), rounded to 1e-6 deg."""
        return round(float(azimuth_deg) % 180.0, 6) % 180.0

    def along(self, azimuth_deg: float) -> np.ndarray:
        """Horizontal acceleration in the plane of ``azimuth_deg`` [m s-2]."""
        k = self.key(azimuth_deg)
        if k not in self._along:
            # a combination of finite series is finite: checked once here, not at every simulation
            self._along[k] = np.ascontiguousarray(project(self.h, self.az0, float(azimuth_deg)),
                                                  dtype=np.float64).view(FiniteSeries)
        return self._along[k]

    def quiet(self, azimuth_deg: float) -> QuietTable:
        """The plane's :class:`~.numerics.ground.QuietTable` (with the vertical, where recorded), built once and
        shared by every block simulated in it."""
        k = self.key(azimuth_deg)
        if k not in self._quiet:
            self._quiet[k] = quiet_table(self.along(azimuth_deg), self.vertical)
        return self._quiet[k]

    def ratio(self, azimuth_deg: float) -> float:
        """Demand ratio max |a| / (g + a_v) in that plane (:func:`planner.demand_ratio`)."""
        k = self.key(azimuth_deg)
        if k not in self._ratio:
            self._ratio[k] = demand_ratio(self.along(azimuth_deg), self.vertical, g_ms2=self.g)
        return self._ratio[k]

    def by_demand(self, keys: tuple) -> tuple[list[float], np.ndarray]:
        """The planes ``keys`` sorted by decreasing demand ratio (ties in the given order), with their
        ratios; computed once per record and list of planes (every scanned block of a record shares it)."""
        if keys not in self._orders:
            ratios = np.array([self.ratio(k) for k in keys])
            order = np.argsort(-ratios, kind="stable")
            self._orders[keys] = ([keys[i] for i in order], ratios[order])
        return self._orders[keys]

    def vector_ratio(self) -> float:
        """max_t |a_vec(t)| / (g + a_v(t)): no plane's demand ratio exceeds it (exact certificate; computed
        once per record, asked once per block)."""
        if self._vector_ratio is None:
            self._vector_ratio = demand_ratio(np.sqrt(np.sum(self.h ** 2, axis=0)), self.vertical, g_ms2=self.g)
        return self._vector_ratio


@dataclass(frozen=True)
class PlaneResult:
    """The governing plane of a scene and its simulated outcome."""

    scene: Scene
    #: azimuth of the governing plane [deg, in [0, 180)]
    azimuth_deg: float
    #: planes integrated (0: proven at rest in every plane)
    planes_simulated: int
    #: each plane integrated, as (azimuth [deg], theta_max / alpha), in the order simulated (the scan stops at the
    #: first plane that overturns; the planes proven at rest are not listed)
    responses: tuple = ()


def _worse(a: Scene, b: Scene) -> bool:
    """True when scene ``a`` is worse than ``b`` (overturn, free flight, then rotation, then sliding)."""
    def rank(s: Scene) -> tuple:
        return (s.overturned, s.response == Response.free_flight, s.theta_max,
                0.0 if math.isnan(s.sliding_max_m) else s.sliding_max_m)
    return rank(a) > rank(b)


def worst_plane(planes: Planes, azimuths_deg, dt_s: float, *, block: Block,
                settings: SimulationConfig = SimulationConfig(), refine_span_deg: float = 0.0,
                refine_deg: float = 0.0) -> PlaneResult:
    """Simulate a block in each plane of ``azimuths_deg`` that moves and return the worst.

    Parameters
    ----------
    planes : Planes
        The record's projections.
    azimuths_deg : sequence of float
        Planes to test [deg]; the first is reported when the block rests in every plane.
    dt_s : float
        Sampling interval [s].
    block : Block
        The block (:meth:`pipeline.blocks.Inventory.rocking_blocks`).
    settings : SimulationConfig
        Integration settings.
    refine_span_deg, refine_deg : float
        When no plane overturns, the planes within ``refine_span_deg`` of the worst one are also
        simulated every ``refine_deg`` (0: no refinement).
    """
    keys = tuple(dict.fromkeys(Planes.key(a) for a in azimuths_deg))
    first = keys[0]
    thr = motion_threshold(block.alpha, block.mu)
    if len(keys) > 1 and not planes.vector_ratio() > thr:
        return PlaneResult(REST_SCENE, first, 0)            # no plane can lift or slip the block
    state = PlaneResult(REST_SCENE, first, 0)
    guard = 0                                               # the guards met in any plane (Guard bits)
    responses: list[tuple[float, float]] = []

    def scan(candidates: tuple) -> bool:
        """Simulate the candidates that move the block, strongest demand first; True at the first overturn."""
        nonlocal state, guard
        ordered, ratios = planes.by_demand(candidates)
        moving = int(np.count_nonzero(ratios > thr))        # sorted by decreasing ratio: a prefix moves
        for k, ratio in zip(ordered[:moving], ratios[:moving].tolist()):
            sc = simulate_scene(planes.along(k), planes.vertical, dt_s, ratio=ratio, block=block, settings=settings,
                                quiet=planes.quiet(k))
            guard |= sc.guard
            responses.append((k, float(sc.theta_max)))
            n = state.planes_simulated + 1
            none_yet = state.planes_simulated == 0              # a simulated scene replaces the rest scene
            state = PlaneResult(sc, k, n) if none_yet or sc.overturned or _worse(sc, state.scene) else \
                PlaneResult(state.scene, state.azimuth_deg, n)
            if sc.overturned:
                return True
        return False

    if not scan(keys) and refine_deg > 0 and refine_span_deg > refine_deg and state.scene.theta_max > 0:
        m = int(math.ceil(refine_span_deg / refine_deg - GRID_TOL_DEG))
        extra = dict.fromkeys(Planes.key(state.azimuth_deg + j * refine_deg) for j in range(-m + 1, m) if j)
        scan(tuple(k for k in extra if k not in keys))
    scene = replace(state.scene, guard=guard) if guard != state.scene.guard else state.scene
    return PlaneResult(scene, state.azimuth_deg, state.planes_simulated, tuple(responses))
