"""A rigid convex body on a moving rigid ground in 3D, every contact mode at once: stick, slide, twist, rock on an
edge or a corner, lift-off, free flight and landing, by Moreau-Jean time stepping (compiled).

The body is its convex hull's vertices (a box exactly by its eight corners; a cylinder by points of its rims) about
its centre of mass G, with its principal inertias per unit mass. Each vertex at or below the ground at the middle of
a step is a contact (looked for among a list of the vertices near the ground, kept between steps, that gives exactly
the same contacts: :mod:`.near_ground`) with Coulomb friction (the isotropic cone, ``|P_t| <= mu P_n``). The contact
impulses of the step solve the velocity-level complementarity problem of Moreau (1988) and Jean (1999): a contact
keeps its normal velocity at ``-e_n`` times its value before (``e_n = 0``: a plastic impact) or separates with no
impulse; it sticks, or slides with the largest friction against its slip. The problem is solved by projected
Gauss-Seidel over the contacts (Jean 1999), each contact by De Saxce and Feng's (1998) fixed point on the cone,
started from a Newton solve of all the contacts together where at most eight touch (:mod:`.contact_problem`), to a
stated tolerance or a cap of sweeps (the step is then flagged, never silently accepted). Where more touch (a
cylinder's base flat on its 32 rim points), it is first solved on the eight extreme ones, and that solution is kept
where every other contact, without impulse, does not approach the ground: then it solves the whole step
(:mod:`.contact_reduced`).

**Overturned** is the body lying on a side: its axis tilted to within :data:`LYING_SLACK_RAD` of the horizontal.
A box that falls lands on its side face at a tilt of pi/2 less what the landing step lets it sink into the ground
(a velocity-level step keeps contacts from approaching, not from overlapping by up to a step's travel), so a test of
exactly pi/2 decided such a fall by the last step's rounding. An irregular body (a scan, :mod:`..scanned.hull3d`)
may instead come to rest on another face of its hull short of lying on its side (a granite rock toppled onto a
face at 72 deg); given its smallest static tipping angle (``tipping_rad``), a body found at rest after the record
(three contacts or more, every speed below :data:`REST_SPEED`) tilted beyond it has overturned too. The tilt is
always measured from how the body stood at the start (``rest``: its principal axes as it stands).

A plastic impact at a new sticking contact reduces to Housner's (1963) rule for a block pivoting without slip:
the angular momentum about the new pivot is conserved and the old pivot lifts (tested against the planar kernel).

**The step** is the record's interval in the fewest equal parts of at most :data:`MAX_STEP_S` (the ground is linear
between samples, so a finer sampling of the record asks for no finer step). Measured: on
Kocaeli at Yarimca a 0.4 x 1.6 m cylinder that the exact cylinder model rocks from 0.004 to 0.28 alpha before its
base would slip peaked at 0.008 alpha with 0.5 ms steps, and followed the exact model with 0.1 ms steps. An impact
is resolved within one step, and at a small tilt the rate at impact is small against what gravity adds in a step
(an estimate for that cylinder at 0.004 alpha: it lands at about 0.065 rad/s, and gravity turns it by about
1.1e-3 rad/s in 0.5 ms). While the tilt is between :data:`FINE_TILT_FROM` and :data:`FINE_TILT_TO` times the
smallest static tipping angle, each step is therefore taken as :data:`FINE_SUBSTEPS` steps (that cylinder then
peaks at 0.27 alpha; docs/validation.md), and so is every step while the body flies and for :data:`AFTER_FLIGHT_S`
after. Where the body tilts beyond :data:`FINE_TILT_TO` alpha, is not around a flight and no vertex clear of the
ground would reach it within twice the longer step at its present speed, a few steps are taken as one of at most
``LONG_STEP_S`` (:mod:`.long_steps`).

The ground is the plane z = 0 of the ground's frame, which moves with the record: the body feels gravity and the
inertial force -a_g (x, y the record's two horizontals, z up).

A body flat on its base and still (the body at a start from rest, or one found again with its tilt below
:data:`REST_TILT_RAD` and every speed below :data:`REST_SPEED`) is held at rest, nothing integrated, for as long as
the ground's demand |a_h| / (g + a_v) at the middle of a step (the force the step applies) stays at or below
min(mu, tan alpha_min) (:func:`base_threshold`): a step the stepping itself would leave at rest. A body found at rest
again is set down flat (its tilt of at most 1e-3 rad set to 0, its heading and place kept) and its next motion
starts from no impulse, as at the start. Against holding only the body at the start, on 144 scenes on real records
(benchmarks/contact3d_peer.py's families) this took 8.6x less time and changed one verdict (a statue on RSN1503, which
also turns with the solver's tolerance: now overturned, as PyBullet overturns it robustly). A body still on three
contacts or more off its base during the record (a scan toppled onto another face of its hull) is held the same way
where it lies, against the threshold of the polygon those contacts span (:mod:`.at_rest`); after the record it has
come to rest there and the run ends. On 984 runs of the granite rocks on their shake-table tests this left every
verdict as it was and integrated 12 % fewer steps, 43 % fewer on the runs that overturn (docs/validation.md).

A body flat on its base beyond that threshold, sticking or sliding without turning, is stepped as the translation
it is for as long as the impulses that keep it flat exist (the centre of the normal impulses its friction needs in
its base's polygon, g + a_v > 0: :mod:`.flat_slide`): a solution of Moreau's step for plastic contacts, written
out, which the solver is measured to find too. Against every step solved, on the bundled records, docs/validation.md
says what it changed.

``screen`` judges cylinders and boxes by the exact models of :mod:`.solid3d`; with ``[simulation] contact3d =
true`` the scenes they stop are handed to this model, which goes on from the exact model's last certified state
(:mod:`.contact_scene`; a :class:`~.contact_start.Start` instead of rest).

References
----------
Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics. In Nonsmooth Mechanics and
Applications, CISM Courses and Lectures 302, 1-82. Springer.
De Saxce, G. & Feng, Z.-Q. (1998). The bipotential method: a constructive approach to design the complete contact
law with friction and improved numerical algorithms. Mathematical and Computer Modelling 28(4-8), 225-245.
Jean, M. (1999). The non-smooth contact dynamics method. Computer Methods in Applied Mechanics and Engineering
177(3-4), 235-257.
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import jit_inline, jit_lean
from ...constants import G
from .at_rest import ground_at, set_down, set_still
from .attitude import energy, rotation, turned, world_inverse_inertia
from .contact_pose import (
    LYING_SLACK_RAD,
    Pose,
    degrees,
    extent,
    lean_of,
    lie_down,
    lowest,
    measure,
    pose,
)
from .contact_problem import MAX_SWEEPS
from .contact_reduced import solve_step, solvers
from .contact_room import Room, made_fresh, room
from .contact_start import Start, begin, place
from .convex_body import ConvexBody, base_threshold, support_threshold
from .edge_stop import handback
from .flat_slide import flat_and_sliding, held_through, set_flat
from .long_steps import impact_ahead, last_passed, steps_merged
from .near_ground import listed

#: The largest step [s]: a sampling interval is taken in the fewest equal steps of at most this.
MAX_STEP_S = 5e-4
#: After the record: the body is followed until it rests (every velocity below REST_SPEED [m s-1, rad s-1 times
#: the body's size]) or for at most TAIL_S [s] (then flagged).
REST_SPEED = 1e-6
TAIL_S = 20.0

#: A body in contact, tilted less than REST_TILT_RAD [rad], whose every speed is below REST_SPEED is at rest: it is
#: set down flat and held there, nothing integrated, for as long as the ground's demand |a_h| / (g + a_v) stays at
#: or below the exact at-rest threshold min(mu, tan alpha_min) (:func:`base_threshold`); the body standing on its
#: base at the start is. A body that lands flat stays sunk by what the landing step let it overlap the ground (up to
#: h times the landing speed at an edge, over the base's width), so a bound of 1e-4 rad missed such rests (a 0.5 m
#: box back on its base after rocking to 1.3e-4 rad) and integrated them to the end of the tail.
REST_TILT_RAD = 1e-3

#: A body tilted between FINE_TILT_FROM and FINE_TILT_TO times its smallest static tipping angle lands slowly against
#: what gravity adds in a step: each of its steps is taken as FINE_SUBSTEPS steps [-] (chosen on real records against
#: the exact cylinder model, docs/validation.md).
FINE_TILT_FROM = 1e-3
FINE_TILT_TO = 0.02
FINE_SUBSTEPS = 3
#: A body in flight (:data:`FLIGHT_CLEARANCE_M`) lands at a tilt the step resolves as coarsely: its steps are taken in
#: FINE_SUBSTEPS parts while it is clear of the ground and for AFTER_FLIGHT_S [s] after (chosen against every step
#: at 0.1 ms on the flight scenes of benchmarks/contact3d_peer.py, docs/validation.md).
AFTER_FLIGHT_S = 0.02

#: A body in flight: it lost every contact at a step and its lowest point rose more than this above the ground
#: [m]. A step without contact whose lowest point stays within it is the stepping's rounding at a pivot (a velocity-
#: level step keeps a pivot from approaching the ground, not from rising by up to h^2 times its centripetal
#: acceleration): measured on the bundled run, such steps rose at most 0.64 um, and 1,949 of the 2,503 runs with
#: any step without contact had only single steps, while 255 rose more than 0.1 mm.
FLIGHT_CLEARANCE_M = 1e-5

#: A vertex at most this far above the ground at a step's middle is a contact [m]: the body's height is a sum of
#: rounded terms, so a base resting flat has its corners at +-1e-17 m, and a strict test of 0 let the rounding
#: drop two of a sliding box's four corners at one step and tip it (1.8e-6 rad on Newmark's pulse at 0.5 ms steps).
#: A contact takes an impulse only where the step would otherwise move it towards the ground, so a vertex this near,
#: counted as one, is kept from passing into the ground at most this far early and is otherwise left free.
CONTACT_GAP_M = 1e-9

#: The outcome's flags (bits).
FLAG_SWEEP_CAP = 1          # a step's contact problem ended at MAX_SWEEPS
FLAG_TAIL_CAP = 2           # still moving TAIL_S after the record


class Contact3DOutcome(NamedTuple):
    """What the contact model found.

    Attributes
    ----------
    overturned : bool
        The body lies on a side (its standing axis within :data:`LYING_SLACK_RAD` of the horizontal), or, with the
        body's ``tipping_rad``, rests after the record on another face tilted beyond it.
    t_overturn : float
        When [s] (NaN: it did not): when it came to lie on its side, or when it last tilted beyond ``tipping_rad``
        before it rested on another face.
    tilt_max_rad : float
        The largest tilt of its axis from the vertical [rad] (pi/2 once overturned).
    slide_max_m : float
        The largest horizontal displacement of G from where it stood [m].
    twist_max_rad : float
        The largest rotation about the vertical [rad].
    flight : bool
        It lost every contact at some step and rose more than :data:`FLIGHT_CLEARANCE_M` clear of the ground.
    steps : int
        Steps taken.
    flags : int
        :data:`FLAG_SWEEP_CAP`, :data:`FLAG_TAIL_CAP`.
    capped_steps : int
        Steps whose contact problem ended at :data:`MAX_SWEEPS` (each part of a finely taken step counted).
    energy_gain_max : float
        The largest energy gained over one step while the ground stood still after the record [J kg-1] (0 when
        none: the contacts only dissipate).
    integrated_steps : int
        Steps integrated, a step taken in :data:`FINE_SUBSTEPS` parts counted as that many and a long step (several
        taken as one, :mod:`.long_steps`) as one (``steps`` counts it as those several; the rest of ``steps`` are
        held at rest by the exact at-rest certificate).
    sweeps : int
        Gauss-Seidel sweeps over all steps (the cost of the contact problems).
    lean_at_peak_deg : float
        Where its axis leant at its largest tilt, as an azimuth from x toward y [deg] (NaN: it never tilted).
    tilt_rad : ndarray or None
        With ``history``: its tilt at each sample [rad] (pi/2 from its overturning on).
    lean_deg : ndarray or None
        With ``history``: where its axis leans at each sample [deg] (NaN while upright; after overturning, where it
        fell).
    tilt_end_rad : float
        Its tilt where the run ended [rad]: at rest on its base (below :data:`REST_TILT_RAD`), at rest on another
        face (three contacts or more, still, after the record), lying on a side, or where the tail ended.
    edge : int
        With ``edges`` given (:func:`simulate_contact3d`), the one the body turned on without slipping when the run
        stopped there, at ``t_end_s``; -1 where it did not stop so.
    t_end_s : float
        When the run ended [s].
    q_end, rate_end_rad_s : ndarray or None
        Where it stopped on an ``edge``: its orientation (unit quaternion (w, x, y, z), principal axes to the
        ground's frame) and angular velocity in the ground's frame [rad s-1].
    """

    overturned: bool
    t_overturn: float
    tilt_max_rad: float
    slide_max_m: float
    twist_max_rad: float
    flight: bool
    steps: int
    flags: int
    capped_steps: int
    energy_gain_max: float
    integrated_steps: int
    sweeps: int
    lean_at_peak_deg: float = math.nan
    tilt_rad: np.ndarray | None = None
    lean_deg: np.ndarray | None = None
    tilt_end_rad: float = math.nan
    edge: int = -1
    t_end_s: float = math.nan
    q_end: np.ndarray | None = None
    rate_end_rad_s: np.ndarray | None = None


def simulate_contact3d(ax_ms2, ay_ms2, az_ms2, dt_s: float, body: ConvexBody, *, yaw_deg: float = 0.0,
                       g_ms2: float = G, history: bool = False, start: Start | None = None,
                       edges: np.ndarray | None = None, flat_slides: bool = True,
                       prepared: Prepared | None = None) -> Contact3DOutcome:
    """The body, standing on its base with its x axis at ``yaw_deg`` from the record's x (counter-clockwise seen
    from above), under the ground acceleration (ax, ay, az) [m s-2] (az None: none) sampled at ``dt_s``; with
    ``history`` its tilt and lean at each sample too; with ``start``, from that state at its time instead of from
    rest (the outcome counts what the start says came before: its largest tilt and its history). With ``edges``
    (pairs of vertex indices, shape (k, 2); a pair (i, i) the vertex i alone), the run stops at the first sample of
    the record after a whole sampling interval turning on them without slipping, the vertices of one pair loaded and
    sticking, every other vertex without impulse: the outcome's ``edge``, ``t_end_s``, ``q_end`` and
    ``rate_end_rad_s`` say where (an exact model goes on from there: :mod:`.alternate`). With ``flat_slides`` (and
    plastic contacts), a body flat on its base is stepped as the translation it is while each step's impulses allow
    it (:mod:`.flat_slide`); without, every step is the contact problem's. With ``prepared`` (:func:`prepare`'s, for
    this ``body``, ``dt_s`` and ``flat_slides``), its arrays are taken instead of made again: the room made fresh in
    place (:func:`~.contact_room.made_fresh`), and the rest the kernel writes before it reads, so the run is the one
    new arrays give, double for double (tested)."""
    ax = np.ascontiguousarray(ax_ms2, dtype=float)
    ay = np.ascontiguousarray(ay_ms2, dtype=float)
    az = np.zeros_like(ax) if az_ms2 is None else np.ascontiguousarray(az_ms2, dtype=float)
    kit = prepare(body, dt_s, flat_slides=flat_slides) if prepared is None else prepared
    if prepared is not None:
        made_fresh(kit.room)
    hist = np.full((ax.size if history else 0, 2), math.nan)
    pairs = np.zeros((0, 2), dtype=np.int64) if edges is None else np.ascontiguousarray(edges, dtype=np.int64)
    out = _run(ax, ay, az, float(dt_s), kit.n_sub, kit.vertices, kit.inertia, float(body.mu), float(body.restitution),
               math.radians(yaw_deg), float(g_ms2), kit.work, hist, kit.stance, kit.room,
               begin(start, dt_s / kit.n_sub, float(dt_s), kit.stance.up, hist), pairs, kit.merge)
    if out.edge >= 0:
        out = out._replace(q_end=kit.room.q.copy(), rate_end_rad_s=kit.room.w.copy())
    return out._replace(tilt_rad=hist[:, 0], lean_deg=np.degrees(hist[:, 1])) if history else out


def steps_per_sample(dt_s: float) -> int:
    """The steps a sampling interval of ``dt_s`` [s] is taken in: the fewest of at most :data:`MAX_STEP_S`."""
    return max(1, int(math.ceil(dt_s / MAX_STEP_S - 1e-9)))


class Prepared(NamedTuple):
    """A body's arrays for the kernel on a record sampled at one interval (:func:`prepare`), made once for the runs
    of one scene (:mod:`.alternate`'s, from each hand-back): its vertices and inertias as the kernel takes them, its
    :class:`~.contact_pose.Pose`, the kernel's :class:`~.contact_room.Room` and solvers, the steps a sample is taken
    in and those taken as one (:func:`~.long_steps.steps_merged`)."""

    vertices: np.ndarray
    inertia: np.ndarray
    stance: Pose
    room: Room
    work: tuple
    n_sub: int
    merge: int


def prepare(body: ConvexBody, dt_s: float, *, flat_slides: bool = True) -> Prepared:
    """The :class:`Prepared` arrays of ``body`` on a record sampled at ``dt_s`` [s] (``flat_slides`` as
    :func:`simulate_contact3d`'s)."""
    vertices = np.ascontiguousarray(body.vertices, dtype=float)
    n_sub = steps_per_sample(dt_s)
    return Prepared(vertices, np.ascontiguousarray(body.inertia, dtype=float),
                    pose(vertices, body.rest, body.tipping_rad, base=flat_slides and float(body.restitution) == 0.0),
                    room(vertices), solvers(len(vertices)), n_sub, steps_merged(n_sub, dt_s / n_sub))


@jit_inline
def _free_velocity(v, w, rm, inv_i, inertia, h, gx, gy, gz_total):
    """The step's velocities without the contacts: gravity and the ground's inertial force (``gz_total`` =
    g + a_v), and the gyroscopic term -I^-1 (w x I w), explicit."""
    v[0] -= h * gx
    v[1] -= h * gy
    v[2] -= h * gz_total
    i0 = inertia[0] * (rm[0, 0] * w[0] + rm[1, 0] * w[1] + rm[2, 0] * w[2])      # I w in the body's axes
    i1 = inertia[1] * (rm[0, 1] * w[0] + rm[1, 1] * w[1] + rm[2, 1] * w[2])
    i2 = inertia[2] * (rm[0, 2] * w[0] + rm[1, 2] * w[1] + rm[2, 2] * w[2])
    l0 = rm[0, 0] * i0 + rm[0, 1] * i1 + rm[0, 2] * i2                           # ... in the world's
    l1 = rm[1, 0] * i0 + rm[1, 1] * i1 + rm[1, 2] * i2
    l2 = rm[2, 0] * i0 + rm[2, 1] * i1 + rm[2, 2] * i2
    cx, cy, cz = w[1] * l2 - w[2] * l1, w[2] * l0 - w[0] * l2, w[0] * l1 - w[1] * l0
    for a in range(3):
        w[a] -= h * (inv_i[a, 0] * cx + inv_i[a, 1] * cy + inv_i[a, 2] * cz)


@jit_inline
def _contacts(vertices, rm, z_g, v, w, dv_z, impulses, arms, index, u_before, p, nr):
    """The vertices at or below the ground at the step's middle, to within :data:`CONTACT_GAP_M` (G at height
    ``z_g``), looked for among those :func:`~.near_ground.listed` in ``nr`` (the same, in the same order, as among
    all): their arms from G, indices, normal velocities before the step's forces (``dv_z`` the step's vertical
    change) and last impulses (the warm start); how many."""
    n_c, n_look = 0, listed(vertices, rm, z_g, CONTACT_GAP_M, nr)
    for j in range(vertices.shape[0] if n_look < 0 else n_look):
        i = j if n_look < 0 else nr.members[j]
        r2 = rm[2, 0] * vertices[i, 0] + rm[2, 1] * vertices[i, 1] + rm[2, 2] * vertices[i, 2]
        if z_g + r2 <= CONTACT_GAP_M:               # the height first: a scan's hull has hundreds of vertices
            r0 = rm[0, 0] * vertices[i, 0] + rm[0, 1] * vertices[i, 1] + rm[0, 2] * vertices[i, 2]
            r1 = rm[1, 0] * vertices[i, 0] + rm[1, 1] * vertices[i, 1] + rm[1, 2] * vertices[i, 2]
            arms[n_c, 0], arms[n_c, 1], arms[n_c, 2] = r0, r1, r2
            index[n_c] = i
            p[n_c, 0], p[n_c, 1], p[n_c, 2] = impulses[i, 0], impulses[i, 1], impulses[i, 2]
            u_before[n_c] = v[2] + dv_z + w[0] * r1 - w[1] * r0
            n_c += 1
    return n_c


@jit_inline
def _moreau_step(x, q, v, w, frames, vertices, inertia, contact, mu, e_n, g, h, ground, work):
    """One Moreau-Jean step of the body at (x, q) moving at (v, w), all updated in place: to the step's middle,
    the free velocities, the contacts at the middle and their impulses, to the step's end. ``frames``: room for the
    middle's quaternion, rotation and world inverse inertia; ``contact``: the last impulses at each vertex (the
    warm start, replaced by this step's) and room for the contacts' arms, indices, normal velocities and impulses;
    ``ground``: its acceleration at the middle. Returns the contacts and the sweeps taken (-1: at the cap)."""
    qm, rm, inv_i = frames
    impulses, arms, index, u_before, p, nr, loaded = contact
    gx, gy, gz = ground
    for i in range(3):                                          # Moreau's midpoint
        x[i] += 0.5 * h * v[i]
    turned(q, w[0], w[1], w[2], 0.5 * h, qm)
    rotation(qm, rm)
    world_inverse_inertia(rm, inertia, inv_i)
    _free_velocity(v, w, rm, inv_i, inertia, h, gx, gy, g + gz)
    n_c = _contacts(vertices, rm, x[2], v, w, h * (g + gz), impulses, arms, index, u_before, p, nr)
    # int(n_c): one compiled version, not one more for the literal 0 n_c starts at (pipeline.compiled)
    taken = 0 if n_c == 0 else solve_step(v, w, inv_i, arms, int(n_c), u_before, mu, e_n, g * h, p, work)
    for c in range(loaded[0]):              # the last step's impulses, the only ones not zero, cleared
        impulses[loaded[c + 1], 0], impulses[loaded[c + 1], 1], impulses[loaded[c + 1], 2] = 0.0, 0.0, 0.0
    for c in range(n_c):
        impulses[index[c], 0], impulses[index[c], 1], impulses[index[c], 2] = p[c, 0], p[c, 1], p[c, 2]
        loaded[c + 1] = index[c]
    loaded[0] = n_c
    for i in range(3):
        x[i] += 0.5 * h * v[i]
    turned(qm, w[0], w[1], w[2], 0.5 * h, q)
    return n_c, taken


@jit_inline
def _advance(x, q, v, w, frames, vertices, inertia, contact, mu, e_n, g, h, ax, ay, az, k, n_sub, during, parts,
             work, lo, span):
    """Steps ``k`` to ``k + span`` of the run (``span`` of them as one: :mod:`.long_steps`) from the fraction
    ``lo`` of the first on (:func:`_moreau_step`), as ``parts`` steps of h (span - lo) / parts each, the ground at
    each one's middle (``during`` the record; else none). The fewest contacts of a part, the sweeps taken
    (MAX_SWEEPS for a part at the cap) and the parts at the cap."""
    least, sweeps, capped = vertices.shape[0], 0, 0
    for j in range(parts):                  # (the fractions written so that lo = 0 rounds as a whole step does)
        ground = ground_at(ax, ay, az, k, n_sub, lo + (j + 0.5) * (span - lo) / parts) if during else (0.0, 0.0, 0.0)
        n_c, taken = _moreau_step(x, q, v, w, frames, vertices, inertia, contact, mu, e_n, g, h * (span - lo) / parts,
                                  ground, work)
        least = min(least, n_c)
        sweeps += MAX_SWEEPS if taken < 0 else taken
        if taken < 0:
            capped += 1
    return least, sweeps, capped


@jit_inline
def _clear_of_ground(vertices, r, z_g):
    """Every vertex more than :data:`FLIGHT_CLEARANCE_M` above the ground (rotation ``r``, G at height ``z_g``)."""
    return z_g + lowest(vertices, r) > FLIGHT_CLEARANCE_M


@jit_inline
def _still(v, w, size):
    """Every speed below REST_SPEED (the rate times the body's size)."""
    return (math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2) < REST_SPEED
            and math.sqrt(w[0] ** 2 + w[1] ** 2 + w[2] ** 2) * size < REST_SPEED)


@jit_inline
def _aloft(n_c, vertices, r, z_g, flight, aloft, after_flight):
    """Whether the body has flown, and its fine steps left after a flight: :data:`AFTER_FLIGHT_S` worth
    (``after_flight`` steps) from a step without contact that left it clear of the ground (:func:`_clear_of_ground`),
    else ``aloft`` as counted."""
    if n_c == 0 and _clear_of_ground(vertices, r, z_g):
        return True, after_flight
    return flight, aloft


@jit_inline
def _stepping(tilt, fine_low, fine_high, aloft, merge, k, lo, vertices, r, x, v, w, nr, h):
    """How step ``k`` (of ``h`` [s], from its fraction ``lo`` on) is taken: in :data:`FINE_SUBSTEPS` parts where the
    tilt is within the fine band (``fine_low``, ``fine_high``) or the body is ``aloft`` (or just was), and as one
    with the ``merge`` - 1 after it where the body tilts beyond the band, the step is whole and at a multiple of
    ``merge``, and no impact is ahead (:func:`~.long_steps.impact_ahead`; ``r`` the body's rotation now: the last
    step's, or the start's). Returns (parts, steps taken as one)."""
    if fine_low < tilt < fine_high or aloft > 0:
        return FINE_SUBSTEPS, 1
    if (merge > 1 and tilt >= fine_high and k % merge == 0 and lo == 0.0
            and not impact_ahead(vertices, r, x, v, w, nr, CONTACT_GAP_M, merge * h)):
        return 1, merge
    return 1, 1


@jit_inline
def _bounds(standing, mu):
    """The body's size and G's height as it stands (:func:`~.contact_pose.extent`), its at-rest threshold
    min(mu, tan alpha_min) on its base, and the tilts [rad] the fine band runs between (FINE_TILT_FROM and
    FINE_TILT_TO times alpha_min)."""
    size, z0 = extent(standing)
    tan_alpha = base_threshold(standing, math.inf)                    # of the smallest static tipping angle
    return size, z0, min(mu, tan_alpha), FINE_TILT_FROM * math.atan(tan_alpha), FINE_TILT_TO * math.atan(tan_alpha)


@jit_inline
def _on_face(v, w, impulses, arms, n_c, mu, r, up, tilt):
    """A body found still off its base, on the ``n_c`` contacts at ``arms``: held where it lies
    (:func:`~.at_rest.set_still`); True (it rests), the threshold of those contacts
    (:func:`~.convex_body.support_threshold`), its tilt and lean [rad]."""
    return set_still(v, w, impulses), support_threshold(arms, n_c, mu), tilt, lean_of(r, up, tilt)


#: How a step left the body (:func:`_on_base`).
OFF_BASE = 0                # neither still nor flat on its base
STILL = 1                   # still on its base: set down there (:func:`~.at_rest.set_down`)
FLAT = 2                    # moving flat on its base: set flat (:func:`~.flat_slide.set_flat`)


@jit_inline
def _on_base(n_c, tilt, v, w, q, x, r, z0, impulses, loaded, pose, size, aloft):
    """Where a step left the body on ``n_c`` contacts, tilted ``tilt`` [rad], moving at (``v``, ``w``): still on
    its base (set down: :func:`~.at_rest.set_down`), moving flat on it with a base to take flat steps on and no fine
    steps after a flight due (``aloft``; set flat: :func:`~.flat_slide.set_flat`), or neither; which."""
    if n_c > 0 and tilt < REST_TILT_RAD and _still(v, w, size):
        set_down(v, w, q, x, r, z0, impulses, pose)
        return STILL
    if pose.n_base > 0 and aloft <= 0 and flat_and_sliding(n_c, tilt, REST_TILT_RAD, v, w, size, REST_SPEED, impulses,
                                                           loaded):
        set_flat(v, w, q, x, r, z0, impulses, pose)
        return FLAT
    return OFF_BASE


@jit_inline
def _toppled(tilt, toppled, t_beyond, t_over, tilt_max):
    """A body at rest after the record off its base: overturned (when it last passed its tipping angle
    ``toppled``, its peak a side's) where it rests tilted beyond that angle, else as it was."""
    if tilt > toppled:
        return True, t_beyond, 0.5 * math.pi
    return False, t_over, tilt_max


@jit_inline
def _energy_now(q, r, v, w, inertia, x, g):
    """Its energy per unit mass at orientation ``q`` (its rotation written into ``r``) [J kg-1]."""
    rotation(q, r)
    return energy(v, w, r, inertia, x[2], g)


@jit_lean
def _run(ax, ay, az, dt, n_sub, vertices, inertia, mu, e_n, yaw, g, work, hist, pose, room, begin, edges, merge):
    """The body from ``begin`` (at rest: still at ``yaw``) through the record (steps of ``dt`` / ``n_sub``, taken as
    :func:`_stepping` says) and after it until it rests or :data:`TAIL_S`: held still or flat on its base where
    :func:`~.flat_slide.held_through` allows (``held``: the at-rest threshold; flat on the base of ``pose``), else
    stepped (:func:`_advance`); its tilt and lean at the samples into ``hist``; with ``edges``, to where it turns on
    one without slipping (:func:`~.edge_stop.handback`)."""
    size, z0, threshold, fine_low, fine_high = _bounds(pose.standing, mu)
    contact, frames, r, impulses = room.contact, room.frames, room.r, room.contact[0]
    x, q, v, w = place(room, vertices, z0, yaw, pose, begin)
    resting, edge, stuck, h, n, flags, capped, t_over = begin.k < 0, -1, 0, dt / n_sub, ax.size, 0, 0, math.nan
    aloft, after_flight, held, tilt_held, lean_held = 0, int(AFTER_FLIGHT_S / h), threshold, 0.0, math.nan
    tilt_max, slide_max, twist_max, energy_gain, overturned, flight = begin.tilt_max, 0.0, 0.0, 0.0, False, False
    t, k, k_end, integrated, sweeps, lo = begin.t, max(begin.k, 0), (n - 1) * n_sub + int(TAIL_S / h), 0, 0, begin.lo
    tilt, lean_peak, tilt_before, t_beyond, steps = begin.tilt, begin.lean_peak, begin.tilt, math.nan, k
    while True:
        if k >= k_end:
            flags |= FLAG_TAIL_CAP
            break
        if resting:                             # held still, or flat on its base (on it: tilt_held 0)
            k, resting, ended, steps, integrated, slide_max = held_through(
                ax, ay, az, k, n_sub, k_end, held, g, hist, tilt_held, lean_held, x, v, mu, h, z0, r, pose.x_ref,
                pose.base, pose.n_base if tilt_held == 0.0 else 0, slide_max, steps, integrated)
            if ended:                           # at rest after the record: toppled where on a face beyond alpha
                overturned, t_over, tilt_max = _toppled(tilt_held, pose.toppled, t_beyond, t_over, tilt_max)
                break
            if resting:
                continue
        during = k < (n - 1) * n_sub
        e_before = 0.0 if during else _energy_now(q, r, v, w, inertia, x, g)   # checked after the record
        parts, span = _stepping(tilt, fine_low, fine_high, aloft, merge, k, lo, vertices, r, x, v, w, contact[5], h)
        n_c, taken, capped_now = _advance(x, q, v, w, frames, vertices, inertia, contact, mu, e_n, g, h, ax, ay, az, k,
                                          n_sub, during, parts, work, lo, float(span))
        capped, sweeps, integrated, aloft, lo = capped + capped_now, sweeps + taken, integrated + parts, aloft - 1, 0.0
        t_step, k, steps, t = t, k + span, steps + span, (k + span) * h
        rotation(q, r)
        flight, aloft = _aloft(n_c, vertices, r, x[2], flight, aloft, after_flight)
        tilt, tilt_max, lean_peak, slide_max, twist_max = measure(r, x, pose, yaw, hist, k, n_sub, tilt_max,
                                                                   lean_peak, slide_max, twist_max)
        energy_gain = energy_gain if during else max(energy_gain, energy(v, w, r, inertia, x[2], g) - e_before)
        if tilt >= 0.5 * math.pi - LYING_SLACK_RAD:
            overturned, t_over, tilt_max = True, t, 0.5 * math.pi            # it lies on a side
            lie_down(hist, k // n_sub + 1, lean_of(r, pose.up, tilt))
            break
        base = _on_base(n_c, tilt, v, w, q, x, r, z0, impulses, contact[6], pose, size, aloft)
        if base != OFF_BASE:                    # set down on its base, still or moving flat
            resting, held, tilt_held, lean_held = True, threshold, 0.0, math.nan
            if base == STILL and not during:
                break
        t_beyond, tilt_before = last_passed(t_step, t, tilt_before, tilt, pose.toppled, t_beyond), tilt
        stuck, edge = handback(impulses, edges, mu, stuck, during, k % n_sub == 0, n_sub, span)
        if edge >= 0:
            break
        if not resting and n_c >= 3 and _still(v, w, size):     # at rest on three contacts or more, off its base
            if not during:
                overturned, t_over, tilt_max = _toppled(tilt, pose.toppled, t_beyond, t_over, tilt_max)
                break
            resting, held, tilt_held, lean_held = _on_face(v, w, impulses, contact[1], n_c, mu, r, pose.up, tilt)
    return Contact3DOutcome(overturned, t_over, tilt_max, slide_max, twist_max, flight, steps,
                            flags | (FLAG_SWEEP_CAP if capped else 0), capped, energy_gain, integrated, sweeps,
                            degrees(lean_peak), None, None, tilt, edge, k * h, None, None)
