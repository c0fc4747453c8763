"""Each planar scene model's ``may_claim`` (what a run without draws warms up) against the planner's choice: a model
whose ``may_claim`` leaves a block out is never the one the certificates choose for a scene of that block, whatever
the record, the exact tie mu = tan alpha included; a model only continued from others claims every block."""

from __future__ import annotations

import math

from hypothesis import example, given
from hypothesis import strategies as st

from pipeline.rocking import models
from pipeline.rocking.contract import SceneFacts, never
from pipeline.rocking.rules import TIE_RTOL, motion_threshold, rocks

alphas = st.floats(0.01, 1.5)
mus = st.floats(0.01, 2.0)
ratios = st.one_of(st.floats(0.0, 5.0), st.just(math.inf))


def _facts(alpha, mu, ratio, vertical):
    """A scene's facts as the planner forms them (:func:`pipeline.rocking.planner.scene_facts`) for any record."""
    return SceneFacts(ratio=ratio, threshold=motion_threshold(alpha, mu), rocks=rocks(alpha, mu), vertical=vertical,
                      alpha=alpha, mu=mu)


@given(alphas, mus, ratios, st.booleans())
@example(math.atan(0.5), 0.5, 0.6, True)                          # mu = tan alpha: the transformer 3.0 x 1.5 m
@example(math.atan(0.5), 0.5 * (1.0 + TIE_RTOL), 0.6, False)      # at the tie's edge
@example(math.atan(0.5), 0.5 * (1.0 + 2.0 * TIE_RTOL), 0.6, False)  # beyond it: rocks
def test_the_model_chosen_for_a_scene_may_claim_its_block(alpha, mu, ratio, vertical):
    chosen = models.choose(_facts(alpha, mu, ratio, vertical))
    assert chosen.may_claim(alpha, mu)


@given(alphas, mus)
def test_a_model_only_continued_from_others_claims_every_block(alpha, mu):
    for model in models.MODELS:
        if model.certificate is never:
            assert model.may_claim(alpha, mu)


def test_a_block_at_the_tie_reaches_no_rocking_model():
    """mu = tan alpha: the block slides where it moves (rule 1's tie), so the rocking models do not claim it and a run
    without draws does not compile them (the hard case: 3.0 x 1.5 m, mu 0.5)."""
    alpha = math.atan2(1.5, 3.0)
    claimed = {models.Physics(m.physics).name for m in models.MODELS if m.may_claim(alpha, 0.5)}
    assert claimed == {"none", "sliding", "general"}
