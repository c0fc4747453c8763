"""The scene-model registry: the planner and the sampled kernels choose through it, and a new model is one registry
line (a toy model registered here, in the test only, and run through ``screen``)."""

from __future__ import annotations

import dataclasses
import itertools
import math

import netCDF4
import numpy as np
import pytest

from pipeline import cli
from pipeline.constants import G
from pipeline.rocking import models
from pipeline.rocking.block import Block, BlockShape, dynamics
from pipeline.rocking.contract import SceneFacts, SceneModel
from pipeline.rocking.planar.sampled import SampledMotion, SampleRules, sample_verdicts, sampled_blocks
from pipeline.rocking.planner import REST_SCENE, Physics, scene_facts, simulate_scene
from pipeline.rocking.settings import SimulationConfig
from pipeline.rocking.simulate import step_control
from pipeline.uncertainty.sampling import sample_block
from pipeline.uncertainty.settings import UncertaintyConfig


def _rule_of_the_planner(f: SceneFacts) -> int:
    """The planner's rule as its documentation states it (Shenton 1996; Yim et al. 1980), written independently
    of the registry: at rest unless the demand exceeds min(tan alpha, mu); a block that cannot rock slides;
    otherwise it rocks, with the vertical where the simulation keeps it."""
    if not f.ratio > f.threshold:
        return Physics.none
    if not f.rocks:
        return Physics.sliding
    return Physics.rocking_vertical if f.vertical else Physics.rocking


@pytest.mark.parametrize("ratio, threshold, rocks, vertical", list(itertools.product(
    (0.0, 0.2, 0.2 * (1 + 1e-15), 0.5, math.inf), (0.2, 0.5), (False, True), (False, True))))
def test_the_registry_chooses_what_the_planners_rule_says(ratio, threshold, rocks, vertical):
    facts = SceneFacts(ratio=ratio, threshold=threshold, rocks=rocks, vertical=vertical, alpha=0.2, mu=0.6)
    assert models.choose(facts).physics == _rule_of_the_planner(facts)


def test_every_physics_member_has_one_registered_model_and_the_last_certificate_takes_every_scene():
    assert len({m.physics for m in models.MODELS}) == len(models.MODELS)      # one planar scene model each
    for m in models.MODELS:
        assert models.by_physics(m.physics) is m
    chosen_last = [m for m in models.MODELS if m.certificate is not models.never][-1]
    assert chosen_last.certificate(SceneFacts(ratio=1.0, threshold=0.1, rocks=True, vertical=False, alpha=0.2,
                                              mu=0.6))


def test_a_registry_without_a_model_for_a_scene_says_so():
    facts = SceneFacts(ratio=1.0, threshold=0.1, rocks=True, vertical=False, alpha=0.2, mu=0.6)
    with pytest.raises(LookupError, match="registry must end"):
        models.choose(facts, models.MODELS[:2])


def test_a_model_named_by_physics_runs_its_own_entry():
    """The general contact model is never chosen up front, and runs by name: a block that rocks under a
    half-sine pulse, simulated from rest by the general model, gives a rocking response of the general model."""
    t = np.arange(0.0, 3.0, 0.005)
    a = np.where(t < 0.5, 0.6 * G * np.sin(2 * np.pi * t), 0.0)
    block = dynamics([BlockShape(height_m=1.2, width_m=0.4, mu=0.8)])[0]
    sc = simulate_scene(a, None, 0.005, block=block, physics=Physics.general)
    assert sc.physics == Physics.general and sc.theta_max > 0.0
    assert simulate_scene(a, None, 0.005, block=block).physics == Physics.rocking


def test_the_sampled_kernels_dispatch_through_the_registry_like_the_planner():
    """With unit factors, the sampled kernel's verdict (the registry's compiled twins) is the nominal one (its
    Python entries), over blocks chosen to reach every model: at rest, sliding, rocking, and sliding into the
    ground's free flight (general)."""
    t = np.arange(0.0, 4.0, 0.01)
    ah = 0.5 * G * np.sin(2 * np.pi * t / 0.8) * (t < 1.6)
    falling = np.where((t > 2.0) & (t < 2.2), -1.2 * G, 0.0)
    mild = 0.1 * G * np.sin(2 * np.pi * t / 0.3)
    shapes = [BlockShape(height_m=1.0, width_m=0.9, mu=0.9),      # squat: tan alpha 0.9 > the demand: at rest
              BlockShape(height_m=0.5, width_m=1.0, mu=0.3),      # too squat to rock: slides
              BlockShape(height_m=2.0, width_m=0.4, mu=0.8)]      # rocks
    control = step_control(SimulationConfig())
    unit = UncertaintyConfig(amplitude_cov=0.0, restitution_cov=0.0, friction_cov=0.0, size_cov=0.0)
    seen = set()
    for shape, av in itertools.product(shapes, (None, mild, falling)):
        block = dynamics([shape])[0]
        nominal = simulate_scene(ah, av, 0.01, block=block)
        seen.add(nominal.physics)
        sb = sample_block(np.zeros((1, 6)), shape, settings=unit)
        out, planes = np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.int64)
        sample_verdicts(SampledMotion(ah, np.zeros_like(ah), np.zeros(0) if av is None else av, 0.01),
                        np.ones((1, 1)), np.zeros((1, 1)), sampled_blocks(sb), SampleRules(G, 0.0, True, control),
                        out, planes)
        assert out[0] == nominal.verdict, (shape, av is None, nominal)
    assert {Physics.none, Physics.sliding, Physics.rocking, Physics.rocking_vertical, Physics.general} <= seen


@pytest.mark.slow
def test_a_toy_model_is_one_registry_line_and_runs_through_screen(make_records, tmp_path, monkeypatch):
    """A toy model, registered in this test only: a block declared anchored (its friction coefficient at or above
    5, the toy's convention) stays at rest whatever the ground does. One line in the registry, and ``screen``
    uses it end to end; the same block with an ordinary friction rocks under the same record."""
    anchored = SceneModel(physics=Physics.none, certificate=lambda f: f.mu >= 5.0, simulate=lambda s: REST_SCENE,
                          twin=models.MODELS[0].twin, warmup=lambda: None)
    registered = models.MODELS
    monkeypatch.setattr(models, "MODELS", (anchored, *registered))
    root = make_records("peer-at2/RSN1063_NORTHR_RRS228.AT2", "peer-at2/RSN1063_NORTHR_RRS318.AT2")
    inventory = tmp_path / "blocks.csv"
    inventory.write_text("id,height_m,width_m,mu,azimuth_deg\nANCHORED,2.0,0.4,5.0,45\nFREE,2.0,0.4,0.8,45\n")
    out = tmp_path / "out"
    code = cli.main(["--records", str(root), "--blocks", str(inventory), "--out", str(out), "--samples", "0",
                     "-n", "1", "-q"])
    assert code == 0
    with netCDF4.Dataset(out / "screening.nc") as ds:
        blocks = list(ds["block"][:])
        physics = np.asarray(ds["physics"][:])
        theta = np.asarray(ds["theta_max"][:])
    anchored_j, free_j = blocks.index("ANCHORED"), blocks.index("FREE")
    assert physics[0, anchored_j] == Physics.none and theta[0, anchored_j] == 0.0
    assert physics[0, free_j] != Physics.none and theta[0, free_j] > 0.0
    # without the toy model the anchored block would have moved: its demand exceeds its threshold
    block = dynamics([BlockShape(height_m=2.0, width_m=0.4, mu=5.0)])[0]
    facts = scene_facts(np.array([0.0, 0.5 * G]), None, alpha=block.alpha, mu=block.mu)
    assert models.choose(facts).physics == Physics.none
    assert models.choose(facts, registered).physics == Physics.rocking


def test_the_nominal_block_and_its_samples_come_from_one_derivation():
    """dynamics() and sample_block() with zero spreads give the same doubles (restitution derived once, clipped to
    [0, 1]: a block too squat to rock gets 0 in both)."""
    zero = UncertaintyConfig(amplitude_cov=0.0, restitution_cov=0.0, friction_cov=0.0, size_cov=0.0)
    for shape in (BlockShape(height_m=1.85, width_m=0.55, mu=0.6), BlockShape(height_m=0.5, width_m=1.0, mu=0.4),
                  BlockShape(height_m=3.0, width_m=1.5, mu=0.5, restitution=0.7)):
        nominal = dynamics([shape])[0]
        assert sample_block(np.zeros((1, 6)), shape, settings=zero).block(0) == nominal
        assert 0.0 <= nominal.e <= 1.0


def test_blocks_are_built_by_keyword_only():
    with pytest.raises(TypeError):
        Block(2.0, 0.2, 0.9, 1.0, 0.6)  # type: ignore[misc]
    with pytest.raises(TypeError):
        BlockShape(1.0, 0.3, 0.6)  # type: ignore[misc]
    assert dataclasses.replace(BlockShape(height_m=1.0, width_m=0.3, mu=0.6), depth_m=0.2).depth_m == 0.2
    assert scene_facts(np.zeros(3), None, alpha=0.2, mu=0.6).ratio == 0.0


def test_a_model_whose_scene_equals_rest_still_names_itself_in_the_worst_plane(monkeypatch):
    """A plane simulated by a model that leaves the block as at rest (theta 0, nothing slid) is stored as that
    model's scene, not as the at-rest certificate's: its physics reaches screening.nc."""
    from pipeline.rocking.orientation import Planes, worst_plane

    quiet = SceneModel(physics=Physics.general, certificate=lambda f: True,
                       simulate=lambda s: dataclasses.replace(REST_SCENE, physics=Physics.general),
                       twin=models.MODELS[0].twin, warmup=lambda: None)
    monkeypatch.setattr(models, "MODELS", (quiet, *models.MODELS))
    t = np.arange(0.0, 2.0, 0.01)
    h = np.vstack([0.5 * G * np.sin(2 * np.pi * t), 0.3 * G * np.cos(2 * np.pi * t)])
    block = dynamics([BlockShape(height_m=2.0, width_m=0.4, mu=0.8)])[0]
    got = worst_plane(Planes(h, 0.0, None), [0.0, 45.0, 90.0], 0.01, block=block)
    assert got.planes_simulated == 3 and got.scene.physics == Physics.general
