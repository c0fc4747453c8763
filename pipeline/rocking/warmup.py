"""Compile the simulator once, in one process, before any worker needs it.

numba compiles the kernels on their first call and keeps them on disk (``cache=True``), so only the first run
of an install pays for it. :func:`compile_kernels` makes that first call on a tiny scene, in the calling
process, so that the workers of a run load the compiled kernels instead of each compiling them, and so that
the caller can say what is happening.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from ..compiled import HAVE_NUMBA
from ..constants import G
from ..shapes.hull import rectangle_chain
from ..ticker import Ticker
from .models import MODELS
from .planar.sampled import sample_plane_outcomes, sample_verdicts
from .references.asymmetric import TwoSided
from .scanned.rolling import roll_on_hull
from .scanned.two_sided import rock_two_sided_fast
from .settings import SimulationConfig
from .simulate import step_control
from .solids.box3d import Box, simulate_box
from .solids.cylinder3d import Cylinder, simulate_cylinder

#: Seconds after which a compilation still running is announced (shorter ones stay silent), and between two
#: lines while it goes on.
ANNOUNCE_AFTER_S = 1.0
REPEAT_S = 2.0


def compile_kernels(*, announce: Callable[[str], None] | None = None, cylinders: bool = True,
                    boxes: bool = True, planar: bool = True, sampled: bool = True, scanned: bool = True) -> float:
    """Call every compiled kernel once on a tiny scene; return the seconds it took.

    Parameters
    ----------
    announce : callable, optional
        Called with a message when the call has not finished after :data:`ANNOUNCE_AFTER_S` ("compiling" where
        numba has compiled a function by then, the first run of an install; else "loading", from numba's cache),
        every :data:`REPEAT_S` while it goes on, and with the time it took.
    cylinders : bool
        Compile the 3D cylinder's kernel too (about 10 s on a fresh install; a run without cylinders never uses it).
    boxes : bool
        Compile the 3D box's kernel too (a run without a box that has a depth and an azimuth never uses it).
    planar, sampled : bool
        Compile the planar models' kernels, and the sampled kernels of the probabilities (False: leave them to
        another process compiling beside this one; the kernels are cached on disk one function each).
    scanned : bool
        Compile the kernels of bodies given by their scans (:mod:`.rolling`, :mod:`.two_sided`).
    """
    t0 = time.perf_counter()
    if not HAVE_NUMBA:
        return 0.0
    compiles = CompileCounter()

    def tell(elapsed_s: float) -> None:
        if announce is None:
            return
        if not ticker.spoke:
            announce("compiling the simulator (numba, once per install; later runs load it from disk) ..."
                     if compiles.n else "loading the simulator (numba's cache on disk) ...")
        else:
            announce(f"{'compiling' if compiles.n else 'loading'} the simulator ... {elapsed_s:.0f} s")

    ticker = Ticker(tell, every_s=REPEAT_S, first_after_s=ANNOUNCE_AFTER_S)      # bound before its thread starts
    with ticker:
        with compiles.listening():
            _warm(planar=planar, sampled=sampled, cylinders=cylinders, boxes=boxes, scanned=scanned)
    elapsed = time.perf_counter() - t0
    if ticker.spoke and announce is not None:
        announce(f"{'compiled' if compiles.n else 'loaded'} the simulator in {elapsed:.0f} s")
    return elapsed


def _warm(*, planar: bool, sampled: bool, cylinders: bool, boxes: bool, scanned: bool) -> None:
    """Call the kernels asked for once, each on a tiny scene."""
    a = 3.0 * np.sin(2.0 * np.pi * np.linspace(0.0, 2.0, 201))
    if planar:
        for model in MODELS:
            model.warmup()
    if sampled:
        _compile_sampled(a)
    if cylinders:           # the 3D cylinder (a tiny scene that lifts it)
        simulate_cylinder(a, 0.5 * a, None, 0.01, Cylinder(radius_m=0.1, half_height_m=0.5, mu=0.7, restitution=0.8))
    if boxes:               # the 3D box (a tiny scene that lifts it onto a corner)
        simulate_box(a, 0.5 * a, None, 0.01, Box(half_width_m=0.1, half_depth_m=0.15, half_height_m=0.5, mu=0.7))
    if scanned:             # the two-sided and rolling kernels, with and without a vertical (a scene that lifts it)
        for vertical in (None, 0.1 * a):
            rock_two_sided_fast(a, 0.01, TwoSided(0.05, 0.08, 0.5, 0.02), av=vertical)
            for history in (None, np.zeros_like(a)):
                roll_on_hull(a, 0.01, rectangle_chain(0.2, 1.0), av_ms2=vertical, theta_out=history)


class CompileCounter:
    """Counts the functions numba compiles while :meth:`listening` (numba's ``numba:compile`` events), so that the
    warm-up says "compiling" only when it compiles, and "loading" when numba reads its cache."""

    def __init__(self) -> None:
        self.n = 0

    def listening(self):
        """A context in which numba's compilations are counted."""
        from numba.core import event

        counter = self

        class _Listener(event.Listener):
            def on_start(self, ev) -> None:
                counter.n += 1

            def on_end(self, ev) -> None:
                pass

        return event.install_listener("numba:compile", _Listener())


def _compile_sampled(a: np.ndarray) -> None:
    """The sampled kernels, each on a tiny scene (``a``: a ground motion)."""
    one = np.ones(1)
    out = np.zeros(1, dtype=np.int64)
    control = step_control(SimulationConfig())
    block = (one, 2.0 * one, 0.2 * one, 0.9 * one, one, 0.7 * one)      # eps, p, alpha, e, R, mu arrays
    for vertical in (np.zeros(0), 0.1 * a):
        sample_verdicts(a, np.zeros_like(a), vertical, 0.01, np.ones((1, 1)), np.zeros((1, 1)), *block, G, 0.0,
                        True, control, out, out.copy())
        sample_plane_outcomes(a, np.zeros_like(a), vertical, 0.01, np.ones((1, 2)), np.zeros((1, 2)), *block, G,
                              0.0, True, control, np.zeros((1, 2), dtype=np.int8), out.copy())
