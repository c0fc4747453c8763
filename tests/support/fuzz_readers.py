"""Fuzz rockscreen's readers in this process, under an address-space cap: mutated and random tables (plain and gzip),
AT2, COSMOS and DMG files, meshes (OBJ, PLY, STL) and inventories. Every input must be read or refused by a named
error (a RockscreenError); anything else (a traceback, a MemoryError) is printed and the exit status is 1.

Run: ``python fuzz_readers.py CAP_GB N SEED`` (by ``tests/records/test_fuzz_readers.py``, in ``make test-slow``).
"""

from __future__ import annotations

import gzip
import random
import resource
import sys
import tempfile
import traceback
from pathlib import Path

PROJECT = Path(__file__).resolve().parents[2]
REAL = ["peer-at2/RSN1063_NORTHR_RRS228.AT2", "cosmos/CE23837.V1C", "dmg/CE58667.V2", "dmg/CICLC.v1"]
MESHES = ["balanced-rock.obj", "box-0.3x3.0x1.5.obj"]
TABLE = "# dt_s=0.01 units=g\n" + "".join(f"{0.01 * (k % 13 - 6):.5f}\n" for k in range(1500))
INVENTORY = (PROJECT / "configs" / "blocks.csv").read_text()
TOKENS = [b"nan", b"inf", b"-1e308", b"1e308", b"0", b"-", b",", b"\x00", b"\xef\xbb\xbf", b"\n" * 50,
          b"99999999999999999999", b"# dt_s=1e-30", b"# n=-5", b"f 1 2 99999999", b"element face 4000000000",
          b"\xff\xfe", b"units=furlongs", b"solid", b"1" * 5000]


def mutate(data: bytes, rng: random.Random) -> bytes:
    """Cut, splice tokens into, flip bytes of, or repeat part of ``data``."""
    data = bytearray(data)
    for _ in range(rng.randint(1, 6)):
        kind = rng.randrange(4)
        at = rng.randrange(len(data) + 1)
        if kind == 0:
            del data[at:at + rng.randint(1, 200)]
        elif kind == 1:
            data[at:at] = rng.choice(TOKENS)
        elif kind == 2 and data:
            data[min(at, len(data) - 1)] = rng.randrange(256)
        else:
            data[at:at] = bytes(data[at:at + rng.randint(1, 400)]) * rng.randint(1, 20)
    return bytes(data)


def one_input(rng: random.Random, root: Path) -> tuple[str, Path]:
    """A fuzzed file in ``root``: its kind and path."""
    kind = rng.choice(["table", "table.gz", "record", "mesh", "inventory", "random"])
    if kind == "table":
        path, data = root / "t.txt", mutate(TABLE.encode(), rng)
    elif kind == "table.gz":
        path, data = root / "t.txt.gz", gzip.compress(mutate(TABLE.encode(), rng))
    elif kind == "record":
        rel = rng.choice(REAL)
        path, data = root / Path(rel).name, mutate((PROJECT / "records" / rel).read_bytes(), rng)
    elif kind == "mesh":
        name = rng.choice(MESHES)
        path, data = root / name, mutate((PROJECT / "examples" / "scans" / name).read_bytes(), rng)
    elif kind == "inventory":
        path, data = root / "blocks.csv", mutate(INVENTORY.encode(), rng)
    else:
        path, data = root / rng.choice(["r.AT2", "r.txt", "r.obj", "r.stl", "r.ply", "r.V2"]), rng.randbytes(
            rng.randint(0, 5000))
    path.write_bytes(data)
    return kind, path


def read(kind: str, path: Path) -> None:
    """Read the file as rockscreen would."""
    from pipeline.blocks import read_inventory
    from pipeline.config import Config
    from pipeline.records.loader import iter_records
    from pipeline.shapes.scan import read_scan

    if kind == "inventory":
        read_inventory(path, default_mu=0.6)
    elif kind == "mesh" or path.suffix in (".obj", ".stl", ".ply"):
        read_scan(path)
    else:
        for _record in iter_records(path.parent, config=Config()):
            pass


def main() -> int:
    cap_gb, n, seed = float(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
    cap = int(cap_gb * 1e9)
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
    from pipeline.errors import RockscreenError

    rng = random.Random(seed)
    bad = 0
    for k in range(n):
        with tempfile.TemporaryDirectory() as tmp:
            kind, path = one_input(rng, Path(tmp))
            try:
                read(kind, path)
            except RockscreenError:
                pass
            except BaseException:                          # a traceback or MemoryError: a finding
                bad += 1
                print(f"input {k} ({kind}, {path.name}):", file=sys.stderr)
                traceback.print_exc()
    print(f"{n} inputs, {bad} not read nor refused by a named error")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
