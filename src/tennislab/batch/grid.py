"""Lazy Cartesian grids: chunk inputs by index arithmetic, never materialised.

A launcher table (speed x spin x axis x elevation x heading x height at the
machine's steps) has ~10^10 rows; :class:`GridSpec` stores only its axes and
computes the values of rows [lo, hi) from the row indices (C order: the first
axis varies slowest, exactly like ``np.meshgrid(*axes, indexing="ij")``
raveled).  The spec is small and picklable, so Dask workers build their own
chunks and nothing but the spec crosses the network.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field

import numpy as np

from tennislab.batch.sources import hash_arrays
from tennislab.errors import InputError


@dataclass(frozen=True, eq=False)
class GridSpec:
    """A Cartesian product of named 1-D axes (first axis slowest).

    Attributes
    ----------
    axes : dict name -> 1-D array of that axis' values (in the axis' own units,
        e.g. [m/s], [rad/s], [rad], [m]); every axis must be non-empty.
    row_key : if set, every chunk also carries the global row index (int64)
        under this name (for per-row random streams, see :mod:`tennislab.batch.rng`).
    """

    axes: dict
    row_key: str | None = None
    kind: str = field(default="grid", init=False, repr=False)
    remote: bool = field(default=True, init=False, repr=False)

    def __post_init__(self):
        if not isinstance(self.axes, dict) or not self.axes:
            raise InputError("axes: expected a non-empty dict name -> 1-D array")
        clean = {}
        for name, values in self.axes.items():
            a = np.ascontiguousarray(np.asarray(values))
            if a.ndim != 1 or a.size == 0:
                raise InputError(f"axes[{name!r}]: expected a non-empty 1-D array, got shape {a.shape}")
            if a.dtype.kind == "f" and not np.all(np.isfinite(a)):
                raise InputError(f"axes[{name!r}]: values must be finite")
            a.setflags(write=False)
            clean[str(name)] = a
        if self.row_key is not None and self.row_key in clean:
            raise InputError(f"row_key: {self.row_key!r} is also an axis name")
        object.__setattr__(self, "axes", clean)
        if self.size >= 2**62:
            raise InputError(f"axes: grid of {self.size} rows is too large for int64 row indices")

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(a.size for a in self.axes.values())

    @property
    def size(self) -> int:
        """Number of rows (product of the axis lengths; a Python int, no overflow)."""
        return math.prod(self.shape)

    n_rows = size

    def n_chunks(self, chunk_size: int) -> int:
        return -(-self.size // int(chunk_size))

    def rows(self, lo: int, hi: int) -> dict[str, np.ndarray]:
        """Input arrays of rows [lo, hi) (clipped to the grid)."""
        lo = max(0, int(lo))
        hi = min(self.size, int(hi))
        idx = np.arange(lo, max(lo, hi), dtype=np.int64)
        out = {}
        rem = idx.copy()
        for name, a in reversed(list(self.axes.items())):
            out[name] = a[rem % a.size]
            rem //= a.size
        out = {name: out[name] for name in self.axes}  # keep axis order
        if self.row_key is not None:
            out[self.row_key] = idx
        return out

    def chunk(self, i: int, chunk_size: int) -> dict[str, np.ndarray]:
        """Input arrays of chunk ``i`` (rows [i*chunk_size, (i+1)*chunk_size))."""
        c = int(chunk_size)
        return self.rows(int(i) * c, (int(i) + 1) * c)

    def index(self, **positions: int) -> int:
        """Row index of the grid point with the given per-axis positions."""
        r = 0
        for name, a in self.axes.items():
            k = int(positions[name])
            if not 0 <= k < a.size:
                raise InputError(f"{name}: position {k} outside [0, {a.size - 1}]")
            r = r * a.size + k
        return r

    def fingerprint(self) -> str:
        h = hashlib.blake2b(digest_size=16)
        h.update(("|".join(self.axes) + f"|row_key={self.row_key}|").encode())
        return "grid:" + hash_arrays({f"{i:03d}:{k}": v for i, (k, v) in enumerate(self.axes.items())}, h)
