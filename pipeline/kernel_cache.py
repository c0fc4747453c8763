"""numba's cache of the compiled kernels, checked against every module a kernel may take code from.

numba keeps each compiled kernel beside its module (``__pycache__/<module>.<function>-<line>.<python>.nbi`` and
``.nbc``) and checks it against that module's own source only, not against the functions it calls or inlines from
other modules: a kernel whose callee changed would be loaded as it was compiled before (measured: the 3D contact
model kept its old contact solver after the solver's module changed, and 11 of 70 runs differed from a fresh
compilation). At import (:func:`drop_stale_kernels`), each module that has cached kernels is stamped with the
path, size and modification time of every module of the package it imports, directly or through others (its
relative imports, read from its source); where the stamp differs from the one recorded when its kernels were
cached, its kernels alone are deleted and compiled again on their first call. A change elsewhere keeps them:
dropping every kernel at any change made the first run after it compile everything (a planar block on one record,
45 s instead of 5 s).
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from pathlib import Path

#: The stamps of the modules whose kernels are cached, kept in the package's ``__pycache__``.
STAMP_NAME = "kernels.json"
#: A relative import: its dots, its module, the names it imports (``from .a.b import c, d``, ``from . import x``).
_RELATIVE_IMPORT = re.compile(r"^\s*from\s+(\.+)([\w.]*)\s+import\s+(\([^)]*\)|[^\n]*)", re.MULTILINE)


def package_imports(module: Path) -> set[Path]:
    """The package modules ``module`` imports by relative imports (a module, a package's ``__init__``, or the
    submodules a ``from . import x`` names)."""
    found: set[Path] = set()
    for dots, name, names in _RELATIVE_IMPORT.findall(module.read_text(encoding="utf-8", errors="replace")):
        base = module.parent
        for _ in range(len(dots) - 1):
            base = base.parent
        target = base.joinpath(*name.split(".")) if name else base
        candidates = [target / "__init__.py"] + ([target.with_suffix(".py")] if name else [])
        named = (n.split()[0] for n in names.strip("()").replace("\n", " ").split(",") if n.strip())
        candidates += [target / f"{n}.py" for n in named]
        found.update(c for c in candidates if c.is_file())
    return found


def _closure(module: Path, imports: dict[Path, set[Path]]) -> set[Path]:
    """``module`` and every package module it imports, directly or through others (``imports`` memoises reads)."""
    seen, todo = {module}, [module]
    while todo:
        current = todo.pop()
        if current not in imports:
            imports[current] = package_imports(current)
        for dep in imports[current] - seen:
            seen.add(dep)
            todo.append(dep)
    return seen


def _stamp(module: Path, root: Path, imports: dict[Path, set[Path]]) -> str:
    digest = hashlib.sha256()
    for path in sorted(_closure(module, imports)):
        st = path.stat()
        digest.update(f"{path.relative_to(root).as_posix()}\0{st.st_size}\0{st.st_mtime_ns}\n".encode())
    return digest.hexdigest()


def _cached(root: Path) -> dict[Path, list[Path]]:
    """The cached kernels' files under ``root``, by the module they were compiled from."""
    out: dict[Path, list[Path]] = {}
    for cache in [*root.rglob("__pycache__/*.nbi"), *root.rglob("__pycache__/*.nbc")]:
        out.setdefault(cache.parent.parent / f"{cache.name.split('.')[0]}.py", []).append(cache)
    return out


def drop_stale_kernels(root: Path) -> int:
    """Delete the cached kernels of every module under ``root`` whose stamp (its own and its imports' sources)
    differs from the one recorded, record the stamps of the modules that define kernels, and return how many files
    were deleted. A tree that cannot be written (an installed, read-only package) is left as it is: numba then caches
    elsewhere, in ``NUMBA_CACHE_DIR``."""
    record = root / "__pycache__" / STAMP_NAME
    try:
        old = json.loads(record.read_text())
    except (OSError, ValueError):
        old = {}
    imports: dict[Path, set[Path]] = {}
    stamps = {p.relative_to(root).as_posix(): _stamp(p, root, imports)
              for p in root.rglob("*.py") if "__pycache__" not in p.parts and "jit" in p.read_text(errors="replace")}
    dropped = 0
    try:
        for source, files in _cached(root).items():
            rel = source.relative_to(root).as_posix()
            if rel not in stamps or old.get(rel) != stamps[rel]:
                for cache in files:
                    cache.unlink(missing_ok=True)
                    dropped += 1
        if stamps != old:
            record.parent.mkdir(exist_ok=True)
            partial = record.with_name(f"{STAMP_NAME}.{os.getpid()}")
            partial.write_text(json.dumps(stamps, sort_keys=True))
            partial.replace(record)
    except OSError:
        pass
    return dropped
