"""The launcher's database of hits and training programs (SQLite, one file): the storage layer.

Wojcicki, Pucilowski & Kulesza (2010) close with its purpose: "Based on
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
                   clearance, flight time, bounce speed and spin, apex height, and (schema 5)
                   ``branch``: 0 on the rising branch of distance against elevation (low), 1 on the
                   falling one (high, lobs).
``hits_rtree``     R*Tree over (landing x, landing y, speed, spin): a lookup
                   with speed and spin reads the few rows in a box around the
                   target whose speed and spin match, never the table.
``hits_cell``, ``hits_speed_cell``, ``hits_spin_cell``  covering indexes over
                   ([speed or spin,] 1 cm band of landing y, landing x, y, net
                   clearance, branch, apex, flight time, ...) for lookups that fix at
                   most one of the two, filtered on the trajectory preferences in the
                   index.  (Schema 3 had ``hits_xy``, an R*Tree over landing x, y.)
``fills``, ``fill_chunks``  which chunks of which settings grid are stored
                   (``launcher table`` resumes from them).
``drills``, ``drill_shots`` training programs: the drill file's text verbatim
                   (export is byte-exact) and its shots, with a revision
                   (:mod:`tennislab.launcher._dbdrills`).

WAL journal mode lets a lookup read while ``launcher table`` writes.  Readers never
write: a file without a pending write-ahead log is opened ``immutable`` (no lock, no
``-wal``/``-shm`` created), one with a live log ``mode=ro`` (it reads the log, never
checkpoints it).  A file is identified (SQLite header, ``application_id``) from its
bytes before SQLite opens it, so a foreign file is never opened for writing.  Problems
of the file are :class:`DatabaseFileError` (an :class:`~tennislab.errors.InputError`
without the path: :class:`~tennislab.launcher.hitsdb.HitsDB` adds it).
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
from urllib.parse import quote

import numpy as np

import tennislab.launcher._dbguard as _guard
from tennislab import __version__
from tennislab.errors import InputError
from tennislab.io.files import check_input_file, note_input, shown, stream_link
from tennislab.launcher._schema import MIGRATIONS

#: Schema version of the file (``PRAGMA user_version``); see :data:`MIGRATIONS`.
SCHEMA_VERSION = 5
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
#: Columns of a schema-4 row; schema 5 adds ``branch``.
HIT_COLUMNS_V4 = ("id",) + HIT_SETTINGS + HIT_RESULTS
HIT_COLUMNS = HIT_COLUMNS_V4 + ("branch",)
#: Files smaller than this are checked with ``PRAGMA quick_check`` when opened (larger ones on any
#: unexpected error, and by ``launcher info --check``): the check reads the whole file.
QUICK_CHECK_MAX_BYTES = 64 * 1024 * 1024


class DatabaseFileError(InputError):
    """A problem of the database file itself (foreign, truncated, damaged, stale, empty); no path in the message."""


def _now() -> str:
    return _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


def _first_line(exc: BaseException) -> str:
    return str(exc).splitlines()[0] if str(exc) else type(exc).__name__


def damaged(conn: sqlite3.Connection | None, exc: BaseException | None = None) -> DatabaseFileError:
    """The one-line error for a file that failed while in use: ``PRAGMA quick_check`` says whether it is damaged."""
    report = ""
    if conn is not None:
        try:
            rows = conn.execute("PRAGMA quick_check(5)").fetchall()
            report = "; ".join(str(r[0]) for r in rows)
        except sqlite3.DatabaseError as e:
            report = _first_line(e)
    if report and report != "ok":
        return DatabaseFileError(f"damaged file (quick_check: {report[:200]}); rebuild it with `launcher table`")
    why = _first_line(exc) if exc is not None else "unexpected content"
    return DatabaseFileError(f"damaged or unusable file ({why[:200]}); rebuild it with `launcher table`")


def quick_check(conn: sqlite3.Connection) -> None:
    """``PRAGMA quick_check`` (page structure, record formats, NOT NULL): DatabaseFileError if not ok."""
    try:
        rows = conn.execute("PRAGMA quick_check(5)").fetchall()
    except sqlite3.DatabaseError as exc:
        raise DatabaseFileError(f"damaged file ({_first_line(exc)}); rebuild it with `launcher table`") from None
    report = "; ".join(str(r[0]) for r in rows)
    if report != "ok":
        raise DatabaseFileError(f"damaged file (quick_check: {report[:200]}); rebuild it with `launcher table`")


@contextlib.contextmanager
def guard(conn: sqlite3.Connection | None = None):
    """Errors met while using an open file (SQLite errors, a value of the wrong type) -> one-line DatabaseFileError."""
    try:
        yield
    except InputError:
        raise
    except (sqlite3.DatabaseError, TypeError, ValueError, KeyError, IndexError, OverflowError, AttributeError) as exc:
        if _guard.is_interrupted(exc):
            raise DatabaseFileError(
                f"a read ran past its budget of {_guard.READ_STEP_BUDGET:,} SQLite steps and was stopped; "
                "the file is not a table tennislab wrote"
            ) from None
        raise damaged(conn, exc) from None


def _wal_pending(path: str) -> bool:
    wal = path + "-wal"
    if not os.path.lexists(wal):
        return False
    try:
        check_input_file(wal)
    except InputError as exc:  # a FIFO, a device or a directory beside the file: never handed to SQLite
        raise DatabaseFileError(f"its write-ahead log {exc}") from None
    return os.path.getsize(wal) > 0


def _uri(path: str, pending: bool | None = None) -> str:
    """The read-only URI of ``path`` (any encoding: its bytes are percent-encoded)."""
    pending = _wal_pending(path) if pending is None else pending
    return "file:" + quote(os.fsencode(os.path.abspath(path))) + ("?mode=ro" if pending else "?mode=ro&immutable=1")


def check_not_truncated(path: str) -> None:
    """Refuse a file shorter than the page count in its SQLite header (a cut copy).

    Checked only when no write-ahead log is pending (``-wal`` absent or empty): with a
    live WAL the main file's header may be older than its pages.
    """
    if _wal_pending(path):
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
        raise DatabaseFileError(
            f"truncated file ({size} bytes, its header says {n_pages} pages of {page} bytes = {n_pages * page} bytes)"
        )


def _wal_page1(path: str) -> bytes | None:
    """The newest committed image of page 1 in a file's write-ahead log (its first 108 bytes), or None.

    WAL format (sqlite.org/fileformat2.html#walformat): a 32-byte header (magic, version, page
    size, checkpoint sequence, salts, checksums), then frames of a 24-byte header (page number,
    database size after a commit frame or 0, salts, checksums) and one page.  Frames whose salts
    differ from the header's are stale; frames after the last commit frame are not committed.
    """
    wal = path + "-wal"
    try:
        with open(wal, "rb") as fh:
            head = fh.read(32)
            if len(head) < 32 or int.from_bytes(head[0:4], "big") not in (0x377F0682, 0x377F0683):
                return None
            page = int.from_bytes(head[8:12], "big")
            if page < 512 or page > 65536 or page & (page - 1):
                return None
            salts = head[16:24]
            newest, pending = None, None
            for _ in range(1 << 22):  # bounded: a WAL of at most 4 M frames is read
                frame = fh.read(24)
                if len(frame) < 24 or frame[8:16] != salts:
                    break
                pgno, commit = int.from_bytes(frame[0:4], "big"), int.from_bytes(frame[4:8], "big")
                if pgno == 1:
                    pending = fh.read(108)
                    fh.seek(page - 108, os.SEEK_CUR)
                else:
                    fh.seek(page, os.SEEK_CUR)
                if commit and pending is not None:
                    newest = pending
    except OSError:
        return None
    return newest


def header_identity(path: str) -> tuple[int, int, bool] | None:
    """(user_version, application_id, has_tables) of a file from its bytes, without SQLite opening it.

    From the SQLite header and the schema page's b-tree header (page 1, offsets 100-107: its cell
    count is 0 for a file without tables) of the main file, or of the newest committed page 1 in
    a pending write-ahead log (the main file's when the log holds no committed page 1); None for an
    empty main file with a pending log (only SQLite can tell).  An empty file gives (0, 0, False);
    other bytes raise DatabaseFileError.
    """
    head = _wal_page1(path) if _wal_pending(path) else None
    if head is None:  # no committed page 1 in a log: the main file's page 1 is the current one
        with open(path, "rb") as fh:
            head = fh.read(108)
        if not head:
            return None if _wal_pending(path) else (0, 0, False)
    if len(head) < 108 or not head.startswith(b"SQLite format 3\x00"):
        raise DatabaseFileError("not a usable tennislab launcher database (file is not a database)")
    version = int.from_bytes(head[60:64], "big", signed=True)
    app = int.from_bytes(head[68:72], "big", signed=True)
    has_tables = head[100] != 0x0D or int.from_bytes(head[103:105], "big") > 0
    return version, app, has_tables


def _identity_error(version: int, app: int, has_tables: bool) -> DatabaseFileError | None:
    """Why a file of this header is not ours (None if it is ours, or new and empty)."""
    if version == 0:
        if has_tables or app not in (0, APPLICATION_ID):
            return DatabaseFileError(
                "a SQLite file of another application (it has tables but no tennislab schema version); "
                "refusing to open it"
            )
        return None
    if app != APPLICATION_ID:
        return DatabaseFileError(f"a SQLite file of another application (application_id {app:#x}); refusing to open it")
    if version > max(MIGRATIONS):
        return DatabaseFileError(
            f"schema version {version} is newer than this tennislab understands ({max(MIGRATIONS)}); upgrade tennislab"
        )
    return None


def _check_identity(conn: sqlite3.Connection) -> int:
    """Schema version of an open file; DatabaseFileError for another application's file or a newer schema."""
    version = conn.execute("PRAGMA user_version").fetchone()[0]
    app = conn.execute("PRAGMA application_id").fetchone()[0]
    n = conn.execute("SELECT count(*) FROM sqlite_master").fetchone()[0] if version == 0 else 0
    err = _identity_error(version, app, bool(n))
    if err is not None:
        raise err
    return version


def migrate(conn: sqlite3.Connection, target: int = SCHEMA_VERSION) -> int:
    """Upgrade the schema of an open read-write file to ``target``; return the old version.

    A new (empty) file is initialised; a file written by a newer tennislab, or a
    SQLite file of another application, is refused.  Each step is one transaction.
    """
    version = _check_identity(conn)
    for v in range(version + 1, target + 1):
        conn.execute("BEGIN IMMEDIATE")
        try:
            branched = v != 5
            for stmt in _statements(MIGRATIONS[v]):
                if not branched and stmt.startswith("CREATE INDEX"):  # before the indexes that carry it
                    _branch_from_neighbours(conn)
                    branched = True
                conn.execute(stmt)
            conn.execute(f"PRAGMA application_id = {APPLICATION_ID}")
            conn.execute(f"PRAGMA user_version = {v}")
            conn.execute("COMMIT")
        except BaseException:
            conn.execute("ROLLBACK")
            raise
    return version


def _branch_from_neighbours(conn: sqlite3.Connection) -> None:
    """Set ``hits.branch`` of stored hits (schema 4 -> 5) from their neighbours in elevation.

    Along one line of settings (every setting but the elevation fixed), the hit is on the
    falling branch (high) when the next stored elevation (at most 3 steps up) lands nearer the
    machine, or else the previous one (at most 3 steps down) lands farther; a hit without such a
    neighbour is high above 45 deg.  (New fills fly each hit's branch instead: table.fly_chunk.)
    """
    row = conn.execute("SELECT spec_json, position_x, position_y FROM machine WHERE id = 1").fetchone()
    if row is None or conn.execute("SELECT 1 FROM hits LIMIT 1").fetchone() is None:
        return
    spec = stored_json(row[0], "machine.spec_json")

    def size(name):
        r = spec[name]
        return int(math.floor((r["hi"] - r["lo"]) / r["step"] + 1e-9)) + 1

    n_head, n_elev = size("heading"), size("elevation")
    conn.execute(
        """
        UPDATE hits SET branch = nb.branch FROM (
          SELECT id, CASE
            WHEN nxt_e IS NOT NULL AND nxt_e - e <= 3 THEN (nxt_d2 < d2)
            WHEN prv_e IS NOT NULL AND e - prv_e <= 3 THEN (prv_d2 > d2)
            ELSE (elev > 45.0) END AS branch
          FROM (SELECT id, e, d2, elev,
                       LEAD(e) OVER w AS nxt_e, LEAD(d2) OVER w AS nxt_d2,
                       LAG(e) OVER w AS prv_e, LAG(d2) OVER w AS prv_d2
                FROM (SELECT id, (id / :h) % :e AS e, id - ((id / :h) % :e) * :h AS line, elevation_deg AS elev,
                             (land_x - :px) * (land_x - :px) + (land_y - :py) * (land_y - :py) AS d2 FROM hits)
                WINDOW w AS (PARTITION BY line ORDER BY e))
        ) AS nb WHERE hits.id = nb.id
        """,
        {"h": n_head, "e": n_elev, "px": row[1], "py": row[2]},
    )


def ensure_math(conn: sqlite3.Connection) -> None:
    """``cos`` and ``radians`` in SQL (built into SQLite >= 3.35 with its math functions; else Python's)."""
    try:
        conn.execute("SELECT cos(radians(0.0))").fetchone()
    except sqlite3.OperationalError:
        conn.create_function("cos", 1, math.cos, deterministic=True)
        conn.create_function("radians", 1, math.radians, deterministic=True)


def _statements(script: str):
    buf = ""
    for line in script.splitlines(keepends=True):
        buf += line
        if sqlite3.complete_statement(buf):
            if buf.strip():
                yield buf.strip()
            buf = ""


#: the files SQLite keeps beside a database (each must be a regular file when it exists)
_SIDE_FILES = (("-wal", "write-ahead log"), ("-shm", "shared-memory index"), ("-journal", "rollback journal"))


def _check_path(path: str, must_exist: bool) -> None:
    if os.path.isdir(path):
        raise DatabaseFileError("is a directory")
    if must_exist and not os.path.exists(path):
        raise DatabaseFileError("no such file")
    if os.path.lexists(path):
        stream = stream_link(path)
        if stream is not None:  # SQLite would read, lock and write beside whatever that stream is now
            raise DatabaseFileError(f"is a link to {shown(stream)} (a device or a process's stream), not a file")
        try:
            st = check_input_file(path)  # a FIFO or a device is never handed to SQLite (it would block)
        except InputError as exc:
            raise DatabaseFileError(str(exc)[len(shown(path)) + 2 :]) from None
        note_input(path, st)
    for suffix, what in _SIDE_FILES:  # SQLite opens these itself, blocking on a FIFO (a hot journal is read)
        side = path + suffix
        if os.path.lexists(side):
            stream = stream_link(side)
            if stream is not None:
                raise DatabaseFileError(f"its {what} {shown(side)}: is a link to {shown(stream)}, not a file")
            try:
                check_input_file(side)
            except InputError as exc:
                raise DatabaseFileError(f"its {what} {exc}") from None
    d = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(d):
        raise DatabaseFileError(f"directory {d} does not exist")


def open_readonly(path: str, *, min_version: int = MIN_READ_VERSION, check: bool | None = None) -> sqlite3.Connection:
    """Open an existing database for reading without writing anything beside it (module docstring).

    The file must be ours, of schema ``min_version`` .. :data:`SCHEMA_VERSION`; ``check``
    runs ``PRAGMA quick_check`` (default: for files up to :data:`QUICK_CHECK_MAX_BYTES`).
    """
    _check_path(path, must_exist=True)
    check_not_truncated(path)
    ident = header_identity(path)
    if ident is not None:
        if os.path.getsize(path) == 0 and not _wal_pending(path):
            raise DatabaseFileError("empty file, not a tennislab launcher database")
        err = _identity_error(*ident)
        if err is not None:
            raise err
        if ident[0] == 0:
            raise DatabaseFileError("not a tennislab launcher database (no schema version)")
    conn = None
    try:
        conn = _guard.connect(_uri(path), uri=True)
        version = conn.execute("PRAGMA user_version").fetchone()[0]
        app = conn.execute("PRAGMA application_id").fetchone()[0]
        if app != APPLICATION_ID or version == 0:
            raise DatabaseFileError("not a tennislab launcher database")
        if version > SCHEMA_VERSION:
            raise DatabaseFileError(
                f"schema version {version} is newer than this tennislab understands ({SCHEMA_VERSION}); "
                "upgrade tennislab"
            )
        if version < min_version:
            raise DatabaseFileError(
                f"schema version {version} is older than {min_version}; rerun `launcher table` on it to migrate it "
                "(finished chunks are skipped)"
            )
        _guard.check_schema(conn, version, DatabaseFileError)
        if check if check is not None else os.path.getsize(path) <= QUICK_CHECK_MAX_BYTES:
            quick_check(conn)
        if check:  # `info --check`: every stored hit in its ranges too (one scan)
            _guard.check_stored_hits(conn, DatabaseFileError)
        conn.execute("SELECT count(*) FROM machine").fetchone()
        ensure_math(conn)
    except (sqlite3.DatabaseError, InputError) as exc:
        if conn is not None:
            conn.close()
        if isinstance(exc, InputError):
            raise
        raise DatabaseFileError(f"not a usable tennislab launcher database ({_first_line(exc)})") from None
    return conn


def _identify(path: str) -> int:
    """Schema version of an existing file, read without writing (DatabaseFileError if not ours)."""
    ident = header_identity(path)
    if ident is not None:
        err = _identity_error(*ident)
        if err is not None:
            raise err
    conn = None
    try:
        conn = _guard.connect(_uri(path), uri=True)
        version = _check_identity(conn)
        _guard.check_schema(conn, version, DatabaseFileError)
        return version
    except sqlite3.DatabaseError as exc:
        raise DatabaseFileError(f"not a usable tennislab launcher database ({_first_line(exc)})") from None
    finally:
        if conn is not None:
            conn.close()


def open_db(path: str, *, create: bool = True, target_version: int = SCHEMA_VERSION) -> sqlite3.Connection:
    """Open (or create) a database for writing: WAL mode, migrated to the current schema.

    An existing file is identified read-only first (:func:`open_readonly` rules), so a foreign
    or damaged file is refused before anything could write to it.
    """
    _check_path(path, must_exist=not create)
    if os.path.exists(path) and (os.path.getsize(path) > 0 or _wal_pending(path)):
        check_not_truncated(path)
        _identify(path)
    conn = None
    try:
        conn = _guard.connect(path, readonly=False)
        _guard.check_schema(conn, _check_identity(conn), DatabaseFileError)
        mode = conn.execute("PRAGMA journal_mode=WAL").fetchone()[0]
        if mode.lower() != "wal":
            raise sqlite3.DatabaseError(f"cannot switch to WAL mode (got {mode})")
        conn.execute("PRAGMA synchronous=NORMAL")
        conn.execute("PRAGMA foreign_keys=ON")
        conn.execute("PRAGMA cache_size=-131072")  # 128 MiB: R*Tree inserts touch many nodes
        migrate(conn, target_version)
        conn.execute("SELECT count(*) FROM machine").fetchone()
    except (sqlite3.DatabaseError, InputError) as exc:
        if conn is not None:
            conn.close()
        if isinstance(exc, InputError):
            raise
        raise DatabaseFileError(f"not a usable tennislab launcher database ({_first_line(exc)})") from None
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


def _stored_physics(params) -> dict:
    """The physics constants of a :class:`~tennislab.core.flight.FlightParams` as the database stores them.

    Ball, atmosphere, aero model (name and parameter array), spin decay, court
    (net profile), the longest flight and the fill's integration tolerances.  This is the file's
    format, not a second JSON of the parameters (results report :meth:`FlightParams.to_dict`): its
    hash (:func:`config_hash`) identifies the tables already written, so its keys never change.
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
        "physics": _stored_physics(params),
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
    if row is None:
        return None
    cfg = stored_json(row[1], "machine.config_json")
    if not isinstance(row[0], str) or not isinstance(cfg, dict):
        raise DatabaseFileError("damaged file: the machine row is malformed")
    return row[0], cfg


def config_diff(stored: dict, cfg: dict, fields: tuple[str, ...] | None = None) -> list[str]:
    """Differences between a stored and a given config; only under the ``fields`` path prefixes if given."""
    diffs = _diff(stored, json.loads(canonical_json(cfg)))
    if fields is not None:
        diffs = [d for d in diffs if any(d == f or d.startswith((f + ".", f + "[", f + " ")) for f in fields)]
    return diffs


def check_config(conn: sqlite3.Connection, cfg: dict, fields: tuple[str, ...] | None = None) -> str:
    """Refuse a file built for another machine or physics; return the file's hash.

    The message names the first differing fields, e.g. ``physics.aero.name``; with ``fields``
    (config path prefixes) only those are compared (the settings a user gave).
    """
    h = config_hash(cfg)
    stored = stored_config(conn)
    if stored is None:
        raise DatabaseFileError("the table is empty (no machine); fill it with `launcher table`")
    if stored[0] != h:
        diffs = config_diff(stored[1], cfg, fields)
        if fields is not None and not diffs:
            return stored[0]
        what = "; ".join(diffs[:3]) + (f"; and {len(diffs) - 3} more" if len(diffs) > 3 else "")
        raise DatabaseFileError(
            f"built for another machine/physics (hash {stored[0][:12]} in the file, {h[:12]} given): "
            f"{what or 'format changed'}"
        )
    return h


def bind_config(conn: sqlite3.Connection, cfg: dict) -> str:
    """Record the machine config in a new file, or check it against an existing one."""
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
    return check_config(conn, cfg)


# ---------------------------------------------------------------------- hits
def has_column(conn: sqlite3.Connection, table: str, column: str) -> bool:
    return any(r[1] == column for r in conn.execute(f"PRAGMA table_info({table})"))


def insert_hits(conn: sqlite3.Connection, hits: dict) -> int:
    """Insert hit rows (dict of equal-length arrays named :data:`HIT_COLUMNS`) and index them.

    Must run inside the caller's transaction.  Rows whose ``id`` is already
    stored are skipped (a resumed or overlapping fill never duplicates a setting).
    A file of schema < 5 takes the columns of :data:`HIT_COLUMNS_V4`; rows without
    ``branch`` get 0 (low).  Returns the number of rows inserted.
    """
    n = len(hits["id"])
    if n == 0:
        return 0
    columns = HIT_COLUMNS if has_column(conn, "hits", "branch") else HIT_COLUMNS_V4
    hits = dict(hits)
    hits.setdefault("branch", np.zeros(n, dtype=np.int64))
    cols = [np.asarray(hits[c]) for c in columns]
    for name, c in zip(columns, cols):
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
    values = [ids[keep].tolist()]
    for name, c in zip(columns[1:], cols[1:]):
        values.append(c[keep].astype(np.int64 if name == "branch" else float).tolist())
    conn.executemany(
        f"INSERT INTO hits ({','.join(columns)}) VALUES ({','.join('?' * len(columns))})", list(zip(*values))
    )
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


def _damaged(msg: str) -> DatabaseFileError:
    return DatabaseFileError(msg)


def stored_json(text, what: str):
    """JSON stored in a column (``table.column``), parsed with the file readers' limits; damaged otherwise."""
    return _guard.stored_json(text, what, DatabaseFileError)
