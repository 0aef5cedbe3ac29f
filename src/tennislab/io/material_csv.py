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

G0 = 9.80665  #: standard gravity [m/s^2]


def _read(path: str, required_any: list[tuple[str, ...]], optional: tuple[str, ...] = ()) -> dict[str, list[float]]:
    with open(path, newline="") as fh:
        lines = [ln for ln in fh if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise InputError(f"{path}: empty file (expected a header line and data rows)")
    reader = csv.reader(lines)
    header = [h.strip() for h in next(reader)]
    cols = {}
    for alternatives in required_any:
        found = [a for a in alternatives if a in header]
        if not found:
            raise InputError(f"{path}: missing column {' or '.join(alternatives)} (header: {', '.join(header)})")
        cols[found[0]] = header.index(found[0])
    for o in optional:
        if o in header:
            cols[o] = header.index(o)
    out = {c: [] for c in cols}
    for lineno, row in enumerate(reader, start=2):
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
