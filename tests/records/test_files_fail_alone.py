"""One bad file fails alone, named, and never stops the others: a table with an unknown unit beside a good one;
a compressed file that would expand beyond what a record of max_samples samples takes is refused before obspy
decompresses it into memory (gzip, bz2, zip and tar, as obspy opens them)."""

from __future__ import annotations

import bz2
import gzip
import io
import tarfile
import zipfile

import pytest

from pipeline.config import Config
from pipeline.errors import RecordFormatError
from pipeline.records.compressed import refuse_if_expands_beyond
from pipeline.records.listing import find_records

ROWS = "".join(f"{0.01 * (k % 7):.4f}\n" for k in range(2000))


def test_a_table_in_furlongs_fails_alone_and_the_good_one_is_found(tmp_path):
    (tmp_path / "good.txt").write_text("# dt_s=0.01 units=g\n" + ROWS)
    (tmp_path / "bad.txt").write_text("# dt_s=0.01 units=furlongs\n" + ROWS)
    sources, failures = find_records(tmp_path, config=Config())
    assert [s.record_id for s in sources] == ["good"]
    assert len(failures) == 1 and "bad.txt: header units=: unknown acceleration unit 'furlongs'" in failures[0].reason


def _gz(path, data):
    with gzip.open(path, "wb") as fh:
        fh.write(data)


def _bz2(path, data):
    path.write_bytes(bz2.compress(data))


def _zip(path, data):
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("inside.txt", data)


def _tar(path, data):
    with tarfile.open(path, "w:gz") as t:
        info = tarfile.TarInfo("inside.txt")
        info.size = len(data)
        t.addfile(info, io.BytesIO(data))


@pytest.mark.parametrize("name, pack", [("r.txt.gz", _gz), ("r.txt.bz2", _bz2), ("r.zip", _zip), ("r.tar.gz", _tar)])
def test_a_compressed_file_is_measured_as_a_stream_and_refused_past_the_limit(tmp_path, name, pack):
    path = tmp_path / name
    pack(path, b"0.000000\n" * 500_000)                                 # 4.5 MB inside
    refuse_if_expands_beyond(path, 5_000_000)                            # within: nothing said
    with pytest.raises(RecordFormatError, match=rf"{name}: decompresses to more than 1,000,000 bytes.*max_samples"):
        refuse_if_expands_beyond(path, 1_000_000)


def test_a_plain_file_is_not_measured(tmp_path):
    path = tmp_path / "plain.txt"
    path.write_bytes(b"0.0\n" * 1000)
    refuse_if_expands_beyond(path, 10)


def test_a_file_name_that_is_not_utf8_fails_alone_named_with_the_fix(tmp_path):
    """A Latin-1 name (b'caf\\xe9.txt') beside a good record: it fails alone, shown with its byte escaped; the good
    one is found; and the up-to-date check's digest of the folder takes the name as bytes."""
    import os

    from pipeline.run.uptodate import tree_sha256

    text = "# dt_s=0.01 units=g\n" + ROWS
    (tmp_path / "good.txt").write_text(text)
    try:
        with open(os.path.join(os.fsencode(tmp_path), b"caf\xe9.txt"), "w") as fh:
            fh.write(text)
    except OSError:
        pytest.skip("this file system refuses names that are not UTF-8")
    sources, failures = find_records(tmp_path, config=Config())
    assert [s.record_id for s in sources] == ["good"]
    assert len(failures) == 1 and "caf\\xe9.txt: the file name is not UTF-8" in failures[0].reason
    digest, n = tree_sha256(tmp_path)
    assert n == 2 and len(digest) == 64
