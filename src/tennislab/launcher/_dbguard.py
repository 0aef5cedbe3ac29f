"""Opening a launcher database that somebody else may have written: what is checked before and while
it is read (docs/security.md, D6-D9).

A hits database is a file a coach may get from anyone.  SQLite runs what a file's schema says: a view
is a query run whenever it is read, a trigger runs on every insert, and both may recurse without end
or delete rows.  So, on every connection tennislab opens:

* :func:`connect` - ``PRAGMA trusted_schema=OFF`` (no function with side effects from the schema) and,
  for readers, a step budget: SQLite's progress handler counts virtual-machine instructions and stops
  any statement past :data:`READ_STEP_BUDGET` per operation (:func:`reset_budget`), so no read can hang.
* :func:`check_schema` - the file's schema (``sqlite_master``) must be exactly the one our own
  migrations create for its version: the same objects with the same SQL text, nothing else (no view,
  no trigger, no virtual table or index we did not create).
* :func:`stored_json` - JSON stored in a column is parsed with the file readers' limits (size, depth,
  duplicate keys; :func:`tennislab.io.formats.load_json_document`).
* :func:`check_hit_rows` - every stored hit read for an answer is finite and within its column's
  physical range (:data:`HIT_RANGES`); :func:`check_drill_row` the same for a stored drill.

Problems are :class:`~tennislab.launcher.db.DatabaseFileError`-like one-line errors (``make_error``
builds them) that say the file is foreign or damaged.
"""

from __future__ import annotations

import functools
import math
import re
import sqlite3

import numpy as np

from tennislab.errors import InputError, escape_text
from tennislab.io.formats import load_json_document
from tennislab.launcher._schema import MIGRATIONS

#: virtual-machine instructions one read operation may run (a lookup needs ~10^4-10^6, ``info`` on a
#: 10^7-hit file ~10^6: a count is one instruction); past it the statement is interrupted
READ_STEP_BUDGET = 200_000_000
#: instructions between two calls of the progress handler
_HANDLER_EVERY = 10_000
#: largest JSON text stored in a column [bytes] (a fill's grid: one index list per setting)
MAX_STORED_JSON = 16_000_000
#: deepest nesting of stored JSON (a machine spec needs 3)
MAX_STORED_DEPTH = 16


class GuardedConnection(sqlite3.Connection):
    """A connection whose statements run within a step budget (readers: :func:`connect`)."""

    budget: int = 0
    steps_left: int = 0

    def _tick(self) -> int:
        self.steps_left -= _HANDLER_EVERY
        return 1 if self.steps_left < 0 else 0  # nonzero: SQLite interrupts the statement


def connect(target: str | bytes, *, uri: bool = False, readonly: bool = True, timeout: float = 30.0):
    """Open a connection with ``trusted_schema=OFF`` and, when ``readonly``, the read step budget."""
    conn = sqlite3.connect(target, uri=uri, timeout=timeout, isolation_level=None, factory=GuardedConnection)
    try:
        conn.execute("PRAGMA trusted_schema=OFF")
        if readonly:
            conn.budget = READ_STEP_BUDGET
            conn.steps_left = READ_STEP_BUDGET
            conn.set_progress_handler(conn._tick, _HANDLER_EVERY)
    except BaseException:
        conn.close()
        raise
    return conn


def reset_budget(conn) -> None:
    """Give a reader connection its full step budget again (at the start of each operation)."""
    if isinstance(conn, GuardedConnection) and conn.budget:
        conn.steps_left = conn.budget


def is_interrupted(exc: BaseException) -> bool:
    """Whether an SQLite error is the step budget stopping a statement."""
    return isinstance(exc, sqlite3.OperationalError) and "interrupted" in str(exc)


# ------------------------------------------------------------------------------ schema
@functools.lru_cache(maxsize=8)
def expected_schema(version: int) -> frozenset:
    """``(type, name, tbl_name, sql)`` of every schema object our migrations create up to ``version``
    (replayed on an empty in-memory database with this SQLite)."""
    conn = sqlite3.connect(":memory:", isolation_level=None)
    try:
        for v in range(1, version + 1):
            conn.executescript(MIGRATIONS[v])
        return frozenset(conn.execute("SELECT type, name, tbl_name, sql FROM sqlite_master").fetchall())
    finally:
        conn.close()


def schema_problem(conn: sqlite3.Connection, version: int) -> str | None:
    """Why the schema of an open file is not exactly ours for ``version`` (None if it is)."""
    try:
        rows = conn.execute("SELECT type, name, tbl_name, sql FROM sqlite_master").fetchall()
    except sqlite3.DatabaseError as exc:
        return f"its schema cannot be read ({str(exc).splitlines()[0][:120]})"
    want = expected_schema(version)
    have = set(rows)
    if len(rows) != len(have):
        return "its schema lists an object twice"
    extra = sorted(have - want, key=lambda r: (str(r[0]), str(r[1])))
    if extra:
        kind, name = extra[0][0], extra[0][1]
        ours = {(r[0], r[1]) for r in want}
        what = "a changed definition of" if (kind, name) in ours else "an object tennislab did not create:"
        return f"{what} {escape_text(kind, 20)} {escape_text(name, 60)!s}"
    missing = sorted(want - have, key=lambda r: (str(r[0]), str(r[1])))
    if missing:
        return f"its {missing[0][0]} {missing[0][1]} is missing"
    return None


def check_schema(conn: sqlite3.Connection, version: int, make_error) -> None:
    """Refuse a file whose schema is not exactly the one tennislab writes for ``version``."""
    if version <= 0 or version not in MIGRATIONS:
        return
    why = schema_problem(conn, version)
    if why is not None:
        raise make_error(
            f"not a tennislab launcher database as tennislab writes it: {why}; refusing to read it "
            "(a file from elsewhere may hold views or triggers that run on every read)"
        )


# ------------------------------------------------------------------------------ stored values
def stored_json(text, what: str, make_error):
    """The JSON stored in column ``what``, parsed with the file readers' limits; damaged otherwise."""
    if isinstance(text, bytes):
        try:
            text = text.decode("utf-8")
        except UnicodeDecodeError:
            raise make_error(f"damaged file: {what} is not UTF-8 text") from None
    if not isinstance(text, str):
        raise make_error(f"damaged file: {what} is {type(text).__name__}, not JSON text")
    if len(text) > MAX_STORED_JSON:
        raise make_error(f"damaged file: {what} is larger than {MAX_STORED_JSON:,} bytes")
    try:
        return load_json_document(text, what, max_depth=MAX_STORED_DEPTH)
    except InputError as exc:
        raise make_error(f"damaged file: {exc}") from None


#: physical range of each stored result column (settings are checked against the machine's ranges)
HIT_RANGES = {
    "land_x": (-40.0, 40.0),  # [m] the court and its margin
    "land_y": (-20.0, 20.0),  # [m]
    "net_clearance_m": (-1e-6, 50.0),  # a stored hit cleared the net
    "flight_time_s": (1e-6, 120.0),
    "bounce_speed_ms": (0.0, 200.0),
    "bounce_spin_rpm": (-1e5, 1e5),
    "apex_z_m": (0.0, 200.0),
    "branch": (0, 1),
}


def check_hit_rows(columns, rows, make_error) -> None:
    """Every value of ``rows`` (tuples in ``columns`` order) in its :data:`HIT_RANGES` range, finite."""
    if not rows:
        return
    cols = [c for c in columns if c in HIT_RANGES]
    if not cols:
        return
    idx = [columns.index(c) for c in cols]
    try:
        a = np.array([[r[i] for i in idx] for r in rows], dtype=float)
    except (TypeError, ValueError):
        raise make_error("damaged file: a stored hit holds a value that is not a number") from None
    lo = np.array([HIT_RANGES[c][0] for c in cols])
    hi = np.array([HIT_RANGES[c][1] for c in cols])
    with np.errstate(invalid="ignore"):
        bad = ~(np.isfinite(a) & (a >= lo) & (a <= hi))
    if bad.any():
        i, j = (int(k[0]) for k in np.nonzero(bad))
        ident = rows[i][columns.index("id")] if "id" in columns else "?"
        raise make_error(
            f"damaged file: hit {ident} has {cols[j]} = {float(a[i, j])!r}, outside [{HIT_RANGES[cols[j]][0]:g}, "
            f"{HIT_RANGES[cols[j]][1]:g}]"
        )


def check_stored_hits(conn: sqlite3.Connection, make_error) -> None:
    """Every stored hit's results in :data:`HIT_RANGES` (one full scan of ``hits``, for ``info --check``):
    a hit no lookup reads (a landing stored as a text, an infinity, a branch 7) is found too.  The scan is
    bounded by the table (the schema is checked first), so it runs without the read step budget."""
    cols = list(HIT_RANGES)
    cond = " OR ".join(
        f"typeof({c}) NOT IN ('real', 'integer') OR {c} NOT BETWEEN {lo!r} AND {hi!r}"
        for c, (lo, hi) in HIT_RANGES.items()
    )
    guarded = conn if isinstance(conn, GuardedConnection) and conn.budget else None
    if guarded is not None:
        guarded.set_progress_handler(None, 0)
    try:
        row = conn.execute(f"SELECT id, {', '.join(cols)} FROM hits WHERE {cond} LIMIT 1").fetchone()
    finally:
        if guarded is not None:
            guarded.set_progress_handler(guarded._tick, _HANDLER_EVERY)
    if row is not None:
        check_hit_rows(["id", *cols], [row], make_error)
        raise make_error(f"damaged file: hit {row[0]} holds a value outside the ranges of a stored hit")


_SHA256 = re.compile(r"[0-9a-f]{64}\Z")
_MAX_TEXT = 1000


def check_drill_row(info: dict, make_error) -> dict:
    """A stored drill's info row (name, file name, revision, counts, ...) has the types and ranges
    tennislab stores; its texts are returned as they are (shown through the escaper when printed)."""
    for key in ("name", "filename", "imported_utc", "sha256"):
        v = info.get(key)
        if not isinstance(v, str) or not v or len(v) > _MAX_TEXT:
            raise make_error(f"damaged file: a stored drill has {key} = {escape_text(repr(v), 80)}")
    if info.get("format_version") is not None and not isinstance(info["format_version"], str):
        raise make_error("damaged file: a stored drill has a format_version that is not a text")
    if not _SHA256.match(info["sha256"]):
        raise make_error(f"damaged file: stored drill {escape_text(info['name'], 60)!r} has a malformed sha256")
    for key, lo, hi in (("revision", 1, 10**9), ("n_distinct", 0, 10**6), ("n_shots", 0, 10**7)):
        v = info.get(key)
        if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
            raise make_error(f"damaged file: stored drill {escape_text(info['name'], 60)!r} has {key} = {v!r}")
    return info


def check_sequence(seq, name: str, make_error) -> list:
    """A stored drill's firing order: a list of shot names (texts)."""
    if not isinstance(seq, list) or not all(isinstance(s, str) and 0 < len(s) <= _MAX_TEXT for s in seq):
        raise make_error(f"damaged file: stored drill {escape_text(name, 60)!r} has a malformed sequence_json")
    return seq


def finite_or_damaged(value, what: str, make_error) -> float:
    """A stored number that must be finite."""
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise make_error(f"damaged file: {what} = {value!r}")
    return float(value)
