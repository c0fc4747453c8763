"""The arrays the 3D contact model's kernel (:mod:`.contact3d`) works in: made once for a body, and made fresh again
in place for each run of a scene that hands the body back and forth (:mod:`.alternate`), so that those runs do not
make them again (the kernel itself makes none: :func:`~pipeline.compiled.jit_lean`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .near_ground import emptied, near


class Room(NamedTuple):
    """The arrays the kernel works in: ``contact`` the last impulse per vertex (the warm start), room for the
    contacts' arms, indices, velocities and impulses, the vertices near the ground (:class:`~.near_ground.Near`) and
    the vertices the last step loaded (how many, then which: the only impulses not zero, cleared at the next step
    rather than every vertex's); ``frames`` room for a step's middle quaternion, rotation and world inverse inertia;
    ``r`` the rotation at a step's end; the body's place ``x``, orientation ``q``, velocity ``v`` and rate ``w``."""

    contact: tuple
    frames: tuple
    r: np.ndarray
    x: np.ndarray
    q: np.ndarray
    v: np.ndarray
    w: np.ndarray


def room(vertices: np.ndarray) -> Room:
    """The kernel's arrays for a body of ``vertices`` (:class:`Room`), the warm start at zero, no list of the
    vertices near the ground yet."""
    n_v = len(vertices)
    return Room((np.zeros((n_v, 3)), np.empty((n_v, 3)), np.empty(n_v, dtype=np.int64), np.empty(n_v),
                 np.empty((n_v, 3)), near(vertices), np.zeros(n_v + 1, dtype=np.int64)),
                (np.empty(4), np.empty((3, 3)), np.empty((3, 3))),
                np.empty((3, 3)), np.empty(3), np.empty(4), np.empty(3), np.empty(3))


def made_fresh(rm: Room) -> None:
    """``rm`` made, in place, as :func:`room` makes it: the warm start at zero, no list of the vertices near the
    ground, no vertex loaded by a last step (the kernel writes the rest before it reads it)."""
    rm.contact[0].fill(0.0)
    emptied(rm.contact[5])
    rm.contact[6].fill(0)
