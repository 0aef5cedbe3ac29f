"""The launcher database's training programs (tables ``drills`` and ``drill_shots``, see
:mod:`tennislab.launcher.db`): a drill file's bytes stored verbatim with its validated shots and sequence,
revisions, and every stored row checked on the way out (:mod:`tennislab.launcher._dbguard`)."""

from __future__ import annotations

import hashlib
import os
import sqlite3

import tennislab.launcher._dbguard as _guard
from tennislab.errors import InputError, escape_text
from tennislab.launcher.db import DatabaseFileError, _damaged, _now, _plain, canonical_json, stored_json


def import_drill(conn: sqlite3.Connection, record: dict, data: bytes, filename: str) -> dict:
    """Store a drill (its file's bytes verbatim, and its validated record: shots, sequence); a changed
    drill of the same name gets the next revision; re-importing identical bytes changes nothing.

    ``record`` is :func:`tennislab.launcher.drill_schema.drill_record` of the parsed file and
    ``filename`` the base name it is exported under by default.  Returns the drill's info row.
    """
    name, version = record["name"], record.get("version")
    shots, seq = [_plain(x) for x in record["shots"]], _plain(record["sequence"])
    sha = hashlib.sha256(data).hexdigest()
    filename = os.path.basename(filename)
    list_drills(conn)  # the stored drills are what tennislab stores, checked before anything is written
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
                (filename, version, rev, sha, data, canonical_json(seq), _now(), row[0]),
            )
            did = row[0]
        else:
            did = conn.execute(
                "INSERT INTO drills (name, filename, format_version, revision, sha256, source, "
                "sequence_json, imported_utc) VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                (name, filename, version, rev, sha, data, canonical_json(seq), _now()),
            ).lastrowid
        conn.executemany(
            "INSERT INTO drill_shots VALUES (?, ?, ?)", [(did, i, canonical_json(s)) for i, s in enumerate(shots)]
        )
        conn.execute("COMMIT")
    except BaseException:
        if conn.in_transaction:
            conn.execute("ROLLBACK")
        raise
    return drill_info(conn, name)


_INFO_SQL = (
    "SELECT d.name, d.filename, d.format_version, d.revision, d.sha256, d.imported_utc, "
    "(SELECT count(*) FROM drill_shots s WHERE s.drill_id = d.id), d.sequence_json FROM drills d "
)


def _info_row(row) -> dict:
    keys = ("name", "filename", "format_version", "revision", "sha256", "imported_utc", "n_distinct")
    out = dict(zip(keys, row[:7]))
    seq = _guard.check_sequence(stored_json(row[7], "drills.sequence_json") if row[7] else [], str(row[0]), _damaged)
    out["n_shots"] = len(seq)
    return _guard.check_drill_row(out, _damaged)


def stored_drill_name(conn: sqlite3.Connection, name: str, key_of) -> str | None:
    """The stored drill a name means: the same name, or the same key (``key_of``), or None."""
    rows = [r[0] for r in conn.execute("SELECT name FROM drills ORDER BY name")]
    if name in rows:
        return name
    want = key_of(name)
    hits = [r for r in rows if key_of(r) == want]
    return hits[0] if hits else None


def drill_info(conn: sqlite3.Connection, name: str) -> dict:
    """Name, file name, revision, counts (``n_shots`` fired, ``n_distinct``) of a stored drill."""
    row = conn.execute(_INFO_SQL + "WHERE d.name = ?", (name,)).fetchone()
    if row is None:
        names = [r[0] for r in conn.execute("SELECT name FROM drills ORDER BY name")]
        raise InputError(f"drill: {name!r} is not in the database (stored: {', '.join(names) or 'none'})"[:400])
    return _info_row(row)


def list_drills(conn: sqlite3.Connection) -> list[dict]:
    return [_info_row(r) for r in conn.execute(_INFO_SQL + "ORDER BY d.name").fetchall()]


def drill_source(conn: sqlite3.Connection, name: str) -> bytes:
    """The drill file exactly as imported."""
    info = drill_info(conn, name)
    data = conn.execute("SELECT source FROM drills WHERE name = ?", (name,)).fetchone()[0]
    data = data.encode("utf-8", "surrogatepass") if isinstance(data, str) else data
    if not isinstance(data, bytes) or hashlib.sha256(data).hexdigest() != info["sha256"]:
        raise DatabaseFileError(f"damaged file: stored drill {escape_text(name, 60)!r} differs from its sha256")
    return data


def drill_sequence(conn: sqlite3.Connection, name: str) -> list | None:
    """Shot names in firing order (the drill's expanded program), as stored at import."""
    drill_info(conn, name)
    row = conn.execute("SELECT sequence_json FROM drills WHERE name = ?", (name,)).fetchone()
    if row[0] is None:
        return None
    return _guard.check_sequence(stored_json(row[0], "drills.sequence_json"), name, _damaged)


def drill_shots(conn: sqlite3.Connection, name: str) -> list[dict]:
    """The drill's distinct shots (resolved fields), in file order."""
    drill_info(conn, name)
    return [
        stored_json(r[0], "drill_shots.shot_json")
        for r in conn.execute(
            "SELECT s.shot_json FROM drill_shots s JOIN drills d ON d.id = s.drill_id WHERE d.name = ? ORDER BY s.idx",
            (name,),
        )
    ]
