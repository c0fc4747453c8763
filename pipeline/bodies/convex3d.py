"""A body model for any rigid convex body judged in 3D by the contact model (:mod:`pipeline.rocking.solids.contact3d`):
it may slide, twist, rock on an edge or a corner, roll over its hull's facets and lift off, under both horizontals
and the vertical at once. A family of such bodies is what builds its :class:`~pipeline.rocking.solids.convex_body.
ConvexBody` from an inventory row (:class:`ConvexBodies`); :func:`convex_model` makes its registry entry, as the
scanned body in 3D (:mod:`.scanned3d`) is made.

**The frame.** The contact model's x axis points to a compass azimuth (the body's x axis where the inventory gives
its azimuth and the record's azimuth is known, else the record's first horizontal), its y axis 90 degrees
counter-clockwise of it seen from above; the horizontals are projected on both (one horizontal: along its own
azimuth). **The yaw.** Where the body's azimuth is given on a record of known azimuth, the body stands as given;
otherwise it is judged at every yaw of a :data:`YAW_STEP_DEG` grid, in turn, until one overturns it (the worst yaw:
overturned first, then the largest tilt). Where several yaws overturn it, the worst is the first of them in the grid,
not the one whose draws overturn it most often, and which comes first can turn with rounding
(docs/validation.md, "Another machine"). **Probabilities**: each draw of the declared uncertainty (amplitude, the
body's width and height about G, friction; :func:`~pipeline.uncertainty.two_sided.draw_factors`) is one run, at the
worst yaw (``p_overturn``) and, where the yaw is not known, at the grid's yaws in turn (``p_random_orientation``: the
draws cycle over the grid). The restitution draw does not apply: the contacts are plastic (Housner's rule at a
pivot). **Margins**: the first factor on the record that overturns the body at the worst yaw in the upward scan of
:func:`~.factor_sweep.factor_sweep` (steps of ``margin_step``), from the factor at which the ground's demand first
reaches the at-rest threshold min(mu, tan alpha_min) (:func:`~pipeline.rocking.solids.convex_body.base_threshold`).
**Pulses** (``screen infer``): along the direction the body tips in most easily (its family's), either way.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial
from typing import NamedTuple

import numpy as np

from ..records.record import Record, project
from ..rocking.block import Block, BlockShape
from ..rocking.codes import Verdict
from ..rocking.orientation import Orientation, PlaneResult
from ..rocking.scene import Physics, Scene
from ..rocking.settings import SimulationConfig
from ..rocking.solids.contact3d import Contact3DOutcome, pose, simulate_contact3d
from ..rocking.solids.contact_scene import outcome_scene
from ..rocking.solids.convex_body import ConvexBody, base_threshold
from ..uncertainty.orientations import NOT_EVALUATED_ORIENTATION, OrientationProbability, one_plane
from ..uncertainty.sampling import common_normals
from ..uncertainty.scenes import Probability, sample_until_decided
from ..uncertainty.settings import UncertaintyConfig
from ..uncertainty.two_sided import draw_factors
from .contract import (
    BodyModel,
    BodyScene,
    Margin,
    OnRecord,
    Placement,
    PulseJudge,
    PulseOutcome,
    Setup,
    claims_on_two_horizontals,
)
from .factor_sweep import factor_sweep
from .solids import contact_warmup

#: The yaws a body of unknown orientation is judged at [deg]
YAW_STEP_DEG = 30.0


class Frame(NamedTuple):
    """A record in the contact model's frame: x toward compass ``x_deg``, y 90 deg counter-clockwise of it; the
    yaws of the body's settled x axis from x to judge [deg]; whether the body's azimuth is given."""

    ax: np.ndarray
    ay: np.ndarray
    av: np.ndarray | None
    dt_s: float
    x_deg: float
    yaws_deg: np.ndarray
    given: bool


class Judged(NamedTuple):
    """The worst yaw's scene, that yaw [deg], the contact model's outcome there and the runs."""

    scene: Scene
    yaw_deg: float
    outcome: Contact3DOutcome
    runs: int


def frame(rec: Record, shape: BlockShape) -> Frame:
    """The record in the contact model's frame for ``shape`` (see the module)."""
    a0 = float(rec.azimuths_deg[0])
    given = bool(rec.azimuth_known) and math.isfinite(shape.azimuth_deg)
    x_deg = float(shape.azimuth_deg) if given else a0
    h = np.atleast_2d(rec.horizontal_ms2)
    if h.shape[0] == 1:
        turn = math.radians(a0 - x_deg)
        ax, ay = math.cos(turn) * h[0], -math.sin(turn) * h[0]
    else:
        ax, ay = project(h, a0, x_deg), project(h, a0, x_deg - 90.0)
    yaws = np.zeros(1) if given else np.arange(0.0, 360.0, YAW_STEP_DEG)
    return Frame(np.ascontiguousarray(ax, dtype=float), np.ascontiguousarray(ay, dtype=float), rec.vertical_ms2,
                 float(rec.dt_s), x_deg, yaws, given)


class ConvexBodies(NamedTuple):
    """A family of convex bodies judged by :func:`convex_model`: how an inventory row becomes a body.

    Attributes
    ----------
    body_of : callable
        ``body_of(shape, *, width=1.0, height=1.0, friction=1.0) -> ConvexBody``: the contact model's body of the row,
        stretched by a draw's factors (its width and height about G, its friction).
    weakest_deg : callable
        ``weakest_deg(shape) -> float``: the azimuth, in the body's axes, toward which it tips most easily [deg]
        (the direction of ``screen infer``'s pulses).
    """

    body_of: Callable[..., ConvexBody]
    weakest_deg: Callable[[BlockShape], float]


def tipping_angle(body: ConvexBody) -> float:
    """The angle the body's tilt is reported against, its smallest static tipping angle [rad]: its own where given
    (a scan's), else that of the base it stands on, atan of :func:`~pipeline.rocking.solids.convex_body.base_threshold`
    without friction."""
    if math.isfinite(body.tipping_rad):
        return float(body.tipping_rad)
    return math.atan(base_threshold(pose(body.vertices, body.rest).standing, math.inf))


def run(fr: Frame, body: ConvexBody, yaw_deg: float, *, g_ms2: float, amplitude: float = 1.0,
        history: bool = False) -> Contact3DOutcome:
    """One run of the contact model: the body at ``yaw_deg`` under the record times ``amplitude``."""
    av = None if fr.av is None else amplitude * np.asarray(fr.av, dtype=float)
    return simulate_contact3d(amplitude * fr.ax, amplitude * fr.ay, av, fr.dt_s, body, yaw_deg=yaw_deg, g_ms2=g_ms2,
                              history=history)


def judge(fr: Frame, body: ConvexBody, *, g_ms2: float, amplitude: float = 1.0) -> Judged:
    """The worst of the frame's yaws (overturned first, then the largest tilt), stopping at the first that
    overturns the body."""
    worst: tuple[float, Contact3DOutcome] | None = None
    runs = 0
    for yaw in fr.yaws_deg:
        out = run(fr, body, float(yaw), g_ms2=g_ms2, amplitude=amplitude)
        runs += 1
        if worst is None or (out.overturned, out.tilt_max_rad) > (worst[1].overturned, worst[1].tilt_max_rad):
            worst = (float(yaw), out)
        if out.overturned:
            break
    assert worst is not None
    return Judged(outcome_scene(worst[1], tipping_angle(body)), worst[0], worst[1], runs)


def _lean_deg(fr: Frame, out: Contact3DOutcome) -> float:
    """The compass azimuth the body leant toward at its peak (NaN: it never tilted)."""
    return (fr.x_deg - out.lean_at_peak_deg) % 360.0 if out.tilt_max_rad > 0.0 else math.nan


def yaw_draws(fr: Frame, shape: BlockShape, z: np.ndarray, yaws: np.ndarray, drawn: dict[int, ConvexBody], *,
           family: ConvexBodies, settings: UncertaintyConfig, g_ms2: float) -> Probability:
    """The probability of overturning over the draws ``z``, draw k at ``yaws[k % len(yaws)]``, stopped by the sequential
    rule (:func:`~pipeline.uncertainty.scenes.sample_until_decided`); each draw's stretched body (its tipping angle
    costs a search over the hull) is kept in ``drawn`` under k, for the other draws of the same k."""
    def judge_draws(sl: slice, verdicts: np.ndarray, runs: np.ndarray) -> None:
        for k in range(sl.start, sl.stop):
            f = draw_factors(z[k], settings)
            if k not in drawn:
                drawn[k] = family.body_of(shape, width=f.width, height=f.height, friction=f.friction)
            out = run(fr, drawn[k], float(yaws[k % len(yaws)]), g_ms2=g_ms2, amplitude=f.amplitude)
            verdicts[k] = Verdict.overturns if out.overturned else Verdict.stands
            runs[k] = 1 if out.integrated_steps else 0

    return sample_until_decided(len(z), judge_draws, settings=settings)


def scene(on: OnRecord, shape: BlockShape, block: Block, direction_deg: float, *, bodies: ConvexBodies) -> BodyScene:
    """The body's scene in 3D on ``on`` (see the module)."""
    rec, setup = on.record, on.setup
    fr = frame(rec, shape)
    j = judge(fr, bodies.body_of(shape), g_ms2=setup.g_ms2)
    moved = j.outcome.integrated_steps > 0
    res = PlaneResult(j.scene, _lean_deg(fr, j.outcome), j.runs if moved else 0, ())
    code = (Orientation.given if fr.given else Orientation.single_component if rec.single_component
            else Orientation.scanned if rec.azimuth_known else Orientation.scanned_relative)
    orient = NOT_EVALUATED_ORIENTATION
    if on.base is not None and on.draws is not None:
        unc = setup.uncertainty
        drawn: dict[int, ConvexBody] = {}
        worst = yaw_draws(fr, shape, on.draws[0], np.array([j.yaw_deg]), drawn, family=bodies, settings=unc,
                       g_ms2=setup.g_ms2)
        if fr.given:
            orient = one_plane(worst, res.azimuth_deg)
        else:
            rnd = yaw_draws(fr, shape, on.draws[0], fr.yaws_deg, drawn, family=bodies, settings=unc, g_ms2=setup.g_ms2)
            orient = OrientationProbability(worst, res.azimuth_deg, rnd.p, rnd.low, rnd.high,
                                            worst.simulations + rnd.simulations)
    yaws = "given" if fr.given else f"{j.runs} of {len(fr.yaws_deg)} yaws"
    return BodyScene(res, orient, code,
                     lambda: f"convex body in 3D ({yaws}), leaning toward {res.azimuth_deg:.0f} deg")


def _first_lift(fr: Frame, body: ConvexBody, g_ms2: float) -> float:
    """The smallest factor on the record at which the ground's demand reaches the body's at-rest threshold
    (nothing moves below it) [-]."""
    threshold = base_threshold(pose(body.vertices, body.rest).standing, body.mu)
    push = np.hypot(fr.ax, fr.ay) - (threshold * fr.av if fr.av is not None else 0.0)
    if not np.any(push > 0.0):
        return math.inf
    return float(np.min(threshold * g_ms2 / push[push > 0.0]))


def margin(fr: Frame, body: ConvexBody, yaw_deg: float, *, settings: SimulationConfig, g_ms2: float,
           overturns_at_one: bool | None = None) -> tuple[float, int]:
    """The first factor of the upward scan (:func:`~.factor_sweep.factor_sweep`) that overturns the body at
    ``yaw_deg``, and the runs."""
    first = _first_lift(fr, body, g_ms2)
    if not math.isfinite(first):
        return math.inf, 0

    def verdict_at(factor: float) -> int:
        return int(run(fr, body, yaw_deg, g_ms2=g_ms2, amplitude=factor).overturned)

    return factor_sweep(first, verdict_at, settings=settings, overturns_at_one=overturns_at_one)


def margins(rec, shape: BlockShape, block: Block, direction_deg: float, *, setup: Setup, overturned: bool,
            want_history: bool, bodies: ConvexBodies) -> Margin:
    """The body's margins in 3D on its governing record at its worst yaw: the margin, its history when at
    risk (shape (2, n): tilt over the smallest tipping angle, and the compass azimuth it leans toward), and the
    sampled margins (each draw's own body, as factors on the nominal record)."""
    g, settings = setup.g_ms2, setup.settings
    fr = frame(rec, shape)
    body = bodies.body_of(shape)
    yaw = judge(fr, body, g_ms2=g).yaw_deg
    scale, runs = margin(fr, body, yaw, settings=settings, g_ms2=g, overturns_at_one=overturned)
    history = None
    if want_history or scale <= setup.history_below_scale:
        out = run(fr, body, yaw, g_ms2=g, history=True)
        if out.tilt_max_rad > 0.0 and out.tilt_rad is not None and out.lean_deg is not None:
            history = np.vstack([out.tilt_rad / tipping_angle(body), (fr.x_deg - out.lean_deg) % 360.0])
    n = setup.uncertainty.margin_samples if setup.sampling else 0
    sampled = np.full(max(n, 0), np.nan)
    if n > 0:
        z = common_normals(setup.uncertainty.seed, n)
        for k in range(n):
            f = draw_factors(z[k], setup.uncertainty)
            drawn = bodies.body_of(shape, width=f.width, height=f.height, friction=f.friction)
            s_k, r = margin(fr._replace(ax=f.amplitude * fr.ax, ay=f.amplitude * fr.ay,
                                        av=None if fr.av is None else f.amplitude * np.asarray(fr.av)),
                            drawn, yaw, settings=settings, g_ms2=g)
            sampled[k], runs = s_k * f.amplitude, runs + r
    return Margin(scale, runs, history, rec.dt_s, sampled)


def scale(rec, shape: BlockShape, block: Block, plane_deg: float, *, settings: SimulationConfig,
          g_ms2: float, bodies: ConvexBodies) -> float:
    """The simulated margin at the worst yaw (on the record's horizontals: ``plane_deg`` is not used)."""
    fr = frame(rec, shape)
    body = bodies.body_of(shape)
    return margin(fr, body, judge(fr, body, g_ms2=g_ms2).yaw_deg, settings=settings, g_ms2=g_ms2)[0]


def pulse(shape: BlockShape, block: Block, *, settings: SimulationConfig, g_ms2: float,
          bodies: ConvexBodies) -> PulseJudge:
    """A judge of one-directional pulses: along the direction the body tips in most easily, either way; two runs."""
    body = bodies.body_of(shape)
    weakest_deg = bodies.weakest_deg(shape)

    def judge_pulse(ah_ms2: np.ndarray, dt_s: float) -> PulseOutcome:
        ah = np.ascontiguousarray(ah_ms2, dtype=float)
        return PulseOutcome(any(simulate_contact3d(sense * ah, np.zeros_like(ah), None, dt_s, body,
                                                   yaw_deg=-weakest_deg, g_ms2=g_ms2).overturned
                                for sense in (1.0, -1.0)), 2)

    return judge_pulse


def convex_model(name: str, claims: Callable[[BlockShape, Placement, SimulationConfig], bool],
                 bodies: ConvexBodies) -> BodyModel:
    """The registry entry of a family of convex bodies judged in 3D (see the module): its kernel is the contact model
    the cylinder and the box hand over to (their warm-up)."""
    return BodyModel(name=name, physics=(Physics.contact3d,), claims=claims,
                     may_claim=claims_on_two_horizontals(claims), scene=partial(scene, bodies=bodies),
                     margins=partial(margins, bodies=bodies), scale=partial(scale, bodies=bodies),
                     pulse=partial(pulse, bodies=bodies), shared_warmups=(contact_warmup,))
