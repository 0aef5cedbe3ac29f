"""Lookups in the hits table: the stored hit nearest a target among those meeting a query.

A :class:`HitQuery` says which hits may answer: speed and spin windows (a tolerance around the
asked values), launch height and spin axis windows, the trajectory branch (low/high), the
highest apex, a net-clearance band and the longest flight.  :func:`nearest_hit` finds the hit
whose landing is nearest the target among them, by the R*Tree ``hits_rtree`` when both a speed
and a spin are given, else by the band indexes (schema 4+: ``hits_cell``, ``hits_speed_cell``,
``hits_spin_cell``), which carry every column the query filters on (schema 5), so a lookup reads
index entries only; :func:`scan_nearest` is the brute-force reference.

Tie rule (every form, and the scan): landings within :data:`TIE_M` (1 mm) of the nearest are a
tie; among them the smaller change from the asked speed wins, then from the asked spin, then the
larger net clearance (a safer ball for the same landing), then the smaller hit id.

Fallback (:func:`fallback`): a table holds the settings it was filled with, so its nearest hit may
land decimetres from a target that the machine's own steps reach to a millimetre.  When the nearest
accepted hit lands farther than :data:`FALLBACK_M` (or none does), the lookup asks the machine's aim
(:func:`tennislab.launcher.aim.aim`, started from the reach map of :mod:`tennislab.launcher.reach`,
the inverse map of the machine's whole reach) with the file's physics, and answers it when it lands
nearer: ``refined`` (the aim at the stored hit's height) or ``inverse-map`` (no hit: the asked height,
or every height).
"""

from __future__ import annotations

import dataclasses
import math
import sqlite3
from dataclasses import dataclass, field, replace

import numpy as np

from tennislab.core.court import ITF_COURT
from tennislab.errors import InputError, check_finite
from tennislab.launcher.db import HIT_COLUMNS, HIT_SETTINGS, DatabaseFileError, has_column, stored_json
from tennislab.launcher.preferences import BRANCH_HIGH, BRANCH_LOW, Preferences

#: Two candidates whose misses differ by less than this are a tie [m] (module docstring).
TIE_M = 1e-3
_INF = 1e30


@dataclass(frozen=True)
class HitQuery:
    """Which stored hits may answer a lookup (edge units; None = any).

    ``speed_kmh`` and ``spin_rpm`` are the asked values (for the tie rule); ``speed_window`` and
    ``spin_window`` (lo, hi) the stored values accepted; ``where`` {column: (lo, hi)} on other
    settings (``height_m``, ``spin_axis_deg``); ``preferences`` the trajectory bounds;
    ``spin_vector`` (rate [rpm], axis [deg], tolerance [rpm], axis tolerance [deg]) keeps the hits
    whose spin vector lies within the tolerance of the asked one, or (axis tolerance > 0) whose rate
    lies within it about an axis turned by at most the axis tolerance (``aim``'s rule).
    """

    speed_kmh: float | None = None
    spin_rpm: float | None = None
    speed_window: tuple[float, float] | None = None
    spin_window: tuple[float, float] | None = None
    where: dict = field(default_factory=dict)
    preferences: Preferences | None = None
    spin_vector: tuple[float, float, float, float] | None = None

    @classmethod
    def exact(cls, speed_kmh=None, spin_rpm=None, tol: float = 1e-3, where=None, preferences=None) -> HitQuery:
        """A query for these speed and spin (within ``tol``), as stored."""
        return cls(
            speed_kmh,
            spin_rpm,
            None if speed_kmh is None else (speed_kmh - tol, speed_kmh + tol),
            None if spin_rpm is None else (spin_rpm - tol, spin_rpm + tol),
            dict(where or {}),
            preferences,
        )

    def conditions(self, skip: str | None = None, prefix: str = "", branch: bool = True) -> tuple[str, list]:
        """SQL ``AND ...`` conditions on hit columns (all but the window of ``skip``; the trajectory branch
        only with ``branch``) and their arguments."""
        parts: list[str] = []
        args: list = []
        for col, win in (("speed_kmh", self.speed_window), ("spin_rpm", self.spin_window)):
            if win is not None and col != skip:
                parts.append(f"{prefix}{col} BETWEEN ? AND ?")
                args += list(win)
        for col, (lo, hi) in self.where.items():
            if col not in HIT_SETTINGS:
                raise InputError(f"{col}: not a setting of a hit; allowed: {', '.join(HIT_SETTINGS)}")
            parts.append(f"{prefix}{col} BETWEEN ? AND ?")
            args += [lo, hi]
        p = self.preferences
        if p is not None:
            if p.trajectory != "any" and branch:
                parts.append(f"{prefix}branch = ?")
                args.append(BRANCH_LOW if p.trajectory == "low" else BRANCH_HIGH)
            if p.max_apex_m is not None:
                parts.append(f"{prefix}apex_z_m <= ?")
                args.append(p.max_apex_m)
            if p.max_flight_time_s is not None:
                parts.append(f"{prefix}flight_time_s <= ?")
                args.append(p.max_flight_time_s)
            if p.net_clearance_m is not None:
                parts.append(f"{prefix}net_clearance_m BETWEEN ? AND ?")
                args += list(p.net_clearance_m)
        if self.spin_vector is not None:  # last: the dearest test, on the rows the others let through
            w0, g0, tol, gtol = self.spin_vector
            vec = (
                f"{prefix}spin_rpm * {prefix}spin_rpm + ? - 2.0 * ? * {prefix}spin_rpm * "
                f"cos(radians({prefix}spin_axis_deg - ?)) <= ?"
            )
            dg = f"min(abs({prefix}spin_axis_deg - ?), 360.0 - abs({prefix}spin_axis_deg - ?))"
            if gtol > 0:
                parts.append(f"({vec} OR (abs({prefix}spin_rpm - ?) <= ? AND {dg} <= ?))")
                args += [w0 * w0, w0, g0, tol * tol + 1e-6, w0, tol + 1e-9, g0, g0, gtol + 1e-9]
            else:
                if w0 > tol:  # a cheap necessary test first: the axis turns by at most asin(tol / w0)
                    delta = math.degrees(math.asin(tol / w0)) + 1e-6
                    if -180.0 <= g0 - delta and g0 + delta <= 180.0:
                        parts.append(f"{prefix}spin_axis_deg BETWEEN ? AND ?")
                        args += [g0 - delta, g0 + delta]
                parts.append(vec)
                args += [w0 * w0, w0, g0, tol * tol + 1e-6]
        return "".join(" AND " + c for c in parts), args

    def needs_branch(self) -> bool:
        return self.preferences is not None and self.preferences.trajectory != "any"

    def mask(self, rows: dict) -> np.ndarray:
        """The same conditions on arrays of hit columns (numpy; for the brute-force reference)."""
        n = len(rows["id"])
        m = np.ones(n, bool)
        for col, win in (("speed_kmh", self.speed_window), ("spin_rpm", self.spin_window)):
            if win is not None:
                m &= (rows[col] >= win[0]) & (rows[col] <= win[1])
        for col, (lo, hi) in self.where.items():
            m &= (rows[col] >= lo) & (rows[col] <= hi)
        if self.spin_vector is not None:
            w0, g0, tol, gtol = self.spin_vector
            w, g = np.asarray(rows["spin_rpm"], float), np.radians(np.asarray(rows["spin_axis_deg"], float) - g0)
            ok = w * w + w0 * w0 - 2.0 * w0 * w * np.cos(g) <= tol * tol + 1e-6
            if gtol > 0:
                dg = np.abs(np.asarray(rows["spin_axis_deg"], float) - g0)
                ok |= (np.abs(w - w0) <= tol + 1e-9) & (np.minimum(dg, 360.0 - dg) <= gtol + 1e-9)
            m &= ok
        p = self.preferences
        if p is not None:
            if p.trajectory != "any":
                m &= rows["branch"] == (BRANCH_LOW if p.trajectory == "low" else BRANCH_HIGH)
            m &= p.accepts(rows["apex_z_m"], rows["net_clearance_m"], rows["flight_time_s"])
        return m


def _columns_sql(conn) -> str:
    cols = HIT_COLUMNS if has_column(conn, "hits", "branch") else HIT_COLUMNS[:-1]
    return "SELECT " + ", ".join(cols) + " FROM hits "


def _check_branch(conn, q: HitQuery) -> None:
    if q.needs_branch() and not has_column(conn, "hits", "branch"):
        raise DatabaseFileError(
            "this file (schema older than 5) has no trajectory branches; rerun `launcher table` on it to migrate "
            "it, or ask for trajectory any"
        )


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
    query: HitQuery | None = None,
):
    """The stored hit whose landing is nearest (x, y) among those the query accepts (module docstring).

    ``query`` (a :class:`HitQuery`) or, for short, ``speed_kmh``/``spin_rpm`` within
    ``speed_tol``/``spin_tol`` and ``where`` {column: (lo, hi)}.  Returns a dict (columns of
    ``hits`` plus ``miss_m``, ``n_candidates`` (index entries read) and ``n_read`` (rows of ``hits``
    read)) or None when no such hit lands within ``max_m`` of the target.  An index-only R*Tree
    check answers None at once when no hit of the speed and spin windows lands near.  One speed and
    one spin (windows narrower than 1 km/h and 1 rpm): :func:`_box_candidates` on ``hits_rtree``;
    otherwise (tolerance windows over several stored values, one or neither given)
    :func:`_band_candidates` on a band index keyed by the speed if given, else the spin, which
    carries every other condition (a file of schema 3 has none: box queries on ``hits_xy`` or
    ``hits_rtree``).  Both collect a superset of the hits that can be nearest or tie; :func:`_pick`
    decides on their exact landings.
    """
    q = query or HitQuery(
        speed_kmh,
        spin_rpm,
        None if speed_kmh is None else (speed_kmh - speed_tol, speed_kmh + speed_tol),
        None if spin_rpm is None else (spin_rpm - spin_tol, spin_rpm + spin_tol),
        {c: lh for c, lh in (where or {}).items() if c in HIT_SETTINGS},
    )
    _check_branch(conn, q)
    sw, ww = q.speed_window, q.spin_window
    col = None if sw is None and ww is None else ("spin_rpm" if sw is None else "speed_kmh")
    # the 4-D R*Tree for one speed and one spin; windows over several stored values (tolerances) read
    # the speed band index, which carries the spin and every other condition (no row reads)
    exact = sw is not None and ww is not None and sw[1] - sw[0] < 1.0 and ww[1] - ww[0] < 1.0
    if not any_near(conn, x, y, q, max_m + tie_m):  # nothing of these speeds and spins lands near (index only)
        return None
    if (
        not exact
        and conn.execute(
            "SELECT 1 FROM sqlite_master WHERE type = 'index' AND name = ?", (_BAND_INDEX[col],)
        ).fetchone()
    ):
        win = sw if col == "speed_kmh" else ww
        bound = math.inf
        if sw is not None and ww is not None and q.speed_kmh is not None and q.spin_rpm is not None:
            # tolerance windows: the nearest accepted hit of the asked speed and spin themselves (R*Tree)
            # bounds the distance, so the band walk reads only the bands nearer than it
            seed = replace(
                q, speed_window=(q.speed_kmh - 0.3, q.speed_kmh + 0.3), spin_window=(q.spin_rpm - 0.3, q.spin_rpm + 0.3)
            )
            got = _box_candidates(conn, x, y, seed, min(start_m, 0.05), max_m + tie_m, tie_m)
            if got is not None and got[0]:
                bound = min(math.hypot(r[1] - x, r[2] - y) for r in got[0]) * (1 + 1e-12) + 1e-9
        found = _band_candidates(conn, x, y, max_m, tie_m, q, col, win, bound)
    else:
        found = _box_candidates(conn, x, y, q, start_m, max_m + tie_m, tie_m)
    if found is None:
        return None
    rows, n_entries, n_read = found
    return _pick(conn, x, y, q, rows, n_entries, n_read, max_m, tie_m)


def _tie_order(q: HitQuery, speed, spin, clearance, ids) -> np.ndarray:
    """Order of tied candidates by the tie rule (module docstring)."""
    ds = np.abs(speed - q.speed_kmh) if q.speed_kmh is not None else np.zeros(len(ids))
    dw = np.abs(spin - q.spin_rpm) if q.spin_rpm is not None else np.zeros(len(ids))
    return np.lexsort((ids, -clearance, np.round(dw, 9), np.round(ds, 9)))


def _pick(conn, x, y, q, rows, n_entries, n_read, max_m, tie_m):
    """The answer among candidate rows (id, land_x, land_y, net_clearance_m, speed, spin); None past max_m."""
    if not rows:
        return None
    a = np.array(rows, dtype=float)
    miss = np.hypot(a[:, 1] - x, a[:, 2] - y)
    dmin = float(miss.min())
    if dmin > max_m:
        return None
    cand = np.flatnonzero(miss <= dmin + tie_m)
    best = int(cand[_tie_order(q, a[cand, 4], a[cand, 5], a[cand, 3], a[cand, 0])[0]])
    row = conn.execute(_columns_sql(conn) + "WHERE id = ?", (int(a[best, 0]),)).fetchone()
    out = dict(zip(HIT_COLUMNS, row))
    out.update(miss_m=float(miss[best]), n_candidates=int(n_entries), n_read=int(n_read))
    return out


_BOX = "r.max_x >= ? AND r.min_x <= ? AND r.max_y >= ? AND r.min_y <= ?"
_SPEED_SPIN = " AND r.max_speed >= ? AND r.min_speed <= ? AND r.max_spin >= ? AND r.min_spin <= ?"


def _box_candidates(conn, x, y, q: HitQuery, start_m, lim, tie_m):
    """Box queries on an R*Tree (``hits_rtree``; ``hits_xy`` if neither speed nor spin is given).

    The half-width starts at ``start_m`` and doubles until the box holds an accepted hit; once the
    nearest accepted candidate is d_min away, a box of half-width d_min + ``tie_m`` holds every
    point that could be nearer or tie, so one more query at most makes the set complete.  The box
    queries read the index alone (its float32 boxes bound each distance from below and above);
    when the query filters on other columns, the entries' rows are read nearest first, in batches,
    only until the nearest accepted hit is known (:func:`_accepted_nearest`).  Returns (rows, index
    entries of the last box, rows read) or None.
    """
    extra, xargs = _strip_windows(q)
    sw = q.speed_window or (-_INF, _INF)
    ww = q.spin_window or (-_INF, _INF)
    free = q.speed_window is None and q.spin_window is None
    if free and not conn.execute("SELECT 1 FROM sqlite_master WHERE name = 'hits_xy'").fetchone():
        free = False  # a file with neither band indexes nor hits_xy: the 4-D tree over every speed and spin
    sql = (
        f"SELECT r.id, r.min_x, r.max_x, r.min_y, r.max_y FROM {'hits_xy' if free else 'hits_rtree'} r WHERE "
        + _BOX
        + ("" if free else _SPEED_SPIN)
    )
    fixed = [] if free else [sw[0], sw[1], ww[0], ww[1]]
    d = min(start_m, lim)
    n_read = 0
    seen: dict = {}  # id -> accepted row, or None when rejected: a growing box reads each row once
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
            if not extra:
                dmin = float(hi.min())
                if dmin + tie_m <= d or d >= lim:
                    ids = [int(i) for i in b[lo <= dmin + tie_m, 0]]
                    cand = _rows_by_id(conn, ids, "", [])
                    return cand, len(rows), len(cand)
                d = min(dmin + tie_m, lim)
                continue
            cand, dmin, k = _accepted_nearest(conn, x, y, b[:, 0], lo, extra, xargs, tie_m, seen)
            n_read += k
            if cand:
                if dmin + tie_m <= d or d >= lim:
                    return cand, len(rows), n_read
                d = min(dmin + tie_m, lim)
                continue
        if d >= lim:
            return None
        d = min(2.0 * d, lim)


def _rows_by_id(conn, ids: list, extra: str, xargs: list) -> list:
    out = []
    for i in range(0, len(ids), 500):  # SQLite before 3.32 binds at most 999 variables
        part = ids[i : i + 500]
        out += conn.execute(
            "SELECT id, land_x, land_y, net_clearance_m, speed_kmh, spin_rpm FROM hits AS h NOT INDEXED "
            f"WHERE id IN ({','.join('?' * len(part))}){extra}",
            part + xargs,
        ).fetchall()
    return out


def _accepted_nearest(conn, x, y, ids, lo, extra, xargs, tie_m, seen: dict, batch: int = 64):
    """The accepted rows among index entries, read nearest first (by the boxes' lower bounds) in batches
    until no unread entry can be nearer than the nearest accepted one + ``tie_m``; ``seen`` remembers
    the rows read (accepted row or None) across calls.

    Returns (accepted rows within the nearest + ``tie_m``, the nearest distance, rows read)."""
    order = np.argsort(lo, kind="stable")
    found = [r for r in seen.values() if r is not None]
    best = min((math.hypot(r[1] - x, r[2] - y) for r in found), default=math.inf)
    n = 0
    for i in range(0, order.size, batch):
        part = order[i : i + batch]
        if lo[part[0]] > best + tie_m:
            break
        new = [int(v) for v in ids[part] if int(v) not in seen]
        if not new:
            continue
        got = _rows_by_id(conn, new, extra, xargs)
        n += len(new)
        seen.update(dict.fromkeys(new))
        for r in got:
            seen[int(r[0])] = r
            best = min(best, math.hypot(r[1] - x, r[2] - y))
        found += got
    near = [r for r in found if math.hypot(r[1] - x, r[2] - y) <= best + tie_m]
    return near, best, n


def _strip_windows(q: HitQuery) -> tuple[str, list]:
    """The query's conditions other than the speed and spin windows (the R*Tree holds those)."""
    return HitQuery(None, None, None, None, q.where, q.preferences, q.spin_vector).conditions(prefix="h.")


#: Bound arguments per batched probe statement (SQLite before 3.32 binds at most 999).
_PROBE_ARGS = 800
#: Band of a landing in the band indexes: 1 cm of landing y (the offset keeps it positive for y > -10 km).
_BAND = "CAST(land_y * 100.0 + 1000000.0 AS INTEGER)"
#: Covering index per lookup form: neither speed nor spin, speed only, spin only (schema 4+).
_BAND_INDEX = {None: "hits_cell", "speed_kmh": "hits_speed_cell", "spin_rpm": "hits_spin_cell"}


def _band(y: float) -> int:
    return int(y * 100.0 + 1000000.0)  # the arithmetic of _BAND (CAST truncates toward zero)


def _band_dy(b: int, y: float) -> float:
    """Distance [m] from y to the landings of band b (0 inside; the band widened by 1 nm)."""
    y0, y1 = (b - 1000000) / 100.0 - 1e-9, (b - 999999) / 100.0 + 1e-9
    return 0.0 if y0 <= y <= y1 else min(abs(y0 - y), abs(y1 - y))


def _band_candidates(conn, x, y, max_m, tie_m, q: HitQuery, col, window, bound: float = math.inf):
    """Hits within the nearest distance + ``tie_m`` of (x, y) from a band index: (rows, n, 1) or None.

    The index (``col``, speed or spin, if given; 1 cm band of landing y; landing x, y, net
    clearance and the query's other columns) answers without reading ``hits``.  Index seeks find
    the stored values of ``col`` within ``window``, then bound the nearest distance by d: in each
    band nearer than d, the accepted landings next to x on either side (bands outwards from y).
    Then one index range per band, clipped to the disc of radius d + ``tie_m``, reads every hit
    that can be nearest or tie (a square box would read 10^4 entries of a dense ray of landings
    at 10^7 hits where the disc holds a few hundred).  n counts the index entries read.
    """
    idx = _BAND_INDEX[col]
    pre: list[tuple] = [()]
    if col is not None:
        seek = f"SELECT {col} FROM hits INDEXED BY {idx} WHERE {col} {{}} ? ORDER BY {col} LIMIT 1"
        pre, row = [], conn.execute(seek.format(">="), (window[0],)).fetchone()
        while row is not None and row[0] <= window[1] and len(pre) < 100_000:
            pre.append(row)
            row = conn.execute(seek.format(">"), (row[0],)).fetchone()
    keyed = has_column(conn, "hits", "branch")  # schema 5: the band indexes are keyed by the branch too
    if keyed:
        p = q.preferences
        branches = (
            (0, 1) if p is None or p.trajectory == "any" else ((BRANCH_LOW if p.trajectory == "low" else BRANCH_HIGH),)
        )
        pre = [(*v, b) for v in pre for b in branches]
    extra, xargs = q.conditions(skip=col, branch=not keyed)
    key = ("" if col is None else col + " = ? AND ") + ("branch = ? AND " if keyed else "")
    head = (
        f"SELECT id, land_x, land_y, net_clearance_m, speed_kmh, spin_rpm FROM hits INDEXED BY {idx} WHERE "
        f"{key}{_BAND} = ? AND land_x BETWEEN ? AND ?{extra}"
    )
    probe = (
        f"SELECT * FROM ({head} ORDER BY land_x LIMIT 1) UNION ALL SELECT * FROM ({head} ORDER BY land_x DESC LIMIT 1)"
    )
    best, lim, n, k, band = bound, max_m + tie_m, 0, 0, _band(y)
    while pre:
        todo = [b for b in {band - k, band + k} if _band_dy(b, y) < min(best, lim)]
        if not todo:
            break
        probes = []
        for b in todo:  # each probe clipped to the disc that can still hold a nearer landing
            r = min(best, lim)
            h = math.sqrt(max(r * r - _band_dy(b, y) ** 2, 0.0)) * (1.0 + 1e-12) + 1e-9
            probes += [(*p, b, x, x + h, *xargs, *p, b, x - h, x, *xargs) for p in pre]
        per = max(1, _PROBE_ARGS // len(probes[0]))
        for i in range(0, len(probes), per):  # the probes of these bands, a few statements at most
            part = probes[i : i + per]
            sql = " UNION ALL ".join([probe] * len(part))
            for r in conn.execute(sql, [v for pr in part for v in pr]).fetchall():
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
    query: HitQuery | None = None,
):
    """The same answer as :func:`nearest_hit` by a full scan of ``hits`` (baseline for benchmarks/tests).

    Reads the nearest 64 accepted rows; when all of them tie, scans again for 8 times as many.
    """
    q = query
    if q is None:
        q = HitQuery(
            speed_kmh,
            spin_rpm,
            None if speed_kmh is None else (speed_kmh - speed_tol, speed_kmh + speed_tol),
            None if spin_rpm is None else (spin_rpm - spin_tol, spin_rpm + spin_tol),
        )
    _check_branch(conn, q)
    extra, args = q.conditions()
    cols = _columns_sql(conn)[len("SELECT ") : -len(" FROM hits ")]
    sql = (
        f"SELECT {cols}, (land_x - ?) * (land_x - ?) + (land_y - ?) * (land_y - ?) AS d2 "
        f"FROM hits NOT INDEXED WHERE 1{extra} ORDER BY d2 LIMIT ?"
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
    a = np.array([rows[i][:14] for i in cand], dtype=float)
    best = int(cand[_tie_order(q, a[:, 2], a[:, 5], a[:, 9], a[:, 0])[0]])
    out = dict(zip(HIT_COLUMNS, rows[best][:-1]))
    out["miss_m"] = float(miss[best])
    return out


_STATS: dict = {}
#: Expected rows in a lookup's first box; its half-width follows from the table's density.
FIRST_BOX_ROWS = 8.0


def table_stats(conn: sqlite3.Connection) -> dict:
    """Hits stored and the speed/spin values filled (from ``fill_chunks``/``fills``; cached per connection)."""
    key = id(conn)
    if key in _STATS and _STATS[key][0] is conn:
        return _STATS[key][1]
    n = conn.execute("SELECT coalesce(sum(n_hits), 0) FROM fill_chunks").fetchone()[0]
    vals = grid_values(conn) if conn.execute("SELECT 1 FROM machine").fetchone() else {}
    speeds, spins = vals.get("speed_kmh") or [], vals.get("spin_rpm") or []
    stats = {
        "n": int(n),
        "n_speed": max(1, len(speeds)),
        "n_spin": max(1, len(spins)),
        "speeds": np.asarray(speeds, float),
        "spins": np.asarray(spins, float),
    }
    if len(_STATS) > 16:
        _STATS.clear()
    _STATS[key] = (conn, stats)
    return stats


def first_box(stats: dict, speed_window=None, spin_window=None, area_m2: float = 170.0) -> float:
    """Half-width [m] of a box expected to hold :data:`FIRST_BOX_ROWS` matching hits.

    Hits spread over about ``area_m2`` (a doubles half court plus the 1 m margin); a speed
    (spin) window keeps the share of the filled speed (spin) values inside it (``True`` for a
    window of one value).
    """

    def share(window, values, count):
        if window is None or window is False:
            return 1.0
        if window is True or not len(values):
            return 1.0 / count
        inside = np.count_nonzero((values >= window[0]) & (values <= window[1]))
        return max(inside, 1) / count

    n = stats["n"] * share(speed_window, stats.get("speeds", ()), stats["n_speed"])
    n *= share(spin_window, stats.get("spins", ()), stats["n_spin"])
    if n <= 0:
        return 0.05
    return float(np.clip(0.5 * math.sqrt(FIRST_BOX_ROWS * area_m2 / n), 0.002, 1.0))


def has_hits(conn: sqlite3.Connection, q: HitQuery) -> bool:
    """True if any stored hit has the query's speed and spin (an R*Tree query, not a scan)."""
    s = q.speed_window or (-_INF, _INF)
    w = q.spin_window or (-_INF, _INF)
    return (
        conn.execute(
            "SELECT 1 FROM hits_rtree WHERE max_speed >= ? AND min_speed <= ? AND max_spin >= ? "
            "AND min_spin <= ? LIMIT 1",
            (s[0], s[1], w[0], w[1]),
        ).fetchone()
        is not None
    )


def any_near(conn: sqlite3.Connection, x: float, y: float, q: HitQuery, d: float) -> bool:
    """True if any hit of the query's speed and spin windows lands in the box of half-width ``d`` (index only)."""
    s = q.speed_window or (-_INF, _INF)
    w = q.spin_window or (-_INF, _INF)
    sql = "SELECT 1 FROM hits_rtree r WHERE " + _BOX + _SPEED_SPIN + " LIMIT 1"
    return conn.execute(sql, (x - d, x + d, y - d, y + d, s[0], s[1], w[0], w[1])).fetchone() is not None


def grid_values(conn: sqlite3.Connection, spec_json: dict | None = None) -> dict:
    """Per setting, the sorted values filled into the file (from ``fills``' grids, no scan of ``hits``)."""
    spec = spec_json or stored_json(
        conn.execute("SELECT spec_json FROM machine WHERE id = 1").fetchone()[0], "machine.spec_json"
    )
    attrs = {
        "height_m": "height",
        "speed_kmh": "speed",
        "spin_rpm": "spin",
        "spin_axis_deg": "spin_axis",
        "elevation_deg": "elevation",
        "heading_deg": "heading",
    }
    out: dict[str, set] = {f: set() for f in attrs}
    for (g,) in conn.execute("SELECT grid_json FROM fills"):
        gj = stored_json(g, "fills.grid_json")
        if not isinstance(spec, dict) or not isinstance(gj, dict):
            raise DatabaseFileError("damaged file: a fill's grid or the machine spec is not a JSON object")
        for f, attr in attrs.items():
            r = spec[attr]
            idx = gj.get(f) or []
            if not isinstance(idx, list) or not all(isinstance(i, int) and 0 <= i < 10**7 for i in idx):
                raise DatabaseFileError(f"damaged file: fills.grid_json: {f} is not a list of grid indices")
            out[f].update(round(r["lo"] + i * r["step"], 9) for i in idx)
    return {f: sorted(v) for f, v in out.items()}


def table_ranges(conn: sqlite3.Connection) -> dict:
    """(min, max) per setting of the grids filled into the file ((inf, -inf) when none)."""
    vals = grid_values(conn)
    return {f: ((v[0], v[-1]) if v else (math.inf, -math.inf)) for f, v in vals.items()}


def target_area(machine_x: float) -> str:
    """Court area a machine at ``machine_x`` aims at: the doubles area of the other half."""
    return "doubles" if machine_x < 0 else "near-doubles"


def check_target(x: float, y: float, machine_x: float = -1.0, court=None) -> tuple[float, float]:
    """Validate a target in the doubles area (lines included) of the half opposite the machine."""
    court = court or ITF_COURT
    x = check_finite("target", x)
    y = check_finite("target", y)
    area = target_area(machine_x)
    if not court.contains(area, x, y):
        b = court.area_bounds(area)
        raise InputError(
            f"target: ({x:g}, {y:g}) m is off the court; a machine at x = {machine_x:g} m "
            f"aims at the {area} area, x in [{b[0]:g}, {b[1]:g}] m, y in [{b[2]:g}, {b[3]:g}] m"
        )
    return x, y


# ------------------------------------------------------------------ the fallback: the machine's own aim
#: A stored hit farther than this from the target sends a lookup to the machine's aim [m] (the inverse
#: map's promise: settings within 2 cm for a reachable target)
FALLBACK_M = 0.02
#: The aim's answer replaces the stored hit only when it lands nearer by more than this [m]
FALLBACK_GAIN_M = 1e-3
SOURCES = ("table", "refined", "inverse-map")


def params_from_physics(p: dict):
    """The :class:`~tennislab.core.flight.FlightParams` a file's ``physics`` record describes (its court
    too: the table kept the hits that land in it), or None when it cannot be rebuilt (a table aero model:
    its grid is not stored)."""
    from tennislab.core.aero import get_aero_model  # the flight physics: only when a lookup falls back
    from tennislab.core.court import Court
    from tennislab.core.flight import FlightParams

    try:
        court = Court(**p["court"]) if "court" in p else None
        model = get_aero_model(p["aero"]["name"])
        model = dataclasses.replace(model, params=np.asarray(p["aero"]["params"], dtype=float))
        ball, atm = p["ball"], p["atmosphere"]
        return FlightParams.from_options(
            aero=model,
            mass=ball["mass"],
            radius=ball["radius"],
            inertia_factor=ball.get("inertia_factor"),
            air_density=atm["density"],
            gravity=atm["gravity"],
            wind=atm["wind"],
            spin_decay=p["spin_decay"],
            t_max=p["t_max"],
            court=court,
        )
    except (InputError, KeyError, TypeError, ValueError):
        return None


def fallback(spec, physics: dict, target, hit: dict | None, asked: dict, tolerances, prefs: Preferences):
    """The machine's aim for a lookup whose table holds nothing within :data:`FALLBACK_M` (module docstring).

    With a stored nearest hit, the aim at its height (``source`` ``refined``); without one, at the asked
    height or every height (``inverse-map``: the reach map and the search on the machine's steps,
    :func:`tennislab.launcher.aim.aim`).  The speed and spin are the asked ones (else the hit's), within
    the lookup's tolerances and preferences.  Returns a hit-shaped dict (``id`` None, plus ``source``) or
    None when there is no answer (no speed, physics that cannot be rebuilt, an unreachable target).
    """
    from tennislab.launcher.aim import aim  # the machine's aim (and its flights): only here

    params = params_from_physics(physics)
    speed = asked.get("speed_kmh") if asked.get("speed_kmh") is not None else (hit or {}).get("speed_kmh")
    if params is None or speed is None:
        return None
    speed = float(speed)
    spin = asked.get("spin_rpm") if asked.get("spin_rpm") is not None else (hit or {}).get("spin_rpm")
    spin = 0.0 if spin is None else float(spin)
    axis = asked.get("spin_axis_deg")
    if axis is None:
        axis = (hit or {}).get("spin_axis_deg", 0.0) if asked.get("spin_rpm") is None else 0.0
    height = (hit or {}).get("height_m") if hit is not None else asked.get("height_m")
    try:
        res = aim(
            target,
            speed,
            spin,
            float(axis),
            None if height is None else float(height),
            spec,
            params,
            trajectory=prefs.trajectory,
            speed_tolerance_kmh=tolerances.speed_kmh,
            spin_tolerance_rpm=tolerances.spin_rpm,
            spin_axis_tolerance_deg=tolerances.spin_axis_deg,
            max_apex_m=prefs.max_apex_m,
            net_clearance_m=prefs.net_clearance_m,
            max_flight_time_s=prefs.max_flight_time_s,
        )
    except InputError:
        return None
    sol = res.solution
    st = sol.settings
    out: dict = {k: float(getattr(st, k)) for k in HIT_SETTINGS}
    out.update(
        id=None,
        land_x=sol.landing[0],
        land_y=sol.landing[1],
        net_clearance_m=sol.net_clearance_m,
        flight_time_s=sol.flight_time_s,
        bounce_speed_ms=sol.landing_speed_ms,
        bounce_spin_rpm=st.spin_rpm * math.exp(-params.spin_decay * sol.flight_time_s),
        apex_z_m=sol.apex_z_m,
        branch=BRANCH_LOW if sol.solution == "low" else BRANCH_HIGH,
        miss_m=sol.miss_mm * 1e-3,
        n_candidates=0,
        n_read=0,
        source="refined" if hit is not None else "inverse-map",
    )
    return out
