"""Exceptions for user-facing errors.

Every error a user can cause by bad input (a NaN, an out-of-range value, an
unknown model name, a malformed file) is an :class:`InputError`.  The CLI turns
it into a one-line message on stderr and exit code 2, with no traceback.

Numbers given by a user are checked here (:func:`check_finite`, :func:`check_range`,
:func:`check_vector`): finite, and within their range.  A subnormal number (nonzero, of magnitude
below :data:`TINY` = 2.2e-308, such as ``1e-320``) is never a physical value and dividing by it gives
``inf``: it is read as 0, so a parameter that must be positive (a mass, a speed, a time) refuses it and
one that may be 0 takes 0.  (The command line refuses subnormals outright: ``cli.common.finite_float``.)
Answers are checked finite before they are shown (:func:`check_answer`).  Text that came from a
file or a file name is shown through one escaper (:func:`escape_text`).
"""

from __future__ import annotations

import math
import sys

#: smallest positive normal float (2.2e-308); a nonzero number of smaller magnitude is subnormal
TINY = sys.float_info.min

__all__ = [
    "InputError",
    "TennisLabError",
    "check_answer",
    "check_finite",
    "check_range",
    "check_vector",
    "escape_text",
    "is_subnormal",
]


class TennisLabError(Exception):
    """Base class of all tennislab errors."""


class InputError(TennisLabError, ValueError):
    """Bad user input: the message names the field and the allowed range."""


def is_subnormal(v: float) -> bool:
    """Whether ``v`` is a nonzero float of magnitude below :data:`TINY` (2.2e-308)."""
    return v != 0.0 and abs(v) < TINY


def check_finite(name: str, value: float) -> float:
    """Return ``float(value)`` (a subnormal read as a signed 0) or raise :class:`InputError` if it is not
    finite."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected a number, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"{name}: must be a finite number, got {value!r}")
    return math.copysign(0.0, v) if is_subnormal(v) else v


def check_answer(name: str, value: float, unit: str = "") -> float:
    """Return ``float(value)`` if it is finite, else raise :class:`InputError`: an answer that is not a
    number (``inf``, ``nan``) is never shown as a result; the inputs are outside what the model answers."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: the computed value {value!r} is not a number") from None
    if not math.isfinite(v):
        u = f" {unit}" if unit else ""
        raise InputError(f"{name}: the computed value is {v}{u}; the inputs are outside the range this model answers")
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
        given = float(value)
        sub = " (a subnormal number, read as 0)" if is_subnormal(given) else ""
        raise InputError(f"{name}: {given:g}{u}{sub} is outside the allowed range {rng}{u}")
    return v


def check_vector(name: str, value, n: int = 3):
    """Return a float tuple of length ``n`` with finite entries, else raise :class:`InputError`."""
    try:
        vals = tuple(float(x) for x in value)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected {n} numbers, got {value!r}") from None
    if len(vals) != n:
        raise InputError(f"{name}: expected {n} numbers, got {len(vals)}")
    return tuple(check_finite(f"{name}[{i}]", x) for i, x in enumerate(vals))


def _escape_char(ch: str) -> str:
    o = ord(ch)
    if 0xDC80 <= o <= 0xDCFF:  # a byte of a file name that is not UTF-8 (os.fsdecode's surrogateescape)
        return f"\\x{o - 0xDC00:02x}"
    if ch in "\t\n\r":
        return {"\t": "\\t", "\n": "\\n", "\r": "\\r"}[ch]
    if o < 0x100:
        return f"\\x{o:02x}"
    return f"\\u{o:04x}" if o < 0x10000 else f"\\U{o:08x}"


def escape_text(text: object, limit: int | None = None) -> str:
    """``text`` (from a file, a database or a file name) safe to print on one line of a terminal.

    Printable characters are kept; control characters (newlines, terminal escape codes such as
    ``ESC [``), format characters (bidirectional overrides), unassigned code points and the
    undecodable bytes of a non-UTF-8 file name are written as escapes (``\\x1b``, ``\\n``,
    ``\\u202e``, ``\\xff``), so the result always encodes as UTF-8 and cannot move the cursor, clear
    the screen or break a line.  With ``limit``, longer text is cut to ``limit`` characters and ends in
    ``...``.
    """
    s = str(text)
    if not s.isprintable():
        s = "".join(ch if ch.isprintable() else _escape_char(ch) for ch in s)
    if limit is not None and len(s) > limit:
        s = s[: max(0, limit - 3)] + "..."
    return s
