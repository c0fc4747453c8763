"""A new 3D body is one module and one registry line: a toy triangular prism (a pillar of equilateral cross-section),
its body built from a new inventory column and judged by the contact model (:mod:`pipeline.bodies.convex3d`), runs
through ``screen`` with sampling on: its nominal scenes, its probabilities, its margins and its report, nothing
else written for it. Its margin is checked against the exact bound below which nothing moves."""

from __future__ import annotations

import csv
import dataclasses
import math

import numpy as np
import pytest

from pipeline.bodies import registry
from pipeline.bodies.convex3d import ConvexBodies, convex_model
from pipeline.constants import G
from pipeline.rocking.block import BlockShape
from pipeline.rocking.scene import Physics
from pipeline.rocking.solids.convex_body import ConvexBody

# ---- the toy's module: the new column, the body, the registry entry ----

@dataclasses.dataclass(frozen=True, kw_only=True)
class _Prismatic(BlockShape):
    """The block with the column a prism needs: the side of its equilateral cross-section."""

    prism_side_m: float = dataclasses.field(default=math.nan, metadata={
        "rule": "the side of the prism's equilateral cross-section in metres (blank: not a prism)",
        "ok": lambda x: x > 0})


def prism_body(shape: BlockShape, *, width: float = 1.0, height: float = 1.0, friction: float = 1.0) -> ConvexBody:
    """A uniform prism of equilateral cross-section (side a, a vertex toward x) and height h, per unit mass: its six
    corners about G and its principal inertias a^2/24 + h^2/12 (twice) and a^2/12 about its axis."""
    a, h = shape.prism_side_m * width, shape.height_m * height
    r = a / math.sqrt(3.0)
    corners = [(r * math.cos(t), r * math.sin(t), z) for z in (-h / 2, h / 2) for t in (0.0, 2 * math.pi / 3,
                                                                                        4 * math.pi / 3)]
    side = a * a / 24.0 + h * h / 12.0
    return ConvexBody(np.array(corners), np.array([side, side, a * a / 12.0]), shape.mu * friction)


def _is_prism(shape, placement, settings) -> bool:
    return math.isfinite(getattr(shape, "prism_side_m", math.nan)) and not placement.single_component


#: The registry entry: a prism tips most easily toward the middle of a side (the side opposite the vertex at x).
TOY_PRISM = convex_model("toy: triangular prism", _is_prism, ConvexBodies(prism_body, lambda shape: 180.0))

# ---- the test ----

SIDE_M, HEIGHT_M, MU = 0.3, 1.2, 0.9


@pytest.fixture(scope="module")
def screened(kocaeli, tmp_path_factory):
    """The prism (blank azimuth) and an ordinary block screened with the toy registered, sampling on."""
    from pipeline import blocks
    from pipeline.cli import main
    from pipeline.store import open_results

    out = tmp_path_factory.mktemp("prism")
    (out / "b.csv").write_text("id,height_m,width_m,mu,azimuth_deg,prism_side_m\n"
                               f"P,{HEIGHT_M},{SIDE_M},{MU},,{SIDE_M}\nB,1.2,0.3,0.9,,\n")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(blocks, "BlockShape", _Prismatic)                        # the column, declared
        mp.setattr(registry, "BODIES", (TOY_PRISM, *registry.BODIES))       # the one registry line
        assert main(["--records", str(kocaeli), "--blocks", str(out / "b.csv"), "--out", str(out / "res"), "-q",
                     "--samples", "24", "-n", "1"]) == 0
    return open_results(out / "res" / "screening.nc"), out / "res"


def test_the_prism_is_judged_by_its_model_with_probabilities_and_a_report(screened):
    ds, res = screened
    j = list(ds["block"].values).index("P")
    assert set(ds["physics"].values[:, j].tolist()) == {int(Physics.contact3d)}
    assert np.all(ds["samples_drawn"].values[:, j] > 0)
    p = ds["p_overturn"].values[:, j]
    assert np.all((p >= 0) & (p <= 1))
    assert np.all(np.isfinite(ds["theta_max"].values[:, j]))             # reported against its tipping angle
    other = list(ds["block"].values).index("B")
    assert int(Physics.contact3d) not in set(ds["physics"].values[:, other].tolist())      # it claims the prism only
    assert "<b>P</b>" in (res / "report.html").read_text()                # the report's asset table lists it
    with open(res / "assets.csv") as f:
        row = next(r for r in csv.DictReader(f) if r["block"] == "P")
    assert row["physics"] == "contact3d" and row["recommendation"] and row["robustness"]


def test_the_prisms_margin_is_at_least_where_the_ground_first_moves_it(screened, kocaeli, config):
    """Nothing moves a body standing on its base while the ground's demand |a_h| / (g + a_v) stays at or below
    min(mu, tan alpha_min); for this prism tan alpha_min is the inradius over the height of G, a / (sqrt(3) h). The
    record times f (its vertical too) first reaches it at the smallest f = t g / (|a_h| - t a_v) over the samples
    (t the threshold), so no smaller factor can overturn the prism: its simulated margin is at least that."""
    from pipeline.records.loader import iter_records

    ds, _ = screened
    j = list(ds["block"].values).index("P")
    rec = next(iter_records(kocaeli, config=config))
    threshold = min(MU, SIDE_M / (math.sqrt(3.0) * HEIGHT_M))
    push = np.hypot(*rec.horizontal_ms2) - threshold * (0.0 if rec.vertical_ms2 is None else rec.vertical_ms2)
    first_moves = float(np.min(threshold * G / push[push > 0]))
    margin = float(ds["overturn_scale_simulated"].values[j])
    assert margin >= first_moves * (1.0 - 1e-9)


def test_the_prisms_tipping_angle_is_its_closed_form():
    """The angle its tilt is reported against: atan(inradius / height of G) = atan(a / (sqrt(3) h))."""
    from pipeline.bodies.convex3d import tipping_angle

    shape = _Prismatic(height_m=HEIGHT_M, width_m=SIDE_M, mu=MU, azimuth_deg=math.nan, prism_side_m=SIDE_M)
    assert tipping_angle(prism_body(shape)) == pytest.approx(math.atan(SIDE_M / (math.sqrt(3.0) * HEIGHT_M)),
                                                             rel=1e-12)

