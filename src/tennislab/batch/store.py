"""Resumable Parquet output: one file per chunk plus a manifest that vouches for each.

Layout of an output directory::

    manifest.json          what the job is (fn, inputs fingerprint, chunk size, ...) and,
                           once complete, every part's row count, size and checksum
    part-00000.parquet     outputs of chunk 0 (rows [0, c))
    part-00001.parquet     ...
    .ledger.jsonl          while the job is incomplete: one line per finished part
                           {"part", "rows", "bytes", "blake2b"} (folded into the manifest at the end)
    .lock                  held by the run writing the directory

A part is written to a temporary name (``.part-00000.parquet.tmp-XXXX``), flushed
to disk (fsync), renamed into place, and only then recorded in the ledger
(fsync again).  A part counts as finished only if its size and BLAKE2b checksum
match its record: a zero-byte, truncated or bit-flipped part, or one written but
not yet recorded when the run was killed, is computed again on a rerun, and
:func:`read_output` refuses a damaged one.  A rerun that describes a different job
(other inputs, function, chunk size, format) is refused with :class:`InputError`
-- results of two jobs are never mixed; a ``manifest.json`` that is not a
manifest (e.g. ``[]``) is one line too.

Files are only ever removed when they belong to the job: leftover temporary
parts of *this* job (matching names) after its manifest was found to match.  A
refused start creates nothing (a directory that holds files but no manifest, or
another job's, is left exactly as it was) and a run that fails before writing
its first part removes the directory it created.  Files are created with the
user's umask (0644 typically).
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import secrets
import stat
from typing import IO

import numpy as np

from tennislab.errors import InputError
from tennislab.io.files import read_input, shown
from tennislab.io.formats import load_json_document, unique_pairs

MANIFEST = "manifest.json"
LEDGER = ".ledger.jsonl"
LOCK = ".lock"
FORMAT = "tennislab.batch/2"
_PART_RE = re.compile(r"^part-(\d{5,})\.parquet\Z")
#: temporary files this module writes (and may remove): ``.<final name>.tmp-<random>``
_TMP_RE = re.compile(r"^\.(part-\d{5,}\.parquet|manifest\.json)\.tmp-[0-9a-f]{16}\Z")
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
#: manifest keys that describe the run's state, not the job
_STATE_KEYS = ("complete", "n_chunks", "total_rows", "parts")
_META_KEY = b"tennislab.batch"
#: largest manifest read [bytes]
_MAX_MANIFEST = 64 * 1024 * 1024
#: deepest JSON nesting of a manifest (it needs 3)
_MAX_DEPTH = 16


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


# ------------------------------------------------------------------ files
def _checksum(data: bytes) -> str:
    return hashlib.blake2b(data, digest_size=16).hexdigest()


def _fsync_dir(path: str) -> None:
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:  # pragma: no cover - not POSIX
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover - some file systems refuse fsync on directories
        pass
    finally:
        os.close(fd)


def write_durable(path: str, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically and durably, with the user's umask.

    A temporary file ``.<name>.tmp-<random>`` beside ``path`` (created with mode
    0666 & ~umask), fsync, rename, fsync of the directory.
    """
    d, name = os.path.split(os.path.abspath(path))
    tmp = os.path.join(d, f".{name}.tmp-{secrets.token_hex(8)}")
    try:
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    except OSError as exc:
        raise InputError(f"{shown(path)}: cannot be written ({exc.strerror or type(exc).__name__})") from None
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException as exc:
        if os.path.exists(tmp):
            os.unlink(tmp)
        if isinstance(exc, OSError):  # no space left, ...: the one line names the file (as atomic_path does)
            raise InputError(f"{shown(path)}: cannot be written ({exc.strerror or type(exc).__name__})") from None
        raise
    _fsync_dir(d)


def _load_json(path: str, what: str):
    try:
        raw = read_input(path, _MAX_MANIFEST)
    except InputError as exc:
        if "larger than" in str(exc):
            raise InputError(f"out: {path} is too large to be a tennislab {what}") from None
        raise InputError(f"out: {exc}") from None
    try:
        return load_json_document(raw.decode("utf-8"), path, max_depth=_MAX_DEPTH)
    except UnicodeDecodeError:
        raise InputError(f"out: {path} is not a tennislab {what} (not JSON)") from None
    except InputError as exc:
        why = "a key given twice" if "duplicate key" in str(exc) else "not JSON"
        raise InputError(f"out: {path} is not a tennislab {what} ({why})") from None


def load_manifest(path: str) -> dict:
    """The manifest of output directory ``path`` (validated: a JSON object with this format's keys)."""
    mpath = os.path.join(os.fspath(path), MANIFEST)
    man = _load_json(mpath, "batch manifest")
    if not isinstance(man, dict) or not isinstance(man.get("format"), str):
        raise InputError(f"out: {mpath} is not a tennislab batch manifest")
    if man["format"] != FORMAT:
        raise InputError(f"out: {path} was written by another version of tennislab ({man['format']}, now {FORMAT})")
    parts = man.get("parts", {})
    if not isinstance(parts, dict) or not all(_part_key(k) is not None and _valid_record(r) for k, r in parts.items()):
        raise InputError(f"out: {mpath} is damaged (malformed part records)")
    n = man.get("n_chunks")
    if n is not None and (not isinstance(n, int) or isinstance(n, bool) or n < 0):
        raise InputError(f"out: {mpath} is damaged (n_chunks is not a count)")
    return man


def _part_key(k) -> int | None:
    """The part index a manifest key names (``"0"``, ``"12"``: decimal digits), else None."""
    return int(k) if isinstance(k, str) and k.isascii() and k.isdigit() and len(k) <= 12 else None


def _valid_record(r) -> bool:
    return (
        isinstance(r, dict)
        and all(isinstance(r.get(k), int) and not isinstance(r.get(k), bool) and r[k] >= 0 for k in ("rows", "bytes"))
        and isinstance(r.get("blake2b"), str)
        and len(r["blake2b"]) == 32
    )


class ChunkStore:
    """The output directory of one job (see module docstring)."""

    def __init__(self, path: str, manifest: dict, *, lock: bool = False):
        from tennislab import __version__

        self.path = os.fspath(path)
        self._lock_fh: IO | None = None
        self._created = False
        self._records: dict[int, dict] = {}
        self._verified: set[int] = set()
        self._written = 0
        job = {k: v for k, v in manifest.items() if k not in _STATE_KEYS}
        self.manifest = dict(job, format=FORMAT, tennislab=__version__)
        if os.path.exists(self.path) and not os.path.isdir(self.path):
            raise InputError(f"out: {self.path} is a file, expected a directory")
        if os.path.isdir(self.path):
            self._check_existing()  # refuse before creating anything
        else:
            try:
                os.makedirs(self.path)
            except OSError as exc:
                raise InputError(f"out: cannot create {self.path}: {exc.strerror or exc}") from None
            self._created = True
        try:
            if lock:
                self._lock()
            self._open()
        except BaseException:
            self.close()
            self.discard_if_unused()
            raise

    # -------------------------------------------------------------- opening
    def _mpath(self) -> str:
        return os.path.join(self.path, MANIFEST)

    def _check_existing(self) -> None:
        """Refuse another job's directory or a foreign non-empty one (nothing touched)."""
        if os.path.exists(self._mpath()):
            self._check_same_job(load_manifest(self.path))
        elif [n for n in os.listdir(self.path) if n != LOCK]:
            raise InputError(f"out: {self.path} is not empty and has no {MANIFEST}; use an empty or new directory")

    def _open(self) -> None:
        if not os.path.exists(self._mpath()):  # new job (re-checked under the lock)
            self._check_existing()
            self.manifest["complete"] = False
            self._write_manifest()
            return
        old = load_manifest(self.path)
        self._check_same_job(old)
        self._records = {int(k): v for k, v in old.get("parts", {}).items()}
        self._records.update(self._read_ledger())
        for name in os.listdir(self.path):  # leftovers of a killed run of this job (only names it writes)
            if self._own_temporary(name, old):
                os.unlink(os.path.join(self.path, name))
        self._verified = {i for i in self._records if self._verify(i)}
        n = old.get("n_chunks")
        complete = bool(old.get("complete")) and isinstance(n, int) and self._verified.issuperset(range(n))
        self.manifest.update({k: old[k] for k in ("n_chunks", "total_rows") if k in old})
        self.manifest["complete"] = complete
        if old.get("complete") and not complete:  # a damaged part: no longer complete until recomputed
            self._write_manifest()

    def _n_parts(self, old: dict) -> int | None:
        """How many parts this job has (from the manifest: its chunk count, or rows / chunk size)."""
        n = old.get("n_chunks")
        if isinstance(n, int):
            return n
        c, rows = self.manifest.get("chunk_size"), self.manifest.get("n_rows")
        if isinstance(c, int) and isinstance(rows, int) and c > 0:
            return -(-rows // c)
        return None

    def _own_temporary(self, name: str, old: dict) -> bool:
        """Whether ``name`` is a temporary file this job writes: ``.manifest.json.tmp-<16 hex>`` or
        ``.part-NNNNN.parquet.tmp-<16 hex>`` of one of its parts (a stream's: at most one past the last
        recorded); a file that only looks like one (another part number or spelling) is the user's."""
        m = _TMP_RE.match(name)
        if m is None:
            return False
        if m.group(1) == MANIFEST:
            return True
        i = int(m.group(1)[len("part-") : -len(".parquet")])
        if m.group(1) != os.path.basename(self.part_path(i)):
            return False
        n = self._n_parts(old)
        if n is None:
            n = max(self._records, default=-1) + 2
        return i < n

    def _read_ledger(self) -> dict[int, dict]:
        path = os.path.join(self.path, LEDGER)
        out: dict[int, dict] = {}
        if not os.path.lexists(path):
            return out
        for line in read_input(path, _MAX_MANIFEST).splitlines():
            try:
                rec = json.loads(line.decode("utf-8"), object_pairs_hook=unique_pairs(path))
            except (UnicodeDecodeError, ValueError, RecursionError):
                continue  # a line torn by a crash (or a key given twice): its part is simply not trusted
            part = rec.get("part") if isinstance(rec, dict) else None
            if isinstance(part, int) and not isinstance(part, bool) and part >= 0 and _valid_record(rec):
                out[part] = {k: rec[k] for k in ("rows", "bytes", "blake2b")}
        return out

    def _expected_rows(self, i: int) -> int | None:
        c, n = self.manifest.get("chunk_size"), self.manifest.get("n_rows")
        if not isinstance(c, int) or not isinstance(n, int):
            return None  # a stream: chunk lengths are not known up front
        return max(0, min(c, n - i * c))

    def _verify(self, i: int) -> bool:
        """Whether part ``i`` on disk is the one its record describes (size, checksum, row count)."""
        rec = self._records.get(i)
        path = self.part_path(i)
        if rec is None or not os.path.isfile(path) or os.path.getsize(path) != rec["bytes"]:
            return False
        want = self._expected_rows(i)
        if want is not None and rec["rows"] != want:
            return False
        try:
            return _checksum(read_input(path, rec["bytes"])) == rec["blake2b"]
        except InputError:  # replaced meanwhile (a FIFO, a larger file): not this part
            return False

    def _lock(self) -> None:
        """Hold an exclusive lock on DIR/.lock until :meth:`close`: two runs never share a directory."""
        try:
            import fcntl
        except ImportError:  # pragma: no cover - not POSIX: no locking
            return
        lock_path = os.path.join(self.path, LOCK)
        flags = os.O_WRONLY | os.O_CREAT | os.O_APPEND | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
        if os.path.lexists(lock_path) and not os.path.isfile(lock_path):
            raise InputError(f"out: {lock_path} is not a regular file; remove it or use another output folder")
        try:
            fd = os.open(lock_path, flags, 0o666)  # non-blocking: a FIFO named .lock cannot hang the run
        except OSError as exc:
            raise InputError(f"out: cannot write in {self.path}: {exc.strerror or exc}") from None
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            os.close(fd)
            raise InputError(f"out: {lock_path} is not a regular file; remove it or use another output folder")
        fh = os.fdopen(fd, "a")
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

    def discard_if_unused(self) -> None:
        """Remove the directory this store created if no part was written in it (a failed start)."""
        if not self._created or self._written:
            return
        for name in (MANIFEST, LEDGER, LOCK):
            p = os.path.join(self.path, name)
            if os.path.exists(p):
                os.unlink(p)
        try:
            os.rmdir(self.path)
        except OSError:  # something else appeared in it: leave it
            pass
        self._created = False

    def _check_same_job(self, old: dict) -> None:
        for key in IDENTITY_KEYS:
            a, b = old.get(key), self.manifest.get(key)
            if a != b:
                raise InputError(
                    f"out: {self.path} holds another job ({key} differs: {_short(a)} there, "
                    f"{_short(b)} now); use a new --out-dir or delete the old one"
                )

    def _write_manifest(self) -> None:
        """Write the manifest with the records of the parts verified or written so far."""
        self.manifest["parts"] = {str(i): self._records[i] for i in sorted(self._verified)}
        write_durable(self._mpath(), (json.dumps(self.manifest, indent=2, sort_keys=True) + "\n").encode())

    # -------------------------------------------------------------- parts
    def part_path(self, i: int) -> str:
        return os.path.join(self.path, f"part-{i:05d}.parquet")

    def done(self) -> set[int]:
        """Indices of the chunks whose part exists and matches its record (size, checksum, rows)."""
        return set(self._verified)

    def write(self, i: int, outputs: dict[str, np.ndarray], meta: dict) -> None:
        """Write part ``i`` durably, then record it in the ledger."""
        pa, pq = _pa()
        table = outputs_to_table(outputs, dict(meta, chunk=i))
        sink = pa.BufferOutputStream()
        pq.write_table(table, sink)
        data = sink.getvalue().to_pybytes()
        write_durable(self.part_path(i), data)
        self._written += 1
        rec = {"rows": int(table.num_rows), "bytes": len(data), "blake2b": _checksum(data)}
        self._records[i] = rec
        self._verified.add(i)
        line = (json.dumps({"part": i, **rec}, sort_keys=True) + "\n").encode()
        fd = os.open(os.path.join(self.path, LEDGER), os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o666)
        try:
            os.write(fd, line)
            os.fsync(fd)
        finally:
            os.close(fd)

    def read_meta(self, i: int) -> dict:
        """The metadata stored in part ``i`` (chunk index, rows, input hash)."""
        _, pq = _pa()
        table = pq.read_table(self._pa_source(i))
        return json.loads((table.schema.metadata or {}).get(_META_KEY, b"{}"))

    def read(self, i: int, columns=None) -> dict[str, np.ndarray]:
        """The outputs of part ``i`` (verified against its record)."""
        _, pq = _pa()
        return table_to_outputs(pq.read_table(self._pa_source(i)), columns)

    def _pa_source(self, i: int):
        pa, _ = _pa()
        return pa.BufferReader(_read_part(self.path, i, self._records.get(i)))

    def finish(self, n_chunks: int, n_rows: int) -> None:
        """Mark the job complete: the manifest takes every part's record; the ledger goes."""
        self.manifest.update(complete=True, n_chunks=int(n_chunks), total_rows=int(n_rows))
        self._write_manifest()
        ledger = os.path.join(self.path, LEDGER)
        if os.path.exists(ledger):
            os.unlink(ledger)


def _read_part(path: str, i: int, rec: dict | None) -> bytes:
    """The bytes of part ``i`` of output ``path``, checked against its record ``rec``."""
    name = os.path.join(path, f"part-{i:05d}.parquet")
    bad = InputError(f"out: {name} is damaged or not this job's (checksum differs); rerun the job to recompute it")
    if rec is None:
        raise bad
    try:
        data = read_input(name, rec["bytes"])
    except InputError as exc:
        if "larger than" in str(exc):
            raise bad from None
        raise InputError(f"out: {exc}; rerun the job to recompute it") from None
    if len(data) != rec["bytes"] or _checksum(data) != rec["blake2b"]:
        raise bad
    return data


def _short(v) -> str:
    s = json.dumps(v)
    return s if len(s) <= 60 else s[:57] + "..."


def read_manifest(path: str) -> dict:
    """The manifest of a batch output directory (one-line :class:`InputError` if absent or malformed)."""
    if not os.path.exists(os.path.join(os.fspath(path), MANIFEST)):
        raise InputError(f"out: {path} has no {MANIFEST} (not a tennislab batch output)")
    return load_manifest(path)


def iter_output(path: str, columns=None):
    """Yield ``(chunk_index, outputs)`` of a finished output directory in chunk order (bounded memory).

    Every part is checked against the manifest's record (size, checksum); a damaged
    one is an :class:`InputError` (rerun the job: it recomputes the part).
    """
    pa, pq = _pa()
    man = read_manifest(path)
    n = man.get("n_chunks")
    parts = man.get("parts", {})
    if not man.get("complete") or not isinstance(n, int) or not all(str(i) in parts for i in range(n)):
        have = sum(1 for name in os.listdir(path) if _PART_RE.match(name))
        raise InputError(f"out: {path} is incomplete ({have} parts); rerun the job to finish it")
    for i in range(n):
        data = _read_part(os.fspath(path), i, parts[str(i)])
        table = pq.read_table(pa.BufferReader(data))
        if table.num_rows != parts[str(i)]["rows"]:
            raise InputError(
                f"out: part {i} of {path} has {table.num_rows} rows, its record says {parts[str(i)]['rows']}"
            )
        yield i, table_to_outputs(table, columns)


def read_output(path: str, columns=None) -> dict[str, np.ndarray]:
    """All outputs of a finished output directory, concatenated in row order."""
    parts = [o for _, o in iter_output(path, columns)]
    if not parts:
        return {}
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
