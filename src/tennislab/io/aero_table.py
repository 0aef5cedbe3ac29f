"""Read an aerodynamic coefficient table (e.g. wind-tunnel data) from CSV.

Columns: ``speed_ms, spin_rpm, cd, cl`` (header required), one row per grid
point of a full speed x spin grid, in any order.  Returns the grid axes in SI
(speed [m/s], spin [rad/s]) and the coefficient matrices (n_speed x n_spin).
"""

from __future__ import annotations

import csv
import math

import numpy as np

from tennislab.errors import InputError
from tennislab.units import RPM

REQUIRED = ("speed_ms", "spin_rpm", "cd", "cl")


def read_aero_table(path: str):
    """(speed [m/s], spin [rad/s], cd (n x m), cl (n x m)) from a CSV file."""
    try:
        fh = open(path, newline="")
    except OSError as exc:
        raise InputError(f"aero table {path}: {exc.strerror}") from None
    with fh:
        reader = csv.DictReader(fh)
        cols = [c.strip() for c in (reader.fieldnames or [])]
        missing = [c for c in REQUIRED if c not in cols]
        if missing:
            raise InputError(
                f"aero table {path}: missing column(s) {', '.join(missing)}; required: {', '.join(REQUIRED)}"
            )
        rows = []
        for i, row in enumerate(reader, start=2):
            row = {k.strip(): v for k, v in row.items() if k is not None}
            try:
                vals = tuple(float(row[c]) for c in REQUIRED)
            except (TypeError, ValueError):
                raise InputError(f"aero table {path}, line {i}: non-numeric value") from None
            if not all(math.isfinite(v) for v in vals):
                raise InputError(f"aero table {path}, line {i}: values must be finite")
            rows.append(vals)
    if not rows:
        raise InputError(f"aero table {path}: no data rows")
    a = np.array(rows)
    v = np.unique(a[:, 0])
    w = np.unique(a[:, 1])
    if len(v) * len(w) != len(a):
        raise InputError(
            f"aero table {path}: rows must form a full speed x spin grid "
            f"({len(v)} speeds x {len(w)} spins != {len(a)} rows)"
        )
    cd = np.full((len(v), len(w)), np.nan)
    cl = np.full((len(v), len(w)), np.nan)
    iv = np.searchsorted(v, a[:, 0])
    iw = np.searchsorted(w, a[:, 1])
    cd[iv, iw] = a[:, 2]
    cl[iv, iw] = a[:, 3]
    if np.isnan(cd).any():
        raise InputError(f"aero table {path}: duplicate grid points")
    return v, w * RPM, cd, cl
