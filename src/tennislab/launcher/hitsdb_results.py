"""The results of :class:`tennislab.launcher.hitsdb.HitsDB`'s workflows: what a database holds
(``launcher info``), a lookup, a drill played from the file, the drills listed and imported.
Each ``to_dict()`` is the JSON its command prints."""

from __future__ import annotations

from dataclasses import dataclass, field

import tennislab.launcher.db as _db
from tennislab.launcher.machine import Settings
from tennislab.launcher.preferences import BRANCH_HIGH, Preferences, Tolerances
from tennislab.results import Result, Table
from tennislab.units import KMH


@dataclass(frozen=True)
class DbInfo(Result):
    """What a database holds (the JSON of ``launcher info``)."""

    path: str
    size_bytes: int
    schema_version: int
    hash: str | None
    created_utc: str | None
    tennislab_version: str | None
    machine: dict | None
    physics: dict | None
    hits: int
    fills: list
    ranges: dict
    drills: list
    quick_check: str | None
    physics_preset: str | None = None  #: the preset whose physics the file stores (None: a physics of its own)


@dataclass(frozen=True)
class LookupResult(Result):
    """The stored hit a lookup chose, with the request (``to_dict()`` has ``launcher aim``'s keys and ``lookup_ms``).

    ``source`` says where the answer comes from: ``table`` (the stored hit), ``refined`` or
    ``inverse-map`` (the machine's aim, when the table holds nothing within 2 cm:
    :func:`tennislab.launcher.lookup.fallback`; ``db.hit_id`` is then null); ``table_miss_mm`` is the
    nearest stored hit's miss (null if none), ``fallback_ms`` the aim's time (null if not asked).
    """

    path: str
    hash: str
    target: tuple
    hit: dict
    lookup_ms: float
    machine: dict
    physics: dict
    rollers: tuple
    asked: dict
    tolerances: Tolerances
    preferences: Preferences
    index_entries_read: int = 0
    hits_read: int = 0
    source: str = "table"
    table_miss_mm: float | None = None
    fallback_ms: float | None = None
    physics_preset: str | None = None  #: the preset whose physics the file stores (None: a physics of its own)

    @property
    def settings(self) -> Settings:
        return Settings(**{k: float(self.hit[k]) for k in _db.HIT_SETTINGS})

    @property
    def miss_mm(self) -> float:
        return float(self.hit["miss_m"]) * 1e3

    @property
    def branch(self) -> str:
        return "high" if int(self.hit.get("branch") or 0) == BRANCH_HIGH else "low"

    def to_dict(self) -> dict:
        h, st = self.hit, self.settings
        dev = {
            "speed_kmh": st.speed_kmh - self.asked["speed_kmh"] if self.asked.get("speed_kmh") is not None else None,
            "spin_rpm": st.spin_rpm - self.asked["spin_rpm"] if self.asked.get("spin_rpm") is not None else None,
        }
        return {
            "solution": "lookup",
            "branch": self.branch,
            "target": {"x": self.target[0], "y": self.target[1]},
            "settings": st.to_dict(),
            "rollers": {"rpm1": self.rollers[0], "rpm2": self.rollers[1]},
            "landing": {"x": float(h["land_x"]), "y": float(h["land_y"])},
            "miss_mm": self.miss_mm,
            "net_clearance_m": float(h["net_clearance_m"]),
            "net_result": "over",
            "flight_time_s": float(h["flight_time_s"]),
            "apex_z_m": float(h["apex_z_m"]),
            "landing_speed_kmh": float(h["bounce_speed_ms"]) / KMH,
            "bounce_spin_rpm": float(h["bounce_spin_rpm"]),
            "asked": self.asked,
            "deviation": dev,
            "trajectory": self.preferences.trajectory,
            "tolerances": self.tolerances.to_dict(),
            "preferences": self.preferences.to_dict(),
            "machine": self.machine,
            "physics": self.physics,
            "physics_preset": self.physics_preset,
            "lookup_ms": self.lookup_ms,
            "source": self.source,
            "table_miss_mm": self.table_miss_mm,
            "fallback_ms": self.fallback_ms,
            "db": {
                "path": self.path,
                "hash": self.hash,
                "hit_id": None if h["id"] is None else int(h["id"]),
                "index_entries_read": self.index_entries_read,
                "hits_read": self.hits_read,
            },
        }


@dataclass(frozen=True)
class PlayResult(Table):
    """A drill run from the database: the timed settings a controller sends (``to_dict()``; ``rows()`` per
    shot, the ``--jsonl`` lines; ``to_frame()`` the same with units in every name)."""

    FRAME_COLUMNS = {
        "rpm1": "roller1_rpm",
        "rpm2": "roller2_rpm",
        "landing_x": "landing_x_m",
        "landing_y": "landing_y_m",
    }

    drill: str
    key: str
    source: str
    path: str
    hash: str
    machine: dict
    distinct: list
    sequence: list = field(default_factory=list)
    physics: dict | None = None  #: the file's physics (as a lookup's ``physics``)
    physics_preset: str | None = None  #: the preset whose physics the file stores (None: a physics of its own)

    @property
    def duration_s(self) -> float:
        return float(sum(r["interval_s"] for r in self.sequence))

    def rows(self) -> list[dict]:
        return list(self.sequence)

    def to_dict(self) -> dict:
        return {
            "drill": self.drill,
            "key": self.key,
            "source": self.source,
            "db": {"path": self.path, "hash": self.hash},
            "machine": self.machine,
            "n_shots": len(self.sequence),
            "n_distinct": len(self.distinct),
            "duration_s": self.duration_s,
            "distinct": self.distinct,
            "sequence": self.sequence,
            "physics": self.physics,
            "physics_preset": self.physics_preset,
        }


@dataclass(frozen=True)
class DrillList(Table):
    """Drills stored in a database and shipped with tennislab (the JSON of ``launcher drills list``)."""

    drills: list

    def rows(self) -> list[dict]:
        return list(self.drills)

    def to_dict(self) -> dict:
        return {"drills": self.drills}


@dataclass(frozen=True)
class DrillsImported(Table):
    """Drills stored by ``import_drills`` (the JSON of ``launcher drills import``): per drill its
    ``name``, ``revision``, ``n_shots`` and ``n_distinct``."""

    imported: list

    def rows(self) -> list[dict]:
        return list(self.imported)

    def to_dict(self) -> dict:
        return {"imported": self.imported}
