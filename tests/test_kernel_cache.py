"""The compiled kernels' cache (pipeline.kernel_cache): a module's cached kernels are dropped when it or a module it
imports changed, and kept when only an unrelated module did. numba checks a cached kernel against its own module
only, so a kernel whose callee in another module changed would otherwise be loaded as it was compiled before."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from pipeline.kernel_cache import STAMP_NAME, drop_stale_kernels, package_imports


def _tree(root: Path) -> Path:
    (root / "solids" / "__pycache__").mkdir(parents=True)
    (root / "__init__.py").write_text("")
    (root / "solids" / "__init__.py").write_text("")
    (root / "solids" / "kernel.py").write_text("from .solver import solve\n\n@jit\ndef run(): return solve()\n")
    (root / "solids" / "solver.py").write_text("@jit\ndef solve(): return 1\n")
    (root / "report.py").write_text("def page(): return 'unrelated'\n")
    return root / "solids" / "__pycache__" / "kernel.run-3.py311.nbi"


def test_a_changed_callee_drops_the_cached_kernels(tmp_path):
    cached = _tree(tmp_path)
    cached.write_bytes(b"index")
    cached.with_suffix(".nbc").write_bytes(b"code")
    assert drop_stale_kernels(tmp_path) == 2                    # no stamp yet: nothing vouches for them
    assert (tmp_path / "__pycache__" / STAMP_NAME).is_file()
    cached.write_bytes(b"index")                                # compiled again from these sources
    assert drop_stale_kernels(tmp_path) == 0 and cached.is_file()
    solver = tmp_path / "solids" / "solver.py"
    solver.write_text("@jit\ndef solve(): return 2\n")         # the callee changes, the kernel's module does not
    assert drop_stale_kernels(tmp_path) == 1 and not cached.exists()


def test_a_change_elsewhere_keeps_the_cached_kernels(tmp_path):
    """A module the kernel does not import changes: its kernels stay (the first run after an edit need not compile
    everything)."""
    cached = _tree(tmp_path)
    drop_stale_kernels(tmp_path)
    cached.write_bytes(b"index")
    (tmp_path / "report.py").write_text("def page(): return 'edited'\n")
    assert drop_stale_kernels(tmp_path) == 0 and cached.is_file()


def test_a_touched_source_counts_as_changed(tmp_path):
    cached = _tree(tmp_path)
    drop_stale_kernels(tmp_path)
    cached.write_bytes(b"index")
    kernel = tmp_path / "solids" / "kernel.py"
    st = kernel.stat()
    os.utime(kernel, ns=(st.st_atime_ns, st.st_mtime_ns + 1_000_000_000))
    assert drop_stale_kernels(tmp_path) == 1 and not cached.exists()


def test_the_imports_read_are_the_modules_relative_imports(tmp_path):
    """Every form the package uses: a sibling, a parent's module, a package's submodules by name, a multi-line list."""
    (tmp_path / "a" / "b").mkdir(parents=True)
    for rel in ("__init__.py", "x.py", "a/__init__.py", "a/y.py", "a/z.py", "a/b/__init__.py", "a/b/w.py"):
        (tmp_path / rel).write_text("")
    (tmp_path / "a" / "b" / "w.py").write_text("import math\nfrom ...x import f\nfrom .. import y, z\n"
                                               "from ..y import (\n    g,\n    h,\n)\nfrom numpy import array\n")
    got = {p.relative_to(tmp_path).as_posix() for p in package_imports(tmp_path / "a" / "b" / "w.py")}
    assert got == {"x.py", "a/__init__.py", "a/y.py", "a/z.py"}


def test_a_tree_that_cannot_be_written_is_left_as_it_is(tmp_path):
    cached = _tree(tmp_path)
    cached.write_bytes(b"index")
    (tmp_path / "solids" / "__pycache__").chmod(0o500)
    try:
        if os.access(cached.parent, os.W_OK):
            pytest.skip("running as root: a read-only directory is still writable, so this cannot be checked")
        assert drop_stale_kernels(tmp_path) == 0 and cached.is_file()
    finally:
        (tmp_path / "solids" / "__pycache__").chmod(0o700)
