"""Every benchmark loads: its imports resolve where the package and the tests keep things now (nothing else runs
the benchmarks, so a moved helper would otherwise break one unseen). Loaded, not run: each keeps its work under
``if __name__ == "__main__"``."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
#: The test extras a benchmark may need at import (the independent engines): without them it is not a failure here
EXTRAS = ("pybullet", "mujoco", "openseespy", "openquake", "pelicun")

_LOAD_ALL = """
import importlib.util, json, pathlib, sys
folder = pathlib.Path(sys.argv[1])
sys.path.insert(0, str(folder))
failed = {}
for path in sorted(folder.glob("*.py")):
    spec = importlib.util.spec_from_file_location("benchmark_" + path.stem, path)
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
    except ModuleNotFoundError as e:
        failed[path.name] = ["missing", e.name]
    except Exception as e:
        failed[path.name] = ["error", repr(e)]
print(json.dumps(failed))
"""


@pytest.mark.slow                   # about 5 s; the developers' benchmarks, not the product
def test_every_benchmark_loads_with_the_package_and_the_tests_as_they_are():
    assert sorted(BENCHMARKS.glob("*.py")), "no benchmark found"
    out = subprocess.run([sys.executable, "-c", _LOAD_ALL, str(BENCHMARKS)], capture_output=True, text=True,
                         check=True)
    failed = json.loads(out.stdout.strip().splitlines()[-1])
    broken = {name: why for name, (kind, why) in failed.items()
              if kind == "error" or str(why).split(".")[0] not in EXTRAS}
    assert broken == {}, f"these benchmarks no longer load: {broken}"
