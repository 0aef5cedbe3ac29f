"""Atomic file writes: nothing half-written on error or interruption.

A file is written to a temporary name in the destination directory and renamed
into place (``os.replace`` is atomic on POSIX and Windows).
"""

from __future__ import annotations

import os
import tempfile

from tennislab.errors import InputError


def atomic_path(path: str, write_fn) -> None:
    """Call ``write_fn(tmp_path)`` to write a temporary file, then rename it to ``path``."""
    d = os.path.dirname(os.path.abspath(path)) or "."
    os.makedirs(d, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=d, prefix=".tmp-", suffix=os.path.splitext(path)[1])
    os.close(fd)
    try:
        write_fn(tmp)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def atomic_write(path: str, write_fn, mode: str = "w") -> None:
    """Write ``path`` atomically through a file handle: ``write_fn(fh)``."""

    def _w(tmp):
        with open(tmp, mode) as fh:
            write_fn(fh)

    atomic_path(path, _w)


def read_text(path: str, limit: int) -> str:
    """Read at most ``limit`` bytes of ``path`` as UTF-8 text (a BOM is dropped).

    Not UTF-8 -> :class:`InputError` ``"PATH: not UTF-8 text"``.
    """
    with open(path, "rb") as fh:
        data = fh.read(limit)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise InputError(f"{path}: not UTF-8 text") from None
