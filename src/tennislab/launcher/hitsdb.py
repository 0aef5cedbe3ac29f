"""``HitsDB``: the launcher's database file as one object (the workflows behind ``launcher info | lookup |
play | table | drills``).

A database describes itself: its ``machine`` row holds the machine spec, its position and the
physics every hit was flown with, so :meth:`HitsDB.info`, :meth:`HitsDB.lookup` and
:meth:`HitsDB.play` need no machine or physics from the caller.  Settings a caller does give
(``spec``/``params`` with ``given`` naming which) are compared with the file's and refused, naming
the fields, when they differ.

Errors of the file (missing, foreign, truncated, damaged, built for another machine) are one line
starting ``db: PATH:``; a file that fails while in use is checked with ``PRAGMA quick_check`` and
reported as damaged (:func:`tennislab.launcher.db.damaged`).  Readers never write beside the file;
a writer that fails before storing anything leaves no file behind.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import re
import sqlite3
import time
from dataclasses import replace

import tennislab.launcher._dbdrills as _dd
import tennislab.launcher._dbguard as _guard
import tennislab.launcher.db as _db
import tennislab.launcher.lookup as lk
import tennislab.launcher.table as T
from tennislab.core.ball import Ball
from tennislab.core.court import ITF_COURT
from tennislab.errors import InputError
from tennislab.io.drill import drill_format, read_drill_bytes
from tennislab.launcher.drill_schema import (
    drill_record,
    find_drill_source,
    parse_drill,
    shipped_drills,
    shipped_path,
)
from tennislab.launcher.drills import Drill, ShotSpec, drill_key, expand_program
from tennislab.launcher.hitsdb_results import DbInfo, DrillList, DrillsImported, LookupResult, PlayResult
from tennislab.launcher.machine import MachineSpec, Range, Settings, machine_entry, speed_in_kmh
from tennislab.launcher.preferences import Preferences, Tolerances
from tennislab.launcher.rollers import roller_geometry, roller_speeds
from tennislab.units import KMH, RPM

#: Config paths compared when a caller gives a setting (``given`` keys of :meth:`HitsDB.check_given`).
GIVEN_FIELDS = {
    "machine_position": ("position", "machine.position"),
    "roller_radius": ("machine.roller_radius",),
    "roller_axis_distance": ("machine.roller_axis_distance",),
    "aero": ("physics.aero",),
    "cd": ("physics.aero",),
    "cl": ("physics.aero",),
    "aero_table": ("physics.aero",),
    "mass": ("physics.ball.mass",),
    "radius": ("physics.ball.radius",),
    "air_density": ("physics.atmosphere.density",),
    "gravity": ("physics.atmosphere.gravity",),
    "wind": ("physics.atmosphere.wind",),
    "spin_decay": ("physics.spin_decay",),
    # a named preset (tennislab.core.names.PRESETS) sets the aero, the ball and the air
    "physics_preset": (
        "physics.aero",
        "physics.ball.mass",
        "physics.ball.radius",
        "physics.atmosphere.density",
        "physics.atmosphere.gravity",
    ),
}


def spec_from_json(d: dict) -> MachineSpec:
    """A :class:`MachineSpec` from the file's ``spec_json``."""
    ranges = {k: Range(**v) for k, v in d.items() if isinstance(v, dict) and {"lo", "hi", "step"} <= set(v)}
    return MachineSpec(
        **ranges,
        roller_radius=float(d["roller_radius"]),
        roller_axis_distance=float(d["roller_axis_distance"]),
        position=tuple(d["position"]),
    )


def stored_text(name: str) -> str:
    """A file name as it is stored (a text column is UTF-8): bytes of a name that are not UTF-8 kept as
    ``\\xff`` escapes (``os.fsencode`` of the name, decoded with ``backslashreplace``)."""
    try:
        return os.fsencode(name).decode("utf-8", "backslashreplace")
    except (TypeError, ValueError):  # a str that fsencode cannot take (a lone surrogate not from a byte)
        return str(name).encode("utf-8", "backslashreplace").decode("utf-8")


def safe_filename(name: str, key: str) -> str:
    """A base name safe to write in the working folder from a name stored in a file (never a path).

    Directories, ``..``, control and shell characters are dropped; the result keeps a drill
    extension (``.yaml``, ``.yml``, ``.json``; else ``.yaml``) and falls back to ``KEY.yaml``.
    """
    base = os.path.basename(str(name).replace("\\", "/"))
    base = re.sub(r"[^A-Za-z0-9._-]+", "_", base).lstrip(".-_")[:100]
    stem, ext = os.path.splitext(base)
    if ext.lower() not in (".yaml", ".yml", ".json"):
        stem, ext = base, ".yaml"
    stem = stem.strip("._-") or drill_key(key) or "drill"
    return stem[:100] + ext.lower()


class HitsDB:
    """A launcher database file (module docstring).  ``with HitsDB(path) as db:`` keeps one read-only
    connection open for many lookups; every method also works without it."""

    def __init__(self, path: str):
        if not isinstance(path, str | os.PathLike) or not str(path):
            raise InputError("db: give the database file")
        self.path = str(path)
        self._conn: sqlite3.Connection | None = None
        self._cfg: tuple[str, dict] | None = None

    # ----------------------------------------------------------- plumbing
    def __enter__(self) -> HitsDB:
        self._reader()
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        if self._conn is not None:
            self._conn.close()
            self._conn = None

    def _err(self, exc: InputError) -> InputError:
        return InputError(f"db: {self.path}: {exc}")

    @contextlib.contextmanager
    def _errors(self, conn: sqlite3.Connection | None = None):
        """File problems as ``db: PATH: ...``; anything unexpected while reading -> quick_check -> damaged."""
        try:
            with _db.guard(conn):
                yield
        except _db.DatabaseFileError as exc:
            raise self._err(exc) from None

    def _reader(self) -> sqlite3.Connection:
        if self._conn is None:
            with self._errors():
                self._conn = _db.open_readonly(self.path)
        return self._conn

    @contextlib.contextmanager
    def _read(self):
        keep = self._conn is not None
        conn = self._reader()
        _guard.reset_budget(conn)  # each operation gets the whole read budget
        try:
            with self._errors(conn):
                yield conn
        finally:
            if not keep:
                self.close()

    def _config(self, conn) -> tuple[str, dict]:
        if self._cfg is None:
            stored = _db.stored_config(conn)
            if stored is None:
                raise _db.DatabaseFileError("the table is empty (no machine); fill it with `launcher table`")
            self._cfg = stored
        return self._cfg

    # ------------------------------------------------------------ readers
    def spec(self) -> MachineSpec:
        """The machine the file was built for."""
        with self._read() as conn:
            return spec_from_json(self._config(conn)[1]["machine"])

    def check_given(self, spec=None, params=None, given=()) -> None:
        """Refuse settings a caller gave (``given``: keys of :data:`GIVEN_FIELDS`) that differ from the file's."""
        if not given:
            return
        fields = tuple(p for g in given for p in GIVEN_FIELDS.get(g, ()))
        if not fields:
            return
        with self._read() as conn:
            stored = self._config(conn)[1]
            cfg = _db.config_dict(spec if spec is not None else spec_from_json(stored["machine"]), params)
            diffs = _db.config_diff(stored, cfg, fields)
            if diffs:
                what = "; ".join(diffs[:3]) + (f"; and {len(diffs) - 3} more" if len(diffs) > 3 else "")
                raise self._err(
                    _db.DatabaseFileError(f"built for another machine/physics than the flags given: {what}")
                )

    def info(self, check: bool | None = None) -> DbInfo:
        """What the file holds: machine, physics, fills, hits, ranges covered, drills, schema, hash."""
        with self._errors():
            conn = _db.open_readonly(self.path, check=check)
        try:
            with self._errors(conn):
                version = conn.execute("PRAGMA user_version").fetchone()[0]
                row = conn.execute(
                    "SELECT hash, config_json, created_utc, tennislab_version FROM machine WHERE id = 1"
                ).fetchone()
                cfg = _db.stored_json(row[1], "machine.config_json") if row else None
                fills = []
                for r in conn.execute(
                    "SELECT f.id, f.grid_json, f.n_rows, f.chunk_size, f.n_chunks, f.started_utc, f.finished_utc, "
                    "(SELECT count(*) FROM fill_chunks c WHERE c.fill_id = f.id) FROM fills f ORDER BY f.id"
                ):
                    fills.append(
                        {
                            "id": r[0],
                            "n_rows": r[2],
                            "chunk_size": r[3],
                            "n_chunks": r[4],
                            "chunks_done": r[7],
                            "started_utc": r[5],
                            "finished_utc": r[6],
                        }
                    )
                vals = lk.grid_values(conn, cfg["machine"]) if cfg else {}
                ranges = {
                    k: {"min": v[0] if v else None, "max": v[-1] if v else None, "count": len(v)}
                    for k, v in vals.items()
                }
                hits = _db.count_hits(conn)
                drills = _dd.list_drills(conn)
                qc = None
                if check or (check is None and os.path.getsize(self.path) <= _db.QUICK_CHECK_MAX_BYTES):
                    qc = "ok"  # open_readonly ran it
        finally:
            conn.close()
        return DbInfo(
            self.path,
            os.path.getsize(self.path),
            int(version),
            row[0] if row else None,
            row[2] if row else None,
            row[3] if row else None,
            cfg["machine"] if cfg else None,
            cfg["physics"] if cfg else None,
            int(hits),
            fills,
            ranges,
            drills,
            qc,
            stored_preset(cfg["physics"]) if cfg else None,
        )

    def lookup(
        self,
        target,
        speed_kmh: float | None = None,
        spin_rpm: float | None = None,
        *,
        speed_ms: float | None = None,
        speed_mph: float | None = None,
        spin_axis_deg: float | None = None,
        height_m: float | None = None,
        trajectory: str = "low",
        max_apex_m: float | None = None,
        net_clearance_m: tuple[float, float] | None = None,
        max_flight_time_s: float | None = None,
        speed_tolerance_kmh: float = 3.0,
        spin_tolerance_rpm: float = 100.0,
        spin_axis_tolerance_deg: float = 0.0,
        max_miss_m: float = 1.0,
        fallback: bool = True,
    ) -> LookupResult:
        """The stored hit nearest the target among those meeting the request (the ``launcher lookup`` workflow).

        Speed (km/h, or ``speed_ms``/``speed_mph``) and spin rate [rpm] are optional (None: any), each
        matched within its tolerance (0 = the machine step nearest the asked value); with a spin
        axis too, the spin tolerance bounds the change of the spin vector as in ``aim``
        (``spin_axis_tolerance_deg`` lets the axis turn further); ``height_m`` keeps only hits of that
        height; the trajectory preferences filter the hits (default: the low branch).
        Ties: :mod:`tennislab.launcher.lookup`.  When the nearest accepted hit lands farther than
        :data:`~tennislab.launcher.lookup.FALLBACK_M` (or none does) the machine's aim answers if it lands
        nearer (``source`` ``refined`` or ``inverse-map``; :func:`~tennislab.launcher.lookup.fallback`;
        ``fallback=False``: the table only, no flight).
        InputError (naming the parameter) when neither the file nor the aim has an answer within
        ``max_miss_m``.
        """
        prefs = Preferences(trajectory, max_apex_m, net_clearance_m, max_flight_time_s)
        tols = Tolerances(speed_tolerance_kmh, spin_tolerance_rpm, spin_axis_tolerance_deg)
        if not (isinstance(max_miss_m, int | float) and 0 < max_miss_m <= 100):
            raise InputError(f"max_miss_m: {max_miss_m} m is outside the allowed range (0, 100] m")
        with self._read() as conn:
            h, cfg = self._config(conn)
            spec = spec_from_json(cfg["machine"])
            court = ITF_COURT
            x, y = lk.check_target(*_pair("target", target), spec.position[0], court)
            speed = speed_in_kmh(spec, speed_kmh, speed_ms, speed_mph, required=False)
            speed = None if speed is None else spec.speed.quantise(speed)
            spin = None if spin_rpm is None else spec.spin.quantise(spec.spin.check("spin_rpm", spin_rpm))
            where = {}
            vector = None
            axis = None if spin_axis_deg is None else spec.spin_axis.check("spin_axis_deg", spin_axis_deg)
            if height_m is not None:
                rng = spec.height
                q = rng.quantise(rng.check("height_m", height_m))
                where["height_m"] = (q - rng.step / 3, q + rng.step / 3)
            if axis is not None and spin is not None and tols.spin_rpm > 0:
                vector = (spin, axis, tols.spin_rpm, tols.spin_axis_deg)  # aim's rule: the spin vector
            elif axis is not None and spin != 0:  # zero spin is stored once, about the axis nearest 0 deg
                rng = spec.spin_axis
                q = rng.quantise(axis)
                where["spin_axis_deg"] = (q - rng.step / 3, q + rng.step / 3)
            sw = None if speed is None else _window(spec.speed, speed, tols.speed_kmh)
            ww = None if spin is None else _window(spec.spin, spin, tols.spin_rpm)
            query = lk.HitQuery(speed, spin, sw, ww, where, prefs, vector)
            d0 = lk.first_box(lk.table_stats(conn), sw is not None, ww is not None)
            t0 = time.perf_counter()
            hit = lk.nearest_hit(conn, x, y, query=query, max_m=max_miss_m, start_m=d0)
            ms = (time.perf_counter() - t0) * 1e3
            if hit is not None:
                _sane(hit, spec)
            table_miss = None if hit is None else float(hit["miss_m"])
            fb_ms = None
            if fallback and (table_miss is None or table_miss > lk.FALLBACK_M):  # nothing near: the machine's aim
                t1 = time.perf_counter()
                asked_fb = {"speed_kmh": speed, "spin_rpm": spin, "spin_axis_deg": axis, "height_m": height_m}
                alt = lk.fallback(spec, cfg["physics"], (x, y), hit, asked_fb, tols, prefs)
                fb_ms = (time.perf_counter() - t1) * 1e3
                if alt is not None and (table_miss is None or alt["miss_m"] < table_miss - lk.FALLBACK_GAIN_M):
                    if hit is not None:  # the table's search still read what it read
                        alt.update(n_candidates=hit["n_candidates"], n_read=hit["n_read"])
                    hit = alt
            if hit is None:
                raise self._no_hit(conn, x, y, query, max_miss_m)
            ball = Ball(
                **{k: v for k, v in cfg["physics"]["ball"].items() if k in ("mass", "radius", "inertia_factor")}
            )
        st = Settings(**{k: float(hit[k]) for k in _db.HIT_SETTINGS})
        asked = {
            "speed_kmh": speed,
            "spin_rpm": spin,
            "spin_axis_deg": spin_axis_deg,
            "height_m": height_m,
        }
        return LookupResult(
            self.path,
            h,
            (x, y),
            hit,
            ms,
            machine_entry(spec),
            _physics_summary(cfg["physics"]),
            _rollers(st, spec, ball),
            asked,
            tols,
            prefs,
            int(hit["n_candidates"]),
            int(hit["n_read"]),
            hit.get("source", "table"),
            None if table_miss is None else table_miss * 1e3,
            fb_ms,
            stored_preset(cfg["physics"]),
        )

    def _no_hit(self, conn, x, y, q: lk.HitQuery, max_m: float) -> InputError:
        if _db.count_hits_fast(conn) == 0:
            return self._err(_db.DatabaseFileError("the table holds no hits; fill it with `launcher table`"))
        if not lk.has_hits(conn, q):
            rng = lk.table_ranges(conn)
            name = "speed_kmh" if q.speed_kmh is not None else "spin_rpm"
            want = ", ".join(
                f"{k} {v:g}{u}"
                for k, v, u in (("speed", q.speed_kmh, " km/h"), ("spin", q.spin_rpm, " rpm"))
                if v is not None
            )
            return InputError(
                f"{name}: no hit with {want} in the table (filled: speed {rng['speed_kmh'][0]:g}-"
                f"{rng['speed_kmh'][1]:g} km/h, spin {rng['spin_rpm'][0]:g}-{rng['spin_rpm'][1]:g} rpm)"
            )
        p = q.preferences
        free = replace(q, preferences=None)
        if q.speed_kmh is not None and q.spin_rpm is not None:  # explain with the asked speed and spin (fast)
            free = replace(
                free,
                speed_window=(q.speed_kmh - 0.3, q.speed_kmh + 0.3),
                spin_window=(q.spin_rpm - 0.3, q.spin_rpm + 0.3),
            )
        near = None
        if p is not None and lk.any_near(conn, x, y, q, max_m):  # something lands there: say which bound
            near = None
            if p.trajectory != "any":  # the nearest of the asked branch, judged against the other bounds
                only_branch = replace(p, max_apex_m=None, max_flight_time_s=None, net_clearance_m=None)
                near = lk.nearest_hit(conn, x, y, query=replace(free, preferences=only_branch), max_m=max_m)
            if near is None:
                near = lk.nearest_hit(conn, x, y, query=free, max_m=max_m)
        if near is not None and p is not None:
            where = f"within {max_m:g} m of ({x:g}, {y:g}) m"
            if p.trajectory != "any" and int(near.get("branch") or 0) != (0 if p.trajectory == "low" else 1):
                other = "high" if p.trajectory == "low" else "low"
                return InputError(
                    f"trajectory: no {p.trajectory} hit lands {where} (only {other} ones; try trajectory "
                    f"{other} or any, or another speed)"
                )
            for name, bad, what in (
                ("max_apex_m", p.max_apex_m is not None and near["apex_z_m"] > p.max_apex_m, "peaks higher"),
                (
                    "max_flight_time_s",
                    p.max_flight_time_s is not None and near["flight_time_s"] > p.max_flight_time_s,
                    "flies longer",
                ),
                (
                    "net_clearance_m",
                    p.net_clearance_m is not None
                    and not (p.net_clearance_m[0] <= near["net_clearance_m"] <= p.net_clearance_m[1]),
                    "clears the net outside the band",
                ),
            ):
                if bad:
                    return InputError(
                        f"{name}: no hit {where} meets it (the nearest, {near['miss_m']:.3f} m away, {what}: apex "
                        f"{near['apex_z_m']:.2f} m, {near['flight_time_s']:.2f} s, net clearance "
                        f"{near['net_clearance_m']:.2f} m)"
                    )
            return InputError(f"trajectory: no hit {where} meets every preference ({p.describe()})")
        want = ", ".join(
            [f"{k} {v:g}" for k, v in (("speed", q.speed_kmh), ("spin", q.spin_rpm)) if v is not None]
            + [f"{c} {(lh[0] + lh[1]) / 2:g}" for c, lh in q.where.items()]
        )
        return InputError(
            f"target: no hit in range: nothing{' with ' + want if want else ''} lands within "
            f"{max_m:g} m of ({x:g}, {y:g}) m (see max_miss_m)"
        )

    # -------------------------------------------------------------- drills
    def drill_source(self, name: str) -> tuple[bytes, str] | None:
        """(bytes, file name) of the stored drill ``name`` means (name or key), or None."""
        if not os.path.exists(self.path):
            return None
        with self._read() as conn:
            stored = _dd.stored_drill_name(conn, name, drill_key)
            if stored is None:
                return None
            info = _dd.drill_info(conn, stored)
            return _dd.drill_source(conn, stored), info["filename"]

    def load_drill(self, name: str) -> tuple[Drill, str]:
        """(drill, source) for a name: a file, a drill stored here, or a shipped drill (in that order)."""
        data, source, fmt = find_drill_source(name, stored=self)
        return parse_drill(data, source, fmt), source

    def list_drills(self, shipped: bool = True) -> DrillList:
        """The stored drills (if the file exists) and the shipped library, each with one ``key`` to name it."""
        out = []
        if os.path.exists(self.path):
            with self._read() as conn:
                for r in _dd.list_drills(conn):
                    out.append({**r, "key": drill_key(r["name"]), "source": "stored", "shadowed": False})
        if shipped:
            have = {d["key"] for d in out}
            for key in shipped_drills():
                path = shipped_path(key)
                if path is None:
                    continue
                d = parse_drill(read_drill_bytes(path), path, drill_format(path))
                rec = drill_record(d)
                out.append(
                    {
                        "name": d.name,
                        "key": d.key,
                        "source": "shipped",
                        "shadowed": d.key in have,  # a stored drill of the same key answers its name
                        "filename": os.path.basename(path),
                        "format_version": d.version,
                        "revision": None,
                        "n_shots": rec["n_shots"],
                        "n_distinct": rec["n_distinct"],
                        "imported_utc": None,
                    }
                )
        return DrillList(out)

    def import_drills(self, names) -> DrillsImported:
        """Validate every drill (file or shipped name) first, then store them; nothing is created on bad input."""
        parsed = []
        for name in names:
            data, source, fmt = find_drill_source(name)
            d = parse_drill(data, source, fmt)
            fname = stored_text(os.path.basename(source)) if os.path.exists(source) else f"{d.key}.{fmt}"
            parsed.append((drill_record(d), data, fname))
        created = _create_exclusively(self.path)
        mine = [p for p in (self.path + x for x in ("-wal", "-shm", "-journal")) if not os.path.lexists(p)]
        conn = None
        try:
            with self._errors():
                conn = _db.open_db(self.path)
            with self._errors(conn):
                return DrillsImported([_dd.import_drill(conn, rec, data, fname) for rec, data, fname in parsed])
        except BaseException:
            if conn is not None:
                conn.close()
                conn = None
            if created is not None and _same_file(self.path, created):  # a failed import (no space left, ...)
                for p in [self.path, *mine]:  # leaves no new database behind, and never another's
                    with contextlib.suppress(FileNotFoundError):
                        os.unlink(p)
            raise
        finally:
            if conn is not None:
                conn.close()

    def export_sources(self, name: str | None = None) -> list[tuple[str, int, str, bytes]]:
        """(stored name, revision, safe file name, bytes) of one stored drill (name or key) or of all of them."""
        with self._read() as conn:
            rows = _dd.list_drills(conn)
            if name is not None:
                stored = _dd.stored_drill_name(conn, name, drill_key)
                if stored is None:
                    by_file = [r["name"] for r in rows if r["filename"] == stored_text(os.path.basename(name))]
                    stored = by_file[0] if by_file else None
                if stored is None:
                    names = ", ".join(r["name"] for r in rows) or "none"
                    raise InputError(f"drill: {name!r} is neither a stored drill nor its file name (stored: {names})")
                rows = [r for r in rows if r["name"] == stored]
            return [
                (r["name"], r["revision"], safe_filename(r["filename"], r["name"]), _dd.drill_source(conn, r["name"]))
                for r in rows
            ]

    def play(self, drill: str, *, max_miss_m: float = 1.0) -> PlayResult:
        """The timed settings a controller sends for a drill, every shot looked up in this file (no flight).

        ``drill`` names a file, a stored drill or a shipped one.  Each distinct shot is a
        :meth:`lookup` with its target, speed and spin (within its tolerances), height, spin axis
        and trajectory preferences; the sequence lists, per fired shot, the time, the settings,
        the roller speeds and the launch interval.  InputError naming the shot when the file has
        no hit for it.
        """
        d, source = self.load_drill(drill)
        spec = self.spec()
        if tuple(d.spec.position) != tuple(spec.position):
            raise InputError(
                f"drill: {d.key} is set up for a machine at ({d.spec.position[0]:g}, {d.spec.position[1]:g}) m; "
                f"the database's machine stands at ({spec.position[0]:g}, {spec.position[1]:g}) m"
            )
        names = expand_program(d)
        found: dict[str, dict] = {}
        distinct = []
        keep = self._conn is not None
        self._reader()
        try:
            for name in dict.fromkeys(names):
                shot = d.shots[name]
                try:
                    res = self._shot_lookup(shot, max_miss_m)
                except InputError as exc:
                    raise InputError(f"shots.{name}: {exc}") from None
                out = res.to_dict()
                x0, x1, y0, y1 = shot.zone_bounds()
                in_zone = bool(x0 <= out["landing"]["x"] <= x1 and y0 <= out["landing"]["y"] <= y1)
                found[name] = {**out, "in_zone": in_zone}
                distinct.append(
                    {
                        "name": name,
                        "type": shot.type,
                        "zone": shot.zone_label(),
                        "in_zone": in_zone,
                        "settings": out["settings"],
                        "rollers": out["rollers"],
                        "landing": out["landing"],
                        "miss_mm": out["miss_mm"],
                        "branch": out["branch"],
                        "hit_id": out["db"]["hit_id"],
                    }
                )
        finally:
            if not keep:
                self.close()
        seq = []
        t = 0.0
        for i, name in enumerate(names):
            f = found[name]
            interval = d.shots[name].interval_s
            seq.append(
                {
                    "index": i,
                    "time_s": t,
                    "shot": name,
                    **f["settings"],
                    "rpm1": f["rollers"]["rpm1"],
                    "rpm2": f["rollers"]["rpm2"],
                    "interval_s": interval,
                    "landing_x": f["landing"]["x"],
                    "landing_y": f["landing"]["y"],
                    "miss_mm": f["miss_mm"],
                    "in_zone": f["in_zone"],
                    "hit_id": f["db"]["hit_id"],
                }
            )
            t += interval
        with self._read() as conn:
            h = self._config(conn)[0]
        stored = self._config_physics()
        return PlayResult(
            d.name,
            d.key,
            source,
            self.path,
            h,
            machine_entry(spec),
            distinct,
            seq,
            _physics_summary(stored),
            stored_preset(stored),
        )

    def _config_physics(self) -> dict:
        with self._read() as conn:
            return self._config(conn)[1]["physics"]

    def _shot_lookup(self, shot: ShotSpec, max_miss_m: float) -> LookupResult:
        p = shot.preferences
        return self.lookup(
            shot.target,
            shot.speed_kmh,
            shot.spin_rpm,
            spin_axis_deg=shot.spin_axis_deg,
            height_m=shot.height_m,
            trajectory=p.trajectory,
            max_apex_m=p.max_apex_m,
            net_clearance_m=p.net_clearance_m,
            max_flight_time_s=p.max_flight_time_s,
            speed_tolerance_kmh=shot.speed_tolerance_kmh,
            spin_tolerance_rpm=shot.spin_tolerance_rpm,
            spin_axis_tolerance_deg=shot.spin_axis_tolerance_deg,
            max_miss_m=max_miss_m,
            fallback=False,  # a drill plays from the file alone
        )

    # ------------------------------------------------------------- writers
    def plan(self, spec, params, grid: T.TableGrid, chunk_size: int = T.DEFAULT_CHUNK) -> T.FillPlan:
        """Size and estimated time of filling ``grid`` into this file (chunks already stored not counted)."""
        done = 0
        if os.path.exists(self.path) and os.path.getsize(self.path) > 0:
            with self._read() as conn:
                stored = _db.stored_config(conn)
                if stored is not None:
                    _db.check_config(conn, _db.config_dict(spec, params))
                    gh = hashlib.sha256(grid.to_json().encode()).hexdigest()
                    row = conn.execute("SELECT id FROM fills WHERE grid_hash = ?", (gh,)).fetchone()
                    if row is not None:
                        done = conn.execute("SELECT count(*) FROM fill_chunks WHERE fill_id = ?", (row[0],)).fetchone()[
                            0
                        ]
        return T.plan_fill(spec, params, grid, chunk_size, done)

    def check_writable(self, spec, params) -> None:
        """Refuse, before any work, a foreign file or one built for another machine/physics (nothing written)."""
        if os.path.exists(self.path) and (os.path.getsize(self.path) > 0 or os.path.exists(self.path + "-wal")):
            with self._errors():
                conn = _db.open_readonly(self.path, min_version=0, check=False)
            try:
                with self._errors(conn):
                    stored = _db.stored_config(conn)
                    if stored is not None:
                        cfg = _db.config_dict(spec, params)
                        try:
                            _db.check_config(conn, cfg)
                        except _db.DatabaseFileError as exc:
                            raise _db.DatabaseFileError(f"{exc}{_preset_hint(stored[1], cfg)}") from None
            finally:
                conn.close()
        else:
            with self._errors():
                _db._check_path(self.path, must_exist=False)

    def fill(self, spec, params, grid: T.TableGrid, **kw) -> T.FillReport:
        """Fill (or resume) ``grid`` into the file: :func:`tennislab.launcher.table.fill_table`."""
        self.check_writable(spec, params)
        with self._errors():
            return T.fill_table(self.path, spec, params, grid, **kw)


def _pair(name: str, v) -> tuple[float, float]:
    try:
        a, b = (float(x) for x in v)
    except (TypeError, ValueError):
        raise InputError(f"{name}: expected two numbers (x, y) [m], got {v!r}") from None
    return a, b


def _window(rng: Range, value: float, tol: float) -> tuple[float, float]:
    """Stored values accepted around an asked one: within the tolerance, at least a third of a step."""
    half = max(tol, rng.step / 3.0) + 1e-6
    return value - half, value + half


def _sane(hit: dict, spec: MachineSpec) -> None:
    """A hit read from the file must be finite, its settings within the machine's ranges and its results
    within their physical ranges (:data:`tennislab.launcher._dbguard.HIT_RANGES`), else the file is damaged."""
    for k in _db.HIT_SETTINGS:
        v = hit.get(k)
        rng = spec.range_of(k)
        if isinstance(v, bool) or not isinstance(v, int | float) or not (rng.lo - 1e-6 <= v <= rng.hi + 1e-6):
            raise _db.DatabaseFileError(f"damaged file: hit {hit.get('id')} has {k} = {v!r}")
    cols = ["id", *(c for c in (*_db.HIT_RESULTS, "branch") if c in hit)]
    _guard.check_hit_rows(cols, [tuple(hit[c] for c in cols)], _db.DatabaseFileError)


def stored_preset(physics: dict) -> str | None:
    """The physics preset (:data:`tennislab.core.names.PRESETS`) whose physics a file stores, or None (a
    physics of its own: a preset with flags on top).  The file stores the physics, not its preset's name:
    this names it by building each preset as a fill would store it (a file built before ``standard`` was
    the launcher's default, with its flags, says ``seed002``)."""
    from tennislab.core.flight import FlightParams
    from tennislab.core.names import PRESETS

    have = _db.canonical_json(physics)
    for name in PRESETS:
        if _db.canonical_json(_db._stored_physics(FlightParams.from_options(preset=name))) == have:
            return name
    return None


def _preset_hint(stored: dict, cfg: dict) -> str:
    """What to ask for to extend a file whose physics is a preset's (a file built with the launcher's old
    default, ``seed002``, extended with today's ``standard``): "" when the physics is not what differs."""
    have = stored.get("physics")
    if not isinstance(have, dict) or _db.canonical_json(have) == _db.canonical_json(cfg["physics"]):
        return ""
    name = stored_preset(have)
    return f"; the file's physics is preset {name}'s: fill it with that preset" if name else ""


def _physics_summary(p: dict) -> dict:
    return {
        "aero": p.get("aero", {}).get("name"),
        "mass": p.get("ball", {}).get("mass"),
        "radius": p.get("ball", {}).get("radius"),
        "air_density": p.get("atmosphere", {}).get("density"),
        "gravity": p.get("atmosphere", {}).get("gravity"),
        "wind": p.get("atmosphere", {}).get("wind"),
        "spin_decay": p.get("spin_decay"),
    }


def _rollers(st: Settings, spec: MachineSpec, ball: Ball) -> tuple[float, float]:
    g = roller_geometry(spec, ball)
    w1, w2 = roller_speeds(st.speed_kmh * KMH, st.spin_rpm * RPM, spec.roller_radius, g.deformed_radius)
    return float(w1) / RPM, float(w2) / RPM


__all__ = ["HitsDB", "safe_filename", "spec_from_json"]


def _create_exclusively(path: str) -> tuple[int, int] | None:
    """Create ``path`` as an empty file if nothing is there, atomically (``O_EXCL``: a file another process
    makes at the same moment is never taken for ours); its (device, inode), or None when it was not made
    here (it existed, or the folder refuses: the open that follows then says why)."""
    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
    except OSError:
        return None
    try:
        st = os.fstat(fd)
    finally:
        os.close(fd)
    return st.st_dev, st.st_ino


def _same_file(path: str, ident: tuple[int, int]) -> bool:
    """Is ``path`` still the file of ``ident`` (device, inode)?"""
    try:
        st = os.lstat(path)
    except OSError:
        return False
    return (st.st_dev, st.st_ino) == ident
