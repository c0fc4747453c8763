"""The registry of body models: every model that judges a block, in the order they are asked.

:data:`BODIES` lists them; a block on a record goes to the first that claims it (:func:`body_model`), and the last,
the planar model, claims every block. The planar model's scenes go on to the planar registry's scene models
(:data:`pipeline.rocking.models.MODELS`), chosen per plane by their certificates: together the two tuples reach every
:class:`~pipeline.rocking.scene.Physics` the screening stores (a test keeps it so). Adding a model is a module of its
own that builds one :class:`~.contract.BodyModel`, and one line here; see "Adding a model" in docs/design.md.

The registry is read when used, never copied at import: a model added to :data:`BODIES` (or to the planar
:data:`~pipeline.rocking.models.MODELS`) before a run is the one the run uses, warm-up included.
"""

from __future__ import annotations

from collections.abc import Iterable

from ..rocking import models as scene_models
from ..rocking.block import BlockShape
from ..rocking.settings import SimulationConfig
from .assembly import STACK
from .contract import BodyModel, Placement, Stops
from .planar import PLANAR
from .scanned import SCANNED
from .scanned3d import SCANNED_3D
from .solids import BOX, CYLINDER

#: Every body model, in the order they are asked: a block goes to the first that claims it; the last claims all.
BODIES: tuple[BodyModel, ...] = (STACK, SCANNED_3D, SCANNED, CYLINDER, BOX, PLANAR)


def body_model(shape: BlockShape, placement: Placement, settings: SimulationConfig,
               bodies: tuple[BodyModel, ...] | None = None) -> BodyModel:
    """The first model of ``bodies`` (default: the registry, :data:`BODIES`) that claims ``shape`` on a record
    placed as ``placement`` under the simulator's ``settings``."""
    for model in BODIES if bodies is None else bodies:
        if model.claims(shape, placement, settings):
            return model
    raise LookupError(f"no body model claims {shape} on {placement}: the registry must end with one that claims "
                      "every block")


def models_for(shapes: Iterable[BlockShape] | None, settings: SimulationConfig,
               bodies: tuple[BodyModel, ...] | None = None) -> list[BodyModel]:
    """The models that may claim one of ``shapes`` on some record under the simulator's ``settings`` (shapes None:
    every model), in the registry's order."""
    models = BODIES if bodies is None else bodies
    if shapes is None:
        return list(models)
    shapes = list(shapes)
    return [m for m in models if any(m.may_claim(s, settings) for s in shapes)]


def physics_reached(bodies: tuple[BodyModel, ...] | None = None) -> set[int]:
    """Every :class:`~pipeline.rocking.scene.Physics` code a scene of the registry may store: the body models' and,
    through the planar model, the planar scene models'."""
    reached = {p for m in (BODIES if bodies is None else bodies) for p in m.physics}
    return reached | {m.physics for m in scene_models.MODELS}


def stops(bodies: tuple[BodyModel, ...] | None = None) -> list[Stops]:
    """Where the models of ``bodies`` (default: the registry) stop without a verdict, in the registry's order, each
    :class:`~.contract.Stops` once."""
    out: list[Stops] = []
    for model in BODIES if bodies is None else bodies:
        out.extend(s for s in model.stops if s not in out)
    return out
