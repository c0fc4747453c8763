"""The scenes of a body given by its scan (:class:`~.block.ShapeKind` ``scanned``): the vertical planes it is judged
in, and one plane's scene by the two-sided rocking model (:mod:`.two_sided`).

A scanned body rocks, in each vertical plane, about a pivot on either side at its own distance from G
(:mod:`pipeline.shapes.plane`). Which planes (:func:`scene_planes`):

* **a given azimuth** (the compass direction of the scan's +x axis) on two horizontals of known azimuth: every plane
  of the body on a grid (``step_deg``, over 360 deg: its two sides differ), each under the record's projection on
  that plane's compass direction; the worst is kept;
* **a blank azimuth** (or a record whose absolute azimuth is unknown): the body turned so that its weakest plane
  (:func:`pipeline.shapes.plane.weakest_plane`, the smallest footprint extent) faces the pulse axis and every plane of
  the record's grid over 360 deg; the worst is kept. The weakest plane is a stated choice, not a proof that no
  other orientation of the body is worse;
* **one horizontal**: its plane only, as for every block whatever its azimuth (its direction is rarely known): the
  body's weakest plane facing it, in both senses of the record.

A body's two sides differ, so a plane's compass direction runs over 360 deg (the projection on ``psi + 180`` is
the negated projection on ``psi``). The scene's verdict is the planar two-sided model's: it does not slide (the
friction demand is recorded and ``friction_exceeded`` flags a scene whose pivot would slip), and a ground falling
faster than gravity, the step budget or the free motion's cap leave the scene without a verdict (``model_limit``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..constants import G
from ..records.record import project
from ..shapes.plane import PlaneBody, plane_body, weakest_plane
from .block import BlockShape
from .codes import (
    STATUS_CHATTER,
    STATUS_GROUND_FLIGHT,
    STATUS_STEP_CAP,
    STATUS_TAIL_CAP,
    STATUS_TIE_HOLD,
    ContactMode,
)
from .orientation import PlaneResult
from .scene import FreeFlight, Guard, Physics, Response, Scene
from .settings import SimulationConfig
from .simulate import step_control
from .two_sided import rock_two_sided_compiled, two_sided_block

#: A plane replaces the worst so far only where its theta_max / alpha is larger by more than this fraction, so that
#: a mirror plane of a symmetric body (the same response to rounding) never displaces the first [-]
TIE_RTOL = 1e-9
#: The status bits that leave a scanned scene without a verdict
NO_VERDICT_STATUS = STATUS_GROUND_FLIGHT | STATUS_STEP_CAP | STATUS_TAIL_CAP


class ScannedPlane(NamedTuple):
    """One plane of a scanned scene.

    Attributes
    ----------
    record_deg : float
        Compass azimuth the record is projected on [deg, in [0, 360)].
    sense : float
        +1, or -1 for the recorded horizontal's opposite sense (one horizontal: its sense is the only freedom).
    body_deg : float
        The body's plane facing it, in its settled axes [deg, from x toward y, in [0, 360)].
    """

    record_deg: float
    sense: float
    body_deg: float


def scene_planes(shape: BlockShape, *, direction_deg: float, grid_deg: np.ndarray, single_component: bool,
                 azimuth_known: bool) -> list[ScannedPlane]:
    """The planes a scanned body is judged in on one record (see the module); ``grid_deg`` over [0, 180) is doubled
    to [0, 360). A direction ``psi`` of the record meets the body's plane ``B - psi`` (B: the compass direction of
    the body's +x; the body's y is 90 deg counter-clockwise of x seen from above)."""
    scan = shape.scan
    assert scan is not None
    given = azimuth_known and math.isfinite(shape.azimuth_deg)
    if single_component:                  # as for every block: the recorded plane, whatever the azimuth
        weak = weakest_plane(scan)
        return [ScannedPlane(direction_deg, 1.0, weak), ScannedPlane(direction_deg, -1.0, weak)]
    full = np.concatenate([grid_deg, grid_deg + 180.0])
    if given:
        return [ScannedPlane(float((shape.azimuth_deg - phi) % 360.0), 1.0, float(phi)) for phi in full]
    weak = weakest_plane(scan)
    return [ScannedPlane(float(psi % 360.0), 1.0, weak) for psi in (direction_deg, *full)]


def along(horizontal_ms2: np.ndarray, azimuth0_deg: float, plane: ScannedPlane) -> np.ndarray:
    """The record's horizontal motion along a plane's compass direction, in its sense [m s-2]."""
    return plane.sense * np.ascontiguousarray(project(np.atleast_2d(horizontal_ms2), azimuth0_deg, plane.record_deg),
                                              dtype=float)


def restitution_factor(body: PlaneBody, restitution: float) -> float:
    """The factor on the impact rule's ratios of a declared restitution (NaN: the rule's own, 1): the declared value
    over the geometric mean of the two sides' ratios, so that a rectangle's impacts keep the declared ratio."""
    if not math.isfinite(restitution):
        return 1.0
    two = body.two_sided()
    return restitution / math.sqrt(max(two.impact_ratio(1.0) * two.impact_ratio(-1.0), 1e-300))


def plane_scene(ah_ms2: np.ndarray, av_ms2: np.ndarray | None, dt_s: float, body: PlaneBody, *, restitution: float,
                mu: float, settings: SimulationConfig = SimulationConfig(), g_ms2: float = G, history: bool = False,
                width_factor: float = 1.0, height_factor: float = 1.0, restitution_scale: float = 1.0) -> Scene:
    """One plane's :class:`~.scene.Scene` by the two-sided model.

    Parameters
    ----------
    ah_ms2, av_ms2 : ndarray
        Ground acceleration along the plane's + side and vertical (None: none) [m s-2].
    dt_s : float
        Sampling interval [s].
    body : PlaneBody
    restitution : float
        The declared restitution (NaN: the impact rule's own) [-].
    mu : float
        Friction coefficient, against which the pivot's friction demand is flagged [-].
    width_factor, height_factor, restitution_scale : float
        A draw's factors on the body's sizes and on its impact ratios [-].
    """
    two = body.two_sided(width_factor=width_factor, height_factor=height_factor)
    factor = restitution_factor(body, restitution) * restitution_scale
    theta = np.zeros(np.asarray(ah_ms2).size) if history else np.zeros(0)
    av = np.zeros(0) if av_ms2 is None else np.ascontiguousarray(av_ms2, dtype=float)
    out = rock_two_sided_compiled(np.ascontiguousarray(ah_ms2, dtype=float), av, float(dt_s),
                                  two_sided_block(two, restitution_factor=factor, g_ms2=g_ms2),
                                  step_control(settings), theta)
    (a_plus, _r, _i), (a_minus, _r2, _i2) = two.side(1.0), two.side(-1.0)
    alpha = min(a_plus, a_minus)
    guard = ((Guard.model_limit if out.status & NO_VERDICT_STATUS and not out.overturned else 0)
             | (Guard.tie_hold if out.status & STATUS_TIE_HOLD else 0)
             | (Guard.event_cap if out.status & STATUS_CHATTER else 0))
    flight = out.status & STATUS_GROUND_FLIGHT and not out.overturned
    response = (Response.overturn if out.overturned else Response.free_flight if flight
                else Response.rock if out.n_uplifts else Response.rest)
    return Scene(physics=Physics.two_sided, response=response, overturned=bool(out.overturned),
                 theta_max=max(out.theta_max_plus / a_plus, out.theta_max_minus / a_minus),
                 n_impacts=int(out.n_impacts), t_overturn=float(out.t_overturn),
                 friction_demand=float(out.friction_max),
                 sliding_max_m=math.nan, free_flight=FreeFlight.ground_flight if flight else FreeFlight.none,
                 chatter=bool(out.status & STATUS_CHATTER), friction_exceeded=int(out.friction_max > mu),
                 theta_over_alpha=theta / alpha if history else None,
                 contact_modes=ContactMode.rock if out.n_uplifts else 0, guard=guard)


def worst_scanned(horizontal_ms2: np.ndarray, azimuth0_deg: float, av_ms2: np.ndarray | None, dt_s: float,
                  shape: BlockShape, planes: list[ScannedPlane], *, settings: SimulationConfig = SimulationConfig(),
                  g_ms2: float = G) -> tuple[PlaneResult, ScannedPlane]:
    """The worst of ``planes`` (overturned, then without a verdict, then the largest theta_max / alpha, the first of
    the planes on ties within :data:`TIE_RTOL`) as a :class:`~.orientation.PlaneResult` (its azimuth: the record's
    compass direction),
    and that plane."""
    assert shape.scan is not None
    best: tuple | None = None
    responses = []
    for pl in planes:
        sc = plane_scene(along(horizontal_ms2, azimuth0_deg, pl), av_ms2, dt_s, plane_body(shape.scan, pl.body_deg),
                         restitution=shape.restitution, mu=shape.mu, settings=settings, g_ms2=g_ms2)
        responses.append((pl.record_deg, sc.theta_max))
        rank = (sc.overturned, sc.verdict < 0)
        if best is None or rank > best[0] or (rank == best[0] and sc.theta_max > best[1].theta_max * (1 + TIE_RTOL)):
            best = (rank, sc, pl)
    assert best is not None
    return PlaneResult(scene=best[1], azimuth_deg=best[2].record_deg, planes_simulated=len(planes),
                       responses=tuple(responses)), best[2]
