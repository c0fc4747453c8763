"""A 3D body's scene that left its exact model, run by the contact model and handed back to the exact model wherever
it turns on its base without slipping again (the draws and the margin scan, which keep only the verdict).

The contact model (:mod:`.contact3d`) follows every mode at once, in steps of at most 0.5 ms; an exact model (a box
on an edge or a corner, :mod:`.box3d`; a cylinder rolling on its rim, :mod:`.cylinder3d`) follows the body while its
contact holds, at the steps its error control allows. Once a body has slid, it mostly rocks on its base again with the
contact sticking. The contact model therefore stops at the first sample after a whole sampling interval turning on
one of the places the exact model can take it (:class:`ExactModel`'s ``edges``: a box's base edges, both corners
loaded; a cylinder's rim, one point or two neighbours loaded), every loaded vertex inside its friction cone and no
other vertex loaded, a step taken in parts judged by its last part (``edges`` of
:func:`~.contact3d.simulate_contact3d`), and the exact model goes on from there (its ``state_at``: the contact model's
state, changed by less than its own resolution). Where the exact model stops again (the base would slide or lift
off, or it falls past the tipping point with its contact held), the contact model goes on from the exact model's last
certified state, as in :mod:`.contact_scene`. Where the record ends while the body still moves, it stands if its
energy is below the least it needs to tip over (:func:`cannot_tip_over`: the ground is then still and the contacts
only take energy away), else the contact model follows it to rest or to its side (its tail). After
:data:`MAX_HANDBACKS` hand-backs the contact model runs to the end alone: the run always ends, with the contact
model's verdict.

The impacts: the contact model's plastic contacts give Housner's (1963) rule at a pivot, so the exact model runs with
Housner's restitution, the same physics; a declared restitution is the contact model's (which does not read it)
wherever this alternation runs.

Where the models meet, the verdict can differ from the contact model's alone where the scene is chaotic
(docs/validation.md measures how often, against the contact model and itself at half its step). Only the verdict,
the peak tilt and where it leant, the time of overturning and the costs are kept: not the sliding distance nor the
histories (the nominal scene, which reports them, runs the contact model alone).

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics. In Nonsmooth Mechanics and
Applications, CISM Courses and Lectures 302, 1-82. Springer.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from .attitude import energy, rotation_matrix
from .contact3d import Contact3DOutcome, prepare, simulate_contact3d
from .contact_start import Start
from .convex_body import ConvexBody
from .vec3 import FLAG_NONE

#: Hand-backs to the exact model at most in one scene; then the contact model goes on alone [-].
MAX_HANDBACKS = 50
#: A body still moving at the record's end stands where its energy is below the least it needs to tip over by at least
#: this fraction of that [-] (the rounding of the energy's terms).
ENERGY_MARGIN = 1e-9

#: How a body turns at a state: its orientation (unit quaternion (w, x, y, z)), its rate in the ground's frame
#: [rad s-1] and a point of it on the ground that does not slip (in its principal axes from G [m]).
Turning = tuple[np.ndarray, np.ndarray, np.ndarray]


class ExactModel(NamedTuple):
    """A body's exact model as the alternation uses it (a family's :func:`~.box_handback.box_model`,
    :func:`~.cylinder_handback.cylinder_model`).

    Attributes
    ----------
    body : ConvexBody
        the contact model's body
    edges : ndarray of int, shape (k, 2)
        where the exact model can take the body: the pairs of the contact model's vertices it turns on (a pair
        (i, i): the vertex i alone)
    run : callable
        ``run(ax, ay, az, state)``: the exact model from ``state`` at the first sample of the ground given [m s-2]
        (az None: none); an outcome with ``overturned``, ``t_overturn_s``, ``theta_max_rad``, ``azimuth_max_deg``,
        ``flag``, ``held``, ``handoff`` (whose ``state`` :attr:`turning` reads) and ``end``
    state_at : callable
        ``state_at(out)``: the exact model's state where the contact model's outcome ``out`` stopped on ``out.edge``
    turning : callable
        ``turning(state)``: how the body turns at one of the exact model's states (:data:`Turning`)
    ending : callable
        ``ending(outcome)``: how it turns where an exact run reached the record's end still moving
    at_rest : callable
        ``at_rest(outcome)``: the exact run reached the record's end at rest, flat and still
    barrier_m : float
        the least height G must rise to as the body tips over [m]: its distance to the nearest line of its base's
        edges (a box's sqrt(b^2 + h^2) over its narrower side, a cylinder's sqrt(a^2 + h^2))
    """

    body: ConvexBody
    edges: np.ndarray
    run: Callable[..., Any]
    state_at: Callable[[Contact3DOutcome], Any]
    turning: Callable[[Any], Turning]
    ending: Callable[[Any], Turning]
    at_rest: Callable[[Any], bool]
    barrier_m: float


def alternate(ax, ay, az, dt_s: float, model: ExactModel, azimuth_deg: float, start: Start | None, *,
              g_ms2: float) -> Contact3DOutcome:
    """The body (its x axis at ``azimuth_deg`` in the models' frame) under the ground (ax, ay, az) [m s-2] (az None:
    none) sampled at ``dt_s``, from ``start`` (None: at rest), by the contact model handed back to ``model`` wherever
    it turns on one of its ``edges`` without slipping; the contact model's outcome with the verdict, peak and costs
    of the whole run."""
    ax, ay = np.asarray(ax, dtype=float), np.asarray(ay, dtype=float)
    az = None if az is None or np.size(az) == 0 else np.asarray(az, dtype=float)
    peak, costs = (0.0, math.nan), _Costs()
    handbacks, prepared = 0, prepare(model.body, dt_s)
    while True:
        out = simulate_contact3d(ax, ay, az, dt_s, model.body, yaw_deg=azimuth_deg, g_ms2=g_ms2, start=start,
                                 edges=model.edges if handbacks < MAX_HANDBACKS else None, prepared=prepared)
        peak, costs = _peak(peak, out.tilt_max_rad, out.lean_at_peak_deg), costs.add(out)
        if out.edge < 0:
            return _whole(out, peak, costs)
        handbacks += 1
        i = int(round(out.t_end_s / dt_s))
        exact = model.run(ax[i:], ay[i:], None if az is None else az[i:], model.state_at(out))
        peak = _peak(peak, exact.theta_max_rad, exact.azimuth_max_deg)
        if exact.overturned and exact.held == FLAG_NONE:
            return _whole(out, peak, costs, overturned_at=i * dt_s + exact.t_overturn_s)
        lean = math.radians(peak[1])
        if exact.flag == FLAG_NONE and exact.held == FLAG_NONE:     # the exact segment ran to the record's end
            if model.at_rest(exact):
                return _whole(out, peak, costs)
            ending = model.ending(exact)
            if cannot_tip_over(ending, model, g_ms2):
                return _whole(out, peak, costs)
            start = Start(i * dt_s + (np.size(exact.theta) - 1) * dt_s, *ending, peak[0], lean)    # the tail
            continue
        start, certified = _resume(exact, out, model, i * dt_s, peak[0], lean)
        handbacks = handbacks if certified else MAX_HANDBACKS


def cannot_tip_over(turning: Turning, model: ExactModel, g_ms2: float) -> bool:
    """The body turning so (its orientation, rate and non-slipping point on the ground) on a ground at rest cannot tip
    over: its energy per unit mass, ``|v_G|^2 / 2 + omega . I omega / 2 + g z_G`` (:func:`~.attitude.energy`), is
    below ``g`` times the least height G must rise to (``model.barrier_m``) by :data:`ENERGY_MARGIN` of it. In the
    mechanics the contacts on a still ground only take energy away (Moreau 1988), so G never rises that high: the
    body neither lies on a side nor leaves its base for another face. The margin covers the energy's rounding, not
    what a stepped tail could gain (the contact model's steps are tested to gain at most 1e-9 J kg-1 each)."""
    q, rate, pivot = (np.asarray(v, dtype=float) for v in turning)
    r = rotation_matrix(q / np.linalg.norm(q))
    arm = -(r @ pivot)                                  # G from the non-slipping point, in the ground's frame
    e = energy(np.cross(rate, arm), rate, r, np.asarray(model.body.inertia, dtype=float), float(arm[2]), g_ms2)
    return e < (1.0 - ENERGY_MARGIN) * g_ms2 * model.barrier_m


class _Costs(NamedTuple):
    """What the contact model's runs of a scene cost and flagged, summed (:class:`~.contact3d.Contact3DOutcome`'s
    fields of the same names)."""

    steps: int = 0
    integrated_steps: int = 0
    sweeps: int = 0
    capped_steps: int = 0
    flags: int = 0
    flight: bool = False

    def add(self, out: Contact3DOutcome) -> _Costs:
        """These costs and ``out``'s."""
        return _Costs(self.steps + out.steps, self.integrated_steps + out.integrated_steps, self.sweeps + out.sweeps,
                      self.capped_steps + out.capped_steps, self.flags | out.flags, self.flight or out.flight)


def _peak(peak: tuple[float, float], tilt_rad: float, lean_deg: float) -> tuple[float, float]:
    """The larger of the peak tilt so far and ``tilt_rad`` [rad], with where it leant [deg]."""
    return (tilt_rad, lean_deg) if tilt_rad > peak[0] else peak


def _whole(out: Contact3DOutcome, peak: tuple[float, float], costs: _Costs,
           overturned_at: float = math.nan) -> Contact3DOutcome:
    """The scene's outcome: the last contact run's, with the whole run's peak and costs, overturned at
    ``overturned_at`` [s] where an exact segment overturned it (NaN: as the last contact run says)."""
    by_exact = math.isfinite(overturned_at)
    over = out.overturned or by_exact
    return out._replace(overturned=over, t_overturn=overturned_at if by_exact else out.t_overturn,
                        tilt_max_rad=0.5 * math.pi if over else peak[0], lean_at_peak_deg=peak[1],
                        edge=-1, q_end=None, rate_end_rad_s=None, **costs._asdict())


def _resume(exact, out: Contact3DOutcome, model: ExactModel, t0_s: float, tilt_rad: float,
            lean_rad: float) -> tuple[Start, bool]:
    """Where the contact model goes on after an exact segment that began at ``t0_s`` [s] and stopped before the
    record's end (the peak so far ``tilt_rad`` toward ``lean_rad``), and whether the exact model may take the scene
    again: its certified state where it stopped; where it stopped without one (its step cap), the contact model's own
    state where it handed the scene over (and the contact model goes on alone)."""
    if exact.handoff is not None:
        q, rate, pivot = model.turning(exact.handoff.state)
        return Start(t0_s + exact.handoff.t_s, q, rate, pivot, tilt_rad, lean_rad), True
    q_end, rate_end = np.asarray(out.q_end, dtype=float), np.asarray(out.rate_end_rad_s, dtype=float)
    pivot = np.asarray(model.body.vertices[model.edges[out.edge, 0]], dtype=float)
    return Start(out.t_end_s, q_end, rate_end, pivot, tilt_rad, lean_rad), False
