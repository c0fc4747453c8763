"""The block inventory: CSV schema, validation and rigid-block geometry.

A block is a free-standing rectangular rigid body of full height ``height_m``
and full base width ``width_m`` in its rocking plane (Housner 1963 notation:
half-height h, half-width b). Required columns: ``id,height_m,width_m``;
optional: ``name,mu,azimuth_deg,restitution,base_margin_m,site,notes``. A blank ``mu``
takes ``blocks.default_mu`` from the configuration; a blank ``azimuth_deg``
(the rocking direction, deg clockwise from north, an axis) means "worst
orientation"; a blank ``restitution`` means Housner's value.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during
earthquakes. BSSA 53(2), 403-417.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import logging
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .constants import G
from .errors import InventoryError
from .rocking.block import OBJECT_KINDS, Block, BlockShape, ShapeKind, dynamics
from .rocking.geometry import ALPHA_MAX_ROCKING, Geometry, check_friction, geometry
from .shapes.mesh_limits import DEFAULT_LIMITS, SIZE_RANGE_M, MeshLimits
from .stacks import COLUMNS as STACK_COLUMNS
from .stacks import build_stacks, read_stack_cells
from .tables import close_match, parse_number, read_csv_table

log = logging.getLogger(__name__)

REQUIRED = ("id", "height_m", "width_m")
OPTIONAL = ("name", "mu", "azimuth_deg", "restitution", "base_margin_m", "building", "floor_height_m", "site",
            "notes", "shape", "depth_m", "mesh", "density_kg_m3", "mass_kg", *STACK_COLUMNS)
#: The values of the ``shape`` column (blank: box)
SHAPES = {"box": ShapeKind.box, "cylinder": ShapeKind.cylinder}
#: Asset columns a risk report uses: kept as given and carried to screening.nc (``inventory_<column>``),
#: assets.csv and the report; ``lon`` and ``lat`` [decimal degrees] locate an asset for ``screen event``. Any other
#: extra column is kept too, with a warning (a typo is likely).
ASSET_COLUMNS = ("value", "location", "floor", "owner", "category", "lon", "lat", "object")
#: The ``object`` column's values (:data:`pipeline.rocking.block.OBJECT_KINDS`): what the block is, which decides
#: the words of its recommendation (blank: an asset).
#: What a misspelt optional column costs until it is renamed (said with the suggestion)
UNUSED = {"azimuth_deg": ": every block's azimuth is blank, so each is of unknown orientation (every plane scanned)",
          "mu": ": every block takes blocks.default_mu", "restitution": ": every block takes Housner's restitution",
          "depth_m": ": no box has a depth (each is judged in the plane of its width)",
          "base_margin_m": ": no block's base margin is checked", "shape": ": every block is a box",
          "mesh": ": no block is given by its scan"}
#: Heights above this are accepted but warned about: taller than the free-standing objects screened
#: (columns, obelisks, precarious rock pillars); often centimetres typed as metres [m].
PLAUSIBLE_HEIGHT_M = 30.0
#: Friction coefficients above this are accepted but warned about: above the static friction measured for
#: stone, wood, steel or concrete contacts (about 0.3-1.0) [-].
PLAUSIBLE_MU = 1.5
#: Aspect ratios height/width above this are warned about (alpha below 1.4 deg): more slender than the
#: objects screened (a needle, or a width typed in the wrong unit) [-].
PLAUSIBLE_ASPECT = 40.0


@dataclass(frozen=True)
class Inventory:
    """A validated block inventory (one entry per block, arrays aligned).

    ``mu`` is filled from the default where blank; ``azimuth_deg`` and
    ``restitution`` are NaN where blank.
    """

    ids: tuple[str, ...]
    names: tuple[str, ...]
    sites: tuple[str, ...]
    notes: tuple[str, ...]
    height_m: np.ndarray
    width_m: np.ndarray
    mu: np.ndarray
    azimuth_deg: np.ndarray
    restitution: np.ndarray
    source: str
    #: extra inventory columns (asset value, location, floor, ...), column -> one string per block
    extra: dict = field(default_factory=dict)
    #: free distance from the block's footprint to the edge of what it stands on, in its rocking plane [m]
    #: (NaN: no edge given); empty: none given for any block
    base_margin_m: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: the building each block stands in ("" on the ground); empty: none for any block
    building: tuple = ()
    #: height of its floor above the building's base [m] (NaN: not given); empty: none for any block
    floor_height_m: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: the kind of body (:class:`~pipeline.rocking.block.ShapeKind`); empty: every block a box
    kind: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int8))
    #: a box's base dimension perpendicular to ``width_m`` [m] (NaN: not given); empty: none for any block
    depth_m: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: the settled scan of each block given by a mesh (:class:`~pipeline.shapes.scan.ScannedShape`, None for the
    #: others); empty: none for any block
    scans: tuple = ()
    #: the fields of :class:`~pipeline.rocking.block.BlockShape` declared for a model beyond those above
    #: (:func:`declared_fields`), name -> one number per block; a field absent takes its default
    declared: dict = field(default_factory=dict)
    #: each block's place in its stack (:class:`~pipeline.assemblies.stack.StackPlace`, None for a block that
    #: stands alone; :mod:`pipeline.stacks`); empty: no block is in a stack
    stacks: tuple = ()

    def stack_of(self, j: int):
        """Block ``j``'s place in its stack, or None."""
        return self.stacks[j] if len(self.stacks) == len(self) else None

    def scan_of(self, j: int):
        """Block ``j``'s settled scan, or None."""
        return self.scans[j] if len(self.scans) == len(self) else None

    def kinds(self) -> np.ndarray:
        """:attr:`kind` aligned with the blocks (box where none is given)."""
        return self.kind if self.kind.size == len(self) else np.full(len(self), int(ShapeKind.box), dtype=np.int8)

    def depths(self) -> np.ndarray:
        """:attr:`depth_m` aligned with the blocks (NaN where none is given) [m]."""
        return self.depth_m if self.depth_m.size == len(self) else np.full(len(self), np.nan)

    def cylinders(self) -> np.ndarray:
        """Whether each block is a solid cylinder."""
        return self.kinds() == int(ShapeKind.cylinder)

    def base_margins(self) -> np.ndarray:
        """:attr:`base_margin_m` aligned with the blocks (NaN where none is given) [m]."""
        return self.base_margin_m if self.base_margin_m.size == len(self) else np.full(len(self), np.nan)

    def buildings(self) -> tuple:
        """:attr:`building` aligned with the blocks ("" where none is given)."""
        return self.building if len(self.building) == len(self) else ("",) * len(self)

    def floor_heights(self) -> np.ndarray:
        """:attr:`floor_height_m` aligned with the blocks (NaN where none is given) [m]."""
        return self.floor_height_m if self.floor_height_m.size == len(self) else np.full(len(self), np.nan)

    def __len__(self) -> int:
        return len(self.ids)

    def geometry(self, *, g_ms2: float = G) -> Geometry:
        """Rocking geometry of every block."""
        return geometry(self.height_m, self.width_m, g_ms2=g_ms2, cylinder=self.cylinders())

    def effective_restitution(self, geom: Geometry) -> np.ndarray:
        """Angular-velocity restitution per block as reported: the inventory's value, else Housner's (negative for
        a block too squat to rock; the simulator takes :func:`~pipeline.rocking.geometry.effective_restitution`)."""
        return np.where(np.isnan(self.restitution), geom.e_housner, self.restitution)

    @functools.cached_property
    def _made(self) -> dict:
        """What is made of the inventory once and read many times (every record's task reads every block's shape
        and digest; each margin task its blocks' dynamics): made on first use, by name. The inventory is frozen and
        what is kept is immutable (tuples of frozen shapes and blocks, strings)."""
        return {}

    def __getstate__(self) -> dict:
        """What pickles: the inventory without what it made (the executors send it with every task; the shapes and
        digests of 1,000 blocks took 7 ms to pickle and as long to load, against 0.5 ms for the inventory)."""
        return {k: v for k, v in self.__dict__.items() if k != "_made"}

    def _once(self, key, make):
        made = self._made
        if key not in made:
            made[key] = make()
        return made[key]

    def shape(self, j: int) -> BlockShape:
        """Block ``j`` as the simulator's models read it (:class:`~pipeline.rocking.block.BlockShape`)."""
        return self.shapes()[j]

    def shapes(self) -> tuple[BlockShape, ...]:
        """Every block's :class:`~pipeline.rocking.block.BlockShape` (made once)."""
        return self._once("shapes", self._make_shapes)

    def _make_shapes(self) -> tuple[BlockShape, ...]:
        depths, kinds = self.depths(), self.kinds()
        return tuple(BlockShape(height_m=float(self.height_m[j]), width_m=float(self.width_m[j]), mu=float(self.mu[j]),
                                restitution=float(self.restitution[j]), azimuth_deg=float(self.azimuth_deg[j]),
                                depth_m=float(depths[j]), kind=ShapeKind(int(kinds[j])), scan=self.scan_of(j),
                                stack=self.stack_of(j),
                                **{name: float(values[j]) for name, values in self.declared.items()})
                     for j in range(len(self)))

    def rocking_blocks(self, *, g_ms2: float = G) -> tuple[Block, ...]:
        """Every block as the planar simulator takes it (:func:`pipeline.rocking.block.dynamics`; made once per
        gravity)."""
        return self._once(("rocking_blocks", g_ms2), lambda: tuple(dynamics(list(self.shapes()), g_ms2=g_ms2)))

    def take(self, indices) -> "Inventory":
        """The sub-inventory of the blocks at ``indices`` (in that order)."""
        k = np.asarray(indices, dtype=int)
        pick = lambda seq: tuple(seq[i] for i in k)  # noqa: E731
        return Inventory(ids=pick(self.ids), names=pick(self.names), sites=pick(self.sites),
                         notes=pick(self.notes), height_m=self.height_m[k], width_m=self.width_m[k],
                         mu=self.mu[k], azimuth_deg=self.azimuth_deg[k], restitution=self.restitution[k],
                         source=self.source, extra={c: pick(v) for c, v in self.extra.items()},
                         base_margin_m=self.base_margins()[k], building=pick(self.buildings()),
                         floor_height_m=self.floor_heights()[k], kind=self.kinds()[k], depth_m=self.depths()[k],
                         scans=tuple(self.scan_of(int(i)) for i in k) if len(self.scans) == len(self) else (),
                         declared={name: values[k] for name, values in self.declared.items()},
                         stacks=tuple(self.stack_of(int(i)) for i in k) if len(self.stacks) == len(self) else ())

    def select(self, block_id: str) -> "Inventory":
        """The one-block inventory of ``block_id``.

        Raises
        ------
        InventoryError
            If the id is not in the inventory (the message lists some valid ids).
        """
        try:
            k = self.ids.index(block_id)
        except ValueError:
            shown = ", ".join(self.ids[:10]) + (", ..." if len(self.ids) > 10 else "")
            raise InventoryError(f"{self.source}: no block with id {block_id!r}; ids are {shown}") from None
        return self.take([k])

    def digests(self) -> tuple[str, ...]:
        """Per-block SHA-256 of everything that enters the computation (not names or notes; made once).

        A block whose digest is unchanged between two runs keeps its results.
        """
        return self._once("digests", self._make_digests)

    def _make_digests(self) -> tuple[str, ...]:
        out = []
        kinds, depths, buildings, floor_heights = self.kinds(), self.depths(), self.buildings(), self.floor_heights()
        floors = self.extra.get("floor", ("",) * len(self))
        for j, bid in enumerate(self.ids):
            fields: tuple = (bid, self.height_m[j], self.width_m[j], self.mu[j], self.azimuth_deg[j],
                             self.restitution[j])
            if kinds[j] != ShapeKind.box or not np.isnan(depths[j]):   # a shape or depth enters it
                fields += (int(kinds[j]), depths[j])
            scan = self.scan_of(j)
            if scan is not None:                # a scanned body: its mesh's content
                fields += (hashlib.sha256(scan.vertices_m.tobytes()).hexdigest(),)
            if buildings[j]:                    # a block in a building: its floor enters the computation
                fields += (buildings[j], floor_heights[j], floors[j])
            if self.stack_of(j) is not None:     # a body of a stack: the whole stack enters its computation
                fields += (repr(self.stack_of(j)),)
            fields += _declared_later(self.shape(j))
            out.append(hashlib.sha256(repr(tuple(map(str, fields))).encode()).hexdigest())
        return tuple(out)

    @classmethod
    def single(cls, *, height_m: float, width_m: float, mu: float, block_id: str = "block",
               azimuth_deg: float = math.nan) -> "Inventory":
        """A one-block inventory from sizes given on the command line (validated)."""
        geometry(height_m, width_m)
        check_friction(mu)
        return cls(ids=(block_id,), names=("",), sites=("",), notes=("",), height_m=np.array([height_m]),
                   width_m=np.array([width_m]), mu=np.array([mu]), azimuth_deg=np.array([azimuth_deg]),
                   restitution=np.array([math.nan]), source="<command line>")


#: The fields of :class:`~pipeline.rocking.block.BlockShape` the digest above names one by one; any other field a
#: model declares there enters the digest by itself wherever it differs from its default (:func:`_declared_later`).
DIGESTED_SHAPE_FIELDS = ("height_m", "width_m", "mu", "restitution", "azimuth_deg", "depth_m", "kind", "scan",
                         "stack")


def declared_fields() -> list[dataclasses.Field]:
    """The fields of :class:`~pipeline.rocking.block.BlockShape` beyond :data:`DIGESTED_SHAPE_FIELDS`: what a model
    declares it needs of a block, each a number with a default. Each is read from the inventory column of its name
    (blank: its default), checked by its metadata ``ok`` (a predicate; default: finite) and described by its
    ``rule`` (the error's "expected ..."), and enters the digest."""
    return [f for f in dataclasses.fields(BlockShape) if f.name not in DIGESTED_SHAPE_FIELDS]


def _declared_later(shape: BlockShape) -> tuple:
    """``(name, value)`` of every field of ``shape`` not in :data:`DIGESTED_SHAPE_FIELDS` whose value is not its
    default: a field added to the block for a new model reaches the scene cache's digest without a line here, so
    that a changed value is never answered from the cache."""
    out: tuple = ()
    for f in dataclasses.fields(shape):
        if f.name in DIGESTED_SHAPE_FIELDS:
            continue
        value = getattr(shape, f.name)
        if f.default is dataclasses.MISSING or str(value) != str(f.default):
            out += ((f.name, value),)
    return out


def _implausible(where: str, block_id: str, height_m: float, width_m: float, mu: float, *,
                 height_typed: bool = True, stacked: bool = False) -> list[str]:
    """Warnings for values a real free-standing object does not have (a unit typed wrong, a typo); the height's only
    where it was typed (``height_typed``; a scan's own height is held to the columns' range when it is read). A body of
    a stack (``stacked``) may be squat: its stack's model judges it."""
    out = []
    if height_typed and height_m > PLAUSIBLE_HEIGHT_M:
        out.append(f"{where} ({block_id}): height_m {height_m:g} m is above {PLAUSIBLE_HEIGHT_M:g} m (centimetres "
                   "typed as metres?)")
    if mu > PLAUSIBLE_MU:
        out.append(f"{where} ({block_id}): mu {mu:g} is above {PLAUSIBLE_MU:g}, more than the static friction "
                   "measured for stone, wood, steel or concrete (about 0.3-1.0)")
    alpha = math.atan2(width_m / 2.0, height_m / 2.0)
    if alpha > ALPHA_MAX_ROCKING and not stacked:
        out.append(f"{where} ({block_id}): width_m/height_m {width_m / height_m:.3g} gives slenderness "
                   f"{math.degrees(alpha):.1f} deg, above {math.degrees(ALPHA_MAX_ROCKING):.1f} deg: it cannot "
                   "rock, only slide or stand, and is screened for sliding (if height and width are swapped, fix "
                   "the row)")
    elif height_m / width_m > PLAUSIBLE_ASPECT:
        out.append(f"{where} ({block_id}): height_m/width_m {height_m / width_m:.3g} is above "
                   f"{PLAUSIBLE_ASPECT:g} (a width in the wrong unit?)")
    return out


def read_inventory(path: str | Path, *, default_mu: float, warn_for: str | None = None,
                   mesh_limits: MeshLimits = DEFAULT_LIMITS) -> Inventory:
    """Read and validate an inventory CSV; every bad row is reported, and any stops everything.

    Columns: :data:`REQUIRED`, :data:`OPTIONAL`, those of the fields a model declared on the block
    (:func:`declared_fields`), and any extra ones (kept as given; those not in
    :data:`ASSET_COLUMNS` also warn). ``default_mu`` fills a blank ``mu``; ``warn_for``: warn about implausible
    values of that block alone (a command about one block; default: every block); ``mesh_limits``: the largest scan
    read (``[blocks] max_mesh_faces``, ``max_mesh_mb``).

    Raises
    ------
    InventoryError
        Naming the file, and for each problem the line and column, what was found and what is expected.
    """
    path = Path(path)
    errors: list[str] = []
    header, records = read_csv_table(path, what="inventory", expected_header="id,height_m,width_m,...",
                                     problems=errors, required=REQUIRED)
    declared = [f for f in declared_fields() if f.name in header]
    extras = [c for c in header if c not in REQUIRED + OPTIONAL + tuple(f.name for f in declared)]
    unknown = [c for c in extras if c not in ASSET_COLUMNS]
    for c in unknown:
        meant = close_match(c, [k for k in REQUIRED + OPTIONAL + ASSET_COLUMNS if k not in header])
        if meant is not None:
            log.warning("%s, line 1: column %r is not an inventory column: did you mean %r? Rename it; until then "
                        "it is kept as an extra column and not used%s", path, c, meant, UNUSED.get(meant, ""))
    others = [c for c in unknown if close_match(c, [k for k in REQUIRED + OPTIONAL + ASSET_COLUMNS
                                                    if k not in header]) is None]
    if others:
        log.warning("%s, line 1: column(s) %s are not inventory columns; they are kept and carried to the "
                    "results as given (valid columns: %s; asset columns: %s)", path, others,
                    list(REQUIRED + OPTIONAL), list(ASSET_COLUMNS))
    rows: dict[str, list] = {c: [] for c in REQUIRED + OPTIONAL + tuple(extras) + ("scan",)}
    rows.update({f.name: [] for f in declared})
    seen: dict[str, int] = {}
    wheres: list[str] = []
    typed: list[bool] = []
    for line, where, rec in records:
        try:
            bid = rec["id"]
        except KeyError:
            errors.append(f"{where}: too few fields")
            continue
        if not bid:
            errors.append(f"{where}, column 'id': empty; every block needs a unique id")
        elif bid in seen:
            errors.append(f"{where}, column 'id': duplicate id {bid!r} (first on line {seen[bid]})")
        seen.setdefault(bid, line)
        rows["id"].append(bid)
        _read_row(rec, where, rows, errors, default_mu=default_mu, extras=extras)
        _read_declared(rec, where, declared, rows, errors)
        _read_mesh(rec, where, path.parent, rows, errors, limits=mesh_limits, stacked="stands_on" in header)
        read_stack_cells(rec, where, rows, errors)
        wheres.append(where)
        typed.append(bool(rec.get("height_m", "").strip()))
    stacks = build_stacks(rows, wheres, errors) if "stands_on" in header and not errors else ()
    if not errors:                          # an inventory with errors is not screened: no "screened as given"
        _warn_implausible(path, rows, wheres, typed, stacks, warn_for)
    if errors:
        raise InventoryError(f"{path}: {len(errors)} problem(s):\n  " + "\n  ".join(errors))
    if not rows["id"]:
        raise InventoryError(f"{path}: no blocks; add at least one row under the header")
    return Inventory(
        ids=tuple(rows["id"]), names=tuple(rows["name"]), sites=tuple(rows["site"]),
        notes=tuple(rows["notes"]),
        height_m=np.array(rows["height_m"]), width_m=np.array(rows["width_m"]),
        mu=np.array(rows["mu"]), azimuth_deg=np.array(rows["azimuth_deg"]),
        restitution=np.array(rows["restitution"]), source=str(path),
        extra={c: tuple(rows[c]) for c in extras}, base_margin_m=np.array(rows["base_margin_m"], dtype=float),
        building=tuple(rows["building"]), floor_height_m=np.array(rows["floor_height_m"], dtype=float),
        kind=np.array(rows["shape"], dtype=np.int8), depth_m=np.array(rows["depth_m"], dtype=float),
        scans=tuple(rows["scan"]) if any(x is not None for x in rows["scan"]) else (),
        declared={f.name: np.array(rows[f.name], dtype=float) for f in declared}, stacks=stacks,
    )


def _warn_implausible(path: Path, rows: dict[str, list], wheres: list[str], typed: list[bool], stacks: tuple,
                      warn_for: str | None) -> None:
    """One warning listing the values of every row (of ``warn_for`` alone where given) a real object does not have
    (:func:`_implausible`); ``typed``: each row's height was typed; ``stacks``: each row's place in its stack."""
    implausible: list[str] = []
    for k, bid in enumerate(rows["id"]):
        if warn_for is None or bid == warn_for:        # a command about one block warns about that block alone
            implausible += _implausible(wheres[k], bid, rows["height_m"][k], rows["width_m"][k], rows["mu"][k],
                                        height_typed=typed[k], stacked=bool(stacks) and stacks[k] is not None)
    if implausible:
        log.warning("%s: %d value(s) outside what real objects have; screened as given, check them:\n  %s", path,
                    len(implausible), "\n  ".join(implausible))


def _read_declared(rec: dict, where: str, declared: list[dataclasses.Field], rows: dict[str, list],
                   errors: list[str]) -> None:
    """The cells of the fields a model declared (:func:`declared_fields`): blank takes the field's default."""
    for f in declared:
        value = rec.get(f.name, "")
        ok = f.metadata.get("ok", math.isfinite)
        rule = f.metadata.get("rule", "a number")
        default = float(f.default)  # type: ignore[arg-type]   # a declared field has a numeric default
        rows[f.name].append(default if not value else _cell(errors, where, f.name, value, rule, ok, default))


def _cell(errors: list[str], where: str, column: str, value: str, rule: str, ok, default: float) -> float:
    """A cell's number, or ``default`` with the problem added to ``errors``."""
    try:
        return parse_number(value, where=where, column=column, rule=rule, ok=ok)
    except InventoryError as exc:
        errors.append(str(exc))
        return default


#: Sizes typed in another unit than metres, and their factor to metres: a size above the largest in metres is read in
#: each, and the readings that fall in the sizes' range are offered (the likeliest first: nearest to 1 m).
SIZE_UNITS = (("millimetres", 1e-3), ("centimetres", 1e-2))


def _unit_hint(cell: str) -> str:
    """For a size cell above the largest size in metres, what it reads as in millimetres and in centimetres where
    that is a size (e.g. 1850: '(in millimetres? 1.85 m; in centimetres? 18.5 m; sizes are in metres)'), else ''."""
    lo, hi = SIZE_RANGE_M
    try:
        value = float(cell)
    except ValueError:
        return ""
    readings = [(name, value * factor) for name, factor in SIZE_UNITS if value > hi and lo <= value * factor <= hi]
    if not readings:
        return ""
    readings.sort(key=lambda r: abs(math.log10(r[1])))
    return " (" + "; ".join(f"in {name}? {size:g} m" for name, size in readings) + "; sizes are in metres)"


def _read_row(rec: dict, where: str, rows: dict[str, list], errors: list[str], *, default_mu: float,
              extras: list[str]) -> None:
    """Append a row's cells (but its id) to ``rows``, each checked against its rule; a bad cell's problem goes to
    ``errors`` and a placeholder to ``rows``."""
    lo, hi = SIZE_RANGE_M
    size_rule = f"a size in metres between {lo:g} and {hi:g} (full height, full base width)"
    for c in ("height_m", "width_m"):
        if not rec[c] and rec.get("mesh", ""):
            rows[c].append(math.nan)            # a scanned body's: its equivalent rectangle's (_read_mesh)
        elif not rec[c]:
            errors.append(f"{where}, column {c!r}: missing; expected {size_rule}")
            rows[c].append(1.0)
        else:
            rows[c].append(_cell(errors, where, c, rec[c], size_rule + _unit_hint(rec[c]), lambda x: lo <= x <= hi,
                                 1.0))
    mu = rec.get("mu", "")
    rows["mu"].append(default_mu if not mu else _cell(errors, where, "mu", mu,
                                                      "a friction coefficient > 0 (at most 5)",
                                                      lambda x: 0 < x <= 5, default_mu))
    az = rec.get("azimuth_deg", "")
    rows["azimuth_deg"].append(math.nan if not az else _cell(
        errors, where, "azimuth_deg", az, "an azimuth in [0, 360] deg (blank = the worst rocking plane)",
        lambda x: 0 <= x <= 360, 0.0) % 180.0)
    e = rec.get("restitution", "")
    rows["restitution"].append(math.nan if not e else _cell(
        errors, where, "restitution", e, "a velocity restitution ratio in (0, 1]", lambda x: 0 < x <= 1, math.nan))
    margin = rec.get("base_margin_m", "")
    rows["base_margin_m"].append(math.nan if not margin else _cell(
        errors, where, "base_margin_m", margin,
        "a distance >= 0 m from the block to the edge of its base (blank: none)", lambda x: x >= 0, math.nan))
    _read_shape(rec, where, rows, errors)
    rows["building"].append(rec.get("building", ""))
    fh = rec.get("floor_height_m", "")
    rows["floor_height_m"].append(math.nan if not fh else _cell(
        errors, where, "floor_height_m", fh, "a height in metres >= 0 above the building's base (blank: from floor)",
        lambda x: x >= 0, math.nan))
    for c in ("name", "site", "notes") + tuple(extras):
        rows[c].append(rec.get(c, ""))
    kind = rec.get("object", "").strip().lower()
    if kind and kind not in OBJECT_KINDS:
        errors.append(f"{where}, column 'object': {rec['object']!r}; expected one of {', '.join(OBJECT_KINDS)} (blank: "
                      "asset; natural: a rock in nature, monitored, never anchored)")


def _read_shape(rec: dict, where: str, rows: dict[str, list], errors: list[str]) -> None:
    """The ``shape`` (blank: box) and ``depth_m`` cells (a box's other base dimension; a cylinder has none)."""
    shape = rec.get("shape", "").strip().lower()
    if shape and shape not in SHAPES:
        errors.append(f"{where}, column 'shape': {rec['shape']!r}; expected one of {', '.join(SHAPES)} (blank: box)")
    kind = SHAPES.get(shape or "box", ShapeKind.box)
    rows["shape"].append(int(kind))
    lo, hi = SIZE_RANGE_M
    depth = rec.get("depth_m", "")
    if depth and kind == ShapeKind.cylinder:
        errors.append(f"{where}, column 'depth_m': {depth!r} for a cylinder, whose base is round (width_m is its "
                      "diameter); leave depth_m blank")
        depth = ""
    rows["depth_m"].append(math.nan if not depth else _cell(
        errors, where, "depth_m", depth, f"a size in metres between {lo:g} and {hi:g} (the base dimension "
        "perpendicular to width_m; blank: not given)", lambda x: lo <= x <= hi, math.nan))


def _read_mesh(rec: dict, where: str, folder: Path, rows: dict[str, list], errors: list[str], *,
               limits: MeshLimits = DEFAULT_LIMITS, stacked: bool = False) -> None:
    """The ``mesh`` cell (a scan, relative to the inventory's folder) with ``density_kg_m3`` or ``mass_kg``: the
    settled scan (:func:`pipeline.shapes.scan.read_scan`), the block's kind ``scanned``, its azimuth over 360 deg
    (its two sides differ) and, where blank, its height and width from its equivalent rectangle. ``stacked``: the
    inventory has stacks, whose bodies' masses these columns give too (:mod:`pipeline.stacks`)."""
    from .errors import MeshError
    from .shapes.plane import equivalent_rectangle
    from .shapes.scan import read_scan

    mesh = rec.get("mesh", "").strip()
    density = _cell(errors, where, "density_kg_m3", rec["density_kg_m3"], "a density in kg/m3 > 0 (blank: none)",
                    lambda x: x > 0, math.nan) if rec.get("density_kg_m3", "") else math.nan
    mass = _cell(errors, where, "mass_kg", rec["mass_kg"], "a mass in kg > 0 (blank: none)",
                 lambda x: x > 0, math.nan) if rec.get("mass_kg", "") else math.nan
    rows["density_kg_m3"].append(density)
    rows["mass_kg"].append(mass)
    rows["scan"].append(None)
    if not mesh:
        if (math.isfinite(density) or math.isfinite(mass)) and not stacked:
            log.warning("%s: density_kg_m3 or mass_kg without a mesh is not used (it gives a scanned body's mass, or "
                        "a stacked body's: stands_on)", where)
        return
    if rec.get("shape", "").strip() or rec.get("depth_m", ""):
        errors.append(f"{where}, column 'mesh': {mesh!r} with a shape or depth_m; a mesh gives the body's own shape: "
                      "leave shape and depth_m blank")
        return
    try:
        scan = read_scan(Path(mesh) if Path(mesh).is_absolute() else folder / mesh, density_kg_m3=density,
                         mass_kg=mass, limits=limits)
    except MeshError as exc:
        errors.append(f"{where}, column 'mesh': {exc}")
        return
    rows["scan"][-1] = scan
    rows["shape"][-1] = int(ShapeKind.scanned)
    az = rec.get("azimuth_deg", "")
    if az and math.isfinite(rows["azimuth_deg"][-1]):
        rows["azimuth_deg"][-1] = parse_number(az, where=where, column="azimuth_deg", rule="",
                                               ok=lambda x: True) % 360.0
    height, width = equivalent_rectangle(scan)
    for c, v in (("height_m", height), ("width_m", width)):
        if math.isnan(rows[c][-1]):
            rows[c][-1] = v
