"""Reading material test tables (CSV) for ``tennislab material young|friction``.

Young's modulus tables: columns ``load_n`` (force [N]) or ``load_kg`` (weight
[kg], times g0 = 9.80665 m/s^2) and ``deformation_m`` (diameter reduction [m]).
Friction tables: column ``friction_angle_deg`` [deg], optional
``contact_length_m`` [m].  Extra columns are ignored; blank lines and lines
starting with ``#`` are skipped.  Errors name the file, the line and the column.
"""

from __future__ import annotations

import csv
import math

from tennislab.errors import InputError
from tennislab.io.files import read_text
from tennislab.io.formats import check_header

G0 = 9.80665  #: standard gravity [m/s^2]
#: Largest table read [bytes] (a test table has tens of rows).
MAX_BYTES = 1024 * 1024


def _text(path: str) -> str:
    """The file's text: at most :data:`MAX_BYTES`, UTF-8 (one-line InputError otherwise)."""
    return read_text(path, MAX_BYTES, what="material table")


def _read(path: str, required_any: list[tuple[str, ...]], optional: tuple[str, ...] = ()) -> dict[str, list[float]]:
    lines = [ln for ln in _text(path).splitlines(keepends=True) if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise InputError(f"{path}: empty file (expected a header line and data rows)")
    reader = csv.reader(lines)
    try:
        header = [h.strip() for h in next(reader)]
    except csv.Error as exc:
        raise InputError(f"{path}: not a CSV table ({exc})") from None
    check_header(str(path), header)
    cols = {}
    for alternatives in required_any:
        found = [a for a in alternatives if a in header]
        if not found:
            raise InputError(f"{path}: missing column {' or '.join(alternatives)} (header: {', '.join(header)})")
        cols[found[0]] = header.index(found[0])
    for o in optional:
        if o in header:
            cols[o] = header.index(o)
    out: dict[str, list[float]] = {c: [] for c in cols}
    rows = []
    try:
        rows = list(reader)
    except csv.Error as exc:
        raise InputError(f"{path}: not a CSV table ({exc})") from None
    for lineno, row in enumerate(rows, start=2):
        for c, j in cols.items():
            if j >= len(row) or not row[j].strip():
                raise InputError(f"{path}: line {lineno}: column {c} is empty")
            try:
                v = float(row[j])
            except ValueError:
                raise InputError(f"{path}: line {lineno}: column {c}: {row[j]!r} is not a number") from None
            if not math.isfinite(v):
                raise InputError(f"{path}: line {lineno}: column {c}: must be a finite number")
            out[c].append(v)
    if not next(iter(out.values())):
        raise InputError(f"{path}: no data rows")
    return out


def read_load_deformation(path: str) -> tuple[list[float], list[float]]:
    """(load [N], deformation [m]) from a CSV with ``load_n`` or ``load_kg`` and ``deformation_m``."""
    d = _read(path, [("load_n", "load_kg"), ("deformation_m",)])
    load = d["load_n"] if "load_n" in d else [w * G0 for w in d["load_kg"]]
    return load, d["deformation_m"]


def read_friction_angles(path: str) -> tuple[list[float], list[float] | None]:
    """(friction angle [deg], contact length [m] or None) from a CSV with ``friction_angle_deg``."""
    d = _read(path, [("friction_angle_deg",)], optional=("contact_length_m",))
    return d["friction_angle_deg"], d.get("contact_length_m")
