"""Stacks for the stack contact model's peer comparisons (the slow tests tests/assemblies/test_stack_flight_peer.py
and test_stack_slip_peer.py, benchmarks/stack_flight_peer.py and stack_slip_peer.py): the bundled records whose
vertical reaches VERTICAL_G below gravity at a scale of at most MAX_SCALE, the stacks compared, rockscreen's first
fall, its class of a body under the default draws, and a disagreement in words."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from rigid_body_peer import NONE_FALLS

from pipeline.assemblies.n_block import NBlock, n_block
from pipeline.assemblies.n_block_verdicts import StackVerdicts
from pipeline.assemblies.stack import StackBody, StackPlace
from pipeline.assemblies.stack_scene import AT_REST, stack_run
from pipeline.config import Config
from pipeline.constants import G
from pipeline.records.loader import iter_records
from pipeline.rocking.codes import Verdict
from pipeline.uncertainty.robust import Robustness
from pipeline.uncertainty.sampling import common_normals
from pipeline.uncertainty.scenes import Probability, motion
from pipeline.uncertainty.settings import UncertaintyConfig
from pipeline.uncertainty.stacks import stack_probability

#: each record's vertical scaled down to this below gravity [g], where MAX_SCALE allows
VERTICAL_G = 1.2
MAX_SCALE = 2.2
#: friction of the boxes in PyBullet's sense: mu on the floor, mu^2 between two boxes [-]
MU = 0.8
RHO = 2500.0
#: family -> (width, height) of each box, bottom first [m]
STACKS = {"statue": ((0.70, 1.00), (0.45, 1.70)),
          "two": ((0.60, 1.50), (0.55, 1.20)),
          "three": ((0.62, 1.10), (0.60, 1.10), (0.58, 1.00)),
          "five": ((0.7, 0.8), (0.7, 0.8), (0.7, 0.8), (0.7, 0.8), (0.7, 0.6))}


def flight_records(records_dir: Path) -> list[tuple[str, np.ndarray, np.ndarray, float, float, float]]:
    """(id, horizontals, vertical, first horizontal's azimuth, dt, scale) of each record whose vertical, scaled by
    at most MAX_SCALE, falls to VERTICAL_G below gravity (none scaled down)."""
    out = []
    for r in iter_records(records_dir, config=Config()):
        if r.vertical_ms2 is None or not r.vertical_ms2.size or r.horizontal_ms2.shape[0] < 2:
            continue
        scale = max(1.0, VERTICAL_G * G / -r.vertical_ms2.min())
        if scale <= MAX_SCALE:
            out.append((r.record_id, r.horizontal_ms2 * scale, r.vertical_ms2 * scale, float(r.azimuths_deg[0]),
                        r.dt_s, scale))
    return out


def bodies(family: str, mu: float = MU) -> tuple[StackBody, ...]:
    """The family's boxes as the stack's bodies, bottom first (masses of boxes of one depth), each box's friction at
    its base: ``mu`` on the floor, mu^2 on a box, as PyBullet combines them."""
    return tuple(StackBody(w, h, RHO * w * h, mu if k == 0 else mu * mu) for k, (w, h) in enumerate(STACKS[family]))


def stack(family: str, mu: float = MU) -> tuple[NBlock, tuple]:
    """The family's stack for rockscreen (:func:`bodies`) and each box's friction at its base."""
    boxes = bodies(family, mu)
    return n_block(boxes), tuple(b.mu for b in boxes)


def screen_verdicts(family: str, ah_ms2: np.ndarray, dt_s: float, *, av_ms2: np.ndarray | None = None,
                    mu: float = MU) -> StackVerdicts:
    """The family's stack judged as ``screen`` judges it (:func:`pipeline.assemblies.stack_scene.stack_run`: the rest
    certificate, then the two-block model for two bodies, judged again as the n-block stack where it meets a slip or
    a flight, and the n-block model for more), every body standing where the certificate holds."""
    boxes = bodies(family, mu)
    run = stack_run(StackPlace(boxes, 0, tuple(f"{family}{k}" for k in range(len(boxes)))), ah_ms2, av_ms2, dt_s)
    if run is AT_REST:
        n = len(boxes)
        return StackVerdicts((int(Verdict.stands),) * n, (0.0,) * n, (math.nan,) * n, 0, False, 0, (0.0,) * n)
    return run


def drawn_class(family: str, position: int, horizontal_ms2: np.ndarray, vertical_ms2: np.ndarray | None,
                azimuth0_deg: float, dt_s: float, plane_deg: float, mu: float = MU) -> Probability:
    """The probability and robustness class ``screen`` gives body ``position`` of the family's stack (0: the bottom)
    rocking in ``plane_deg`` (on two horizontals a given azimuth, drawn about it; on one, its plane) under the
    declared uncertainty's default draws (:func:`pipeline.uncertainty.stacks.stack_probability`, the default
    :class:`UncertaintyConfig`)."""
    unc = UncertaintyConfig()
    boxes = bodies(family, mu)
    place = StackPlace(boxes, position, tuple(f"{family}{k}" for k in range(len(boxes))))
    base = motion(horizontal_ms2, azimuth0_deg, vertical_ms2, dt_s)
    return stack_probability(base, common_normals(unc.seed, unc.samples), place, plane_deg=plane_deg,
                             given_azimuth=not base.single, random_orientation=False, settings=unc)


def first_fall(judged) -> int:
    """The lowest body fallen at the first fall of rockscreen's verdicts, or NONE_FALLS."""
    times = [(t, k) for k, (v, t) in enumerate(zip(judged.verdicts, judged.t_fall_s)) if v == Verdict.overturns]
    return min(times)[1] if times else NONE_FALLS


def difference(scene: str, ours: int, ours_robust: bool, engine: int, robust: bool,
               drawn: Probability | None = None) -> str:
    """A disagreement on the first fall in words: each engine's lowest box fallen (:data:`NONE_FALLS`: none),
    whether rockscreen's holds at 0.98 and 1.02 of the record and the engine's at its half step and both scales, and
    rockscreen's probability and class under the draws of the box the engine overturns, where given."""
    text = (f"{scene}: rockscreen {ours} ({'' if ours_robust else 'not '}robust at 0.98 and 1.02), PyBullet {engine} "
            f"({'' if robust else 'not '}robust in the engine)")
    if drawn is not None:
        name = Robustness(drawn.robustness).name if drawn.robustness >= 0 else "undetermined"
        text += f"; rockscreen's box {engine} under the draws: p {drawn.p:.2f}, {name}"
    return text
