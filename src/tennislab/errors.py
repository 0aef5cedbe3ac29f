"""Exceptions for user-facing errors.

Every error a user can cause by bad input (a NaN, an out-of-range value, an
unknown model name, a malformed file) is an :class:`InputError`.  The CLI turns
it into a one-line message on stderr and exit code 2, with no traceback.
"""

from __future__ import annotations

import math


class TennisLabError(Exception):
    """Base class of all tennislab errors."""


class InputError(TennisLabError, ValueError):
    """Bad user input: the message names the field and the allowed range."""


def check_finite(name: str, value: float) -> float:
    """Return ``float(value)`` or raise :class:`InputError` if it is not finite."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected a number, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"{name}: must be a finite number, got {value!r}")
    return v


def check_range(
    name: str, value: float, lo: float | None = None, hi: float | None = None, unit: str = "", lo_open: bool = False
) -> float:
    """Return ``float(value)`` if finite and within [lo, hi], else raise :class:`InputError`.

    ``lo_open=True`` makes the lower bound exclusive (e.g. a mass must be > 0).
    """
    v = check_finite(name, value)
    u = f" {unit}" if unit else ""
    bad_lo = lo is not None and (v <= lo if lo_open else v < lo)
    bad_hi = hi is not None and v > hi
    if bad_lo or bad_hi:
        left = "(" if lo_open else "["
        rng = f"{left}{'-inf' if lo is None else lo}, {'inf' if hi is None else hi}]"
        raise InputError(f"{name}: {v:g}{u} is outside the allowed range {rng}{u}")
    return v


def check_vector(name: str, value, n: int = 3):
    """Return a float tuple of length ``n`` with finite entries, else raise :class:`InputError`."""
    try:
        vals = tuple(float(x) for x in value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected {n} numbers, got {value!r}") from None
    if len(vals) != n:
        raise InputError(f"{name}: expected {n} numbers, got {len(vals)}")
    for i, x in enumerate(vals):
        if not math.isfinite(x):
            raise InputError(f"{name}[{i}]: must be a finite number, got {x!r}")
    return vals
