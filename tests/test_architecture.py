"""The shape of the code: physics and readers are libraries that never import the application."""

from __future__ import annotations

import ast
import functools
import subprocess
import sys
from pathlib import Path

import pytest

#: Application modules no library may load.
APPLICATION = ("pipeline.cli", "pipeline.run", "pipeline.config", "pipeline.report", "pipeline.store",
               "pipeline.schema")


#: The libraries checked for the application modules they load.
LIBRARIES = (
    "pipeline.rocking.planner", "pipeline.rocking.orientation", "pipeline.rocking.references.reference",
    "pipeline.records.loader", "pipeline.records.listing", "pipeline.records.side_files", "pipeline.records.streams",
    "pipeline.pulses", "pipeline.criteria", "pipeline.closed_forms", "pipeline.blocks",
    "pipeline.rocking.planar.sampled", "pipeline.records.intensity", "pipeline.uncertainty.scenes",
    "pipeline.uncertainty.fragility", "pipeline.uncertainty.hazard", "pipeline.uncertainty.sampling",
    "pipeline.rocking.rules", "pipeline.rocking.block", "pipeline.records.duplicates", "pipeline.records.common",
    "pipeline.rocking.planar.contact", "pipeline.rocking.planar.handoff", "pipeline.uncertainty.hazard_files",
    "pipeline.floors.model", "pipeline.floors.motion", "pipeline.shapes.scan", "pipeline.rocking.solids.box_planar",
    "pipeline.rocking.references.asymmetric", "pipeline.rocking.solids.solid3d",
    "pipeline.rocking.scanned.two_sided", "pipeline.rocking.scanned.planes", "pipeline.shapes.plane",
    "pipeline.uncertainty.two_sided", "pipeline.rocking.scanned.rolling", "pipeline.shapes.hull",
    "pipeline.bodies.registry", "pipeline.bodies.warmup", "pipeline.assemblies.stack")


@pytest.mark.parametrize("library", LIBRARIES)
def test_libraries_load_no_application_module(library):
    out = _loaded(library, APPLICATION)
    assert out == "", f"importing {library} loads {out}"


#: Third-party packages the probe imports before it forks a child for each library: none of them imports the
#: package, so the package's modules a child then loads are exactly those importing the library alone loads, and each
#: child pays only for the package (one interpreter per library took 1.0-1.7 s each, 35 s for this file).
THIRD_PARTY = ("numpy", "scipy.fft", "scipy.special", "scipy.optimize", "scipy.spatial", "scipy.signal",
               "scipy.integrate", "scipy.stats", "scipy.linalg", "numba", "pandas", "xarray", "netCDF4", "obspy",
               "jinja2", "matplotlib", "trimesh")

_PROBE = """
import json, os, sys
for name in json.loads(sys.argv[1]):
    try:
        __import__(name)
    except ImportError:
        pass
if any(m == "pipeline" or m.startswith("pipeline.") for m in sys.modules):
    raise SystemExit("a third-party package imported the package: the probe cannot tell what a library loads")
found = {}
for library in json.loads(sys.argv[2]):
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(r)
        try:
            __import__(library)
            text = ",".join(sorted(m for m in sys.modules if m == "pipeline" or m.startswith("pipeline.")))
        except BaseException as exc:
            text = "!" + repr(exc)
        with os.fdopen(w, "w") as f:
            f.write(text)
        os._exit(0)
    os.close(w)
    with os.fdopen(r) as f:
        found[library] = f.read()
    os.waitpid(pid, 0)
print(json.dumps(found))
"""


@functools.cache
def _modules_loaded_by_each() -> dict[str, tuple[str, ...]]:
    """For every library checked here, the package's modules that importing it alone loads: each library imported
    in a child forked from one interpreter that has imported :data:`THIRD_PARTY` and nothing of the package."""
    import json

    libraries = sorted(set(LIBRARIES) | set(PHYSICS) | set(FLOORS))
    run = subprocess.run([sys.executable, "-c", _PROBE, json.dumps(THIRD_PARTY), json.dumps(libraries)],
                         capture_output=True, text=True, check=True)
    found = json.loads(run.stdout)
    failed = {lib: text for lib, text in found.items() if text.startswith("!")}
    assert not failed, f"libraries that do not import: {failed}"
    return {lib: tuple(text.split(",")) for lib, text in found.items()}


def _pipeline_modules_loaded(library: str) -> tuple[str, ...]:
    """The package's modules that importing ``library`` alone loads (:func:`_modules_loaded_by_each`)."""
    return _modules_loaded_by_each()[library]


def _loaded(library: str, prefixes: tuple[str, ...]) -> str:
    """The modules starting with ``prefixes`` that importing ``library`` alone loads."""
    return ",".join(m for m in _pipeline_modules_loaded(library) if m.startswith(prefixes))


#: The physics libraries: they read blocks as arrays or typed blocks, never the inventory module (a CSV reader).
PHYSICS = ("pipeline.rocking.planner", "pipeline.rocking.orientation", "pipeline.rocking.rules",
           "pipeline.rocking.planar.sampled", "pipeline.rocking.planar.contact", "pipeline.rocking.planar.handoff",
           "pipeline.rocking.geometry", "pipeline.criteria", "pipeline.closed_forms", "pipeline.pulses",
           "pipeline.records.loader", "pipeline.records.listing", "pipeline.records.side_files",
           "pipeline.records.streams", "pipeline.records.coordinates", "pipeline.uncertainty.scenes",
           "pipeline.uncertainty.orientations", "pipeline.uncertainty.fragility", "pipeline.uncertainty.sampling",
           "pipeline.floors.model", "pipeline.floors.motion", "pipeline.floors.buildings", "pipeline.event.assets",
           "pipeline.event.shakemap", "pipeline.event.shakecast", "pipeline.shapes.scan", "pipeline.shapes.plane",
           "pipeline.rocking.scanned.two_sided", "pipeline.rocking.scanned.planes", "pipeline.uncertainty.two_sided",
           "pipeline.rocking.scanned.rolling", "pipeline.shapes.hull", "pipeline.bodies.registry",
           "pipeline.assemblies.stack")


@pytest.mark.parametrize("library", PHYSICS)
def test_physics_libraries_do_not_load_the_inventory_module(library):
    assert _loaded(library, ("pipeline.blocks",)) == ""


#: The floors' libraries, which never load the rocking simulator.
FLOORS = ("pipeline.floors.model", "pipeline.floors.motion", "pipeline.floors.buildings")


@pytest.mark.parametrize("library", FLOORS)
def test_floors_do_not_load_the_rocking_simulator(library):
    assert _loaded(library, ("pipeline.rocking",)) == ""


#: The application: the run layer, the CLI, the configuration loader, the inventory module, the store and the
#: report. Every other module of ``pipeline`` is a library below the run layer.
APPLICATION_PARTS = ("run", "cli", "config", "blocks", "store", "report")
PIPELINE = Path(__file__).resolve().parents[1] / "pipeline"


def _imported_parts(path: Path) -> set[str]:
    """The top-level parts of ``pipeline`` a module imports (relative or absolute, at any depth of the module)."""
    package = list(path.relative_to(PIPELINE).parts[:-1])
    parts = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level:
            base = package[:len(package) - (node.level - 1)]
            target = base + (node.module.split(".") if node.module else [])
            parts.update([target[0]] if target else [a.name for a in node.names])
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("pipeline."):
            parts.add(node.module.split(".")[1])
        elif isinstance(node, ast.Import):
            parts.update(a.name.split(".")[1] for a in node.names if a.name.startswith("pipeline."))
    return parts


def test_no_module_below_the_run_layer_imports_the_application():
    """Read from the sources (imports inside functions too): only the application's own modules import it."""
    offenders = []
    for path in sorted(PIPELINE.rglob("*.py")):
        rel = path.relative_to(PIPELINE)
        if rel.parts[0].removesuffix(".py") in APPLICATION_PARTS or rel.name == "__main__.py":
            continue
        bad = _imported_parts(path) & set(APPLICATION_PARTS)
        if bad:
            offenders.append(f"{rel}: {sorted(bad)}")
    assert offenders == []


def test_the_import_scan_sees_an_import_of_the_application():
    """The scan above finds what it looks for: the run layer's screening module imports the inventory module."""
    assert "blocks" in _imported_parts(PIPELINE / "run" / "screening.py")


def _imports_graph() -> dict[str, set[str]]:
    """Module -> the package's modules it imports, at module level or deferred inside a function (``from . import x``
    of a submodule x names x, not the package)."""
    root = Path(__file__).resolve().parents[1] / "pipeline"

    def name_of(p: Path) -> str:
        parts = list(p.relative_to(root.parent).with_suffix("").parts)
        return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)

    mods = {name_of(p): p for p in root.rglob("*.py")}
    graph: dict[str, set[str]] = {}
    for name, path in mods.items():
        package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
        deps = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                base = package.split(".")[:len(package.split(".")) - max(node.level - 1, 0)] if node.level else []
                target = ".".join(base + [node.module]) if node.module else ".".join(base)
                subs = [f"{target}.{a.name}" for a in node.names if f"{target}.{a.name}" in mods]
                deps |= set(subs if len(subs) == len(node.names) else [target, *subs])
            elif isinstance(node, ast.Import):
                deps |= {a.name for a in node.names}
        graph[name] = {d for d in deps if d in mods and d != name}
    return graph


def test_no_import_cycle_in_the_package():
    """No module imports, directly or through others, one that imports it back (deferred imports included: a cycle
    closed inside a function is still a cycle)."""
    graph = _imports_graph()
    cycles = []
    for start in graph:
        seen, stack = set(), [(start, (start,))]
        while stack:
            node, path = stack.pop()
            for dep in graph[node]:
                if dep == start:
                    cycles.append(" -> ".join((*path, dep)))
                elif dep not in seen:
                    seen.add(dep)
                    stack.append((dep, (*path, dep)))
    assert cycles == [], cycles[:5]


def test_the_design_page_names_every_module_and_no_missing_one():
    """docs/design.md's layout does not drift: every module of the package is named in its layout block (by its
    name), and every ``*.py`` the page names exists (in the package, or as the path it gives)."""
    import re

    project = Path(__file__).resolve().parents[1]
    text = (project / "docs" / "design.md").read_text()
    layout = text.split("## Layout", 1)[1].split("```")[1]
    root = project / "pipeline"
    modules = [p.relative_to(root).as_posix() for p in root.rglob("*.py") if p.name != "__init__.py"]
    unnamed = [m for m in modules if not re.search(rf"\b{re.escape(Path(m).stem)}\b", layout)]
    assert unnamed == [], f"name these in docs/design.md's layout: {unnamed}"
    basenames = {Path(m).name for m in modules}
    named = set(re.findall(r"[A-Za-z_][\w/]*\.py\b", text))
    absent = [n for n in named if not ((project / n).is_file() or (root / n).is_file() or Path(n).name in basenames)]
    assert absent == [], f"docs/design.md names modules that do not exist: {absent}"


def test_no_page_of_the_docs_dates_itself_by_issues_or_sessions():
    """The docs describe the software as it is, by topic: no 'issue 39', 'session 14', 'the issue's', 'this
    session'."""
    import re

    project = Path(__file__).resolve().parents[1]
    pattern = re.compile(r"\b(?:issues?[- ]\d+|sessions?[- ]\d+|the issue'?s?\b|this session|rounds? of work)", re.I)
    found = [(page.name, m.group(0)) for page in [project / "README.md", *sorted((project / "docs").glob("*.md"))]
             for m in pattern.finditer(page.read_text())]
    assert found == [], found


def test_the_docs_links_to_validation_sections_resolve():
    """A link to a section of docs/validation.md names a heading it has (GitHub's anchors: lower case, punctuation
    dropped, spaces as hyphens)."""
    import re

    project = Path(__file__).resolve().parents[1]
    headings = re.findall(r"^#+ (.+)$", (project / "docs" / "validation.md").read_text(), flags=re.M)
    anchors = {re.sub(r"[^a-z0-9 _-]", "", h.lower()).replace(" ", "-") for h in headings}
    links = [a for page in [project / "README.md", *(project / "docs").glob("*.md")]
             for a in re.findall(r"validation\.md#([\w-]+)", page.read_text())]
    assert links and [a for a in links if a not in anchors] == []


def test_every_command_docs_validation_quotes_exists():
    """docs/validation.md names the test or command behind each figure: every path it quotes exists, every test it
    names by ``file::test`` is defined there, every ``make`` target is in the Makefile and every ``screen``
    subcommand is one the command line has."""
    import re

    from pipeline.cli.main import SUBCOMMANDS

    project = Path(__file__).resolve().parents[1]
    text = (project / "docs" / "validation.md").read_text()
    quoted = re.findall(r"`([^`]+)`", text)
    missing = []
    for q in quoted:
        for path in re.findall(r"(?:^|\s)((?:benchmarks|tests|pipeline|configs|examples|records)/[\w./*?-]+)", q):
            path, _, test = path.partition("::")
            if not any(project.glob(path.rstrip("/."))):
                missing.append(path)
            elif test and not re.search(rf"^def {re.escape(test)}\(", (project / path).read_text(), flags=re.M):
                missing.append(f"{path}::{test}")
        for target in re.findall(r"^make ([\w-]+)", q):
            if not re.search(rf"^{re.escape(target)}:", (project / "Makefile").read_text(), flags=re.M):
                missing.append(f"make {target}")
        for sub in re.findall(r"^screen ([a-z]+)\b", q):
            if sub not in SUBCOMMANDS:
                missing.append(f"screen {sub}")
    assert quoted and missing == [], missing
