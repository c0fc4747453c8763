"""An independent rigid-body engine for tests only: PyBullet (zlib licence, an optional test dependency).

A deep box on a rigid floor in the ground's frame: the ground's motion enters as a time-varying gravity
(-a_h, 0, -(g + a_v)), linear between the record's samples. Bullet multiplies the two bodies' friction
coefficients, so the floor gets 1 and the block its mu; restitution 0 (the impacting corner does not
rebound). Calibrated on the half-sine threshold of a 2 m x 0.3 m block at omega/p = 3 (tests).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from peers import missing_peer

from pipeline.config import Config
from pipeline.records.loader import iter_records

#: Bullet's fixed step [s]: 1/2000 s is not converged on long chaotic records, 1/4000 s is where the verdicts
#: on the bundled scenes stop changing (1/8000 and 1/16000 s give the same, measured on the disagreements).
STEP_S = 1.0 / 4000.0
#: Free motion followed after the record [s].
TAIL_S = 5.0


def pybullet():
    """The pybullet module, or a skip (a failure where ROCKSCREEN_REQUIRE_PEERS=1, as in CI)."""
    try:
        import pybullet as pb
    except ImportError:
        message = ("pybullet is not installed: the comparison with an independent rigid-body engine is SKIPPED "
                   "(pip install pybullet, or the project's test extras)")
        missing_peer(message)
    return pb


def ground_at(ground: tuple, t: float, dt_s: float) -> tuple[float, float, float]:
    """The ground's (a_x, a_y, a_v) [m s-2] at time ``t`` [s], linear between the samples (a component None: 0; after
    the record: 0)."""
    n = ground[0].size
    if t >= (n - 1) * dt_s:
        return 0.0, 0.0, 0.0
    k = min(int(t / dt_s), n - 2)
    f = t / dt_s - k
    a = [0.0 if x is None else x[k] + f * (x[k + 1] - x[k]) for x in ground]
    return a[0], a[1], a[2]


def _world(pb, step_s: float) -> int:
    """A Bullet world with a rigid floor of friction 1 and restitution 0, stepped at ``step_s``; its client id."""
    cid = pb.connect(pb.DIRECT)
    pb.setPhysicsEngineParameter(fixedTimeStep=step_s, numSolverIterations=150, numSubSteps=0,
                                 restitutionVelocityThreshold=0.0, physicsClientId=cid)
    plane = pb.createMultiBody(0, pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=cid), physicsClientId=cid)
    pb.changeDynamics(plane, -1, lateralFriction=1.0, restitution=0.0, physicsClientId=cid)
    return cid


def _free_body(pb, body: int, mu: float, cid: int) -> None:
    """The body's friction mu (x the floor's 1), no restitution, no rolling or spinning friction, no damping."""
    pb.changeDynamics(body, -1, lateralFriction=mu, restitution=0.0, rollingFriction=0.0, spinningFriction=0.0,
                      linearDamping=0.0, angularDamping=0.0, physicsClientId=cid)


def _shake(pb, cid: int, body: int, ground: tuple, dt_s: float, *, g_ms2: float, step_s: float,
           fallen_rad: float) -> tuple[bool, float]:
    """Step the world under the ground's (a_x, a_y, a_v) [m s-2] (a_y, a_v None: none), linear between samples, as
    a time-varying gravity, through the record and :data:`TAIL_S` after it: (fallen, largest tilt [rad])."""
    t_rec = (ground[0].size - 1) * dt_s
    tilt_max = 0.0
    for i in range(int((t_rec + TAIL_S) / step_s)):
        acc = ground_at(ground, i * step_s, dt_s)
        pb.setGravity(-acc[0], -acc[1], -(g_ms2 + acc[2]), physicsClientId=cid)
        pb.stepSimulation(physicsClientId=cid)
        if i % 4 == 0:
            _pos, q = pb.getBasePositionAndOrientation(body, physicsClientId=cid)
            tilt = math.acos(max(-1.0, min(1.0, pb.getMatrixFromQuaternion(q)[8])))
            tilt_max = max(tilt_max, tilt)
            if tilt >= fallen_rad:
                return True, tilt_max
    return False, tilt_max


def bullet_overturns(ah_ms2: np.ndarray, av_ms2: np.ndarray | None, dt_s: float, *, height_m: float, width_m: float,
                     mu: float, g_ms2: float = 9.80665, step_s: float = STEP_S) -> tuple[bool, float]:
    """(overturned, largest tilt [rad]) of a free-standing box under a ground motion, by PyBullet."""
    pb = pybullet()
    cid = _world(pb, step_s)
    try:
        b, h = width_m / 2, height_m / 2
        depth = max(width_m, height_m)                 # deep: it rocks in its plane, never sideways
        box = pb.createMultiBody(1.0, pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[b, depth / 2, h],
                                                              physicsClientId=cid),
                                 basePosition=[0, 0, h], physicsClientId=cid)
        _free_body(pb, box, mu, cid)
        return _shake(pb, cid, box, (ah_ms2, None, av_ms2), dt_s, g_ms2=g_ms2, step_s=step_s, fallen_rad=math.pi / 2)
    finally:
        pb.disconnect(cid)


def bullet_cylinder_overturns(ax_ms2: np.ndarray, ay_ms2: np.ndarray, az_ms2: np.ndarray | None, dt_s: float, *,
                              height_m: float, diameter_m: float, mu: float, g_ms2: float = 9.80665,
                              step_s: float = STEP_S, scale: float = 1.0) -> tuple[bool, float]:
    """(overturned, largest tilt [rad]) of a free-standing solid cylinder under two horizontal components (x, y:
    y 90 deg counter-clockwise of x seen from above) and the vertical, all times ``scale``, by PyBullet: the same
    setting as :func:`bullet_overturns` (time-varying gravity, restitution 0, friction mu x 1)."""
    pb = pybullet()
    cid = _world(pb, step_s)
    try:
        body = pb.createMultiBody(1.0, pb.createCollisionShape(pb.GEOM_CYLINDER, radius=diameter_m / 2,
                                                               height=height_m, physicsClientId=cid),
                                  basePosition=[0, 0, height_m / 2], physicsClientId=cid)
        _free_body(pb, body, mu, cid)
        scaled = tuple(None if x is None else scale * np.asarray(x) for x in (ax_ms2, ay_ms2, az_ms2))
        # on its side: the rim keeps it a little off pi/2
        return _shake(pb, cid, body, scaled, dt_s, g_ms2=g_ms2, step_s=step_s, fallen_rad=math.pi / 2 - 0.05)
    finally:
        pb.disconnect(cid)


def bullet_box_overturns(ax_ms2: np.ndarray, ay_ms2: np.ndarray, az_ms2: np.ndarray | None, dt_s: float, *,
                         width_m: float, depth_m: float, height_m: float, mu: float, g_ms2: float = 9.80665,
                         step_s: float = STEP_S, scale: float = 1.0) -> tuple[bool, float]:
    """(overturned, largest tilt [rad]) of a free-standing box (its width along x, its depth along y) under two
    horizontal components (x, y: y 90 deg counter-clockwise of x seen from above) and the vertical, all times
    ``scale``, by PyBullet: the same setting as :func:`bullet_overturns`."""
    pb = pybullet()
    cid = _world(pb, step_s)
    try:
        shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[width_m / 2, depth_m / 2, height_m / 2],
                                        physicsClientId=cid)
        body = pb.createMultiBody(1.0, shape, basePosition=[0, 0, height_m / 2], physicsClientId=cid)
        _free_body(pb, body, mu, cid)
        scaled = tuple(None if x is None else scale * np.asarray(x) for x in (ax_ms2, ay_ms2, az_ms2))
        return _shake(pb, cid, body, scaled, dt_s, g_ms2=g_ms2, step_s=step_s, fallen_rad=math.pi / 2)
    finally:
        pb.disconnect(cid)


def perturbed_verdicts(judge) -> set:
    """The engine's verdicts at half its step and at 0.98 and 1.02 of the record (``judge(step_s=..., scale=...)``
    one run): a verdict is robust in the engine where these are all its verdict at its own step and scale 1."""
    return {judge(step_s=STEP_S / 2, scale=1.0)} | {judge(step_s=STEP_S, scale=s) for s in (0.98, 1.02)}


#: What falls first in :func:`bullet_stack_falls`: nothing, the upper box, the lower one (the stack)
STACK_STANDS, TOP_FALLS, STACK_FALLS = 0, 1, 2
#: :func:`bullet_first_fall` when no box falls
NONE_FALLS = -1


def bullet_stack_falls(ah_ms2: np.ndarray, dt_s: float, lower: tuple[float, float], upper: tuple[float, float], *,
                       mu: float = 2.0, density: float = 2500.0, g_ms2: float = 9.80665, step_s: float = STEP_S,
                       scale: float = 1.0) -> int:
    """What falls first of two deep boxes stacked, centred, ((width, height) [m] each, the lower first), under a
    horizontal ground motion along x (times ``scale``), by PyBullet (:func:`bullet_first_fall`): returns
    :data:`STACK_STANDS`, :data:`TOP_FALLS` or :data:`STACK_FALLS`."""
    first = bullet_first_fall(ah_ms2, dt_s, [lower, upper], mu=mu, density=density, g_ms2=g_ms2, step_s=step_s,
                              scale=scale)
    return {NONE_FALLS: STACK_STANDS, 1: TOP_FALLS, 0: STACK_FALLS}[first]


def _stack_bodies(pb, cid: int, boxes, mu: float, density: float) -> list[int]:
    """Deep boxes stacked, centred, ((width, height) [m] each, bottom first), each of friction ``mu``: their ids."""
    depth = 2.0 * max(sum(h for _, h in boxes), max(w for w, _ in boxes))   # deep: the stack rocks in its plane
    bodies, base = [], 0.0
    for w, h in boxes:
        shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[w / 2, depth / 2, h / 2], physicsClientId=cid)
        body = pb.createMultiBody(density * w * h * depth, shape, basePosition=[0, 0, base + h / 2],
                                  physicsClientId=cid)
        _free_body(pb, body, mu, cid)
        bodies.append(body)
        base += h
    return bodies


#: A box of a stack has fallen once its tilt reaches this [rad]
FALLEN_TILT_RAD = math.pi / 2 - 0.02


def _stack_tilts(pb, cid: int, bodies: list[int], ground: tuple, dt_s: float, *, g_ms2: float, step_s: float):
    """Step a stack's world under the ground's (a_x, a_y, a_v) [m s-2] as a time-varying gravity, through the record
    and :data:`TAIL_S` after it, yielding every 8 steps each body's tilt [rad], bottom first."""
    t_rec = (ground[0].size - 1) * dt_s
    for i in range(int((t_rec + TAIL_S) / step_s)):
        acc = ground_at(ground, i * step_s, dt_s)
        pb.setGravity(-acc[0], 0.0, -(g_ms2 + acc[2]), physicsClientId=cid)
        pb.stepSimulation(physicsClientId=cid)
        if i % 8 == 0:
            yield [math.acos(max(-1.0, min(1.0, pb.getMatrixFromQuaternion(
                pb.getBasePositionAndOrientation(body, physicsClientId=cid)[1])[8]))) for body in bodies]


def bullet_stack_fallen(ah_ms2: np.ndarray, dt_s: float, boxes, *, mu: float = 2.0, density: float = 2500.0,
                        g_ms2: float = 9.80665, step_s: float = STEP_S, scale: float = 1.0,
                        av_ms2: np.ndarray | None = None) -> tuple[bool, ...]:
    """Which boxes of a stack have fallen by the end of the record and :data:`TAIL_S` after it (bottom first), in
    the setting of :func:`bullet_first_fall`: a box has fallen once its tilt reaches :data:`FALLEN_TILT_RAD`,
    whatever it does after, or when at the end its centre is below its place in the stack at rest by more than half
    its height (it left the box under it)."""
    pb = pybullet()
    cid = _world(pb, step_s)
    try:
        bodies = _stack_bodies(pb, cid, boxes, mu, density)
        heights = np.array([h for _, h in boxes])
        rest_z = np.cumsum(heights) - 0.5 * heights
        fallen = [False] * len(boxes)
        ground = (scale * np.asarray(ah_ms2), None, None if av_ms2 is None else scale * np.asarray(av_ms2))
        for tilts in _stack_tilts(pb, cid, bodies, ground, dt_s, g_ms2=g_ms2, step_s=step_s):
            fallen = [f or tilt >= FALLEN_TILT_RAD for f, tilt in zip(fallen, tilts)]
            if all(fallen):
                break
        ends = [pb.getBasePositionAndOrientation(body, physicsClientId=cid)[0][2] for body in bodies]
        return tuple(f or z < z0 - 0.5 * h for f, z, z0, h in zip(fallen, ends, rest_z, heights))
    finally:
        pb.disconnect(cid)


def bullet_first_fall(ah_ms2: np.ndarray, dt_s: float, boxes, *, mu: float = 2.0, density: float = 2500.0,
                      g_ms2: float = 9.80665, step_s: float = STEP_S, scale: float = 1.0,
                      av_ms2: np.ndarray | None = None) -> int:
    """The lowest box that has fallen when a box of a stack first falls, or :data:`NONE_FALLS`: deep boxes stacked,
    centred, ((width, height) [m] each, bottom first), under a horizontal ground motion along x and the vertical
    ``av_ms2`` where given (both times ``scale``), by PyBullet: the same setting as :func:`bullet_overturns`
    (time-varying gravity, restitution 0, friction mu x 1 on the floor and mu x mu between the boxes). A box has
    fallen when its tilt reaches :data:`FALLEN_TILT_RAD`."""
    pb = pybullet()
    cid = _world(pb, step_s)
    try:
        bodies = _stack_bodies(pb, cid, boxes, mu, density)
        ground = (scale * np.asarray(ah_ms2), None, None if av_ms2 is None else scale * np.asarray(av_ms2))
        for tilts in _stack_tilts(pb, cid, bodies, ground, dt_s, g_ms2=g_ms2, step_s=step_s):
            fallen = [k for k, tilt in enumerate(tilts) if tilt >= FALLEN_TILT_RAD]
            if fallen:
                return fallen[0]
        return NONE_FALLS
    finally:
        pb.disconnect(cid)


def short_records(records_dir: Path, max_duration_s: float = 60.0) -> list:
    """The records of ``records_dir`` (rockscreen's reader) of at most ``max_duration_s`` [s], in its order: the
    scenes the stacks' peer comparisons run on."""
    return [r for r in iter_records(records_dir, config=Config())
            if r.horizontal_ms2[0].size * r.dt_s <= max_duration_s]
