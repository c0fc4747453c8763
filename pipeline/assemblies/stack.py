"""A stack of rigid blocks in a vertical plane, bottom first: whether it stands at rest, and the certificate that
the ground leaves every one of its interfaces shut and stuck.

Body k (k = 0 the bottom) is a rectangular block of width ``width_m`` in the plane, height ``height_m`` and mass
``mass_kg``, its centre of mass at its centre, its base centred ``offset_m`` from the centre of the top of body k - 1
(body 0: from the origin of the ground), with friction ``mu`` at its lower face. Interface k is body k's base on
body k - 1's top (k = 0: on the ground); it supports what is above it on the overlap of the two faces, [l_k, r_k].

While no interface opens or slips the stack moves with the ground as one rigid body. The part above interface k
(bodies k .. n - 1, mass m, centre of mass (x_k, z_k), z_k above the interface) is then in equilibrium under its
weight and the ground's inertial force per unit mass (-a_h, -(g + a_v)); the interface's contact force balances
them, so its line of action is the resultant's: it crosses the interface at x_k - z_k a_h / (g + a_v). The
interface stays shut (Signorini: a compressive force inside the support) while

    g + a_v > 0   and   (x_k - r_k) / z_k <= a_h / (g + a_v) <= (x_k - l_k) / z_k,

the bound of Housner (1963) for one block (tan alpha = b / h for a block of width 2b and height 2h centred on its
base), and it stays stuck (Coulomb) while |a_h| <= mu_k (g + a_v). Both are linear in (a_h, a_v): the ground being
linear between its samples, they hold between two samples where they hold at both, so checking the samples is
exact. Where every interface meets them at every sample, the stack stays at rest on the ground: every body stands
and no joint opens nor slips.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. Bulletin of the
Seismological Society of America 53(2), 403-417.
Psycharis, I. N. (1990). Dynamic behaviour of rocking two-block assemblies. Earthquake Engineering & Structural
Dynamics 19(4), 555-575.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..constants import G
from ..errors import BlockParameterError


class StackBody(NamedTuple):
    """One body of a stack (see the module).

    Attributes
    ----------
    width_m : float
        width in the plane [m]
    height_m : float
        height [m]
    mass_kg : float
        mass [kg]
    mu : float
        friction coefficient at its lower face [-]
    offset_m : float
        its base's centre from the centre of the top of the body below (the bottom body: from the ground's origin)
        [m]
    """

    width_m: float
    height_m: float
    mass_kg: float
    mu: float
    offset_m: float = 0.0


class StackPlace(NamedTuple):
    """A body's place in its stack: the stack, bottom first, and which body it is (an inventory row's).

    Attributes
    ----------
    bodies : tuple of StackBody
        the stack's bodies, bottom first
    position : int
        this body's (0: the bottom)
    ids : tuple of str
        the bodies' ids, bottom first
    rule : int
        what fails the stack as a whole (:class:`pipeline.stacks.StackRule`; 0: any body falls)
    """

    bodies: tuple[StackBody, ...]
    position: int
    ids: tuple[str, ...]
    rule: int = 0


class Interface(NamedTuple):
    """What interface k must carry at rest: the part above it and the support the two faces share.

    Attributes
    ----------
    left_m, right_m : float
        the support's ends [m] (the ground's frame, at rest)
    x_m : float
        the part above's centre of mass, horizontally [m]
    z_m : float
        ... and its height above the interface [m]
    mu : float
        friction of the interface [-]
    """

    left_m: float
    right_m: float
    x_m: float
    z_m: float
    mu: float


def interfaces(bodies: tuple[StackBody, ...] | list[StackBody], *, label: str = "stack") -> list[Interface]:
    """Each interface of the stack ``bodies`` (bottom first) with what it carries at rest; the stack checked.

    Raises
    ------
    BlockParameterError
        A body's size, mass or friction is not positive and finite, or the stack cannot stand at rest: the centre
        of mass of the part above an interface is not strictly inside its support (named, with by how much).
    """
    _check_bodies(bodies, label)
    centres, bases = placements(bodies)
    out = []
    for k, b in enumerate(bodies):
        above = bodies[k:]
        mass = sum(a.mass_kg for a in above)
        xg = sum(a.mass_kg * centres[k + j] for j, a in enumerate(above)) / mass
        zg = sum(a.mass_kg * (bases[k + j] + 0.5 * a.height_m) for j, a in enumerate(above)) / mass - bases[k]
        left, right = centres[k] - 0.5 * b.width_m, centres[k] + 0.5 * b.width_m
        if k > 0:                                   # the overlap with the top of the body below
            left = max(left, centres[k - 1] - 0.5 * bodies[k - 1].width_m)
            right = min(right, centres[k - 1] + 0.5 * bodies[k - 1].width_m)
        if not left < xg < right:
            where = "the ground" if k == 0 else f"body {k - 1}"
            raise BlockParameterError(
                f"{label}: body {k} (0 = bottom) on {where} cannot stand at rest: the centre of mass of the part "
                f"from it up is at {xg:.4g} m, outside or on the edge of its support [{left:.4g}, {right:.4g}] m "
                f"(short by {max(left - xg, xg - right, 0.0):.3g} m); check the bodies' widths and offsets")
        out.append(Interface(left, right, xg, zg, b.mu))
    return out


def _check_bodies(bodies, label: str) -> None:
    """Every body's size, mass and friction positive and finite, its offset finite (else a named error)."""
    if not bodies:
        raise BlockParameterError(f"{label}: no bodies; a stack needs at least one")
    for k, b in enumerate(bodies):
        for name in ("width_m", "height_m", "mass_kg", "mu"):
            value = getattr(b, name)
            if not (np.isfinite(value) and value > 0):
                raise BlockParameterError(f"{label}, body {k} (0 = bottom): {name} = {value}: expected a positive, "
                                          "finite number")
        if not np.isfinite(b.offset_m):
            raise BlockParameterError(f"{label}, body {k}: offset_m = {b.offset_m}: expected a finite number")


def placements(bodies) -> tuple[list[float], list[float]]:
    """Each body's base centre [m] (each ``offset_m`` from the centre of the top below) and base height [m], at rest,
    bottom first."""
    centres, bases = [], []
    x, z = 0.0, 0.0
    for b in bodies:
        x += b.offset_m
        centres.append(x)
        bases.append(z)
        z += b.height_m
    return centres, bases


def uplift_ratios(face: Interface) -> tuple[float, float]:
    """The ground's a_h / (g + a_v) beyond which the part above ``face`` starts to tip (module's bounds): the lower
    (the ground accelerating toward -x) tips it toward +x about the support's right end, the upper toward -x about
    its left end; Housner's -tan alpha and tan alpha for one block centred on its base."""
    return (face.x_m - face.right_m) / face.z_m, (face.x_m - face.left_m) / face.z_m


def opening_ratio(face: Interface) -> float:
    """The least |a_h| / (g + a_v) of the ground at which the part above ``face`` starts to tip at rest, either way
    (:func:`uplift_ratios`; Housner's tan alpha for one block centred on its base) [-]."""
    low, high = uplift_ratios(face)
    return min(-low, high)


def _rest_breaks(bodies: tuple[StackBody, ...] | list[StackBody], ah_ms2, av_ms2, g_ms2: float
                 ) -> tuple[np.ndarray, np.ndarray]:
    """At each sample of the ground (a_h, a_v) [m s-2], whether the stack at rest would slip at an interface
    (|a_h| > mu (g + a_v)), and whether it would lift at one or lose the ground (g + a_v <= 0): the module's
    conditions, motion only where a demand exceeds (tie rule 2)."""
    ah = np.asarray(ah_ms2, dtype=float)
    gv = g_ms2 + (np.zeros_like(ah) if av_ms2 is None else np.asarray(av_ms2, dtype=float))
    slips = np.zeros(ah.shape, dtype=bool)
    moves = gv <= 0.0
    for face in interfaces(bodies):
        low, high = uplift_ratios(face)
        slips |= np.abs(ah) > face.mu * gv
        moves |= (ah < low * gv) | (ah > high * gv)
    return slips, moves


class AtRest(NamedTuple):
    """What the ground does to the stack at rest (:func:`at_rest`): both questions from one pass over the record."""

    #: no interface lifts off nor slips at any sample (:func:`stays_shut`)
    stays_shut: bool
    #: a joint slips before any part lifts (:func:`slips_at_rest`)
    slips_at_rest: bool


def at_rest(bodies: tuple[StackBody, ...] | list[StackBody], ah_ms2, av_ms2=None, *, g_ms2: float = G) -> AtRest:
    """:func:`stays_shut` and :func:`slips_at_rest` of the ground (a_h, a_v) [m s-2] together."""
    slips, moves = _rest_breaks(bodies, ah_ms2, av_ms2, g_ms2)
    first = int(np.argmax(slips))
    return AtRest(not (slips.any() or moves.any()), bool(slips[first]) and not bool(moves[:first + 1].any()))


def stays_shut(bodies: tuple[StackBody, ...] | list[StackBody], ah_ms2, av_ms2=None, *,
               g_ms2: float = G) -> bool:
    """Whether the ground (a_h, a_v) [m s-2] at its samples (linear between them) leaves every interface of the
    stack shut and stuck, so that the stack stays at rest: the module's certificate. False does not mean that it
    moves by much; it means that this certificate does not decide it."""
    return at_rest(bodies, ah_ms2, av_ms2, g_ms2=g_ms2).stays_shut


def slips_at_rest(bodies: tuple[StackBody, ...] | list[StackBody], ah_ms2, av_ms2=None, *,
                  g_ms2: float = G) -> bool:
    """Whether a joint of the stack needs more friction than it has while the whole stack is still at rest: at the
    first sample where the ground's |a_h| / (g + a_v) passes a body's mu, no sample up to it has lifted any part of
    the stack (its :func:`uplift_ratios`) nor let the ground fall faster than gravity (the ground linear between
    samples, so that the stack rests on every piece up to that sample)."""
    return at_rest(bodies, ah_ms2, av_ms2, g_ms2=g_ms2).slips_at_rest
