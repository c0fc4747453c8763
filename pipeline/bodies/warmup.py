"""Compile the simulator once, before any worker needs it.

numba compiles the kernels on their first call and keeps them on disk (``cache=True``), so only the first run
of an install pays for it. :func:`compile_kernels` makes that first call on a tiny scene, in the calling
process (with helper processes taking some of the calls where it compiles: :mod:`.compile_share`), so that the
workers of a run load the compiled kernels instead of each compiling them, and so that the caller can say what is
happening.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable

from ..compiled import HAVE_NUMBA
from ..rocking.block import BlockShape
from ..rocking.settings import SimulationConfig
from ..ticker import Ticker
from . import registry
from .compile_share import SharedCalls, work_through

#: Seconds after which a compilation still running is announced (shorter ones stay silent), and between two
#: lines while it goes on (a quarter under the 2 s a command may stay silent: the ticker's thread may be woken late
#: while numba compiles in the main thread).
ANNOUNCE_AFTER_S = 1.0
REPEAT_S = 1.5


def compile_kernels(*, announce: Callable[[str], None] | None = None, shapes: Iterable[BlockShape] | None = None,
                    settings: SimulationConfig | None = None, sampling: bool = True,
                    helpers: int = 0) -> float:
    """Call the compiled kernels of every body model of the registry (:data:`.registry.BODIES`) once on a tiny
    scene; return the seconds it took.

    Parameters
    ----------
    announce : callable, optional
        Called with a message when the call has not finished after :data:`ANNOUNCE_AFTER_S` ("compiling" where
        numba has compiled a function by then, the first run of an install; else "loading", from numba's cache),
        every :data:`REPEAT_S` while it goes on, and with the time it took.
    shapes : iterable of BlockShape, optional
        The run's blocks: only the models that may claim one of them are warmed up (None: every model). A run
        without a cylinder never compiles the cylinder's kernel (about 10 s on a fresh install).
    settings : SimulationConfig, optional
        The run's simulator settings, which choose between some models (``scanned_model``); default: the defaults.
    sampling : bool
        Whether the run samples (probabilities under the declared uncertainty): only then are the kernels only the
        draws call warmed up (the models' ``draws_warmups``: the planar draws' took 23 s of the 132 s of every
        model's kernels, in one process on 2 cores).
    helpers : int
        Processes that may take warm-up calls beside this one once it is compiling (a first run; a cache that loads
        starts none): each call is made by whichever process is free (:mod:`.compile_share`), then this process
        makes the calls it did not make itself, loading what the helpers compiled.
    """
    t0 = time.perf_counter()
    if not HAVE_NUMBA:
        return 0.0
    shapes = None if shapes is None else list(shapes)
    shared = SharedCalls(warmup_calls(shapes, settings, sampling), helpers=helpers, target=_helper,
                         args=(shapes, settings, sampling))
    compiles = CompileCounter()

    def tell(elapsed_s: float) -> None:
        started = shared.start_helpers() if compiles.n else 0          # a first run: compile beside helpers
        if announce is None:
            return
        if not ticker.spoke:
            where = f", in {started + 1} processes" if started else ""
            announce(f"compiling the simulator (numba, once per install{where}; later runs load it from disk) ..."
                     if compiles.n else "loading the simulator (numba's cache on disk) ...")
        else:
            announce(f"{'compiling' if compiles.n else 'loading'} the simulator ... {elapsed_s:.0f} s")

    ticker = Ticker(tell, every_s=REPEAT_S, first_after_s=ANNOUNCE_AFTER_S)      # bound before its thread starts
    with ticker:
        with compiles.listening():
            shared.run_here()
    elapsed = time.perf_counter() - t0
    if ticker.spoke and announce is not None:
        announce(f"{'compiled' if compiles.n else 'loaded'} the simulator in {elapsed:.0f} s")
    return elapsed


def warmup_calls(shapes: list[BlockShape] | None, settings: SimulationConfig | None,
                 sampling: bool) -> list[Callable[[], None]]:
    """The warm-up calls of :func:`compile_kernels` (its parameters), each once, in order: the kernels some models
    share, then the draws' where the run samples, then each selected model's own. The longest compilations come
    first, so that processes taking the calls in turn end together: the 3D contact model's kernel (33-38 s) and the
    planar draws' (23 s) against 5-19 s for each model's own. Measured from an empty cache with one helper, every
    model (two runs each, 2 cores): 82.2 and 82.4 s in the order own, shared, draws; 76.8 and 72.8 s in this one."""
    models = registry.models_for(shapes, SimulationConfig() if settings is None else settings)
    own = [f for m in models
           for f in (m.warmups if m.warmups_for is None else m.warmups_for(shapes, sampling))]
    draws = [f for m in models for f in m.draws_warmups] if sampling else []
    return list(dict.fromkeys([f for m in models for f in m.shared_warmups] + draws + own))


def _helper(shapes, settings, sampling, claims, who: int) -> None:
    """A helper process of :func:`compile_kernels`: its share of the same warm-up calls
    (:func:`.compile_share.work_through`)."""
    work_through(warmup_calls(shapes, settings, sampling), claims, who)


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
