"""Readers of the Hawk-Eye CourtVision summary CSVs (as collected in ``ryurko/hawkeye``).

Three formats, all comma-separated with a header row (frame: origin at the net centre on the
ground, x along the court, y across, z up, metres; see ../shared/realdata/README.md):

* **serves** (``courtvision_serves.csv``): one row per serve: ``match, point_ID, serve_num, spd``
  [km/h], ``serve_type, spin_rpm``, the impact point ``x_ball_serve_impact, y_..., z_...``, the
  net-plane crossing ``x_net_serve, y_net_serve, z_net_serve``, the bounce ``x_serve_bounce, y_...,
  z_...``, optionally ``point_end_type, error_type``.
* **ball trajectory** (``<match>_ball_trajectory.csv``): one row per summary point of a stroke:
  ``point_ID, set_num, game_num, point_num, serve_num, strike_index, position`` (``hit``, ``peak``,
  ``net``, ``bounce``, ``last``), ``x, y, z``.
* **point by point** (``<match>_pbp.csv``): one row per point; numbers may carry units as text
  (``"157 KPH"``, ``"0.61 Metre"``) and missing values are ``NA`` or empty.

The readers check the file's form only (size, encoding, header, numbers) and return plain data:
a dict of column name -> NumPy array (``float64`` for numeric columns, with NaN where a value is
optional and missing; ``object`` arrays of ``str`` otherwise).  What the numbers mean (which serves
are usable, how a flight is set up from them) is the business of :mod:`tennislab.calibrate`.
Every problem raises :class:`~tennislab.errors.InputError` with a one-line message naming the file,
the line and the column.
"""

from __future__ import annotations

import csv
import math
import re

import numpy as np

from tennislab.errors import InputError
from tennislab.io.files import read_input
from tennislab.io.formats import check_header

MAX_BYTES = 64_000_000  #: largest file read [bytes] (the real serves file is 1.7 MB)
MAX_ROWS = 500_000  #: most data rows per file

#: serves: numeric columns that every row must give (finite numbers)
SERVE_NUMERIC = (
    "serve_num",
    "spd",
    "spin_rpm",
    "x_ball_serve_impact",
    "y_ball_serve_impact",
    "z_ball_serve_impact",
    "x_net_serve",
    "y_net_serve",
    "z_net_serve",
    "x_serve_bounce",
    "y_serve_bounce",
    "z_serve_bounce",
)
SERVE_TEXT = ("match", "point_ID")  #: serves: text columns every row must give
SERVE_OPTIONAL_TEXT = ("serve_type", "point_end_type", "error_type")  #: kept as "" when absent

TRAJECTORY_NUMERIC = ("set_num", "game_num", "point_num", "serve_num", "x", "y", "z")
TRAJECTORY_OPTIONAL_NUMERIC = ("strike_index",)  #: NaN when empty
TRAJECTORY_TEXT = ("point_ID", "position")
POSITIONS = ("hit", "peak", "net", "bounce", "last")

#: pbp: columns parsed as numbers (NaN when missing); a trailing unit word is dropped
PBP_NUMERIC = (
    "set_num",
    "game_num",
    "point_num",
    "serve_num",
    "serve_speed_kph",
    "fault_distance_missed_m",
    "x_ball_serve_impact",
    "y_ball_serve_impact",
    "z_ball_serve_impact",
    "x_net_serve",
    "y_net_serve",
    "z_net_serve",
    "x_serve_bounce",
    "y_serve_bounce",
    "z_serve_bounce",
    "serve_return_impact_x",
    "serve_return_impact_y",
    "serve_return_impact_z",
    "serve_return_net_x",
    "serve_return_net_y",
    "serve_return_net_z",
    "serve_return_bounce_x",
    "serve_return_bounce_y",
    "serve_return_bounce_z",
    "spin_rpm",
)
PBP_REQUIRED = ("point_ID", "serve_num", "serve_speed_kph")  #: pbp: columns that must be present

_MISSING = {"", "na", "nan", "null", "none"}
#: a number with an optional unit word after it ("157 KPH", "0.61 Metre")
_NUM_UNIT = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-z/]*)\s*$")


def _decode(data: bytes | str, name: str) -> str:
    if isinstance(data, str):
        text = data
    else:
        if len(data) > MAX_BYTES:
            raise InputError(f"{name}: larger than the {MAX_BYTES // 1_000_000} MB allowed")
        try:
            text = bytes(data).decode("utf-8-sig")
        except UnicodeDecodeError as exc:
            raise InputError(f"{name}: not UTF-8 text (byte {exc.start})") from None
    if "\x00" in text:
        raise InputError(f"{name}: contains NUL bytes (not a CSV text file)")
    return text


def _read(path) -> bytes:
    return read_input(path, MAX_BYTES)


def _table(text: str, name: str, required: tuple[str, ...]) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """(header, [(line number, fields)]) of CSV text; checks the header and the field counts."""
    lines = text.splitlines()
    if len(lines) - 1 > MAX_ROWS:
        raise InputError(f"{name}: {len(lines) - 1} rows, more than the {MAX_ROWS} allowed")
    numbered = [(i + 1, ln) for i, ln in enumerate(lines) if ln.strip()]
    if not numbered:
        raise InputError(f"{name}: empty (expected a header row and data rows)")
    try:
        rows = list(csv.reader([ln for _, ln in numbered], strict=True))
    except csv.Error as exc:
        raise InputError(f"{name}: malformed CSV ({exc})") from None
    header = [h.strip() for h in rows[0]]
    missing = [c for c in required if c not in header]
    if missing:
        got = ",".join(header)[:80]
        raise InputError(f"{name}: missing column(s) {', '.join(missing)} in the header (got {got!r})")
    check_header(name, header)
    data = [(numbered[i][0], r) for i, r in enumerate(rows) if i > 0]
    if not data:
        raise InputError(f"{name}: no data rows")
    n = len(header)
    for lineno, r in data:
        if len(r) != n:
            raise InputError(f"{name}: line {lineno}: {len(r)} field(s), expected {n} as in the header")
    return header, data


def _number(s: str, name: str, lineno: int, col: str, *, required: bool, units: bool = False) -> float:
    t = s.strip()
    if t.lower() in _MISSING:
        if required:
            raise InputError(f"{name}: line {lineno}, column {col!r}: missing value (a number is required)")
        return math.nan
    try:
        v = float(t)
    except ValueError:
        m = _NUM_UNIT.match(t) if units else None
        if m is None:
            raise InputError(f"{name}: line {lineno}, column {col!r}: not a number: {t[:30]!r}") from None
        v = float(m.group(1))
    if not math.isfinite(v) or abs(v) > 1e6:
        raise InputError(f"{name}: line {lineno}, column {col!r}: {t[:30]!r} is not a finite number within +-1e6")
    return v


def _columns(
    header: list[str],
    data: list[tuple[int, list[str]]],
    name: str,
    numeric: tuple[str, ...],
    optional_numeric: tuple[str, ...] = (),
    units: bool = False,
) -> dict[str, np.ndarray]:
    out: dict[str, np.ndarray] = {}
    idx = {c: header.index(c) for c in header}
    for col in numeric + optional_numeric:
        if col not in idx:
            continue
        j = idx[col]
        req = col in numeric
        out[col] = np.array([_number(r[j], name, ln, col, required=req, units=units) for ln, r in data], dtype=float)
    for col in header:
        if col and col not in out:
            out[col] = np.array([r[idx[col]].strip() for _, r in data], dtype=object)
    return out


def parse_serves(text: str | bytes, name: str = "serves") -> dict[str, np.ndarray]:
    """Parse a CourtVision serves CSV (module docstring) into columns.

    Every column of :data:`SERVE_NUMERIC` becomes a float array and must hold a finite number in
    every row; ``match`` and ``point_ID`` must be non-empty; :data:`SERVE_OPTIONAL_TEXT` columns
    are filled with ``""`` when absent; other columns are kept as text.
    """
    text = _decode(text, name)
    header, data = _table(text, name, SERVE_TEXT + SERVE_NUMERIC)
    cols = _columns(header, data, name, SERVE_NUMERIC)
    for col in SERVE_TEXT:
        empty = np.flatnonzero(cols[col] == "")
        if empty.size:
            raise InputError(f"{name}: line {data[int(empty[0])][0]}, column {col!r}: missing value")
    n = len(data)
    for col in SERVE_OPTIONAL_TEXT:
        if col not in cols:
            cols[col] = np.array([""] * n, dtype=object)
    cols["line"] = np.array([ln for ln, _ in data], dtype=np.int64)
    return cols


def read_serves(path) -> dict[str, np.ndarray]:
    """Read a CourtVision serves CSV file (:func:`parse_serves`)."""
    return parse_serves(_read(path), name=str(path))


def parse_ball_trajectory(text: str | bytes, name: str = "trajectory") -> dict[str, np.ndarray]:
    """Parse a CourtVision ``*_ball_trajectory.csv`` into columns (``strike_index`` NaN when empty).

    ``position`` must be one of :data:`POSITIONS`.
    """
    text = _decode(text, name)
    header, data = _table(text, name, TRAJECTORY_TEXT + TRAJECTORY_NUMERIC + TRAJECTORY_OPTIONAL_NUMERIC)
    cols = _columns(header, data, name, TRAJECTORY_NUMERIC, TRAJECTORY_OPTIONAL_NUMERIC)
    bad = np.flatnonzero(~np.isin(cols["position"], POSITIONS))
    if bad.size:
        k = int(bad[0])
        raise InputError(
            f"{name}: line {data[k][0]}, column 'position': {str(cols['position'][k])[:20]!r} "
            f"is not one of {', '.join(POSITIONS)}"
        )
    cols["line"] = np.array([ln for ln, _ in data], dtype=np.int64)
    return cols


def read_ball_trajectory(path) -> dict[str, np.ndarray]:
    """Read a CourtVision ``*_ball_trajectory.csv`` file (:func:`parse_ball_trajectory`)."""
    return parse_ball_trajectory(_read(path), name=str(path))


def parse_pbp(text: str | bytes, name: str = "pbp") -> dict[str, np.ndarray]:
    """Parse a CourtVision ``*_pbp.csv`` (point by point) into columns.

    The columns of :data:`PBP_NUMERIC` that are present become float arrays: a value may carry a
    unit word (``"157 KPH"``, ``"0.61 Metre"``; the number is kept as written: km/h, metres) and
    ``NA``/empty is NaN.  ``point_ID``, ``serve_num`` and ``serve_speed_kph`` must be present.
    """
    text = _decode(text, name)
    header, data = _table(text, name, PBP_REQUIRED)
    optional = tuple(c for c in PBP_NUMERIC if c != "serve_num")
    cols = _columns(header, data, name, ("serve_num",), optional, units=True)
    cols["line"] = np.array([ln for ln, _ in data], dtype=np.int64)
    return cols


def read_pbp(path) -> dict[str, np.ndarray]:
    """Read a CourtVision ``*_pbp.csv`` file (:func:`parse_pbp`)."""
    return parse_pbp(_read(path), name=str(path))
