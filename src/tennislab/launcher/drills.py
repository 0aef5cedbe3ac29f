"""Training programs ("drills"): shots compiled to the machine's quantised settings and checked.

Seed 002 (conclusion) proposes "the database of different possible hits and
training programs" for the machine's control system; this module is its
program part.  A :class:`Drill` is a machine set-up, named shots and a program
of items (a shot with repeats, a sequence with repeats, a weighted random
choice among shots).  :func:`compile_drill` expands the program into the
timed list of shots the machine fires, aims every distinct shot once
(:func:`tennislab.launcher.aim.aim`) and checks that it clears the net and
lands in its zone (first ground contact of the ball centre, no bounce model).

Shot types (:data:`SHOT_TYPES`, a registry: add one with :func:`register_shot_type`)
give defaults for speed, spin, spin axis, solution and height; a drill's
``defaults`` override them and a shot's own fields override both.  The file
format (YAML or JSON) is read by :mod:`tennislab.io.drill`; schema in
docs/launcher.md.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from tennislab.core.court import ITF_COURT
from tennislab.core.flight import FlightParams
from tennislab.errors import InputError
from tennislab.launcher.machine import MachineSpec


@dataclass(frozen=True)
class ShotType:
    """Defaults of a kind of shot (edge units: km/h, rpm, deg, m); None leaves the drill's value."""

    name: str
    description: str
    speed_kmh: float | None = None
    spin_rpm: float | None = None
    spin_axis_deg: float | None = None
    solution: str | None = None
    height_m: float | None = None


#: Registry of shot types by name.
SHOT_TYPES: dict[str, ShotType] = {}


def register_shot_type(t: ShotType) -> ShotType:
    """Add a shot type to :data:`SHOT_TYPES` (name must be new)."""
    if t.name in SHOT_TYPES:
        raise ValueError(f"shot type {t.name!r} already registered")
    SHOT_TYPES[t.name] = t
    return t


# Typical feeds of a ball machine.  Speeds and spins are coaching-practice values within the
# seed's ranges (seed 002 section 2: 30-200 km/h, 0-2000 rpm, "maximum ... of the advanced players").
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
SHOT_DEFAULTS = {
    "speed_kmh": 70.0,
    "spin_rpm": 0.0,
    "spin_axis_deg": 0.0,
    "solution": "low",
    "height_m": 1.0,
    "interval_s": 4.0,
}


@dataclass(frozen=True)
class ShotSpec:
    """One shot as the machine fires it (resolved: every field set).

    ``target`` (x, y) [m]; ``zone`` a court area name (:meth:`Court.area_bounds`)
    or a rectangle (xmin, xmax, ymin, ymax) [m]; speed [km/h], spin [rpm], spin
    axis [deg], launch height [m], ``solution`` low/high, ``interval_s`` the
    wait after the shot [s].
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

    @property
    def aim_key(self) -> tuple:
        return (self.target, self.speed_kmh, self.spin_rpm, self.spin_axis_deg, self.height_m, self.solution)

    def zone_bounds(self, court=ITF_COURT) -> tuple:
        if isinstance(self.zone, str):
            return court.area_bounds(self.zone)
        return tuple(self.zone)

    def zone_label(self) -> str:
        return self.zone if isinstance(self.zone, str) else "[" + ", ".join(f"{v:g}" for v in self.zone) + "]"


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
    """Program item: ``count`` shots drawn with replacement from ``shots`` with ``weights``."""

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


def resolve_shot(name: str, fields_: dict, defaults: dict, spec: MachineSpec, where: str) -> ShotSpec:
    """Fill a shot's fields from its type and the drill defaults, check ranges; InputError naming ``where``."""
    tname = fields_.get("type", defaults.get("type", "drive"))
    tname = str(tname).strip().lower().replace("_", "-").replace(" ", "-")  # "serve return" -> serve-return
    if tname not in SHOT_TYPES:
        raise InputError(f"{where}.type: unknown shot type {tname!r}; allowed: {', '.join(SHOT_TYPES)}")
    t = SHOT_TYPES[tname]
    val = {}
    for k, dflt in SHOT_DEFAULTS.items():
        if k in fields_:
            val[k] = fields_[k]
        elif k in defaults:
            val[k] = defaults[k]
        elif getattr(t, k, None) is not None:
            val[k] = getattr(t, k)
        else:
            val[k] = dflt
    for k, rng_field in (
        ("speed_kmh", "speed_kmh"),
        ("spin_rpm", "spin_rpm"),
        ("spin_axis_deg", "spin_axis_deg"),
        ("height_m", "height_m"),
    ):
        rng = spec.range_of(rng_field)
        val[k] = rng.quantise(rng.check(f"{where}.{k}", val[k]))
    val["interval_s"] = spec.check_interval(val["interval_s"], f"{where}.interval_s")
    if val["solution"] not in ("low", "high"):
        raise InputError(f"{where}.solution: {val['solution']!r} is not one of low, high")
    zone = fields_.get("zone")
    target = fields_.get("target")
    if zone is None and target is None:
        raise InputError(f"{where}: needs a target [x, y] or a zone (area name or [xmin, xmax, ymin, ymax])")
    if zone is not None:
        if isinstance(zone, str):
            try:
                b = ITF_COURT.area_bounds(zone)
            except InputError as exc:
                raise InputError(f"{where}.zone: {exc}") from None
        else:
            b = tuple(float(v) for v in zone)
            if len(b) != 4 or not (b[0] < b[1] and b[2] < b[3]):
                raise InputError(f"{where}.zone: expected [xmin, xmax, ymin, ymax] with xmin < xmax, ymin < ymax")
            zone = b
        if target is None:
            target = (0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]))
        elif not (b[0] <= target[0] <= b[1] and b[2] <= target[1] <= b[3]):
            raise InputError(
                f"{where}.target: ({target[0]:g}, {target[1]:g}) m is outside its zone "
                f"[{b[0]:g}, {b[1]:g}] x [{b[2]:g}, {b[3]:g}] m"
            )
    else:
        zone = "full-doubles"
    return ShotSpec(
        name,
        tname,
        (float(target[0]), float(target[1])),
        zone,
        val["speed_kmh"],
        val["spin_rpm"],
        val["spin_axis_deg"],
        val["height_m"],
        val["solution"],
        val["interval_s"],
    )


def expand_program(drill: Drill) -> list[str]:
    """The names of the shots fired, in order (random choices drawn with their seeds)."""
    out: list[str] = []

    def run(items):
        for it in items:
            if isinstance(it, Repeat):
                out.extend([it.shot] * it.repeats)
            elif isinstance(it, Sequence):
                for _ in range(it.repeats):
                    run(it.items)
            elif isinstance(it, RandomChoice):
                rng = np.random.default_rng(it.seed)
                w = np.asarray(it.weights, float)
                idx = rng.choice(len(it.shots), size=it.count, p=w / w.sum())
                out.extend(it.shots[i] for i in idx)
            else:  # pragma: no cover - the loader builds only these
                raise InputError(f"program: unknown item {it!r}")

    for _ in range(drill.repeats):
        run(drill.program)
    return out


@dataclass
class CompiledShot:
    """A distinct shot of a drill with its aim and checks."""

    label: str
    shot: ShotSpec
    solution: object = None  #: :class:`~tennislab.launcher.aim.AimSolution`
    rollers: tuple = (np.nan, np.nan)
    in_zone: bool = False
    clears_net: bool = False
    problem: str = ""

    @property
    def ok(self) -> bool:
        return self.solution is not None and self.in_zone and self.clears_net


@dataclass
class CompiledDrill:
    """A drill compiled to machine settings: the distinct shots and the timed sequence."""

    drill: Drill
    unique: list
    shots: list = field(default_factory=list)  # (index, time_s, CompiledShot)

    @property
    def ok(self) -> bool:
        return all(u.ok for u in self.unique)

    @property
    def duration_s(self) -> float:
        return float(sum(c.shot.interval_s for _, _, c in self.shots))

    def rows(self) -> list[dict]:
        """One flat dict per fired shot (the CSV / JSON rows)."""
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

    def as_dict(self) -> dict:
        d = self.drill
        return {
            "name": d.name,
            "description": d.description,
            "source": d.source,
            "machine": {
                "position": list(d.spec.position),
                "roller_radius_m": d.spec.roller_radius,
                "roller_axis_distance_m": d.spec.roller_axis_distance,
            },
            "ok": self.ok,
            "n_shots": len(self.shots),
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
                    "solution": u.shot.solution,
                    "zone": u.shot.zone_label(),
                }
                for u in self.unique
            ],
            "shots": self.rows(),
        }


def compile_drill(drill: Drill, params: FlightParams | None = None) -> CompiledDrill:
    """Aim every distinct shot of a drill, check net and zone, and lay out the timed sequence.

    A target the machine cannot reach raises :class:`InputError` naming the
    shot; a landing outside its zone (from quantisation) is reported as a
    failed check (``CompiledDrill.ok`` False), not raised.
    """
    from tennislab.launcher.aim import aim, aim_result_dict, launcher_params

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
                sol = aim(
                    shot.target,
                    shot.speed_kmh,
                    shot.spin_rpm,
                    shot.spin_axis_deg,
                    shot.height_m,
                    spec,
                    params,
                    solution=shot.solution,
                )
            except InputError as exc:
                raise InputError(f"shots.{name}: {exc}") from None
            by_key[key] = sol
        sol = by_key[key]
        r = aim_result_dict(sol, spec, params)["rollers"]
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
        c = CompiledShot(name, shot, sol, (r["rpm1"], r["rpm2"]), in_zone, clears, problem)
        compiled[name] = c
        unique.append(c)
    out = CompiledDrill(drill, unique)
    t = 0.0
    for i, name in enumerate(names):
        out.shots.append((i, t, compiled[name]))
        t += drill.shots[name].interval_s
    return out


__all__ = [
    "SHOT_TYPES",
    "ShotType",
    "register_shot_type",
    "ShotSpec",
    "Repeat",
    "Sequence",
    "RandomChoice",
    "Drill",
    "resolve_shot",
    "expand_program",
    "compile_drill",
    "CompiledDrill",
    "CompiledShot",
]
