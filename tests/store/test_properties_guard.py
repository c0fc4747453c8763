"""Property: any combination of links planted under an output directory, met by any command's first touch (the lock,
a publish, the preparation), is refused and leaves every file outside the output as it was."""

from __future__ import annotations

import tempfile
from pathlib import Path

from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from planted_links import ACTIONS, PLANTS, fingerprint, published, victim

from pipeline.errors import UnsafeOutputError


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(plants=st.lists(st.sampled_from(sorted(PLANTS)), min_size=1, max_size=3, unique=True),
       action=st.sampled_from(sorted(ACTIONS)))
def test_any_planted_links_are_refused_by_any_first_touch(plants, action):
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        out = published(root / "out")
        v = victim(root)
        for plant in plants:
            try:
                PLANTS[plant](out, v)
            except (OSError, RuntimeError):  # an earlier plant took the path away or made a loop of it (Python
                assume(False)                # before 3.13 resolves a loop with RuntimeError): not this combination
        before = fingerprint(v)
        try:
            ACTIONS[action](out)
        except UnsafeOutputError:
            pass
        else:
            raise AssertionError(f"{plants} were not refused by {action}")
        assert fingerprint(v) == before
