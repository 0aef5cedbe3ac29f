"""Resumable Parquet output: one file per chunk plus a manifest.

Layout of an output directory::

    manifest.json          what the job is (fn, inputs fingerprint, chunk size, ...)
    part-00000.parquet     outputs of chunk 0 (rows [0, c))
    part-00001.parquet     ...

Every file is written to a temporary name and renamed, so a part either exists
complete or not at all: a rerun (after a crash, Ctrl-C or a lost worker)
skips the parts that exist and computes the others.  A rerun that describes a
different job (other inputs, function, chunk size) is refused with
:class:`InputError` -- results of two jobs are never mixed.  Each part's
Parquet metadata records its chunk index, row range and the hash of its input
chunk (checked on resume for stream sources, which have no up-front
fingerprint).
"""

from __future__ import annotations

import glob
import json
import os
import re

import numpy as np

from tennislab.errors import InputError
from tennislab.io.files import atomic_path

MANIFEST = "manifest.json"
FORMAT = "tennislab.batch/1"
_PART_RE = re.compile(r"^part-(\d{5,})\.parquet$")
#: manifest keys that must agree for a rerun to resume into the same directory
IDENTITY_KEYS = (
    "format",
    "tennislab",
    "fn",
    "tag",
    "source",
    "fingerprint",
    "chunk_size",
    "n_rows",
    "row_key",
    "include_inputs",
)
_META_KEY = b"tennislab.batch"


def _pa():
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:  # pragma: no cover - depends on the environment
        raise InputError("out: Parquet output needs pyarrow (pip install 'tennislab[batch]')") from None
    return pa, pq


def outputs_to_table(outputs: dict[str, np.ndarray], meta: dict):
    """Arrow table of per-row outputs; k-D columns become fixed-size lists (shape kept in metadata)."""
    pa, _ = _pa()
    cols, shapes = {}, {}
    for name, a in outputs.items():
        a = np.ascontiguousarray(a)
        shapes[name] = [a.dtype.str, list(a.shape[1:])]
        if a.ndim == 1:
            cols[name] = pa.array(a)
        else:
            k = int(np.prod(a.shape[1:]))
            cols[name] = pa.FixedSizeListArray.from_arrays(pa.array(a.reshape(-1)), k)
    table = pa.table(cols)
    md = dict(meta, columns=shapes)
    return table.replace_schema_metadata({_META_KEY: json.dumps(md).encode()})


def table_to_outputs(table, columns=None) -> dict[str, np.ndarray]:
    md = json.loads(table.schema.metadata[_META_KEY])
    out = {}
    for name, (dtype, trail) in md["columns"].items():
        if columns is not None and name not in columns:
            continue
        col = table.column(name).combine_chunks()
        if trail:
            vals = col.flatten().to_numpy(zero_copy_only=False)
            a = vals.reshape((len(col), *trail))
        else:
            a = col.to_numpy(zero_copy_only=False)
        out[name] = a.astype(np.dtype(dtype), copy=False)
    return out


class ChunkStore:
    """The output directory of one job (see module docstring)."""

    def __init__(self, path: str, manifest: dict, *, lock: bool = False):
        self.path = os.fspath(path)
        self._lock_fh = None
        from tennislab import __version__

        self.manifest = dict(manifest, format=FORMAT, tennislab=__version__)
        mpath = os.path.join(self.path, MANIFEST)
        if os.path.isfile(self.path):
            raise InputError(f"out: {self.path} is a file, expected a directory")
        os.makedirs(self.path, exist_ok=True)
        if lock:
            self._lock()
        try:
            self._open(mpath)
        except BaseException:
            self.close()
            raise

    def _open(self, mpath: str) -> None:
        for tmp in glob.glob(os.path.join(self.path, ".tmp-*")):  # leftovers of a killed run
            os.unlink(tmp)
        if os.path.exists(mpath):
            with open(mpath) as fh:
                try:
                    old = json.load(fh)
                except json.JSONDecodeError:
                    raise InputError(f"out: {mpath} is not a tennislab batch manifest") from None
            self._check_same_job(old)
            self.manifest["complete"] = old.get("complete", False) and self.manifest.get("n_chunks") == old.get(
                "n_chunks"
            )
        else:
            if [n for n in os.listdir(self.path) if n != ".lock"]:
                raise InputError(f"out: {self.path} is not empty and has no {MANIFEST}; use an empty or new directory")
            self.manifest["complete"] = False
            self._write_manifest()

    def _lock(self) -> None:
        """Hold an exclusive lock on DIR/.lock until :meth:`close`: two runs never share a directory."""
        try:
            import fcntl
        except ImportError:  # pragma: no cover - not POSIX: no locking
            return
        fh = open(os.path.join(self.path, ".lock"), "a")
        try:
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            fh.close()
            raise InputError(
                f"out: {self.path} is in use by another run; wait for it or use another --out-dir"
            ) from None
        self._lock_fh = fh

    def close(self) -> None:
        """Release the directory lock (if any)."""
        if self._lock_fh is not None:
            self._lock_fh.close()
            self._lock_fh = None

    def _check_same_job(self, old: dict) -> None:
        for key in IDENTITY_KEYS:
            a, b = old.get(key), self.manifest.get(key)
            if a != b:
                raise InputError(
                    f"out: {self.path} holds another job ({key} differs: {_short(a)} there, "
                    f"{_short(b)} now); use a new --out-dir or delete the old one"
                )

    def _write_manifest(self) -> None:
        def w(tmp):
            with open(tmp, "w") as fh:
                json.dump(self.manifest, fh, indent=2, sort_keys=True)
                fh.write("\n")

        atomic_path(os.path.join(self.path, MANIFEST), w)

    def part_path(self, i: int) -> str:
        return os.path.join(self.path, f"part-{i:05d}.parquet")

    def done(self) -> set[int]:
        """Indices of the chunks whose part file exists."""
        out = set()
        for name in os.listdir(self.path):
            m = _PART_RE.match(name)
            if m:
                out.add(int(m.group(1)))
        return out

    def write(self, i: int, outputs: dict[str, np.ndarray], meta: dict) -> None:
        _, pq = _pa()
        table = outputs_to_table(outputs, dict(meta, chunk=i))
        atomic_path(self.part_path(i), lambda tmp: pq.write_table(table, tmp))

    def read_meta(self, i: int) -> dict:
        _, pq = _pa()
        md = pq.read_schema(self.part_path(i)).metadata or {}
        return json.loads(md.get(_META_KEY, b"{}"))

    def read(self, i: int, columns=None) -> dict[str, np.ndarray]:
        _, pq = _pa()
        return table_to_outputs(pq.read_table(self.part_path(i)), columns)

    def finish(self, n_chunks: int, n_rows: int) -> None:
        self.manifest.update(complete=True, n_chunks=int(n_chunks), total_rows=int(n_rows))
        self._write_manifest()


def _short(v) -> str:
    s = json.dumps(v)
    return s if len(s) <= 60 else s[:57] + "..."


def read_manifest(path: str) -> dict:
    mpath = os.path.join(os.fspath(path), MANIFEST)
    if not os.path.exists(mpath):
        raise InputError(f"out: {path} has no {MANIFEST} (not a tennislab batch output)")
    with open(mpath) as fh:
        return json.load(fh)


def iter_output(path: str, columns=None):
    """Yield ``(chunk_index, outputs)`` of a finished output directory in chunk order (bounded memory)."""
    man = read_manifest(path)
    have = {int(_PART_RE.match(n).group(1)) for n in os.listdir(path) if _PART_RE.match(n)}
    n = man.get("n_chunks")
    if not man.get("complete") or n is None or not have.issuperset(range(n)):
        raise InputError(f"out: {path} is incomplete ({len(have)} parts); rerun the job to finish it")
    _, pq = _pa()
    for i in range(n):
        yield i, table_to_outputs(pq.read_table(os.path.join(path, f"part-{i:05d}.parquet")), columns)


def read_output(path: str, columns=None) -> dict[str, np.ndarray]:
    """All outputs of a finished output directory, concatenated in row order."""
    parts = [o for _, o in iter_output(path, columns)]
    if not parts:
        return {}
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
