"""The vertices of a body that can touch the ground at a step of the contact model, kept between steps.

A contact of the contact model (:mod:`.contact3d`) is a vertex at most ``gap`` above the ground at a step's middle:
with G at height z_G and the body turned by R, vertex i (v_i about G) is one where

    z_G + u . v_i <= gap,      u = the third row of R (the world's up in the body's axes).

A scan's hull has hundreds of vertices, of which a few are near the ground. The list holds the vertices within a
band above the lowest one, found with the up ``u_0`` of the step the list was made at:

    u_0 . v_i <= c,      c = min_j u_0 . v_j + band.

Any other vertex has u_0 . v_i > c, and since |(u - u_0) . v_i| <= |u - u_0| |v_i|, at a later step

    z_G + u . v_i > z_G + c - |u - u_0| rho,      rho = max_j |v_j|.

Where that bound is above ``gap`` (with :data:`ROUNDING` of rho kept for the rounding of the products) no vertex
outside the list is a contact, and the list, kept in the vertices' order, gives the same contacts in the same order
as a look at every vertex: the steps are the same to the last bit. Where it is not, the list is made again at this
step; where even the new list's bound is not above ``gap`` (a body sunk deeper than the band), every vertex is
looked at.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import jit_inline

#: The band above the lowest vertex a list holds, as a fraction of the body's reach rho [-]: the list is made again
#: once the body has turned by about this many radians since (a wider band makes it less often but longer).
BAND_OF_REACH = 0.02
#: What the bound keeps for the rounding of the heights' products, as a fraction of the body's reach rho [-]
ROUNDING = 1e-12


class Near(NamedTuple):
    """A body's list of vertices near the ground (a numba namedtuple of arrays, updated in place).

    Attributes
    ----------
    members : ndarray of int64, shape (n,)
        the listed vertices, in increasing order, in the first ``n_listed[0]``
    n_listed : ndarray of int64, shape (1,)
        how many are listed; -1: no list yet
    state : ndarray, shape (5,)
        the up u_0 the list was made at (3), its cut c [m] and the body's reach rho [m]
    """

    members: np.ndarray
    n_listed: np.ndarray
    state: np.ndarray


def near(vertices: np.ndarray) -> Near:
    """An empty list for the body's ``vertices`` about G [m] (made at its first step)."""
    reach = float(np.max(np.linalg.norm(vertices, axis=1))) if len(vertices) else 0.0
    nr = Near(np.empty(len(vertices), dtype=np.int64), np.empty(1, dtype=np.int64), np.array([0, 0, 0, 0, reach]))
    emptied(nr)
    return nr


def emptied(nr: Near) -> None:
    """``nr`` made, in place, the empty list :func:`near` makes (its body's reach kept): no vertex listed, made up
    from the upright at no cut."""
    nr.n_listed[0] = -1
    nr.state[:4] = (0.0, 0.0, 1.0, 0.0)


@jit_inline
def _bound(rm, z_g, state):
    """The least height any vertex outside the list can have (rotation ``rm``, G at height ``z_g``) [m]."""
    d0, d1, d2 = rm[2, 0] - state[0], rm[2, 1] - state[1], rm[2, 2] - state[2]
    return z_g + state[3] - (math.sqrt(d0 * d0 + d1 * d1 + d2 * d2) + ROUNDING) * state[4]


@jit_inline
def _make(vertices, rm, nr):
    """The list made at rotation ``rm``: the vertices within the band above the lowest."""
    low = math.inf
    for i in range(vertices.shape[0]):
        low = min(low, rm[2, 0] * vertices[i, 0] + rm[2, 1] * vertices[i, 1] + rm[2, 2] * vertices[i, 2])
    cut = low + BAND_OF_REACH * nr.state[4]
    n = 0
    for i in range(vertices.shape[0]):
        if rm[2, 0] * vertices[i, 0] + rm[2, 1] * vertices[i, 1] + rm[2, 2] * vertices[i, 2] <= cut:
            nr.members[n] = i
            n += 1
    nr.n_listed[0] = n
    nr.state[0], nr.state[1], nr.state[2], nr.state[3] = rm[2, 0], rm[2, 1], rm[2, 2], cut


@jit_inline
def least_outside(rm, z_g, nr):
    """The least height any vertex outside ``nr``'s list can have (rotation ``rm``, G at height ``z_g``) [m]."""
    return _bound(rm, z_g, nr.state)


@jit_inline
def listed(vertices, rm, z_g, gap, nr):
    """How many vertices to look at for contacts at this step (rotation ``rm``, G at height ``z_g``, contacts
    within ``gap`` [m]): the list's first ``n_listed`` (``nr.members``), made again where a vertex outside it could
    touch; -1: every vertex (the body is sunk deeper than the band)."""
    if nr.n_listed[0] >= 0 and _bound(rm, z_g, nr.state) > gap:
        return nr.n_listed[0]
    _make(vertices, rm, nr)
    return nr.n_listed[0] if _bound(rm, z_g, nr.state) > gap else -1
