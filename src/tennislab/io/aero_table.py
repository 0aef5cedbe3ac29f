"""Read an aerodynamic coefficient table (e.g. wind-tunnel data) from CSV.

Columns: ``speed_ms, spin_rpm, cd, cl`` (header required), one row per grid
point of a full speed x spin grid, in any order.  Returns the grid axes in SI
(speed [m/s], spin [rad/s]) and the coefficient matrices (n_speed x n_spin).

This reader checks the file's form (size, UTF-8 text, columns, numbers, a full
grid); the values' physical ranges are checked where they get their meaning,
by the table model (:func:`tennislab.core.aero.table`).  Every problem is one
:class:`~tennislab.errors.InputError` line starting with ``aero_table:``.
"""

from __future__ import annotations

import csv
import io
import math

import numpy as np

from tennislab.errors import InputError
from tennislab.io.files import read_text
from tennislab.io.formats import check_header
from tennislab.units import RPM

REQUIRED = ("speed_ms", "spin_rpm", "cd", "cl")
#: largest file read [bytes] (a 100,000-point grid is ~4 MB)
MAX_BYTES = 8 * 1024 * 1024
#: most data rows
MAX_ROWS = 100_000


def read_aero_table(path: str):
    """(speed [m/s], spin [rad/s], cd (n x m), cl (n x m)) from a CSV file."""
    name = f"aero_table: {path}"
    try:
        text = read_text(path, MAX_BYTES, what="aero table", nul=False)
    except InputError as exc:
        raise InputError(f"aero_table: {exc}") from None
    try:
        rows = _rows(name, text)
    except csv.Error as exc:
        raise InputError(f"{name}: not a readable CSV ({exc})") from None
    a = np.array(rows)
    v = np.unique(a[:, 0])
    w = np.unique(a[:, 1])
    if len(v) * len(w) != len(a):
        raise InputError(
            f"{name}: rows must form a full speed x spin grid ({len(v)} speeds x {len(w)} spins != {len(a)} rows)"
        )
    cd = np.full((len(v), len(w)), np.nan)
    cl = np.full((len(v), len(w)), np.nan)
    iv = np.searchsorted(v, a[:, 0])
    iw = np.searchsorted(w, a[:, 1])
    cd[iv, iw] = a[:, 2]
    cl[iv, iw] = a[:, 3]
    if np.isnan(cd).any():
        raise InputError(f"{name}: duplicate grid points")
    return v, w * RPM, cd, cl


def _rows(name: str, text: str) -> list[tuple[float, ...]]:
    reader = csv.DictReader(io.StringIO(text, newline=""))
    cols = [c.strip() for c in (reader.fieldnames or [])]
    check_header(name, cols)
    missing = [c for c in REQUIRED if c not in cols]
    if missing:
        raise InputError(f"{name}: missing column(s) {', '.join(missing)}; required: {', '.join(REQUIRED)}")
    rows: list[tuple[float, ...]] = []
    for i, row in enumerate(reader, start=2):
        if len(rows) >= MAX_ROWS:
            raise InputError(f"{name}: more than {MAX_ROWS:,} rows")
        row = {k.strip(): v for k, v in row.items() if k is not None}
        try:
            vals = tuple(float(row[c]) for c in REQUIRED)
        except (TypeError, ValueError):
            raise InputError(f"{name}, line {i}: non-numeric value") from None
        if not all(math.isfinite(x) for x in vals):
            raise InputError(f"{name}, line {i}: values must be finite")
        rows.append(vals)
    if not rows:
        raise InputError(f"{name}: no data rows")
    return rows
