"""Training programs ("drills"): shots compiled to the machine's quantised settings and checked.

Wojcicki, Pucilowski & Kulesza (2010, conclusion) propose "the database of different possible
hits and training programs" for the machine's control system; this module is its program part.
A :class:`Drill` is a machine set-up, named shots and a program of items (a shot with repeats, a
sequence with repeats, a random block).  :func:`compile_drill` expands the program into the timed
list of shots the machine fires, aims every distinct shot once (:func:`tennislab.launcher.aim.aim`,
with the shot's trajectory preferences and tolerances) and checks that it clears the net and lands
in its zone (first ground contact of the ball centre, no bounce model).

Random blocks **deal** their ``count`` shots: every shot named in the block is dealt at least once
when ``count`` is at least the number of shots, the rest in proportion to the weights (largest
remainders), and the dealt shots are shuffled with the block's ``seed``.  So a block that lists a
slice among four shots with ``count: 10`` always fires a slice, whatever the seed (an independent
draw with replacement would skip a 1-in-8 slice in a quarter of all sessions).

Shot types (:data:`SHOT_TYPES`, a registry: add one with :func:`register_shot_type`) give defaults
for speed, spin, spin axis, trajectory and height; a drill's ``defaults`` override them and a shot's
own fields override both.  The file format (YAML or JSON, read by :mod:`tennislab.io.drill`) is given
its meaning by :mod:`tennislab.launcher.drill_schema`; docs/launcher.md has the schema.
"""

from __future__ import annotations

import re
from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from tennislab.core.court import ITF_COURT
from tennislab.errors import InputError
from tennislab.launcher.machine import MachineSpec, machine_entry
from tennislab.launcher.preferences import DEFAULT_SPIN_AXIS_TOLERANCE_DEG, Preferences
from tennislab.results import Table

if TYPE_CHECKING:
    from tennislab.core.flight import FlightParams
    from tennislab.launcher.aim import AimSolution


@dataclass(frozen=True)
class ShotType:
    """Defaults of a kind of shot (edge units: km/h, rpm, deg, m); None leaves the drill's value."""

    name: str
    description: str
    speed_kmh: float | None = None
    spin_rpm: float | None = None
    spin_axis_deg: float | None = None
    trajectory: str | None = None
    height_m: float | None = None


#: Registry of shot types by name.
SHOT_TYPES: dict[str, ShotType] = {}


def register_shot_type(t: ShotType) -> ShotType:
    """Add a shot type to :data:`SHOT_TYPES` (name must be new)."""
    if t.name in SHOT_TYPES:
        raise ValueError(f"shot type {t.name!r} already registered")
    SHOT_TYPES[t.name] = t
    return t


# Typical feeds of a ball machine.  Speeds and spins are coaching-practice values within the paper's
# ranges (Wojcicki et al. 2010 section 2: 30-200 km/h, 0-2000 rpm, "maximum ... of the advanced players").
for _t in (
    ShotType("drive", "flat groundstroke feed", 90.0, 300.0, 0.0, "low"),
    ShotType("topspin", "topspin groundstroke feed", 80.0, 1500.0, 0.0, "low"),
    ShotType("slice", "backspin (slice) feed", 70.0, 1000.0, 180.0, "low"),
    ShotType("approach", "short, low ball to approach on", 55.0, 800.0, 180.0, "low"),
    ShotType("volley", "ball to volley, flat and direct", 95.0, 300.0, 0.0, "low"),
    ShotType("passing", "fast topspin ball past a net player", 100.0, 1500.0, 0.0, "low"),
    ShotType("lob", "topspin lob over a net player", 75.0, 1000.0, 0.0, "high"),
    ShotType("smash", "high defensive lob to smash", 65.0, 0.0, 0.0, "high"),
    ShotType("serve-return", "serve from 3 m height to return", 140.0, 500.0, 0.0, "low", 3.0),
):
    register_shot_type(_t)

#: Fields a shot may set and their defaults when nothing sets them.
SHOT_DEFAULTS: dict[str, object] = {
    "speed_kmh": 70.0,
    "spin_rpm": 0.0,
    "spin_axis_deg": 0.0,
    "trajectory": "low",
    "height_m": 1.0,
    "interval_s": 4.0,
    "speed_tolerance_kmh": 3.0,
    "spin_tolerance_rpm": 100.0,
    "spin_axis_tolerance_deg": DEFAULT_SPIN_AXIS_TOLERANCE_DEG,
    "max_apex_m": None,
    "net_clearance_m": None,
    "max_flight_time_s": None,
}


@dataclass(frozen=True)
class ShotSpec:
    """One shot as the machine fires it (resolved: every field set).

    ``target`` (x, y) [m]; ``zone`` a court area name (:meth:`Court.area_bounds`) or a rectangle
    (xmin, xmax, ymin, ymax) [m]; speed [km/h], spin [rpm], spin axis [deg], launch height [m],
    ``solution`` the trajectory (low/high/any), ``interval_s`` the wait after the shot [s]; the
    trajectory bounds and tolerances of :func:`tennislab.launcher.aim.aim`.
    """

    name: str
    type: str
    target: tuple
    zone: object
    speed_kmh: float
    spin_rpm: float
    spin_axis_deg: float
    height_m: float
    solution: str
    interval_s: float
    speed_tolerance_kmh: float = 3.0
    spin_tolerance_rpm: float = 100.0
    spin_axis_tolerance_deg: float = DEFAULT_SPIN_AXIS_TOLERANCE_DEG
    max_apex_m: float | None = None
    net_clearance_m: tuple | None = None
    max_flight_time_s: float | None = None

    @property
    def preferences(self) -> Preferences:
        return Preferences(self.solution, self.max_apex_m, self.net_clearance_m, self.max_flight_time_s)

    @property
    def aim_key(self) -> tuple:
        d = asdict(self)
        for k in ("name", "type", "zone", "interval_s"):
            d.pop(k)
        return tuple((k, tuple(v) if isinstance(v, list) else v) for k, v in sorted(d.items()))

    def zone_bounds(self, court=ITF_COURT) -> tuple:
        if isinstance(self.zone, str):
            return court.area_bounds(self.zone)
        return tuple(self.zone)  # type: ignore[arg-type]

    def zone_label(self) -> str:
        if isinstance(self.zone, str):
            return self.zone
        return "[" + ", ".join(f"{v:g}" for v in self.zone) + "]"  # type: ignore[attr-defined]


@dataclass(frozen=True)
class Repeat:
    """Program item: ``shot`` (a shot name) fired ``repeats`` times."""

    shot: str
    repeats: int = 1


@dataclass(frozen=True)
class Sequence:
    """Program item: the ``items`` in order, the whole sequence ``repeats`` times."""

    items: tuple
    repeats: int = 1


@dataclass(frozen=True)
class RandomChoice:
    """Program item: ``count`` shots dealt from ``shots`` by ``weights`` (module docstring), shuffled by ``seed``."""

    shots: tuple
    weights: tuple
    count: int
    seed: int = 0


@dataclass(frozen=True)
class Drill:
    """A training program: machine set-up, named shots and the program items."""

    name: str
    description: str
    spec: MachineSpec
    shots: dict
    program: tuple
    repeats: int = 1
    source: str = ""
    version: str | None = None

    @property
    def key(self) -> str:
        """The name to type (:func:`drill_key` of the name)."""
        return drill_key(self.name)


def drill_key(name: str) -> str:
    """The one name of a drill on the command line: lower case, words joined by ``_``.

    ``"Baseline rally"``, ``baseline-rally`` and ``baseline_rally.yaml``'s stem all give
    ``baseline_rally``; every command matches a drill by this key.
    """
    return re.sub(r"[^0-9a-z]+", "_", str(name).strip().lower()).strip("_")


def dealt_counts(weights, count: int) -> np.ndarray:
    """Shots per entry of a random block (module docstring): at least one each when ``count`` allows,
    the rest by weight, largest remainders first (ties to the earlier entry)."""
    w = np.asarray(weights, dtype=float)
    k = w.size
    base = np.ones(k, dtype=int) if count >= k else np.zeros(k, dtype=int)
    rest = count - int(base.sum())
    quota = w / w.sum() * count - base  # what each still deserves
    quota = np.maximum(quota, 0.0)
    if quota.sum() > 0:
        quota = quota / quota.sum() * rest
    extra = np.floor(quota).astype(int)
    order = np.lexsort((np.arange(k), -(quota - extra)))
    extra[order[: rest - int(extra.sum())]] += 1
    return base + extra


def _deal(it: RandomChoice) -> list[str]:
    rng = np.random.default_rng(it.seed)
    if it.count < len(it.shots):  # fewer shots than entries: a weighted choice without replacement
        w = np.asarray(it.weights, float)
        idx = rng.choice(len(it.shots), size=it.count, replace=False, p=w / w.sum())
        return [it.shots[i] for i in idx]
    counts = dealt_counts(it.weights, it.count)
    deck = [s for s, c in zip(it.shots, counts) for _ in range(int(c))]
    return [deck[i] for i in rng.permutation(len(deck))]


def expand_program(drill: Drill) -> list[str]:
    """The names of the shots fired, in order (random blocks dealt with their seeds)."""
    out: list[str] = []

    def run(items):
        for it in items:
            if isinstance(it, Repeat):
                out.extend([it.shot] * it.repeats)
            elif isinstance(it, Sequence):
                for _ in range(it.repeats):
                    run(it.items)
            elif isinstance(it, RandomChoice):
                out.extend(_deal(it))
            else:  # pragma: no cover - the schema builds only these
                raise InputError(f"program: unknown item {it!r}")

    for _ in range(drill.repeats):
        run(drill.program)
    return out


def count_shots(items) -> int:
    """Shots fired by program items (without expanding them)."""
    n = 0
    for it in items:
        if isinstance(it, Repeat):
            n += it.repeats
        elif isinstance(it, Sequence):
            n += it.repeats * count_shots(it.items)
        else:
            n += it.count
    return n


@dataclass
class CompiledShot:
    """A distinct shot of a drill with its aim and checks."""

    label: str
    shot: ShotSpec
    solution: AimSolution | None = None
    rollers: tuple = (np.nan, np.nan)
    in_zone: bool = False
    clears_net: bool = False
    problem: str = ""

    @property
    def ok(self) -> bool:
        return self.solution is not None and self.in_zone and self.clears_net


#: Columns of the compiled-drill CSV, in order.
CSV_COLUMNS = (
    "index",
    "time_s",
    "name",
    "type",
    "target_x",
    "target_y",
    "zone",
    "height_m",
    "speed_kmh",
    "elevation_deg",
    "heading_deg",
    "spin_rpm",
    "spin_axis_deg",
    "rpm1",
    "rpm2",
    "interval_s",
    "landing_x",
    "landing_y",
    "miss_mm",
    "net_clearance_m",
    "in_zone",
    "ok",
)


@dataclass(frozen=True)
class CompiledDrill(Table):
    """A drill compiled to machine settings: the distinct shots and the timed sequence (``rows()`` the
    ``--csv`` rows, one per fired shot; ``to_frame()`` the same with units in every name)."""

    COLUMNS = CSV_COLUMNS
    FRAME_COLUMNS = {
        "target_x": "target_x_m",
        "target_y": "target_y_m",
        "rpm1": "roller1_rpm",
        "rpm2": "roller2_rpm",
        "landing_x": "landing_x_m",
        "landing_y": "landing_y_m",
    }

    drill: Drill
    unique: list
    shots: list = field(default_factory=list)  # (index, time_s, CompiledShot)
    params: FlightParams | None = None  #: the physics the shots were aimed with

    @property
    def ok(self) -> bool:
        return all(u.ok for u in self.unique)

    @property
    def duration_s(self) -> float:
        return float(sum(c.shot.interval_s for _, _, c in self.shots))

    def rows(self) -> list[dict]:
        """One flat dict per fired shot (the CSV / JSON rows, :data:`CSV_COLUMNS`)."""
        out = []
        for i, t, c in self.shots:
            s, sol = c.shot, c.solution
            st = sol.settings
            out.append(
                {
                    "index": i,
                    "time_s": t,
                    "name": s.name,
                    "type": s.type,
                    "target_x": s.target[0],
                    "target_y": s.target[1],
                    "zone": s.zone_label(),
                    "height_m": st.height_m,
                    "speed_kmh": st.speed_kmh,
                    "elevation_deg": st.elevation_deg,
                    "heading_deg": st.heading_deg,
                    "spin_rpm": st.spin_rpm,
                    "spin_axis_deg": st.spin_axis_deg,
                    "rpm1": c.rollers[0],
                    "rpm2": c.rollers[1],
                    "interval_s": s.interval_s,
                    "landing_x": sol.landing[0],
                    "landing_y": sol.landing[1],
                    "miss_mm": sol.miss_mm,
                    "net_clearance_m": sol.net_clearance_m,
                    "in_zone": c.in_zone,
                    "ok": c.ok,
                }
            )
        return out

    def to_dict(self) -> dict:
        """The JSON of ``tennislab launcher drill``."""
        d = self.drill
        return {
            "name": d.name,
            "key": d.key,
            "description": d.description,
            "source": d.source,
            "machine": machine_entry(d.spec),
            **({"physics": self.params.to_dict()} if self.params is not None else {}),
            "ok": self.ok,
            "n_shots": len(self.shots),
            "n_distinct": len(self.unique),
            "duration_s": self.duration_s,
            "distinct": [
                {
                    "label": u.label,
                    "name": u.shot.name,
                    "type": u.shot.type,
                    "ok": u.ok,
                    "in_zone": u.in_zone,
                    "clears_net": u.clears_net,
                    "problem": u.problem,
                    "solution": u.solution.solution if u.solution else u.shot.solution,
                    "trajectory": u.shot.solution,
                    "zone": u.shot.zone_label(),
                    "miss_mm": u.solution.miss_mm if u.solution else None,
                    "deviation": u.solution.deviation() if u.solution else None,
                }
                for u in self.unique
            ],
            "shots": self.rows(),
        }


def _aim_shot(shot: ShotSpec, spec: MachineSpec, params: FlightParams) -> AimSolution:
    from tennislab.launcher.aim import aim  # the aim and its flights: loaded by what compiles a drill

    p = shot.preferences
    return aim(
        shot.target,
        shot.speed_kmh,
        shot.spin_rpm,
        shot.spin_axis_deg,
        shot.height_m,
        spec,
        params,
        trajectory=p.trajectory,
        speed_tolerance_kmh=shot.speed_tolerance_kmh,
        spin_tolerance_rpm=shot.spin_tolerance_rpm,
        spin_axis_tolerance_deg=shot.spin_axis_tolerance_deg,
        max_apex_m=p.max_apex_m,
        net_clearance_m=p.net_clearance_m,
        max_flight_time_s=p.max_flight_time_s,
    ).solution


def compile_drill(drill: Drill, params: FlightParams | None = None) -> CompiledDrill:
    """Aim every distinct shot of a drill, check net and zone, and lay out the timed sequence.

    A target the machine cannot reach (or no flight meeting a shot's preferences) raises
    :class:`InputError` naming the shot; a landing outside its zone is reported as a failed
    check (``CompiledDrill.ok`` False), not raised.
    """
    from tennislab.launcher.aim import launcher_params, rollers_rpm

    params = params or launcher_params()
    spec = drill.spec
    names = expand_program(drill)
    by_key: dict = {}
    compiled: dict[str, CompiledShot] = {}
    unique: list[CompiledShot] = []
    for name in dict.fromkeys(names):
        shot = drill.shots[name]
        key = shot.aim_key
        if key not in by_key:
            try:
                by_key[key] = _aim_shot(shot, spec, params)
            except InputError as exc:
                raise InputError(f"shots.{name}: {exc}") from None
        sol = by_key[key]
        x0, x1, y0, y1 = shot.zone_bounds()
        in_zone = bool(x0 <= sol.landing[0] <= x1 and y0 <= sol.landing[1] <= y1)
        clears = sol.net_result == "over" or (
            sol.net_result == "none" and (spec.position[0] < 0) == (sol.landing[0] < 0)
        )
        problem = (
            ""
            if in_zone
            else (f"lands at ({sol.landing[0]:.2f}, {sol.landing[1]:.2f}) m outside zone {shot.zone_label()}")
        )
        if not clears:
            problem = (problem + "; " if problem else "") + "does not clear the net"
        c = CompiledShot(name, shot, sol, rollers_rpm(sol.settings, spec, params), in_zone, clears, problem)
        compiled[name] = c
        unique.append(c)
    out = CompiledDrill(drill, unique, params=params)
    t = 0.0
    for i, name in enumerate(names):
        out.shots.append((i, t, compiled[name]))
        t += drill.shots[name].interval_s
    return out


def drill_trajectories(compiled: CompiledDrill, params: FlightParams | None = None) -> list:
    """The trajectory of every distinct shot of a compiled drill (reference integrator), for figures."""
    from tennislab.launcher.aim import fly_settings, launcher_params

    params = params or launcher_params()
    return [
        None if u.solution is None else fly_settings(u.solution.settings, compiled.drill.spec, params)
        for u in compiled.unique
    ]


__all__ = [
    "drill_trajectories",
    "SHOT_TYPES",
    "SHOT_DEFAULTS",
    "CSV_COLUMNS",
    "ShotType",
    "register_shot_type",
    "ShotSpec",
    "Repeat",
    "Sequence",
    "RandomChoice",
    "Drill",
    "drill_key",
    "dealt_counts",
    "expand_program",
    "count_shots",
    "compile_drill",
    "CompiledDrill",
    "CompiledShot",
]
