"""The launcher's database of hits and training programs (SQLite, one file).

Seed 002 (Wojcicki, Pucilowski & Kulesza) closes with its purpose: "Based on
calculated ball trajectories, the database of different possible hits and
training programs can be created and implemented in the control system."  This
module is that database.  A controller beside the court opens the file
read-only and answers "which settings land a ball there" with an R*Tree query,
without integrating anything.

Layout (schema version :data:`SCHEMA_VERSION`, in ``PRAGMA user_version``;
``PRAGMA application_id`` = :data:`APPLICATION_ID` marks the file as ours):

``machine``        one row: the machine spec, its position on court, the
                   physics constants used and :func:`config_hash` of all of them.
``hits``           one row per quantised setting (``id`` packs the per-axis grid
                   indices, see :func:`tennislab.launcher.table.pack_ids`): settings, landing x, y, net
                   clearance, flight time, bounce speed and spin, apex height.
``hits_rtree``     R*Tree over (landing x, landing y, speed, spin): a lookup
                   with speed and spin reads the few rows in a box around the
                   target whose speed and spin match, never the table.
``hits_cell``, ``hits_speed_cell``, ``hits_spin_cell``  covering indexes over
                   ([speed or spin,] 1 cm band of landing y, landing x, y, net
                   clearance) for lookups that fix at most one of the two.
                   (Schema 3 had ``hits_xy``, an R*Tree over landing x, y.)
``fills``, ``fill_chunks``  which chunks of which settings grid are stored
                   (``launcher table`` resumes from them).
``drills``, ``drill_shots`` training programs: the drill file's text verbatim
                   (export is byte-exact) and its shots, with a revision.

WAL journal mode lets :func:`lookup` read while ``launcher table`` writes; the
reader opens the file with ``mode=ro``.  Every user error (missing, truncated or
foreign file; stale hash; target off the court; no hit in range) is an
:class:`~tennislab.errors.InputError` with a one-line message.
"""

from __future__ import annotations

import contextlib
import dataclasses
import datetime as _dt
import hashlib
import json
import math
import os
import sqlite3

import numpy as np

from tennislab.errors import InputError

#: Schema version of the file (``PRAGMA user_version``); see :data:`MIGRATIONS`.
SCHEMA_VERSION = 4
#: Oldest schema :func:`open_readonly` accepts (lookups on a file of schema 3 use its R*Trees alone).
MIN_READ_VERSION = 3
#: ``PRAGMA application_id`` of a tennislab launcher database ("TLDB").
APPLICATION_ID = 0x544C4442
#: Version of the content of ``hits`` (what a row means, how it is computed);
#: part of the hash, so a change of format makes old tables stale.  The schema
#: version is not: a migration changes the container, never the stored hits.
HITS_FORMAT = 1
#: Integration tolerances used to fill the table (part of the hash).
FILL_RTOL = 1e-7
FILL_ATOL = 1e-7

HIT_SETTINGS = ("height_m", "speed_kmh", "elevation_deg", "heading_deg", "spin_rpm", "spin_axis_deg")
HIT_RESULTS = ("land_x", "land_y", "net_clearance_m", "flight_time_s", "bounce_speed_ms", "bounce_spin_rpm", "apex_z_m")
HIT_COLUMNS = ("id",) + HIT_SETTINGS + HIT_RESULTS

# ----------------------------------------------------------------- migrations
_V1 = """
CREATE TABLE machine (
    id INTEGER PRIMARY KEY CHECK (id = 1),
    hash TEXT NOT NULL,
    spec_json TEXT NOT NULL,
    position_x REAL NOT NULL,
    position_y REAL NOT NULL,
    physics_json TEXT NOT NULL,
    config_json TEXT NOT NULL,
    tennislab_version TEXT NOT NULL,
    created_utc TEXT NOT NULL
);
CREATE TABLE hits (
    id INTEGER PRIMARY KEY,
    height_m REAL NOT NULL, speed_kmh REAL NOT NULL, elevation_deg REAL NOT NULL,
    heading_deg REAL NOT NULL, spin_rpm REAL NOT NULL, spin_axis_deg REAL NOT NULL,
    land_x REAL NOT NULL, land_y REAL NOT NULL, net_clearance_m REAL NOT NULL,
    flight_time_s REAL NOT NULL, bounce_speed_ms REAL NOT NULL, bounce_spin_rpm REAL NOT NULL,
    apex_z_m REAL NOT NULL
);
CREATE VIRTUAL TABLE hits_rtree USING rtree(id, min_x, max_x, min_y, max_y,
                                            min_speed, max_speed, min_spin, max_spin);
CREATE TABLE fills (
    id INTEGER PRIMARY KEY,
    grid_hash TEXT NOT NULL UNIQUE,
    grid_json TEXT NOT NULL,
    n_rows INTEGER NOT NULL,
    chunk_size INTEGER NOT NULL,
    n_chunks INTEGER NOT NULL,
    started_utc TEXT NOT NULL,
    finished_utc TEXT
);
CREATE TABLE fill_chunks (
    fill_id INTEGER NOT NULL REFERENCES fills(id),
    chunk INTEGER NOT NULL,
    n_hits INTEGER NOT NULL,
    PRIMARY KEY (fill_id, chunk)
) WITHOUT ROWID;
"""

_V2 = """
CREATE TABLE drills (
    id INTEGER PRIMARY KEY,
    name TEXT NOT NULL UNIQUE,
    filename TEXT NOT NULL,
    format_version TEXT,
    revision INTEGER NOT NULL,
    sha256 TEXT NOT NULL,
    source BLOB NOT NULL,
    sequence_json TEXT,
    imported_utc TEXT NOT NULL
);
CREATE TABLE drill_shots (
    drill_id INTEGER NOT NULL REFERENCES drills(id) ON DELETE CASCADE,
    idx INTEGER NOT NULL,
    shot_json TEXT NOT NULL,
    PRIMARY KEY (drill_id, idx)
) WITHOUT ROWID;
"""

# v3: a 2-D R*Tree for lookups with neither speed nor spin given.  In the 4-D tree the
# speed and spin dimensions keep the landing "sheets" of different speeds apart, so a box
# query over every speed visits one subtree per sheet (~30 ms at 10^6 hits); the 2-D tree
# packs nearby landings of all sheets into the same leaves.  Existing hits are indexed.
_V3 = """
CREATE VIRTUAL TABLE hits_xy USING rtree(id, min_x, max_x, min_y, max_y);
INSERT INTO hits_xy SELECT id, land_x, land_x, land_y, land_y FROM hits;
"""

# v4: covering B-tree indexes for lookups that fix at most one of speed and spin, replacing hits_xy.
# With an open speed or spin range the 4-D tree's leaves (which mix speeds and spins) reach the
# target by the hundred: 10-100 ms at 10^7 hits.  Landings lie on dense rays (one per heading
# step); hits_xy's square boxes read 10^4 entries of the nearest ray at 10^7 hits, and its leaves
# on the ray of heading 0 (y constant: zero area, no guide for the R*Tree's insertion) span metres.
# An index ordered by 1 cm bands of y, then x reads one range per band, clipped to a disc.
_V4 = """
DROP TABLE hits_xy;
CREATE INDEX hits_cell ON hits (CAST(land_y * 100.0 + 1000000.0 AS INTEGER), land_x, land_y, net_clearance_m,
                                height_m, spin_axis_deg);
CREATE INDEX hits_speed_cell ON hits (speed_kmh, CAST(land_y * 100.0 + 1000000.0 AS INTEGER), land_x, land_y,
                                      net_clearance_m);
CREATE INDEX hits_spin_cell ON hits (spin_rpm, CAST(land_y * 100.0 + 1000000.0 AS INTEGER), land_x, land_y,
                                     net_clearance_m);
"""

#: version -> SQL script that upgrades a file from ``version - 1`` to ``version``.
MIGRATIONS = {1: _V1, 2: _V2, 3: _V3, 4: _V4}


def _now() -> str:
    return _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


def _db_error(path: str, exc: Exception) -> InputError:
    msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    return InputError(f"--db {path}: not a usable tennislab launcher database ({msg})")


@contextlib.contextmanager
def guard(path: str):
    """Turn SQLite errors met while using an open file (e.g. a truncated one) into one-line InputErrors."""
    try:
        yield
    except sqlite3.DatabaseError as exc:
        raise _db_error(path, exc) from None


def check_not_truncated(path: str) -> None:
    """Refuse a file shorter than the page count in its SQLite header (a cut copy).

    Checked only when no write-ahead log is pending (``-wal`` absent or empty): with a
    live WAL the main file's header may be older than its pages.
    """
    wal = path + "-wal"
    if os.path.exists(wal) and os.path.getsize(wal) > 0:
        return
    with open(path, "rb") as fh:
        head = fh.read(100)
    if len(head) < 100 or not head.startswith(b"SQLite format 3\x00"):
        return  # SQLite itself reports "file is not a database"
    page = int.from_bytes(head[16:18], "big")
    page = 65536 if page == 1 else page
    n_pages = int.from_bytes(head[28:32], "big")
    valid = head[92:96] == head[24:28]
    size = os.path.getsize(path)
    if valid and n_pages and size < n_pages * page:
        raise InputError(
            f"--db {path}: truncated file ({size} bytes, its header says "
            f"{n_pages} pages of {page} bytes = {n_pages * page} bytes)"
        )


def _check_identity(conn: sqlite3.Connection, path: str) -> int:
    """Schema version of an open file; InputError for another application's file or a newer schema."""
    version = conn.execute("PRAGMA user_version").fetchone()[0]
    app = conn.execute("PRAGMA application_id").fetchone()[0]
    if version == 0:
        n = conn.execute("SELECT count(*) FROM sqlite_master").fetchone()[0]
        if n or app not in (0, APPLICATION_ID):
            raise InputError(
                f"--db {path}: a SQLite file of another application (it has tables "
                "but no tennislab schema version); refusing to modify it"
            )
    elif app != APPLICATION_ID:
        raise InputError(f"--db {path}: a SQLite file of another application (application_id {app:#x})")
    if version > max(MIGRATIONS):
        raise InputError(
            f"--db {path}: schema version {version} is newer than this tennislab "
            f"understands ({max(MIGRATIONS)}); upgrade tennislab"
        )
    return version


def migrate(conn: sqlite3.Connection, path: str = "", target: int = SCHEMA_VERSION) -> int:
    """Upgrade the schema of an open read-write file to ``target``; return the old version.

    A new (empty) file is initialised; a file written by a newer tennislab, or a
    SQLite file of another application, is refused.  Each step is one transaction.
    """
    version = _check_identity(conn, path)
    for v in range(version + 1, target + 1):
        conn.execute("BEGIN IMMEDIATE")
        try:
            for stmt in _statements(MIGRATIONS[v]):
                conn.execute(stmt)
            conn.execute(f"PRAGMA application_id = {APPLICATION_ID}")
            conn.execute(f"PRAGMA user_version = {v}")
            conn.execute("COMMIT")
        except BaseException:
            conn.execute("ROLLBACK")
            raise
    return version


def _statements(script: str):
    buf = ""
    for line in script.splitlines(keepends=True):
        buf += line
        if sqlite3.complete_statement(buf):
            if buf.strip():
                yield buf.strip()
            buf = ""


def _fail_open(conn, path: str, exc: Exception):
    """Close a half-opened connection and raise ``exc`` as a one-line :class:`InputError`."""
    if conn is not None:
        conn.close()
    if isinstance(exc, InputError):
        raise exc
    raise _db_error(path, exc) from None


def open_db(path: str, *, create: bool = True, target_version: int = SCHEMA_VERSION) -> sqlite3.Connection:
    """Open (or create) a database for writing: WAL mode, migrated to the current schema."""
    if not create and not os.path.exists(path):
        raise InputError(f"--db {path}: no such file")
    if os.path.isdir(path):
        raise InputError(f"--db {path}: is a directory")
    if os.path.exists(path):
        check_not_truncated(path)
    d = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(d):
        raise InputError(f"--db {path}: directory {d} does not exist")
    conn = None
    try:
        conn = sqlite3.connect(path, timeout=30.0, isolation_level=None)
        _check_identity(conn, path)  # before anything could modify another application's file
        mode = conn.execute("PRAGMA journal_mode=WAL").fetchone()[0]
        if mode.lower() != "wal":
            raise sqlite3.DatabaseError(f"cannot switch to WAL mode (got {mode})")
        conn.execute("PRAGMA synchronous=NORMAL")
        conn.execute("PRAGMA foreign_keys=ON")
        conn.execute("PRAGMA cache_size=-131072")  # 128 MiB: R*Tree inserts touch many nodes
        migrate(conn, path, target_version)
        conn.execute("SELECT count(*) FROM machine").fetchone()
    except (sqlite3.DatabaseError, InputError) as exc:
        _fail_open(conn, path, exc)
    return conn


def open_readonly(path: str) -> sqlite3.Connection:
    """Open an existing database read-only (``mode=ro``) and check that it is ours and current."""
    if not os.path.exists(path):
        raise InputError(f"--db {path}: no such file")
    if os.path.isdir(path):
        raise InputError(f"--db {path}: is a directory")
    check_not_truncated(path)
    from urllib.parse import quote

    uri = "file:" + quote(os.path.abspath(path)) + "?mode=ro"
    conn = None
    try:
        conn = sqlite3.connect(uri, uri=True, timeout=30.0, isolation_level=None)
        version = conn.execute("PRAGMA user_version").fetchone()[0]
        app = conn.execute("PRAGMA application_id").fetchone()[0]
        if app != APPLICATION_ID or version == 0:
            raise InputError(f"--db {path}: not a tennislab launcher database")
        if version > SCHEMA_VERSION:
            raise InputError(
                f"--db {path}: schema version {version} is newer than this tennislab "
                f"understands ({SCHEMA_VERSION}); upgrade tennislab"
            )
        if version < MIN_READ_VERSION:
            raise InputError(
                f"--db {path}: schema version {version} is older than {MIN_READ_VERSION}; "
                "rerun `launcher table` on it to migrate it (finished chunks are skipped)"
            )
        conn.execute("SELECT count(*) FROM machine").fetchone()
    except (sqlite3.DatabaseError, InputError) as exc:
        _fail_open(conn, path, exc)
    return conn


# ------------------------------------------------------------ configuration hash
def _plain(obj):
    """Canonical JSON-able form: dataclasses -> dicts, numpy -> lists/floats, tuples -> lists."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return {f.name: _plain(getattr(obj, f.name)) for f in dataclasses.fields(obj) if not f.name.startswith("_")}
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_plain(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [_plain(v) for v in obj.tolist()]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        f = float(obj)
        return f if math.isfinite(f) else repr(f)
    if obj is None or isinstance(obj, str):
        return obj
    if callable(obj):
        return getattr(obj, "__qualname__", repr(obj))
    return repr(obj)


def physics_dict(params) -> dict:
    """The physics constants of a :class:`~tennislab.core.flight.FlightParams` as plain data.

    Ball, atmosphere, aero model (name and parameter array), spin decay, court
    (net profile), the longest flight and the fill's integration tolerances.
    """
    return {
        "ball": _plain(params.ball),
        "atmosphere": _plain(params.atmosphere),
        "aero": {"name": params.aero.name, "params": _plain(np.asarray(params.aero.params))},
        "spin_decay": float(params.spin_decay),
        "t_max": float(params.t_max),
        "court": _plain(params.court),
        "integrator": {"rtol": FILL_RTOL, "atol": FILL_ATOL},
    }


def config_dict(spec, params, position=None) -> dict:
    """Everything a table depends on: machine spec, position on court, physics, formats.

    ``spec`` is the launcher's ``MachineSpec`` (any dataclass or dict);
    ``position`` the machine's (x, y) on court [m] if it is not part of the spec.
    """
    pos = _machine_position(spec, position)
    return {
        "machine": _plain(spec),
        "position": [float(pos[0]), float(pos[1])],
        "physics": physics_dict(params),
        "format": {"hits_format": HITS_FORMAT},
    }


def _machine_position(spec, position):
    if position is not None:
        return tuple(float(v) for v in position)
    for name in ("position", "machine_position", "position_m"):
        v = getattr(spec, name, None) if not isinstance(spec, dict) else spec.get(name)
        if v is not None:
            return tuple(float(x) for x in list(v)[:2])
    raise InputError("machine position: not given and not part of the machine spec")


def canonical_json(obj) -> str:
    """Stable JSON: sorted keys, no spaces, floats as Python's shortest repr."""
    return json.dumps(_plain(obj), sort_keys=True, separators=(",", ":"), allow_nan=False)


def config_hash(cfg: dict) -> str:
    """SHA-256 (hex) of the canonical JSON of a :func:`config_dict`."""
    return hashlib.sha256(canonical_json(cfg).encode()).hexdigest()


def _diff(a, b, prefix="") -> list[str]:
    """Paths where two plain JSON structures differ (for the stale-hash message)."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = []
        for k in sorted(set(a) | set(b)):
            out += _diff(a.get(k), b.get(k), f"{prefix}.{k}" if prefix else k)
        return out
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        out = []
        for i, (x, y) in enumerate(zip(a, b)):
            out += _diff(x, y, f"{prefix}[{i}]")
        return out
    return [] if a == b else [f"{prefix} ({json.dumps(a)} in the file, {json.dumps(b)} given)"]


def stored_config(conn: sqlite3.Connection) -> tuple[str, dict] | None:
    """(hash, config) of the file's machine row, or None for an empty file."""
    row = conn.execute("SELECT hash, config_json FROM machine WHERE id = 1").fetchone()
    return None if row is None else (row[0], json.loads(row[1]))


def check_config(conn: sqlite3.Connection, cfg: dict, path: str = "") -> str:
    """Refuse a file built for another machine or physics; return the hash.

    The message names the first differing fields, e.g. ``physics.aero.name``.
    """
    h = config_hash(cfg)
    stored = stored_config(conn)
    if stored is None:
        raise InputError(f"--db {path}: the table is empty (no machine); fill it with `launcher table`")
    if stored[0] != h:
        diffs = _diff(stored[1], json.loads(canonical_json(cfg)))
        what = "; ".join(diffs[:3]) + (f"; and {len(diffs) - 3} more" if len(diffs) > 3 else "")
        raise InputError(
            f"--db {path}: built for another machine/physics (hash {stored[0][:12]} in the "
            f"file, {h[:12]} given): {what or 'format changed'}"
        )
    return h


def bind_config(conn: sqlite3.Connection, cfg: dict, path: str = "") -> str:
    """Record the machine config in a new file, or check it against an existing one."""
    from tennislab import __version__

    h = config_hash(cfg)
    conn.execute("BEGIN IMMEDIATE")
    try:
        if conn.execute("SELECT 1 FROM machine WHERE id = 1").fetchone() is None:
            pos = cfg["position"]
            conn.execute(
                "INSERT INTO machine VALUES (1, ?, ?, ?, ?, ?, ?, ?, ?)",
                (
                    h,
                    canonical_json(cfg["machine"]),
                    pos[0],
                    pos[1],
                    canonical_json(cfg["physics"]),
                    canonical_json(cfg),
                    __version__,
                    _now(),
                ),
            )
        conn.execute("COMMIT")
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    return check_config(conn, cfg, path)


# ---------------------------------------------------------------------- hits
def insert_hits(conn: sqlite3.Connection, hits: dict) -> int:
    """Insert hit rows (dict of equal-length arrays named :data:`HIT_COLUMNS`) and index them.

    Must run inside the caller's transaction.  Rows whose ``id`` is already
    stored are skipped (a resumed or overlapping fill never duplicates a setting).
    Returns the number of rows inserted.
    """
    n = len(hits["id"])
    if n == 0:
        return 0
    cols = [np.asarray(hits[c]) for c in HIT_COLUMNS]
    for name, c in zip(HIT_COLUMNS, cols):
        if len(c) != n:
            raise InputError(f"hits[{name!r}]: length {len(c)} != {n}")
    ids = cols[0].astype(np.int64)
    have = set()
    lo, hi = int(ids.min()), int(ids.max())
    if conn.execute("SELECT 1 FROM hits WHERE id BETWEEN ? AND ? LIMIT 1", (lo, hi)).fetchone():
        have = {r[0] for r in conn.execute("SELECT id FROM hits WHERE id BETWEEN ? AND ?", (lo, hi))}
    keep = np.fromiter((i not in have for i in ids.tolist()), bool, n) if have else np.ones(n, bool)
    if not keep.any():
        return 0
    rows = list(zip(ids[keep].tolist(), *[c[keep].astype(float).tolist() for c in cols[1:]]))
    conn.executemany(f"INSERT INTO hits VALUES ({','.join('?' * len(HIT_COLUMNS))})", rows)
    x, y = hits["land_x"], hits["land_y"]
    sp, sw = hits["speed_kmh"], hits["spin_rpm"]
    conn.executemany(
        "INSERT INTO hits_rtree VALUES (?,?,?,?,?,?,?,?,?)",
        zip(ids[keep].tolist(), *[np.asarray(a, float)[keep].tolist() for a in (x, x, y, y, sp, sp, sw, sw)]),
    )
    if conn.execute("SELECT 1 FROM sqlite_master WHERE name = 'hits_xy'").fetchone():  # schema 3
        conn.executemany(
            "INSERT INTO hits_xy VALUES (?,?,?,?,?)",
            zip(ids[keep].tolist(), *[np.asarray(a, float)[keep].tolist() for a in (x, x, y, y)]),
        )
    return int(keep.sum())


def count_hits(conn: sqlite3.Connection) -> int:
    return conn.execute("SELECT count(*) FROM hits").fetchone()[0]


def count_hits_fast(conn: sqlite3.Connection) -> int:
    """0 if the table is empty, else a positive number (no full count)."""
    return 1 if conn.execute("SELECT 1 FROM hits LIMIT 1").fetchone() else 0


# -------------------------------------------------------------------- drills
def _parse_drill(path: str, data: bytes) -> tuple[str, str | None, list, list | None]:
    """(name, format version, distinct shots, firing sequence) of a drill file.

    Uses the launcher's drill reader (:func:`tennislab.io.drill.parse_drill_text`),
    so a file is validated exactly as ``launcher drill`` validates it.
    """
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a drill file (not UTF-8 text)") from None
    from tennislab.io.drill import parse_drill_text

    d = parse_drill_text(text, path)
    name, version, shots = d.get("name"), d.get("version"), d.get("shots")
    if not shots:
        raise InputError(f"{path}: drill {name!r} has no shots")
    seq = d.get("sequence")
    return (
        str(name),
        None if version is None else str(version),
        [_plain(x) for x in shots],
        None if seq is None else _plain(seq),
    )


def import_drill(conn: sqlite3.Connection, path: str) -> dict:
    """Store a drill file (verbatim, plus its parsed shots); a changed drill gets the next revision.

    Re-importing an identical file changes nothing.  Returns the drill's row as a dict.
    """
    with open(path, "rb") as fh:
        data = fh.read()
    name, version, shots, seq = _parse_drill(path, data)
    sha = hashlib.sha256(data).hexdigest()
    conn.execute("BEGIN IMMEDIATE")
    try:
        row = conn.execute("SELECT id, revision, sha256 FROM drills WHERE name = ?", (name,)).fetchone()
        if row is not None and row[2] == sha:
            conn.execute("COMMIT")
            return drill_info(conn, name)
        rev = 1 if row is None else row[1] + 1
        if row is not None:
            conn.execute("DELETE FROM drill_shots WHERE drill_id = ?", (row[0],))
            conn.execute(
                "UPDATE drills SET filename = ?, format_version = ?, revision = ?, sha256 = ?, "
                "source = ?, sequence_json = ?, imported_utc = ? WHERE id = ?",
                (os.path.basename(path), version, rev, sha, data, _seq_json(seq), _now(), row[0]),
            )
            did = row[0]
        else:
            did = conn.execute(
                "INSERT INTO drills (name, filename, format_version, revision, sha256, source, "
                "sequence_json, imported_utc) VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                (name, os.path.basename(path), version, rev, sha, data, _seq_json(seq), _now()),
            ).lastrowid
        conn.executemany(
            "INSERT INTO drill_shots VALUES (?, ?, ?)", [(did, i, canonical_json(s)) for i, s in enumerate(shots)]
        )
        conn.execute("COMMIT")
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    return drill_info(conn, name)


def _seq_json(seq) -> str | None:
    return None if seq is None else canonical_json(seq)


def drill_info(conn: sqlite3.Connection, name: str) -> dict:
    row = conn.execute(
        "SELECT d.name, d.filename, d.format_version, d.revision, d.sha256, d.imported_utc, "
        "(SELECT count(*) FROM drill_shots s WHERE s.drill_id = d.id) "
        "FROM drills d WHERE d.name = ?",
        (name,),
    ).fetchone()
    if row is None:
        names = [r[0] for r in conn.execute("SELECT name FROM drills ORDER BY name")]
        raise InputError(f"drill {name!r}: not in the database (stored: {', '.join(names) or 'none'})")
    return dict(zip(("name", "filename", "format_version", "revision", "sha256", "imported_utc", "n_shots"), row))


def list_drills(conn: sqlite3.Connection) -> list[dict]:
    return [drill_info(conn, r[0]) for r in conn.execute("SELECT name FROM drills ORDER BY name").fetchall()]


def drill_source(conn: sqlite3.Connection, name: str) -> bytes:
    """The drill file exactly as imported."""
    drill_info(conn, name)
    return bytes(conn.execute("SELECT source FROM drills WHERE name = ?", (name,)).fetchone()[0])


def drill_sequence(conn: sqlite3.Connection, name: str) -> list | None:
    """Shot names in firing order (the drill's expanded program), as stored at import."""
    drill_info(conn, name)
    row = conn.execute("SELECT sequence_json FROM drills WHERE name = ?", (name,)).fetchone()
    return None if row[0] is None else json.loads(row[0])


def drill_shots(conn: sqlite3.Connection, name: str) -> list[dict]:
    """The drill's distinct shots (resolved fields), in file order."""
    drill_info(conn, name)
    return [
        json.loads(r[0])
        for r in conn.execute(
            "SELECT s.shot_json FROM drill_shots s JOIN drills d ON d.id = s.drill_id WHERE d.name = ? ORDER BY s.idx",
            (name,),
        )
    ]
