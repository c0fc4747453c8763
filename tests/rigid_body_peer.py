"""An independent rigid-body engine for tests only: PyBullet (zlib licence, an optional test dependency).

A deep box on a rigid floor in the ground's frame: the ground's motion enters as a time-varying gravity
(-a_h, 0, -(g + a_v)), linear between the record's samples. Bullet multiplies the two bodies' friction
coefficients, so the floor gets 1 and the block its mu; restitution 0 (the impacting corner does not
rebound). Calibrated on the half-sine threshold of a 2 m x 0.3 m block at omega/p = 3 (tests).
"""

from __future__ import annotations

import math

import numpy as np
from peers import missing_peer

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


def bullet_overturns(ah_ms2: np.ndarray, av_ms2: np.ndarray | None, dt_s: float, *, height_m: float, width_m: float,
                     mu: float, g_ms2: float = 9.80665, step_s: float = STEP_S) -> tuple[bool, float]:
    """(overturned, largest tilt [rad]) of a free-standing box under a ground motion, by PyBullet."""
    pb = pybullet()
    cid = pb.connect(pb.DIRECT)
    try:
        pb.setPhysicsEngineParameter(fixedTimeStep=step_s, numSolverIterations=150, numSubSteps=0,
                                     restitutionVelocityThreshold=0.0, physicsClientId=cid)
        plane = pb.createMultiBody(0, pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=cid),
                                   physicsClientId=cid)
        b, h = width_m / 2, height_m / 2
        depth = max(width_m, height_m)                 # deep: it rocks in its plane, never sideways
        box = pb.createMultiBody(1.0, pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[b, depth / 2, h],
                                                              physicsClientId=cid),
                                 basePosition=[0, 0, h], physicsClientId=cid)
        pb.changeDynamics(plane, -1, lateralFriction=1.0, restitution=0.0, physicsClientId=cid)
        pb.changeDynamics(box, -1, lateralFriction=mu, restitution=0.0, rollingFriction=0.0, spinningFriction=0.0,
                          linearDamping=0.0, angularDamping=0.0, physicsClientId=cid)
        n = ah_ms2.size
        t_rec = (n - 1) * dt_s
        tilt_max = 0.0
        for i in range(int((t_rec + TAIL_S) / step_s)):
            t = i * step_s
            a = v = 0.0
            if t < t_rec:
                k = min(int(t / dt_s), n - 2)
                f = t / dt_s - k
                a = ah_ms2[k] + f * (ah_ms2[k + 1] - ah_ms2[k])
                v = av_ms2[k] + f * (av_ms2[k + 1] - av_ms2[k]) if av_ms2 is not None else 0.0
            pb.setGravity(-a, 0.0, -(g_ms2 + v), physicsClientId=cid)
            pb.stepSimulation(physicsClientId=cid)
            if i % 4 == 0:
                _pos, q = pb.getBasePositionAndOrientation(box, physicsClientId=cid)
                tilt = math.acos(max(-1.0, min(1.0, pb.getMatrixFromQuaternion(q)[8])))
                tilt_max = max(tilt_max, tilt)
                if tilt >= math.pi / 2:
                    return True, tilt_max
        return False, tilt_max
    finally:
        pb.disconnect(cid)


def bullet_cylinder_overturns(ax_ms2: np.ndarray, ay_ms2: np.ndarray, az_ms2: np.ndarray | None, dt_s: float, *,
                              height_m: float, diameter_m: float, mu: float, g_ms2: float = 9.80665,
                              step_s: float = STEP_S, scale: float = 1.0) -> tuple[bool, float]:
    """(overturned, largest tilt [rad]) of a free-standing solid cylinder under two horizontal components (x, y:
    y 90 deg counter-clockwise of x seen from above) and the vertical, all times ``scale``, by PyBullet: the same
    setting as :func:`bullet_overturns` (time-varying gravity, restitution 0, friction mu x 1)."""
    pb = pybullet()
    cid = pb.connect(pb.DIRECT)
    try:
        pb.setPhysicsEngineParameter(fixedTimeStep=step_s, numSolverIterations=150, numSubSteps=0,
                                     restitutionVelocityThreshold=0.0, physicsClientId=cid)
        plane = pb.createMultiBody(0, pb.createCollisionShape(pb.GEOM_PLANE, physicsClientId=cid),
                                   physicsClientId=cid)
        body = pb.createMultiBody(1.0, pb.createCollisionShape(pb.GEOM_CYLINDER, radius=diameter_m / 2,
                                                               height=height_m, physicsClientId=cid),
                                  basePosition=[0, 0, height_m / 2], physicsClientId=cid)
        pb.changeDynamics(plane, -1, lateralFriction=1.0, restitution=0.0, physicsClientId=cid)
        pb.changeDynamics(body, -1, lateralFriction=mu, restitution=0.0, rollingFriction=0.0, spinningFriction=0.0,
                          linearDamping=0.0, angularDamping=0.0, physicsClientId=cid)
        n = ax_ms2.size
        t_rec = (n - 1) * dt_s
        tilt_max = 0.0
        for i in range(int((t_rec + TAIL_S) / step_s)):
            t = i * step_s
            a = b = v = 0.0
            if t < t_rec:
                k = min(int(t / dt_s), n - 2)
                f = t / dt_s - k
                a = scale * (ax_ms2[k] + f * (ax_ms2[k + 1] - ax_ms2[k]))
                b = scale * (ay_ms2[k] + f * (ay_ms2[k + 1] - ay_ms2[k]))
                v = scale * (az_ms2[k] + f * (az_ms2[k + 1] - az_ms2[k])) if az_ms2 is not None else 0.0
            pb.setGravity(-a, -b, -(g_ms2 + v), physicsClientId=cid)
            pb.stepSimulation(physicsClientId=cid)
            if i % 4 == 0:
                _pos, q = pb.getBasePositionAndOrientation(body, physicsClientId=cid)
                tilt = math.acos(max(-1.0, min(1.0, pb.getMatrixFromQuaternion(q)[8])))
                tilt_max = max(tilt_max, tilt)
                if tilt >= math.pi / 2 - 0.05:         # on its side (the rim keeps it a little off pi/2)
                    return True, tilt_max
        return False, tilt_max
    finally:
        pb.disconnect(cid)
