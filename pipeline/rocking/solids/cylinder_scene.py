"""A solid cylinder of the inventory on a record with two horizontal components: its 3D model's body and one run
(:mod:`.cylinder3d`), no orientation scan (the cylinder is axisymmetric, so the record's orientation changes only
the direction it leans toward, tested). :mod:`.solid3d` makes it a :class:`~.scene.Scene` the screening stores
like any other.

Frames: the model's x is the record's first horizontal (compass azimuth ``A``) and its y is 90 deg counter-clockwise
of it seen from above, that is the record's second horizontal (at ``A + 90``, clockwise) reversed. A tilt toward
the model's azimuth ``phi`` leans toward the compass azimuth ``A - phi``.

"""

from __future__ import annotations

import numpy as np

from ...constants import G
from ..block import BlockShape
from ..geometry import cylinder_p_e, effective_restitution
from ..scene import Physics
from ..settings import SimulationConfig
from .alternate import alternate
from .contact3d import Contact3DOutcome
from .contact_start import Start
from .cylinder3d import FLAG_NONE, FLAG_SLIDE, Cylinder, WobbleOutcome, cylinder_from_corner, simulate_cylinder
from .cylinder_handback import cylinder_model
from .family import SolidFamily


def cylinder_of(shape: BlockShape, *, restitution_factor: float = 1.0) -> Cylinder:
    """The 3D model's :class:`~.cylinder3d.Cylinder` of an inventory cylinder: the declared restitution, else the
    cylinder's Housner value (:func:`~.geometry.effective_restitution`)."""
    a, h = shape.width_m / 2.0, shape.height_m / 2.0
    e = float(effective_restitution(np.array(shape.restitution), cylinder_p_e(a, h)[1], restitution_factor))
    return Cylinder(radius_m=a, half_height_m=h, mu=shape.mu, restitution=e)


def run_on_record(h1, h2, vertical, dt_s: float, cylinder: Cylinder, *, settings: SimulationConfig,
                  g_ms2: float = G, amplitude: float = 1.0) -> WobbleOutcome:
    """The 3D model on a record's two horizontals (the second 90 deg clockwise of the first) and its vertical
    (None: none), all scaled by ``amplitude``. The model holds a cylinder that never lifts at rest; where the ground
    then slid its base (|a_h| > mu (g + a_v) at a sample: the ground is linear between samples, so the peak is at
    one) or fell away (g + a_v <= 0), the outcome is flagged FLAG_SLIDE, a stop the model does not follow."""
    x, y = amplitude * np.asarray(h1, dtype=float), -amplitude * np.asarray(h2, dtype=float)
    av = None if vertical is None or np.size(vertical) == 0 else amplitude * np.asarray(vertical, dtype=float)
    out = simulate_cylinder(x, y, av, dt_s, cylinder, g_ms2=g_ms2, rtol=settings.rtol, atol_alpha=settings.atol)
    if out.flag == FLAG_NONE and not out.theta_max_rad > 0:
        gv = g_ms2 + (0.0 if av is None else av)
        if np.any(gv <= 0.0) or np.any(np.hypot(x, y) > cylinder.mu * gv):
            out = out._replace(flag=FLAG_SLIDE)
    return out


def _tipping_tans(cylinder: Cylinder) -> tuple[float, ...]:
    """The tan of its static tipping angle, r / h [-]."""
    return (cylinder.radius_m / cylinder.half_height_m,)


def _drawn(cylinder: Cylinder, azimuth_deg: float, *, R_m: float, alpha: float, mu: float,
           restitution: float) -> tuple[Cylinder, float]:
    """The cylinder of one draw (axisymmetric: its azimuth stays 0)."""
    return cylinder_from_corner(R_m, alpha, mu=mu, restitution=restitution), 0.0


def _run(h1, h2, vertical, dt_s: float, cylinder: Cylinder, azimuth_deg: float, *, settings: SimulationConfig,
         g_ms2: float = G, amplitude: float = 1.0) -> WobbleOutcome:
    """:func:`run_on_record` (axisymmetric: ``azimuth_deg`` is not read)."""
    return run_on_record(h1, h2, vertical, dt_s, cylinder, settings=settings, g_ms2=g_ms2, amplitude=amplitude)


def _alternated(ax, ay, az, dt_s: float, cylinder: Cylinder, azimuth_deg: float, start: Start | None, *,
                g_ms2: float, settings: SimulationConfig) -> Contact3DOutcome:
    """The contact model handed back to the cylinder's exact model wherever it rolls on its rim without slipping
    (:func:`~.alternate.alternate`, the exact model at the settings' tolerances)."""
    model = cylinder_model(cylinder, azimuth_deg, dt_s=dt_s, g_ms2=g_ms2, rtol=settings.rtol,
                           atol_alpha=settings.atol)
    return alternate(ax, ay, az, dt_s, model, azimuth_deg, start, g_ms2=g_ms2)


#: The cylinders' family (:class:`~.family.SolidFamily`).
CYLINDER = SolidFamily(physics=Physics.wobbling, tipping_tans=_tipping_tans, drawn=_drawn, run=_run,
                       alternated=_alternated)
