"""The probability of a stack's body overturning under the declared uncertainty (:mod:`pipeline.stacks`).

Draw k of every scene uses row k of the common random numbers (:mod:`.sampling`): the record's amplitude factor, one
factor on every body's height and one on every body's width (the bodies' sizes drawn together, their masses' ratios
kept), and one on every body's friction; the rocking plane is the given azimuth drawn about its value, the nominal
governing plane of a stack of unknown orientation, or, for the random orientation, a plane uniform on [0, 180) deg
from the draw's azimuth normal. The friction decides where a joint slips (the stack's contact model then follows
it); the models have no restitution of their own (their impacts lose what their impact law loses), so that draw is
not used. Each draw is judged by :func:`pipeline.assemblies.stack_scene.body_verdict` (a draw whose stack stays shut
stands without a run), with the sampling and stopping rule of every other scene
(:func:`.scenes.sample_until_decided`)."""

from __future__ import annotations

import math

import numpy as np

from ..assemblies.stack import StackPlace
from ..assemblies.stack_scene import RunMemo, body_scene
from ..records.record import project
from ..rocking.scene import Physics
from ..rocking.settings import SimulationConfig
from .sampling import lognormal_factor
from .scenes import Probability, SceneMotion, sample_until_decided
from .settings import UncertaintyConfig


def drawn_stack(place: StackPlace, z_row: np.ndarray, settings: UncertaintyConfig) -> StackPlace:
    """``place`` with its bodies' heights and widths (and offsets, with the widths) and their friction scaled by draw
    ``z_row``'s factors."""
    fh = float(lognormal_factor(z_row[3], settings.size_cov))
    fw = float(lognormal_factor(z_row[4], settings.size_cov))
    fmu = float(lognormal_factor(z_row[2], settings.friction_cov))
    bodies = tuple(b._replace(height_m=b.height_m * fh, width_m=b.width_m * fw, offset_m=b.offset_m * fw,
                              mu=b.mu * fmu) for b in place.bodies)
    return place._replace(bodies=bodies)


def uniform_plane_deg(z_azimuth: float) -> float:
    """A plane uniform on [0, 180) deg from a standard normal draw (its normal probability times 180)."""
    return 90.0 * (1.0 + math.erf(z_azimuth / math.sqrt(2.0)))


def stack_probability(m: SceneMotion, z: np.ndarray, place: StackPlace, *, plane_deg: float,
                      given_azimuth: bool, random_orientation: bool, settings: UncertaintyConfig,
                      simulation: SimulationConfig = SimulationConfig(), memo: RunMemo | None = None) -> Probability:
    """Sample the body of ``place`` until its robustness class is decided or ``z`` is used up.

    Parameters
    ----------
    m : SceneMotion
        The record.
    z : ndarray, shape (n, 6)
        Common random numbers.
    place : StackPlace
        The body and its stack.
    plane_deg : float
        The rocking plane [deg]: the given azimuth (drawn about it where ``given_azimuth``) or the nominal
        governing plane.
    given_azimuth, random_orientation : bool
        Draw the plane about a given azimuth; or draw it uniform (the random orientation).
    settings, simulation : UncertaintyConfig, SimulationConfig
        The spreads and the stopping rule; the simulator's settings.
    memo : RunMemo, optional
        The record's stack runs, shared with the stack's other body (a draw's run is the same for both).
    """
    vertical = m.vertical if m.vertical.size else None
    rows = m.h1[None, :] if m.single else np.vstack((m.h1, m.h2))

    def judge(sl: slice, verdicts: np.ndarray, runs: np.ndarray) -> None:
        for r in range(sl.start, sl.stop):
            az = (uniform_plane_deg(float(z[r, 5])) if random_orientation
                  else plane_deg + settings.azimuth_sd_deg * float(z[r, 5]) if given_azimuth else plane_deg)
            amplitude = float(lognormal_factor(z[r, 0], settings.amplitude_cov))
            ah = amplitude * project(rows, m.azimuth0_deg, az)
            sc = body_scene(drawn_stack(place, z[r], settings), ah, None if vertical is None else amplitude * vertical,
                            m.dt_s, settings=simulation, memo=memo, key=("draw", az, amplitude))
            verdicts[r] = sc.verdict            # Scene.verdict's codes are Verdict's
            runs[r] = 0 if sc.physics == Physics.none else 1

    return sample_until_decided(len(z), judge, settings=settings)

