"""The compiled kernels' cache is dropped when any source of the package changed (pipeline.compiled): numba checks
a cached kernel against its own module only, so a kernel whose callee in another module changed would otherwise be
loaded as it was compiled before."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from pipeline.compiled import STAMP_NAME, drop_stale_kernels


def _tree(root: Path) -> Path:
    (root / "solids" / "__pycache__").mkdir(parents=True)
    (root / "solids" / "kernel.py").write_text("def run(): return solve()\n")
    (root / "solids" / "solver.py").write_text("def solve(): return 1\n")
    return root / "solids" / "__pycache__" / "kernel.run-1.py311.nbi"


def test_a_changed_callee_drops_the_cached_kernels(tmp_path):
    cached = _tree(tmp_path)
    cached.write_bytes(b"index")
    cached.with_suffix(".nbc").write_bytes(b"code")
    assert drop_stale_kernels(tmp_path) == 2                    # no fingerprint yet: nothing vouches for them
    assert (tmp_path / "__pycache__" / STAMP_NAME).is_file()
    cached.write_bytes(b"index")                                # compiled again from these sources
    assert drop_stale_kernels(tmp_path) == 0 and cached.is_file()
    solver = tmp_path / "solids" / "solver.py"
    solver.write_text("def solve(): return 2\n")                # the callee changes, the kernel's module does not
    assert drop_stale_kernels(tmp_path) == 1 and not cached.exists()


def test_a_touched_source_counts_as_changed(tmp_path):
    cached = _tree(tmp_path)
    drop_stale_kernels(tmp_path)
    cached.write_bytes(b"index")
    kernel = tmp_path / "solids" / "kernel.py"
    st = kernel.stat()
    os.utime(kernel, ns=(st.st_atime_ns, st.st_mtime_ns + 1_000_000_000))
    assert drop_stale_kernels(tmp_path) == 1 and not cached.exists()


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
