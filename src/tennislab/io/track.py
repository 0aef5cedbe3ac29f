"""Ball tracks as CSV: time-stamped 3-D ball-centre positions from any tracker.

Format (SI units, court frame of :mod:`tennislab.core.court`)::

    # comment lines start with '#'
    t,x,y,z[,sigma]
    0.000,-11.90,0.40,2.85,0.003
    ...

* ``t`` [s] strictly increasing; ``x, y, z`` [m] ball-centre position;
  optional ``sigma`` [m] per-axis 1-sigma noise of that point (> 0).
* Columns may come in any order; extra columns are ignored; names are
  case-insensitive.
* At least :data:`MIN_POINTS` rows.  Any problem raises
  :class:`~tennislab.errors.InputError` with a one-line message naming it
  (row numbers count lines of the file from 1).
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass

import numpy as np

from tennislab.errors import InputError
from tennislab.io.files import read_input
from tennislab.io.formats import check_header

MIN_POINTS = 1  #: fewest rows of a track (a short one is the caller's to judge: linecall answers review)
MAX_ROWS = 2_000_000  #: largest track read [rows]
MAX_BYTES = 200_000_000  #: largest track file read [bytes]
REQUIRED = ("t", "x", "y", "z")


@dataclass(frozen=True)
class Track:
    """A track: times t (N,) [s], positions xyz (N, 3) [m], per-point sigma (N,) [m] or None."""

    t: np.ndarray
    xyz: np.ndarray
    sigma: np.ndarray | None = None

    def __len__(self) -> int:
        return self.t.size


def parse_track(text: str | bytes, name: str = "track") -> Track:
    """Parse CSV text (or bytes, UTF-8) into a :class:`Track`."""
    if isinstance(text, (bytes, bytearray)):
        try:
            text = bytes(text).decode("utf-8-sig")
        except UnicodeDecodeError as exc:
            raise InputError(f"{name}: not UTF-8 text (byte {exc.start})") from None
    if "\x00" in text:
        raise InputError(f"{name}: contains NUL bytes (not a CSV text file)")
    lines = [(i + 1, ln) for i, ln in enumerate(text.splitlines()) if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise InputError(f"{name}: empty (expected a header t,x,y,z[,sigma] and rows)")
    try:
        rows = list(csv.reader([ln for _, ln in lines]))
    except csv.Error as exc:
        raise InputError(f"{name}: malformed CSV ({exc})") from None
    header = [h.strip().lower() for h in rows[0]]
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        raise InputError(
            f"{name}: missing column(s) {', '.join(missing)} in the header "
            f"(need t,x,y,z and optionally sigma; got {','.join(header)[:80]!r})"
        )
    check_header(name, header)
    cols = [header.index(c) for c in REQUIRED]
    has_sigma = "sigma" in header
    if has_sigma:
        cols.append(header.index("sigma"))
    data = rows[1:]
    if len(data) > MAX_ROWS:
        raise InputError(f"{name}: {len(data)} rows, more than the {MAX_ROWS} allowed")
    if len(data) < MIN_POINTS:
        raise InputError(f"{name}: too few points ({len(data)}); need at least {MIN_POINTS}")
    out = np.empty((len(data), len(cols)))
    need = max(cols) + 1
    for r, row in enumerate(data):
        lineno = lines[r + 1][0]
        if len(row) < need:
            raise InputError(f"{name}: row {lineno}: {len(row)} field(s), expected {len(header)}")
        for j, c in enumerate(cols):
            s = row[c].strip()
            try:
                v = float(s)
            except ValueError:
                raise InputError(f"{name}: row {lineno}, column {header[c]!r}: not a number: {s[:30]!r}") from None
            if not math.isfinite(v):
                raise InputError(f"{name}: row {lineno}, column {header[c]!r}: must be finite, got {s[:30]!r}")
            out[r, j] = v
    t = out[:, 0].copy()
    dt = np.diff(t)
    if np.any(dt <= 0):
        k = int(np.argmax(dt <= 0)) + 1
        raise InputError(
            f"{name}: times must be strictly increasing (row {lines[k + 1][0]}: t = {t[k]:g} s after {t[k - 1]:g} s)"
        )
    xyz = np.ascontiguousarray(out[:, 1:4])
    if np.any(np.abs(xyz) > 1000.0):
        k = int(np.argmax(np.any(np.abs(xyz) > 1000.0, axis=1)))
        raise InputError(f"{name}: row {lines[k + 1][0]}: position beyond 1000 m (units must be metres)")
    sigma = None
    if has_sigma:
        sigma = out[:, 4].copy()
        bad = ~((sigma > 0) & (sigma <= 1.0))
        if bad.any():
            k = int(np.argmax(bad))
            raise InputError(
                f"{name}: row {lines[k + 1][0]}, column 'sigma': {sigma[k]:g} m is outside the allowed range (0, 1] m"
            )
    return Track(t, xyz, sigma)


def read_track(path: str) -> Track:
    """Read a track CSV file (see the module docstring)."""
    data = read_input(path, MAX_BYTES)
    return parse_track(data, name=str(path))


def track_to_csv(t, xyz, sigma=None, comment: str = "") -> str:
    """CSV text of a track (the format :func:`parse_track` reads)."""
    buf = io.StringIO()
    for ln in comment.splitlines():
        buf.write(f"# {ln}\n")
    buf.write("t,x,y,z" + (",sigma" if sigma is not None else "") + "\n")
    xyz = np.asarray(xyz)
    for i, ti in enumerate(np.asarray(t)):
        row = f"{ti:.6f},{xyz[i, 0]:.5f},{xyz[i, 1]:.5f},{xyz[i, 2]:.5f}"
        if sigma is not None:
            s = sigma[i] if np.ndim(sigma) else sigma
            row += f",{s:.5f}"
        buf.write(row + "\n")
    return buf.getvalue()
