"""Lookups in the hits table: the settings whose landing is nearest a target.

Split from :mod:`tennislab.launcher.db` (which re-exports these names): the
R*Tree search when speed and spin are both given, the covering-index band
search otherwise (schema 4), the brute-force reference :func:`scan_nearest`,
and the checks of a target and of the table's ranges.
"""

from __future__ import annotations

import json
import math
import sqlite3
import time

import numpy as np

from tennislab.errors import InputError, check_finite
from tennislab.launcher.db import HIT_COLUMNS, HIT_SETTINGS, count_hits_fast

_COLS_SQL = (
    "SELECT id, height_m, speed_kmh, elevation_deg, heading_deg, spin_rpm, spin_axis_deg, land_x, "
    "land_y, net_clearance_m, flight_time_s, bounce_speed_ms, bounce_spin_rpm, apex_z_m FROM hits "
)
_BOX = "r.max_x >= ? AND r.min_x <= ? AND r.max_y >= ? AND r.min_y <= ?"
_SPEED_SPIN = " AND r.max_speed >= ? AND r.min_speed <= ? AND r.max_spin >= ? AND r.min_spin <= ?"

#: Two candidates whose misses differ by less than this are a tie [m]; the one
#: with the larger net clearance wins (a safer ball for the same landing).
TIE_M = 1e-3


def _half_window(value, step):
    """Match tolerance around a quantised setting: a third of the grid step (or 1e-6 absolute)."""
    return max(1e-6, step / 3.0) if step else 1e-6


def nearest_hit(
    conn: sqlite3.Connection,
    x: float,
    y: float,
    *,
    speed_kmh: float | None = None,
    spin_rpm: float | None = None,
    speed_tol: float = 1e-3,
    spin_tol: float = 1e-3,
    start_m: float = 0.05,
    max_m: float = 64.0,
    tie_m: float = TIE_M,
    where: dict | None = None,
):
    """The stored hit whose landing is nearest (x, y) among those matching speed and spin.

    Ties (misses within ``tie_m``) go to the larger net clearance, then to the
    smaller id.  Returns a dict (columns of ``hits`` plus ``miss_m``,
    ``n_candidates`` (index entries read) and ``n_read`` (rows of ``hits``
    read)) or None when no matching hit lands within ``max_m`` of the target.
    ``where`` {column: (lo, hi)} filters on other settings (e.g. ``height_m``).
    Speed and spin given: :func:`_box_candidates` on ``hits_rtree``; otherwise
    :func:`_band_candidates` on ``hits_cell``, ``hits_speed_cell`` or
    ``hits_spin_cell`` (a file of schema 3 has none: box queries on
    ``hits_xy`` or ``hits_rtree``).  Both collect a superset of the hits that
    can be nearest or tie; :func:`_pick` decides on their exact landings.
    """
    where = {c: lh for c, lh in (where or {}).items() if c in HIT_SETTINGS}
    col, val, tol = ("speed_kmh", speed_kmh, speed_tol) if spin_rpm is None else ("spin_rpm", spin_rpm, spin_tol)
    col = None if speed_kmh is None and spin_rpm is None else col
    if (speed_kmh is None or spin_rpm is None) and conn.execute(
        "SELECT 1 FROM sqlite_master WHERE type = 'index' AND name = ?", (_BAND_INDEX[col],)
    ).fetchone():
        found = _band_candidates(conn, x, y, max_m, tie_m, where, col, val, tol)
    else:
        found = _box_candidates(
            conn, x, y, speed_kmh, spin_rpm, speed_tol, spin_tol, start_m, max_m + tie_m, tie_m, where
        )
    return None if found is None else _pick(conn, x, y, *found, max_m, tie_m)


def _filters(where: dict, prefix: str = "") -> tuple[str, list]:
    return ("".join(f" AND {prefix}{c} BETWEEN ? AND ?" for c in where), [v for lh in where.values() for v in lh])


def _pick(conn, x, y, rows, n_entries, n_read, max_m, tie_m):
    """The answer among candidate rows (id, land_x, land_y, net_clearance_m); None if it misses by > max_m."""
    if not rows:
        return None
    a = np.array(rows, dtype=float)
    a = a[np.argsort(a[:, 0], kind="stable")]  # ascending id: equal clearances go to the smaller id
    miss = np.hypot(a[:, 1] - x, a[:, 2] - y)
    dmin = float(miss.min())
    if dmin > max_m:
        return None
    cand = np.flatnonzero(miss <= dmin + tie_m)
    best = int(cand[int(np.argmax(a[cand, 3]))])
    out = dict(zip(HIT_COLUMNS, conn.execute(_COLS_SQL + "WHERE id = ?", (int(a[best, 0]),)).fetchone()))
    out.update(miss_m=float(miss[best]), n_candidates=int(n_entries), n_read=int(n_read))
    return out


def _box_candidates(conn, x, y, speed_kmh, spin_rpm, speed_tol, spin_tol, start_m, lim, tie_m, where):
    """Box queries on an R*Tree (``hits_rtree``; ``hits_xy`` if neither speed nor spin is given).

    The half-width starts at ``start_m`` and doubles until a hit matches; once
    the nearest candidate is at most d_min away, a box of half-width d_min +
    ``tie_m`` holds every point that could be nearer or tie, so one more query
    at most makes the set complete.  The queries read the index alone (its
    float32 boxes bound each distance from below and above); only the entries
    that can be nearest or tie are read from ``hits``.  Returns (rows, index
    entries of the last box, rows read) or None.
    """
    extra, xargs = _filters(where, "h.")
    inf = 1e30
    s_lo, s_hi = (-inf, inf) if speed_kmh is None else (speed_kmh - speed_tol, speed_kmh + speed_tol)
    w_lo, w_hi = (-inf, inf) if spin_rpm is None else (spin_rpm - spin_tol, spin_rpm + spin_tol)
    free = speed_kmh is None and spin_rpm is None
    sql = (
        f"SELECT r.id, r.min_x, r.max_x, r.min_y, r.max_y FROM {'hits_xy' if free else 'hits_rtree'} r"
        + (" JOIN hits h ON h.id = r.id" if extra else "")
        + " WHERE "
        + _BOX
        + ("" if free else _SPEED_SPIN)
        + extra
    )
    fixed = ([] if free else [s_lo, s_hi, w_lo, w_hi]) + xargs
    d = min(start_m, lim)
    while True:
        rows = conn.execute(sql, [x - d, x + d, y - d, y + d] + fixed).fetchall()
        if rows:
            b = np.array(rows)
            lo = np.hypot(
                np.maximum(np.maximum(b[:, 1] - x, x - b[:, 2]), 0.0),
                np.maximum(np.maximum(b[:, 3] - y, y - b[:, 4]), 0.0),
            )
            hi = np.hypot(
                np.maximum(abs(b[:, 1] - x), abs(b[:, 2] - x)), np.maximum(abs(b[:, 3] - y), abs(b[:, 4] - y))
            )
            dmin_hi = float(hi.min())
            if dmin_hi + tie_m <= d or d >= lim:
                break
            d = min(dmin_hi + tie_m, lim)
            continue
        if d >= lim:
            return None
        d = min(2.0 * d, lim)
    ids = [int(i) for i in b[lo <= dmin_hi + tie_m, 0]]
    cand = []
    for i in range(0, len(ids), 900):  # SQLite before 3.32 binds at most 999 variables
        part = ids[i : i + 900]
        cand += conn.execute(
            f"SELECT id, land_x, land_y, net_clearance_m FROM hits WHERE id IN ({','.join('?' * len(part))})", part
        ).fetchall()
    return cand, len(rows), len(cand)


#: Band of a landing in the band indexes: 1 cm of landing y (the offset keeps it positive for y > -10 km).
_BAND = "CAST(land_y * 100.0 + 1000000.0 AS INTEGER)"
#: Covering index per lookup form: neither speed nor spin, speed only, spin only (schema 4).
_BAND_INDEX = {None: "hits_cell", "speed_kmh": "hits_speed_cell", "spin_rpm": "hits_spin_cell"}


def _band(y: float) -> int:
    return int(y * 100.0 + 1000000.0)  # the arithmetic of _BAND (CAST truncates toward zero)


def _band_dy(b: int, y: float) -> float:
    """Distance [m] from y to the landings of band b (0 inside; the band widened by 1 nm)."""
    y0, y1 = (b - 1000000) / 100.0 - 1e-9, (b - 999999) / 100.0 + 1e-9
    return 0.0 if y0 <= y <= y1 else min(abs(y0 - y), abs(y1 - y))


def _band_candidates(conn, x, y, max_m, tie_m, where, col, value, tol):
    """Hits within the nearest distance + ``tie_m`` of (x, y) from a band index: (rows, n, 1) or None.

    The index (``col``, speed or spin, if given; 1 cm band of landing y; landing
    x, y, net clearance) answers without reading ``hits``.  Index seeks find the
    stored values of ``col`` within ``tol`` of ``value``, then bound the nearest
    distance by d: in each band nearer than d, the landings next to x on either
    side (bands outwards from y).  Then one index range per band, clipped to the
    disc of radius d + ``tie_m``, reads every hit that can be nearest or tie
    (a square box would read 10^4 entries of a dense ray of landings at 10^7
    hits where the disc holds a few hundred).  n counts the index entries read.
    """
    idx, pre = _BAND_INDEX[col], [()]
    if col is not None:
        seek = f"SELECT {col} FROM hits INDEXED BY {idx} WHERE {col} {{}} ? ORDER BY {col} LIMIT 1"
        pre, row = [], conn.execute(seek.format(">="), (value - tol,)).fetchone()
        while row is not None and row[0] <= value + tol:
            pre.append(row)
            row = conn.execute(seek.format(">"), (row[0],)).fetchone()
    extra, xargs = _filters(where)
    head = (
        f"SELECT id, land_x, land_y, net_clearance_m FROM hits INDEXED BY {idx} WHERE "
        f"{'' if col is None else col + ' = ? AND '}{_BAND} = ? AND land_x BETWEEN ? AND ?{extra}"
    )
    probe = (
        f"SELECT * FROM ({head} ORDER BY land_x LIMIT 1) UNION ALL SELECT * FROM ({head} ORDER BY land_x DESC LIMIT 1)"
    )
    best, lim, n, k, band = math.inf, max_m + tie_m, 0, 0, _band(y)
    while pre:
        todo = [b for b in {band - k, band + k} if _band_dy(b, y) < min(best, lim)]
        if not todo:
            break
        for b, p in ((b, p) for b in todo for p in pre):
            for r in conn.execute(probe, [*p, b, x, x + lim, *xargs, *p, b, x - lim, x, *xargs]).fetchall():
                best, n = min(best, math.hypot(r[1] - x, r[2] - y)), n + 1
        k += 1
    if best > lim:
        return None
    d = min(best, max_m) * (1.0 + 1e-12) + tie_m + 1e-9
    parts = []
    for b in range(_band(y - d) - 1, _band(y + d) + 2):
        if _band_dy(b, y) <= d:
            h = math.sqrt(d * d - _band_dy(b, y) ** 2) * (1.0 + 1e-12) + 1e-9
            parts += [(*p, b, x - h, x + h, *xargs) for p in pre]
    rows = []
    for i in range(0, len(parts), 100):
        chunk = parts[i : i + 100]
        rows += conn.execute(" UNION ALL ".join([head] * len(chunk)), [v for p in chunk for v in p]).fetchall()
    return rows, n + len(rows), 1


_STATS: dict = {}
#: Expected rows in a lookup's first box; its half-width follows from the table's density.
FIRST_BOX_ROWS = 8.0


def table_stats(conn: sqlite3.Connection) -> dict:
    """Hits stored and speed/spin values per grid (from ``fill_chunks``/``fills``; cached per connection)."""
    key = id(conn)
    if key in _STATS and _STATS[key][0] is conn:
        return _STATS[key][1]
    n = conn.execute("SELECT coalesce(sum(n_hits), 0) FROM fill_chunks").fetchone()[0]
    ns = nw = 1
    for (g,) in conn.execute("SELECT grid_json FROM fills"):
        gj = json.loads(g)
        ns, nw = max(ns, len(gj.get("speed_kmh", ()))), max(nw, len(gj.get("spin_rpm", ())))
    stats = {"n": int(n), "n_speed": ns, "n_spin": nw}
    if len(_STATS) > 16:
        _STATS.clear()
    _STATS[key] = (conn, stats)
    return stats


def first_box(stats: dict, speed_given: bool, spin_given: bool, area_m2: float = 170.0) -> float:
    """Half-width [m] of a box expected to hold :data:`FIRST_BOX_ROWS` matching hits.

    Hits spread over about ``area_m2`` (a doubles half court plus the 1 m margin);
    a given speed (spin) keeps about 1/``n_speed`` (1/``n_spin``) of them.
    """
    n = stats["n"] / (stats["n_speed"] if speed_given else 1) / (stats["n_spin"] if spin_given else 1)
    if n <= 0:
        return 0.05
    return float(np.clip(0.5 * math.sqrt(FIRST_BOX_ROWS * area_m2 / n), 0.002, 1.0))


def has_hits(
    conn: sqlite3.Connection, speed_kmh=None, spin_rpm=None, speed_tol: float = 1e-3, spin_tol: float = 1e-3
) -> bool:
    """True if any stored hit has this speed and spin (an R*Tree query, not a scan)."""
    inf = 1e30
    s = (-inf, inf) if speed_kmh is None else (speed_kmh - speed_tol, speed_kmh + speed_tol)
    w = (-inf, inf) if spin_rpm is None else (spin_rpm - spin_tol, spin_rpm + spin_tol)
    return (
        conn.execute(
            "SELECT 1 FROM hits_rtree WHERE max_speed >= ? AND min_speed <= ? AND max_spin >= ? "
            "AND min_spin <= ? LIMIT 1",
            (s[0], s[1], w[0], w[1]),
        ).fetchone()
        is not None
    )


def scan_nearest(
    conn: sqlite3.Connection,
    x: float,
    y: float,
    *,
    speed_kmh=None,
    spin_rpm=None,
    speed_tol: float = 1e-3,
    spin_tol: float = 1e-3,
    tie_m: float = TIE_M,
):
    """The same answer as :func:`nearest_hit` by a full scan of ``hits`` (baseline for benchmarks/tests).

    Reads the nearest 64 rows; when all of them tie, scans again for 8 times as many.
    """
    where, args = [], []
    if speed_kmh is not None:
        where.append("speed_kmh BETWEEN ? AND ?")
        args += [speed_kmh - speed_tol, speed_kmh + speed_tol]
    if spin_rpm is not None:
        where.append("spin_rpm BETWEEN ? AND ?")
        args += [spin_rpm - spin_tol, spin_rpm + spin_tol]
    sql = (
        f"SELECT {', '.join(HIT_COLUMNS)}, (land_x - ?) * (land_x - ?) + (land_y - ?) * (land_y - ?) AS d2 "
        f"FROM hits NOT INDEXED {'WHERE ' + ' AND '.join(where) if where else ''} ORDER BY d2 LIMIT ?"
    )
    k = 64
    while True:
        rows = conn.execute(sql, [x, x, y, y] + args + [k]).fetchall()
        if not rows:
            return None
        miss = np.hypot(np.array([r[7] for r in rows]) - x, np.array([r[8] for r in rows]) - y)
        if len(rows) < k or miss[-1] > miss.min() + tie_m + 1e-9:
            break
        k *= 8
    cand = np.flatnonzero(miss <= miss.min() + tie_m)
    best = min(cand, key=lambda i: (-rows[i][9], rows[i][0]))  # larger clearance, then smaller id
    out = dict(zip(HIT_COLUMNS, rows[best][:-1]))
    out["miss_m"] = float(miss[best])
    return out


def table_ranges(conn: sqlite3.Connection) -> dict:
    """Speed [km/h] and spin [rpm] ranges of the grids filled into the file (from ``fills``, no scan)."""
    spec = json.loads(conn.execute("SELECT spec_json FROM machine WHERE id = 1").fetchone()[0])
    out = {}
    for field, attr in (("speed_kmh", "speed"), ("spin_rpm", "spin")):
        lo, hi = math.inf, -math.inf
        for (g,) in conn.execute("SELECT grid_json FROM fills"):
            idx = json.loads(g).get(field) or []
            if idx:
                r = spec[attr]
                lo = min(lo, r["lo"] + min(idx) * r["step"])
                hi = max(hi, r["lo"] + max(idx) * r["step"])
        out[field] = (lo, hi)
    return out


def target_area(machine_x: float) -> str:
    """Court area a machine at ``machine_x`` aims at: the doubles area of the other half."""
    return "doubles" if machine_x < 0 else "near-doubles"


def check_target(x: float, y: float, machine_x: float = -1.0, court=None) -> tuple[float, float]:
    """Validate a target in the doubles area (lines included) of the half opposite the machine."""
    from tennislab.core.court import ITF_COURT

    court = court or ITF_COURT
    x = check_finite("target x", x)
    y = check_finite("target y", y)
    area = target_area(machine_x)
    if not court.contains(area, x, y):
        b = court.area_bounds(area)
        raise InputError(
            f"--target: ({x:g}, {y:g}) m is off the court; a machine at x = {machine_x:g} m "
            f"aims at the {area} area, x in [{b[0]:g}, {b[1]:g}] m, y in [{b[2]:g}, {b[3]:g}] m"
        )
    return x, y


def lookup(
    conn: sqlite3.Connection,
    x: float,
    y: float,
    *,
    speed_kmh=None,
    spin_rpm=None,
    steps: dict | None = None,
    max_miss_m: float = 1.0,
    path: str = "",
    where: dict | None = None,
) -> dict:
    """Nearest stored hit to target (x, y) [m] matching speed [km/h] and spin [rpm].

    ``steps`` (grid step per setting, from the machine spec) sets how close a
    requested speed/spin must be to a stored one (a third of a step).  The first
    R*Tree box (:func:`nearest_hit`) is sized from the table's density (:func:`first_box`;
    the statistics are read once per connection, before the timed ``lookup_ms``).  Raises
    :class:`InputError` when nothing matches or the nearest landing misses by
    more than ``max_miss_m``.
    """
    steps = steps or {}
    d0 = first_box(table_stats(conn), speed_kmh is not None, spin_rpm is not None)
    t0 = time.perf_counter()
    st = _half_window(speed_kmh, steps.get("speed_kmh"))
    wt = _half_window(spin_rpm, steps.get("spin_rpm"))
    hit = nearest_hit(
        conn,
        x,
        y,
        speed_kmh=speed_kmh,
        spin_rpm=spin_rpm,
        speed_tol=st,
        spin_tol=wt,
        max_m=max_miss_m,
        where=where,
        start_m=d0,
    )
    ms = (time.perf_counter() - t0) * 1e3
    if hit is None:
        if count_hits_fast(conn) == 0:
            raise InputError(f"--db {path}: the table holds no hits; fill it with `launcher table`")
        want = ", ".join(
            [f"{k} {v:g}" for k, v in (("speed", speed_kmh), ("spin", spin_rpm)) if v is not None]
            + [f"{c} {(lh[0] + lh[1]) / 2:g}" for c, lh in (where or {}).items()]
        )
        if not has_hits(conn, speed_kmh, spin_rpm, st, wt):
            rng = table_ranges(conn)
            raise InputError(
                f"--target: no hit with {want} in the table (filled: speed "
                f"{rng['speed_kmh'][0]:g}-{rng['speed_kmh'][1]:g} km/h, spin "
                f"{rng['spin_rpm'][0]:g}-{rng['spin_rpm'][1]:g} rpm)"
            )
        raise InputError(
            f"--target: no hit in range: nothing{' with ' + want if want else ''} lands within "
            f"{max_miss_m:g} m of ({x:g}, {y:g}) m (see --max-miss-m)"
        )
    hit["lookup_ms"] = ms
    return hit
