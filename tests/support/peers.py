"""What a test does when an independent peer (a library used only by tests) is missing."""

from __future__ import annotations

import os
from typing import NoReturn

import pytest


def missing_peer(message: str) -> NoReturn:
    """Skip loudly, or fail where ROCKSCREEN_REQUIRE_PEERS=1 (as in CI, where every peer must run)."""
    if os.environ.get("ROCKSCREEN_REQUIRE_PEERS") == "1":
        pytest.fail(message)
    print(f"\n*** {message} ***")
    pytest.skip(message)
