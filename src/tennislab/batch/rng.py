"""Per-row random numbers that do not depend on chunking, scheduler or order.

Monte Carlo in chunks must give the same draws for row r whatever chunk row r
falls in; a sequential generator seeded per chunk cannot (its draws depend on
the chunk size).  Here every draw is a pure function of (seed, stream, row):
the SplitMix64 output function (Steele, Lea & Flood 2014, "Fast splittable
pseudorandom number generators", OOPSLA; the finaliser of Vigna's
``splitmix64.c``) applied to a counter built from them, i.e. a counter-based
generator in the sense of Salmon et al. 2011 ("Parallel random numbers: as
easy as 1, 2, 3", SC'11).  Normals use the Box-Muller transform (Box & Muller
1958, Ann. Math. Stat. 29:610).

Use distinct ``stream`` numbers for independent quantities of the same row
(e.g. stream 0 = speed error, 1 = spin error); pass the global row index, e.g.
``map_chunks(..., row_key="row")`` and ``normal(seed, chunk["row"], stream=0)``.
"""

from __future__ import annotations

import numpy as np

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_M1 = np.uint64(0xBF58476D1CE4E5B9)
_M2 = np.uint64(0x94D049BB133111EB)
_STREAM = np.uint64(0xD1B54A32D192ED03)
_SUB = np.uint64(0x8CB92BA72F3D8DD7)


def _mix(z: np.ndarray) -> np.ndarray:
    """SplitMix64 output function (bijective 64-bit mixer), elementwise on uint64 arrays."""
    z = z.copy()
    z ^= z >> np.uint64(30)
    z *= _M1
    z ^= z >> np.uint64(27)
    z *= _M2
    z ^= z >> np.uint64(31)
    return z


def _key(seed: int, stream: int, sub: int) -> np.ndarray:
    s = np.array([int(seed) % 2**64], dtype=np.uint64)
    k = _mix(s) + np.array([int(stream) % 2**64], dtype=np.uint64) * _STREAM
    k = _mix(k) + np.array([sub], dtype=np.uint64) * _SUB
    return _mix(k)


def random_bits(seed: int, rows, stream: int = 0, sub: int = 0) -> np.ndarray:
    """64 random bits per row (uint64), a pure function of (seed, stream, sub, row)."""
    r = np.asarray(rows, dtype=np.int64).astype(np.uint64)
    return _mix(r * _GOLDEN + _key(seed, stream, sub))


def uniform(seed: int, rows, stream: int = 0, sub: int = 0) -> np.ndarray:
    """Uniform draws in the open interval (0, 1), one per row (53-bit resolution)."""
    return ((random_bits(seed, rows, stream, sub) >> np.uint64(11)).astype(np.float64) + 0.5) * 2.0**-53


def normal(seed: int, rows, stream: int = 0) -> np.ndarray:
    """Standard normal draws, one per row (Box-Muller from two independent uniforms)."""
    u1 = uniform(seed, rows, stream, sub=1)
    u2 = uniform(seed, rows, stream, sub=2)
    return np.sqrt(-2.0 * np.log(u1)) * np.cos(2.0 * np.pi * u2)
