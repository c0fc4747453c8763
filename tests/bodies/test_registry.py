"""One registry for every model: it reaches every physics the screening stores; the run layer asks it, never a
block's kind; and a model added by one registration, planar or chosen by the block, runs through ``screen`` with
sampling on (nominal, probabilities and margins), the registry being read as it stands when used."""

from __future__ import annotations

import ast
import dataclasses
from pathlib import Path

import numpy as np
import pytest

from pipeline.bodies import registry
from pipeline.bodies.contract import BodyModel, Placement, Stops
from pipeline.bodies.planar import PLANAR, planar_margins, planar_pulse, planar_scale, planar_scene
from pipeline.compiled import jit
from pipeline.rocking import models
from pipeline.rocking.block import BlockShape, ShapeKind, dynamics
from pipeline.rocking.codes import STANDS
from pipeline.rocking.contract import SceneModel
from pipeline.rocking.scene import REST_SCENE, Physics
from pipeline.rocking.settings import ScannedModel, SimulationConfig

PIPELINE = Path(__file__).resolve().parents[2] / "pipeline"
SCENE_VARS = ("physics", "overturn_simulated", "theta_max", "n_impacts", "p_overturn", "samples_drawn",
              "samples_overturned", "samples_without_verdict", "robustness")


@pytest.fixture(scope="module")
def scan_shape(scans_dir):
    """A block given by one of the example scans."""
    from pipeline.shapes.scan import read_scan

    scan = read_scan(scans_dir / "balanced-rock.obj")
    return BlockShape(height_m=1.0, width_m=0.5, mu=0.6, azimuth_deg=np.nan, kind=ShapeKind.scanned, scan=scan)


def test_the_registry_reaches_every_physics_the_screening_stores():
    assert registry.physics_reached() == set(Physics)


def test_the_last_model_claims_every_block_and_a_registry_without_one_says_so():
    shape = BlockShape(height_m=1.0, width_m=0.2, mu=0.6, restitution=np.nan, azimuth_deg=np.nan)
    assert registry.body_model(shape, Placement(True, 0.0, False), SimulationConfig()) is PLANAR
    with pytest.raises(LookupError, match="claims every block"):
        registry.body_model(shape, Placement(True, 0.0, False), SimulationConfig(), registry.BODIES[:-1])


@pytest.mark.parametrize("kind, depth, placement, expected", [
    (ShapeKind.cylinder, np.nan, Placement(False, 30.0, True), "cylinder"),
    (ShapeKind.cylinder, np.nan, Placement(True, 30.0, True), "planar"),        # one horizontal: planar
    (ShapeKind.box, 0.3, Placement(False, 30.0, True), "box in 3D"),
    (ShapeKind.box, 0.3, Placement(False, 30.0, False), "planar"),              # a relative pair: planar
    (ShapeKind.box, np.nan, Placement(False, 30.0, True), "planar"),            # no depth: planar
])
def test_each_block_goes_to_the_model_its_shape_and_record_call_for(kind, depth, placement, expected):
    shape = BlockShape(height_m=1.0, width_m=0.2, mu=0.6, restitution=np.nan, azimuth_deg=45.0, depth_m=depth,
                       kind=kind)
    assert registry.body_model(shape, placement, SimulationConfig()).name == expected


@pytest.mark.parametrize("model, expected", [(ScannedModel.rolling, "scanned body"),
                                             (ScannedModel.two_sided, "scanned body"),
                                             (ScannedModel.contact3d, "scanned body in 3D")])
@pytest.mark.parametrize("placement", [Placement(False, 30.0, True), Placement(True, 0.0, False)])
def test_a_scan_goes_to_the_model_the_settings_choose_on_any_record(scan_shape, model, expected, placement):
    assert registry.body_model(scan_shape, placement, SimulationConfig(scanned_model=model)).name == expected


def test_exactly_one_model_claims_a_scan_under_each_setting(scan_shape):
    for model in ScannedModel:
        settings = SimulationConfig(scanned_model=model)
        claiming = [m.name for m in registry.BODIES[:-1] if m.claims(scan_shape, Placement(False, 0.0, True), settings)]
        assert len(claiming) == 1, (model, claiming)



@pytest.mark.parametrize("model, expected", [(ScannedModel.rolling, "scanned body"),
                                             (ScannedModel.two_sided, "scanned body"),
                                             (ScannedModel.contact3d, "scanned body in 3D")])
def test_the_warm_up_of_an_inventory_with_a_scan_takes_the_model_the_settings_choose(scan_shape, model, expected):
    """The warm-up compiles the kernels of the models ``models_for`` names: for a scan, the one the settings give
    it (and the planar model, which may claim every block), not the other."""
    names = [m.name for m in registry.models_for([scan_shape], SimulationConfig(scanned_model=model))]
    assert names == [expected, "planar"]

#: What the run layer and the command line may import of the models: the registry and its contract, never a
#: model's module nor the physics of one kind of block.
MODEL_MODULES = ("pipeline.bodies.planar", "pipeline.bodies.solids", "pipeline.bodies.scanned",
                 "pipeline.rocking.solids", "pipeline.rocking.scanned")


def _absolute_imports(path: Path) -> set[str]:
    package = ["pipeline", *path.relative_to(PIPELINE).parts[:-1]]
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = package[:len(package) - (node.level - 1)] if node.level else []
            mod = ".".join(base + (node.module.split(".") if node.module else []))
            out.add(mod)
            out.update(f"{mod}.{a.name}" for a in node.names)
        elif isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
    return out


@pytest.mark.parametrize("part", ["run", "cli"])
def test_the_run_layer_asks_the_registry_never_a_kind_of_block(part):
    offenders = {str(p.relative_to(PIPELINE)): sorted(m for m in _absolute_imports(p) if m.startswith(MODEL_MODULES))
                 for p in sorted((PIPELINE / part).rglob("*.py"))}
    assert {k: v for k, v in offenders.items() if v} == {}


def test_the_import_scan_sees_the_registry_imported():
    assert "pipeline.bodies.registry.body_model" in _absolute_imports(PIPELINE / "run" / "screening.py")


# --- toy models, added by one registration each ----------------------------------------------------------------

#: The toy body model's marker: it claims blocks of this friction coefficient narrower than TOY_WIDTH_M.
TOY_MU, TOY_WIDTH_M = 0.61, 0.3


def _wide(shape: BlockShape) -> BlockShape:
    return dataclasses.replace(shape, width_m=2.0 * shape.width_m)


def _wide_block(shape: BlockShape):
    return dynamics([_wide(shape)])[0]


#: A toy model chosen by the block: it judges a block as the planar model judges the same block twice as wide.
TOY_BODY = BodyModel(
    name="toy: twice as wide", physics=(),
    claims=lambda shape, placement, settings: shape.mu == TOY_MU and shape.width_m < TOY_WIDTH_M,
    may_claim=lambda shape, settings: shape.mu == TOY_MU and shape.width_m < TOY_WIDTH_M,
    scene=lambda on, shape, block, direction: planar_scene(on, _wide(shape), _wide_block(shape), direction),
    margins=lambda rec, shape, block, direction, **kw: planar_margins(rec, _wide(shape), _wide_block(shape), direction,
                                                                       **kw),
    scale=lambda rec, shape, block, plane, **kw: planar_scale(rec, _wide(shape), _wide_block(shape), plane, **kw),
    pulse=lambda shape, block, **kw: planar_pulse(_wide(shape), _wide_block(shape), **kw))


@dataclasses.dataclass(frozen=True, kw_only=True)
class _Anchored(BlockShape):
    """The block as a model needing a new field would declare it: one field, its column's rule beside it."""

    anchor_kN: float = dataclasses.field(default=0.0, metadata={
        "rule": "an anchor's strength in kN >= 0 (blank: none)", "ok": lambda x: x >= 0})


#: A toy body model that reads the new field: an anchored block is judged as the same block twice as wide.
TOY_ANCHORED = dataclasses.replace(TOY_BODY, name="toy: anchored",
                                   claims=lambda shape, placement, settings: getattr(shape, "anchor_kN", 0.0) > 0,
                                   may_claim=lambda shape, settings: getattr(shape, "anchor_kN", 0.0) > 0)


def _rest(scene):
    return REST_SCENE


def _glued(facts) -> bool:
    return facts.mu > 3.0


@jit
def _glued_twin(facts, x, block, control, w):
    return STANDS, False


#: A toy planar scene model: a block whose friction exceeds 3 is glued down: it stands, nothing integrated.
TOY_SCENE = SceneModel(physics=Physics.none, certificate=_glued, simulate=_rest, twin=_glued_twin,
                       warmup=lambda: None)


def _screen(records: Path, out: Path, inventory: str, header: str = "id,height_m,width_m,mu,azimuth_deg"):
    from pipeline.cli import main
    from pipeline.store import open_results

    out.mkdir(parents=True)
    (out / "b.csv").write_text(header + "\n" + inventory)
    assert main(["--records", str(records), "--blocks", str(out / "b.csv"), "--out", str(out / "res"), "-q",
                 "--samples", "24"]) == 0
    return open_results(out / "res" / "screening.nc")


def _scene(ds, block: str) -> dict:
    j = list(ds["block"].values).index(block)
    got = {v: ds[v].values[:, j].tolist() for v in SCENE_VARS}
    got["overturn_scale_simulated"] = float(ds["overturn_scale_simulated"].values[j])
    return got


def test_a_model_chosen_by_the_block_runs_through_screen_with_sampling(kocaeli, tmp_path, monkeypatch):
    narrow = f"T,1.2,0.2,{TOY_MU},45\n"
    wide = f"T,1.2,0.4,{TOY_MU},45\n"              # not claimed by the toy (too wide): the planar model
    plain = _screen(kocaeli, tmp_path / "plain", narrow)
    reference = _screen(kocaeli, tmp_path / "wide", wide)
    monkeypatch.setattr(registry, "BODIES", (TOY_BODY, *registry.BODIES))       # one registration
    toy = _screen(kocaeli, tmp_path / "toy", narrow)
    assert _scene(plain, "T") != _scene(reference, "T")                     # the toy changes what is judged
    assert _scene(toy, "T") == _scene(reference, "T")                       # nominal, probabilities, margins
    assert np.all(toy["samples_drawn"].values > 0)


@pytest.mark.slow
def test_a_planar_model_added_at_run_time_reaches_the_nominal_and_the_sampled_verdicts(kocaeli, tmp_path,
                                                                                         monkeypatch):
    glued = "G,1.2,0.2,5.0,45\n"
    plain = _screen(kocaeli, tmp_path / "plain", glued)
    assert max(plain["theta_max"].values[:, 0]) > 0 and plain["samples_overturned"].values.sum() > 0
    monkeypatch.setattr(models, "MODELS", (TOY_SCENE, *models.MODELS))      # one registration
    toy = _screen(kocaeli, tmp_path / "toy", glued)
    assert toy["theta_max"].values[:, 0].tolist() == [0.0] * toy.sizes["record"]
    assert toy["overturn_simulated"].values[:, 0].tolist() == [0] * toy.sizes["record"]
    assert toy["samples_drawn"].values.sum() > 0 and toy["samples_overturned"].values.sum() == 0    # compiled too


def test_a_model_that_needs_a_new_block_field_is_one_field_and_one_registration(kocaeli, tmp_path, monkeypatch):
    """The field declared once on the block (its default, its column's rule) reaches the inventory, its check,
    the digest and the model; nothing else is written for it."""
    from pipeline import blocks

    reference = _scene(_screen(kocaeli, tmp_path / "wide", f"T,1.2,0.4,{TOY_MU},45\n"), "T")
    monkeypatch.setattr(blocks, "BlockShape", _Anchored)                        # the field, declared
    monkeypatch.setattr(registry, "BODIES", (TOY_ANCHORED, *registry.BODIES))   # the registration
    header = "id,height_m,width_m,mu,azimuth_deg,anchor_kN"
    toy = _screen(kocaeli, tmp_path / "toy", f"T,1.2,0.2,{TOY_MU},45,2.5\n", header)
    assert _scene(toy, "T") == reference
    inv = blocks.read_inventory(tmp_path / "toy" / "b.csv", default_mu=0.6)
    assert inv.shape(0).anchor_kN == 2.5 and inv.take([0]).shape(0).anchor_kN == 2.5
    (tmp_path / "bad.csv").write_text(header + "\nT,1.2,0.2,0.6,45,-1\n")
    with pytest.raises(blocks.InventoryError, match="anchor_kN.*an anchor's strength in kN >= 0"):
        blocks.read_inventory(tmp_path / "bad.csv", default_mu=0.6)


def test_a_models_stops_reach_the_recommendation_by_one_registration(monkeypatch):
    """Where a model stops without a verdict is its own fact: registered with its Stops, the recommendation's cause
    of an unjudged scene of its physics is its words, where without it the same scene reads as a cap; a stop its
    flag limits explains only the flagged scenes."""
    import xarray as xr

    from pipeline.risk import undecided_causes

    ds = xr.Dataset({"physics": (("record", "block"), np.array([[Physics.contact3d], [Physics.contact3d]])),
                     "free_flight": (("record", "block"), np.zeros((2, 1), dtype="i1")),
                     "friction_exceeded": (("record", "block"), np.array([[1], [0]], dtype="i1"))})
    rows = np.ones(2, dtype=bool)
    assert undecided_causes(ds, rows, 0) == "the simulation stopped at a cap"
    toy = dataclasses.replace(TOY_BODY, stops=(Stops((Physics.contact3d,), "the toy's base melts"),))
    monkeypatch.setattr(registry, "BODIES", (toy, *registry.BODIES))           # one registration
    assert undecided_causes(ds, rows, 0) == "the toy's base melts"
    flagged = dataclasses.replace(TOY_BODY, stops=(Stops((Physics.contact3d,), "the toy's base melts",
                                                         flagged_only=True),))
    monkeypatch.setattr(registry, "BODIES", (flagged, *registry.BODIES[1:]))
    assert undecided_causes(ds, rows, 0) == "the toy's base melts; the simulation stopped at a cap"
