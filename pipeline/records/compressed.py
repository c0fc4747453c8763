"""Compressed record files measured before they are opened: obspy decompresses a ``.gz``, ``.bz2``, zip or tar
record whole into memory before its reader sees it, so a small file that expands to gigabytes (a decompression
bomb, or a mistaken archive) would fill memory. :func:`refuse_if_expands_beyond` decompresses it as a stream,
keeping nothing, and refuses it once it passes the limit (the largest file a record of ``[records] max_samples``
samples takes: :func:`pipeline.records.plausibility.file_size_limit`)."""

from __future__ import annotations

import bz2
import gzip
import tarfile
import zipfile
from pathlib import Path

from ..errors import RecordFormatError

#: Bytes decompressed at a time while measuring
CHUNK_BYTES = 1 << 20


def refuse_if_expands_beyond(path: Path, limit_bytes: int) -> None:
    """Refuse ``path`` when it is compressed (gzip, bz2, zip or tar, as obspy would open it) and decompresses to
    more than ``limit_bytes``; nothing is kept in memory but one chunk.

    Raises
    ------
    RecordFormatError
        Naming the file, the limit and the setting that sets it.
    """
    total = 0
    for stream in _members(path):
        with stream:
            while chunk := stream.read(CHUNK_BYTES):
                total += len(chunk)
                if total > limit_bytes:
                    raise RecordFormatError(
                        f"{path}: decompresses to more than {limit_bytes:,} bytes, more than a record of "
                        "[records] max_samples samples takes; refused before it fills memory (raise max_samples if "
                        "the file is a real record, or decompress it and check it)")


def _members(path: Path):
    """The decompressed streams of ``path``, as obspy's reader would see them (none when it is not compressed)."""
    name = str(path)
    try:
        if tarfile.is_tarfile(name):
            with tarfile.open(name, "r|*") as tar:
                for info in tar:
                    if info.isfile():
                        member = tar.extractfile(info)
                        if member is not None:
                            yield member
            return
        if zipfile.is_zipfile(name):
            with zipfile.ZipFile(name) as archive:
                for member_name in archive.namelist():
                    yield archive.open(member_name)
            return
    except (OSError, tarfile.TarError, zipfile.BadZipFile, EOFError) as exc:
        raise RecordFormatError(f"{path}: a damaged archive ({exc}); re-download it") from exc
    if name.endswith(".bz2"):
        yield bz2.open(name, "rb")
    elif name.endswith(".gz"):
        yield gzip.open(name, "rb")
