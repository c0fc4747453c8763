"""Shared fixtures: project data found by fixture, never by string paths in tests. The tests mirror the package
(``tests/rocking/solids/`` tests ``pipeline/rocking/solids/``); the helpers and independent peers they share are in
``tests/support/``, importable by name from every test."""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent / "support"))

import pytest

from pipeline.config import Config

PROJECT = Path(__file__).resolve().parents[1]
RECORDS = PROJECT / "records"
DATA = Path(__file__).resolve().parent / "data"
#: Real files `screen` refuses (a vertical channel alone): kept out of the bundled demo's records, which all screen
REFUSED = DATA / "refused"


@pytest.fixture(scope="session")
def records_dir() -> Path:
    """The bundled real records."""
    return RECORDS


@pytest.fixture(scope="session")
def refused_dir() -> Path:
    """Real record files that cannot be screened (:data:`REFUSED`), laid out as under records/."""
    return REFUSED


@pytest.fixture(scope="session")
def compiled_simulator() -> float:
    """The simulator compiled (or loaded from numba's cache) before a test times a scene: a scene's time budget
    is for the scene, not for the one-time compilation of a fresh install. Returns the seconds it took."""
    from pipeline.bodies.warmup import compile_kernels

    return compile_kernels()


@pytest.fixture(scope="session")
def scans_dir() -> Path:
    """The example scans shipped with the project (``examples/scans``)."""
    return PROJECT / "examples" / "scans"


@pytest.fixture(scope="session")
def data_dir() -> Path:
    """Small test-only data."""
    return DATA


@pytest.fixture(scope="session")
def config() -> Config:
    """The default configuration with nominal verdicts only (samples = 0): the tests of the
    probabilistic default (tests/uncertainty/test_uncertainty.py) build their own."""
    return Config().with_uncertainty(samples=0)


@pytest.fixture(scope="session")
def blocks_csv() -> Path:
    """The sample inventory."""
    return PROJECT / "configs" / "blocks.csv"


#: One station's record of Kocaeli 1999 at Yarimca (YPT): two horizontals of known azimuth and the vertical.
KOCAELI_YPT = ("RSN1176_KOCAELI_YPT060.AT2", "RSN1176_KOCAELI_YPT150.AT2", "RSN1176_KOCAELI_YPT-UP.AT2")


@pytest.fixture(scope="session")
def kocaeli(tmp_path_factory) -> Path:
    """A records folder of :data:`KOCAELI_YPT` alone, with its units.toml."""
    root = tmp_path_factory.mktemp("kocaeli")
    for name in KOCAELI_YPT:
        shutil.copy(RECORDS / "peer-at2" / name, root / name)
    shutil.copy(RECORDS / "units.toml", root / "units.toml")
    return root


@pytest.fixture
def make_records(tmp_path):
    """Copy chosen bundled files (paths relative to records/, or to tests/data/refused/) into a fresh directory."""

    def _make(*relpaths: str, units_toml: bool = True) -> Path:
        root = tmp_path / "recs"
        root.mkdir(exist_ok=True)
        for rel in relpaths:
            dst = root / rel
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy(RECORDS / rel if (RECORDS / rel).is_file() else REFUSED / rel, dst)
        if units_toml:
            shutil.copy(RECORDS / "units.toml", root / "units.toml")
        return root

    return _make


@pytest.fixture(autouse=True)
def _serial_by_default(monkeypatch):
    """Test runs are serial unless a test asks for -n or --scheduler: pytest-xdist already uses the cores.
    (The default of -n, the available cores, is tested on its own.)"""
    monkeypatch.setenv("ROCKSCREEN_NUM_PROCESSES", "1")
