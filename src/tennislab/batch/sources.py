"""Chunk sources: where the input rows of a batch come from.

A *chunk source* hands out the input rows of a job one chunk at a time, so a
job never needs all its inputs in memory.  Three kinds:

:class:`ArraySource`
    A ``dict[str, np.ndarray]`` of equal-length arrays (N rows; arrays may be
    2-D, e.g. ``states`` of shape (N, 9)).  Chunks are slices.
:class:`tennislab.batch.grid.GridSpec`
    A Cartesian grid given by its axes; chunk ``i`` is computed from the row
    indices by integer arithmetic (10^10-row grids are never materialised), so
    workers build their own chunks from the (small, picklable) spec.
:class:`StreamSource`
    Any iterable of chunk dicts (e.g. a generator reading a season of tracked
    bounces).  The iterable defines the chunking; rows are counted on the fly.

Indexable sources (the first two, or any object with ``n_rows``,
``chunk(i, chunk_size)`` and ``fingerprint()``) are preferred: they make the
job's identity checkable up front (the manifest's ``fingerprint``) and chunk
counts known (progress bar with a total).  A stream is fingerprinted chunk by
chunk instead (each Parquet part records the hash of its input chunk).
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterable, Iterator, Sized

import numpy as np

from tennislab.errors import InputError

#: Default number of rows per chunk for large jobs: 65536 rows of a (N, 9)
#: float64 state table are 4.7 MB, about 0.2 s of ``fly_batch`` on one core.
MAX_DEFAULT_CHUNK = 65536
#: Smallest default chunk (small jobs are still split into a few chunks).
MIN_DEFAULT_CHUNK = 1024


def default_chunk_size(n_rows: int) -> int:
    """Rows per chunk when none is given: ~N/64 clamped to [1024, 65536].

    It depends on N only (never on the scheduler or the number of workers) so
    that the same job resumes under any scheduler with the same chunking.
    """
    return int(min(MAX_DEFAULT_CHUNK, max(MIN_DEFAULT_CHUNK, -(-int(n_rows) // 64))))


def hash_arrays(arrays: dict[str, np.ndarray], h=None) -> str:
    """Stable hex digest of named arrays (names, dtypes, shapes and bytes)."""
    h = h or hashlib.blake2b(digest_size=16)
    for name in sorted(arrays):
        a = np.ascontiguousarray(arrays[name])
        h.update(f"{name}|{a.dtype.str}|{a.shape}|".encode())
        h.update(a.data.cast("B") if a.size else b"")  # no copy
    return h.hexdigest()


def check_chunk_dict(name: str, chunk) -> int:
    """Validate a dict of equal-length arrays; return its number of rows."""
    if not isinstance(chunk, dict) or not chunk:
        raise InputError(f"{name}: expected a non-empty dict of equal-length arrays, got {type(chunk).__name__}")
    n: int | None = None
    for key, a in chunk.items():
        if not isinstance(key, str):
            raise InputError(f"{name}: column names must be strings, got {key!r}")
        if not isinstance(a, np.ndarray) or a.ndim == 0:
            raise InputError(f"{name}[{key!r}]: expected a numpy array with one row per item, got {type(a).__name__}")
        if n is None:
            n = a.shape[0]
        elif a.shape[0] != n:
            raise InputError(f"{name}[{key!r}]: has {a.shape[0]} rows, expected {n} like the other columns")
    return int(n or 0)


class ArraySource:
    """Rows of in-memory equal-length arrays; chunk ``i`` is rows [i*c, (i+1)*c)."""

    kind = "arrays"
    remote = False  # chunks are sliced on the client and shipped to workers

    def __init__(self, arrays: dict[str, np.ndarray]):
        arrays = {k: np.asarray(v) for k, v in arrays.items()} if isinstance(arrays, dict) else arrays
        self.n_rows = check_chunk_dict("inputs", arrays)
        self.arrays = arrays
        self._fp: str | None = None

    def n_chunks(self, chunk_size: int) -> int:
        return -(-self.n_rows // chunk_size)

    def chunk(self, i: int, chunk_size: int) -> dict[str, np.ndarray]:
        lo = i * chunk_size
        hi = min(self.n_rows, lo + chunk_size)
        return {k: a[lo:hi] for k, a in self.arrays.items()}

    def fingerprint(self) -> str:
        if self._fp is None:
            self._fp = "arrays:" + hash_arrays(self.arrays)
        return self._fp


class StreamSource:
    """An iterable of chunk dicts of unknown total length (hashed chunk by chunk).

    ``n_chunks`` may be given (or taken from ``len(iterable)``) for the
    progress bar's total.
    """

    kind = "stream"
    remote = False
    n_rows = None

    def __init__(self, chunks: Iterable[dict], n_chunks: int | None = None):
        self.chunks = chunks
        if n_chunks is None and isinstance(chunks, Sized):
            n_chunks = len(chunks)
        self._n_chunks = n_chunks

    def n_chunks(self, chunk_size=None) -> int | None:
        return self._n_chunks

    def __iter__(self) -> Iterator[dict]:
        for i, c in enumerate(self.chunks):
            check_chunk_dict(f"inputs chunk {i}", c)
            yield c

    def fingerprint(self) -> None:
        return None


def is_indexable(obj) -> bool:
    return all(hasattr(obj, a) for a in ("n_rows", "chunk", "fingerprint", "n_chunks"))


def as_source(inputs):
    """Wrap ``inputs`` (dict of arrays, indexable source, or iterable of chunk dicts) as a source."""
    if isinstance(inputs, dict):
        return ArraySource(inputs)
    if is_indexable(inputs) or isinstance(inputs, StreamSource):
        return inputs
    if hasattr(inputs, "__iter__") and not isinstance(inputs, (str, bytes, np.ndarray)):
        return StreamSource(inputs)
    raise InputError(
        "inputs: expected a dict of equal-length arrays, a chunk source (e.g. GridSpec) "
        f"or an iterable of chunk dicts, got {type(inputs).__name__}"
    )


class RowRange:
    """N rows that are just their indices: the lazy input of a Monte Carlo of N draws.

    ``map_chunks(partial(simulate, seed=7), RowRange(10**8))`` gives ``fn`` the
    chunk ``{"row": int64 indices}``; ``fn`` draws its per-row random numbers
    with :mod:`tennislab.batch.rng` and nothing of size N is ever built.
    ``constants`` (small arrays or scalars) are repeated into every chunk.
    """

    kind = "rows"
    remote = True  # workers build their own chunks

    def __init__(self, n: int, key: str = "row", constants: dict | None = None):
        n = int(n)
        if n < 0:
            raise InputError(f"n: {n} is outside the allowed range [0, inf]")
        self.n_rows = n
        self.key = str(key)
        self.constants = {k: np.asarray(v) for k, v in (constants or {}).items()}
        if self.key in self.constants:
            raise InputError(f"constants: {self.key!r} is the row key")

    def n_chunks(self, chunk_size: int) -> int:
        return -(-self.n_rows // int(chunk_size))

    def chunk(self, i: int, chunk_size: int) -> dict[str, np.ndarray]:
        lo = int(i) * int(chunk_size)
        idx = np.arange(lo, min(self.n_rows, lo + int(chunk_size)), dtype=np.int64)
        out = {self.key: idx}
        for k, v in self.constants.items():
            out[k] = np.broadcast_to(v, (len(idx),) + v.shape).copy()
        return out

    def fingerprint(self) -> str:
        return f"rows:{self.n_rows}:{self.key}:" + hash_arrays(self.constants)
