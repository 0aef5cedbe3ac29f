"""The drill file format: plain data (from :mod:`tennislab.io.drill`) given its meaning, and the drill library.

Schema (docs/launcher.md has the full description and examples)::

    name: str                      # required; its key (lower case, words joined by _) names it everywhere
    description: str
    version: int | str             # optional format / content version (stored, not interpreted)
    machine: {position: [x, y], roller_radius_m: r, roller_axis_distance_m: d}
    defaults: {<shot field>: value, ...}      # for every shot (not target/zone)
    shots: {<shot name>: <shot>, ...}         # named shots, or a list [<shot>, ...] (names
                                              # from their ``name`` field or ``shots[i]``)
    program: [<item>, ...]                    # default: every shot once, in order
    repeats: int                              # whole program, 1-1000 (default 1)

    <shot>: {type, target: [x, y], zone: area name | [xmin, xmax, ymin, ymax],
             speed_kmh, spin_rpm, spin_axis_deg | spin_axis: name, height_m,
             trajectory: low|high|any (or solution: low|high), max_apex_m, net_clearance_m: [min, max],
             max_flight_time_s, speed_tolerance_kmh, spin_tolerance_rpm, spin_axis_tolerance_deg,
             interval_s, description}
    <item>: {shot: <shot name> | <shot>, repeats: n}
          | {sequence: [<item>, ...], repeats: n}
          | {random: [{shot: <shot name> | <shot>, weight: w}, ...], count: n, seed: s}

Every error is an :class:`InputError` naming the field by its path (e.g.
``program[2].random[0].weight``) and the allowed values.

The library: drills shipped in ``tennislab/data/drills`` (:func:`shipped_drills`), found with a
stored drill or a file by one name (:func:`find_drill_source`).
"""

from __future__ import annotations

import math
from dataclasses import asdict, replace
from importlib import resources

from tennislab.core.court import ITF_COURT
from tennislab.core.launch import spin_axis_angle
from tennislab.errors import InputError, check_vector
from tennislab.io.drill import drill_format, parse_drill_bytes, read_drill_bytes
from tennislab.launcher.drills import (
    SHOT_DEFAULTS,
    SHOT_TYPES,
    Drill,
    RandomChoice,
    Repeat,
    Sequence,
    ShotSpec,
    count_shots,
    drill_key,
    expand_program,
)
from tennislab.launcher.machine import DEFAULT_SPEC, MachineSpec
from tennislab.launcher.preferences import TRAJECTORIES, Preferences, Tolerances

TOP_KEYS = {"name", "description", "version", "machine", "defaults", "shots", "program", "repeats"}
MACHINE_KEYS = {"position", "roller_radius_m", "roller_axis_distance_m"}
SHOT_KEYS = set(SHOT_DEFAULTS) | {"type", "target", "zone", "description", "name", "solution", "spin_axis"}
MAX_REPEATS = 1000
MAX_SHOTS = 100_000
MAX_NAMED_SHOTS = 1000
_TEXT_KEYS = ("type", "solution", "trajectory", "description", "name", "spin_axis")


# ------------------------------------------------------------------ fields
def _dict(name, v, allowed=None) -> dict:
    if not isinstance(v, dict):
        raise InputError(f"{name}: expected a mapping, got {type(v).__name__}")
    if allowed is not None:
        extra = sorted(set(map(str, v)) - allowed)
        if extra:
            raise InputError(f"{name}.{extra[0]}: unknown field; allowed: {', '.join(sorted(allowed))}")
    return v


def _int(name, v, lo, hi) -> int:
    if isinstance(v, bool) or not isinstance(v, int) or not (lo <= v <= hi):
        raise InputError(f"{name}: {v!r} is not an integer in the allowed range [{lo}, {hi}]")
    return v


def _number(name, v) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise InputError(f"{name}: expected a finite number, got {v!r}"[:200])
    return float(v)


def _shot_fields(where: str, raw) -> dict:
    raw = _dict(where, raw, SHOT_KEYS)
    f: dict[str, object] = {}
    for k, v in raw.items():
        if k in _TEXT_KEYS:
            if k == "spin_axis" and isinstance(v, (int, float)) and not isinstance(v, bool):
                f[k] = float(v)
                continue
            if not isinstance(v, str):
                raise InputError(f"{where}.{k}: expected a string, got {v!r}"[:200])
            f[k] = v
        elif k == "target":
            f[k] = check_vector(f"{where}.target", v if isinstance(v, (list, tuple)) else [v], 2)
        elif k == "net_clearance_m":
            if v is not None:
                f[k] = check_vector(f"{where}.net_clearance_m", v if isinstance(v, (list, tuple)) else [v], 2)
        elif k == "zone":
            if isinstance(v, str):
                f[k] = v
            elif isinstance(v, (list, tuple)):
                f[k] = check_vector(f"{where}.zone", v, 4)
            else:
                raise InputError(f"{where}.zone: expected an area name or [xmin, xmax, ymin, ymax], got {v!r}"[:200])
        elif v is None and SHOT_DEFAULTS.get(k, 0) is None:
            f[k] = None
        else:
            f[k] = _number(f"{where}.{k}", v)
    if "spin_axis" in f:
        if "spin_axis_deg" in f:
            raise InputError(f"{where}.spin_axis: give spin_axis or spin_axis_deg, not both")
        try:
            f["spin_axis_deg"] = math.degrees(spin_axis_angle(f.pop("spin_axis")))
        except InputError as exc:
            raise InputError(f"{where}.{exc}") from None
    if "solution" in f:
        if "trajectory" in f and f["trajectory"] != f["solution"]:
            raise InputError(f"{where}.solution: contradicts trajectory {f['trajectory']!r}")
        f["trajectory"] = f.pop("solution")
    return f


def resolve_shot(name: str, fields_: dict, defaults: dict, spec: MachineSpec, where: str) -> ShotSpec:
    """Fill a shot's fields from its type and the drill defaults, check ranges; InputError naming ``where``."""
    tname = fields_.get("type", defaults.get("type", "drive"))
    tname = str(tname).strip().lower().replace("_", "-").replace(" ", "-")  # "serve return" -> serve-return
    if tname not in SHOT_TYPES:
        raise InputError(f"{where}.type: unknown shot type {tname!r}; allowed: {', '.join(SHOT_TYPES)}")
    t = SHOT_TYPES[tname]
    val: dict = {}
    for k, dflt in SHOT_DEFAULTS.items():
        if k in fields_:
            val[k] = fields_[k]
        elif k in defaults:
            val[k] = defaults[k]
        elif getattr(t, k, None) is not None:
            val[k] = getattr(t, k)
        else:
            val[k] = dflt
    for k in ("speed_kmh", "spin_rpm", "spin_axis_deg", "height_m"):
        rng = spec.range_of(k)
        val[k] = rng.quantise(rng.check(f"{where}.{k}", val[k]))
    val["interval_s"] = spec.check_interval(val["interval_s"], f"{where}.interval_s")
    if val["trajectory"] not in TRAJECTORIES:
        raise InputError(f"{where}.trajectory: {val['trajectory']!r} is not one of {', '.join(TRAJECTORIES)}")
    try:
        prefs = Preferences(val["trajectory"], val["max_apex_m"], val["net_clearance_m"], val["max_flight_time_s"])
        tols = Tolerances(val["speed_tolerance_kmh"], val["spin_tolerance_rpm"], val["spin_axis_tolerance_deg"])
        prefs.check_height(val["height_m"])
    except InputError as exc:
        raise InputError(f"{where}.{exc}") from None
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
            b = tuple(float(v) for v in zone)  # type: ignore[assignment]
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
    assert target is not None  # given, or the zone's centre
    return ShotSpec(
        name,
        tname,
        (float(target[0]), float(target[1])),
        zone,
        val["speed_kmh"],
        val["spin_rpm"],
        val["spin_axis_deg"],
        val["height_m"],
        prefs.trajectory,
        val["interval_s"],
        tols.speed_kmh,
        tols.spin_rpm,
        tols.spin_axis_deg,
        prefs.max_apex_m,
        prefs.net_clearance_m,
        prefs.max_flight_time_s,
    )


# ------------------------------------------------------------------ drills
def drill_from_dict(data, source: str = "", spec: MachineSpec | None = None) -> Drill:
    """Validate parsed drill data and build the :class:`Drill` (InputError naming the field)."""
    data = _dict("drill", data, TOP_KEYS)
    name = data.get("name")
    if not isinstance(name, str) or not name.strip() or not drill_key(name):
        raise InputError("name: required, a non-empty string with a letter or digit")
    if len(name) > 120:
        raise InputError(f"name: {len(name)} characters is more than the allowed 120")
    desc = data.get("description", "")
    if not isinstance(desc, str):
        raise InputError("description: expected a string")
    spec = spec or DEFAULT_SPEC
    m = _dict("machine", data.get("machine", {}), MACHINE_KEYS)
    kw = {}
    if "position" in m:
        kw["position"] = check_vector("machine.position", m["position"], 2)
    if "roller_radius_m" in m:
        kw["roller_radius"] = _number("machine.roller_radius_m", m["roller_radius_m"])
    if "roller_axis_distance_m" in m:
        kw["roller_axis_distance"] = _number("machine.roller_axis_distance_m", m["roller_axis_distance_m"])
    if kw:
        try:
            spec = replace(spec, **kw)
        except InputError as exc:
            raise InputError(f"machine.{exc}") from None
    defaults = _shot_fields("defaults", data.get("defaults", {}))
    for k in ("target", "zone"):
        if k in defaults:
            raise InputError(f"defaults.{k}: not allowed in defaults (give it per shot)")
    version = data.get("version")
    if version is not None and (isinstance(version, bool) or not isinstance(version, (int, str))):
        raise InputError(f"version: expected an integer or a string, got {version!r}"[:200])
    shots: dict[str, ShotSpec] = {}
    raw_shots = data.get("shots", {}) or {}
    if isinstance(raw_shots, list):
        for i, raw in enumerate(raw_shots):
            f = _shot_fields(f"shots[{i}]", raw)
            sname = str(f.pop("name", f"shots[{i}]"))
            if sname in shots:
                raise InputError(f"shots[{i}].name: {sname!r} is used twice")
            shots[sname] = resolve_shot(sname, f, defaults, spec, f"shots[{i}]")
    else:
        for sname, raw in _dict("shots", raw_shots).items():
            sname = str(sname)
            f = _shot_fields(f"shots.{sname}", raw)
            f.pop("name", None)
            shots[sname] = resolve_shot(sname, f, defaults, spec, f"shots.{sname}")
    if len(shots) > MAX_NAMED_SHOTS:
        raise InputError(f"shots: {len(shots)} shots is more than the allowed {MAX_NAMED_SHOTS}")

    def shot_ref(where, v):
        if isinstance(v, str):
            if v not in shots:
                raise InputError(f"{where}: unknown shot {v!r}; defined shots: {', '.join(shots) or '(none)'}"[:300])
            return v
        shots[where] = resolve_shot(where, _shot_fields(where, v), defaults, spec, where)
        return where

    def item(where, raw, depth):
        if depth > 8:
            raise InputError(f"{where}: sequences nested deeper than 8 levels")
        raw = _dict(where, raw)
        kinds = [k for k in ("shot", "sequence", "random") if k in raw]
        if len(kinds) != 1:
            raise InputError(f"{where}: needs exactly one of shot, sequence, random")
        kind = kinds[0]
        allowed = {
            "shot": {"shot", "repeats"},
            "sequence": {"sequence", "repeats"},
            "random": {"random", "count", "seed"},
        }
        _dict(where, raw, allowed[kind])
        if kind == "shot":
            return Repeat(
                shot_ref(f"{where}.shot", raw["shot"]), _int(f"{where}.repeats", raw.get("repeats", 1), 1, MAX_REPEATS)
            )
        if kind == "sequence":
            seq = raw["sequence"]
            if not isinstance(seq, list) or not seq:
                raise InputError(f"{where}.sequence: expected a non-empty list of items")
            out = Sequence(
                tuple(item(f"{where}.sequence[{i}]", x, depth + 1) for i, x in enumerate(seq)),
                _int(f"{where}.repeats", raw.get("repeats", 1), 1, MAX_REPEATS),
            )
            if count_shots([out]) > MAX_SHOTS:
                raise InputError(f"{where}: expands to {count_shots([out])} shots, more than the allowed {MAX_SHOTS}")
            return out
        ch = raw["random"]
        if not isinstance(ch, list) or not ch:
            raise InputError(f"{where}.random: expected a non-empty list of {{shot, weight}}")
        names, weights = [], []
        for i, c in enumerate(ch):
            c = _dict(f"{where}.random[{i}]", c, {"shot", "weight"})
            if "shot" not in c:
                raise InputError(f"{where}.random[{i}].shot: required")
            names.append(shot_ref(f"{where}.random[{i}].shot", c["shot"]))
            w = _number(f"{where}.random[{i}].weight", c.get("weight", 1.0))
            if not (0 < w <= 1e6):
                raise InputError(f"{where}.random[{i}].weight: {w:g} is outside the allowed range (0, 1e6]")
            weights.append(w)
        return RandomChoice(
            tuple(names),
            tuple(weights),
            _int(f"{where}.count", raw.get("count", 1), 1, MAX_REPEATS),
            _int(f"{where}.seed", raw.get("seed", 0), 0, 2**32 - 1),
        )

    prog = data.get("program")
    if prog is None:
        if not shots:
            raise InputError(
                "shots: no shots and no program (give shots, or a program of shot, sequence or random items)"
            )
        program = tuple(Repeat(n) for n in shots)  # default: every shot once, in order
    else:
        if not isinstance(prog, list) or not prog:
            raise InputError("program: a non-empty list of items (shot, sequence or random) if given")
        program = tuple(item(f"program[{i}]", x, 0) for i, x in enumerate(prog))
    repeats = _int("repeats", data.get("repeats", 1), 1, MAX_REPEATS)
    n = count_shots(program) * repeats
    if n > MAX_SHOTS:
        raise InputError(f"program: expands to {n} shots, more than the allowed {MAX_SHOTS}")
    return Drill(
        name.strip(), desc.strip(), spec, shots, program, repeats, source, None if version is None else str(version)
    )


def parse_drill(data, source: str = "<string>", fmt: str = "yaml", spec: MachineSpec | None = None) -> Drill:
    """A :class:`Drill` from a drill file's text or bytes (``fmt`` yaml or json); errors start with ``source``."""
    raw = data.encode("utf-8") if isinstance(data, str) else bytes(data)
    plain = parse_drill_bytes(raw, source, fmt)
    try:
        return drill_from_dict(plain, source, spec)
    except InputError as exc:
        raise InputError(f"{source}: {exc}") from None


def drill_record(drill: Drill) -> dict:
    """A validated drill as plain data for storage: name, key, description, version, machine, the
    distinct shots (resolved fields) and the firing sequence (shot names)."""
    seq = expand_program(drill)
    return {
        "name": drill.name,
        "key": drill.key,
        "description": drill.description,
        "version": drill.version,
        "machine": {
            "position": list(drill.spec.position),
            "roller_radius_m": drill.spec.roller_radius,
            "roller_axis_distance_m": drill.spec.roller_axis_distance,
        },
        "shots": [asdict(s) for s in drill.shots.values()],
        "sequence": seq,
        "n_shots": len(seq),
        "n_distinct": len(drill.shots),
    }


# ------------------------------------------------------------------ library
def _shipped_dir():
    return resources.files("tennislab") / "data" / "drills"


def shipped_drills() -> list[str]:
    """Keys of the drills shipped in ``tennislab/data/drills`` (their file stems)."""
    return sorted(
        p.name.rsplit(".", 1)[0] for p in _shipped_dir().iterdir() if p.name.endswith((".yaml", ".yml", ".json"))
    )


def shipped_path(name: str) -> str | None:
    """The shipped drill file of a name or key, or None."""
    key = drill_key(name)
    for p in _shipped_dir().iterdir():
        if p.name.endswith((".yaml", ".yml", ".json")) and drill_key(p.name.rsplit(".", 1)[0]) == key:
            return str(p)
    return None


def load_drill(path_or_name: str, spec: MachineSpec | None = None) -> Drill:
    """A drill from a file, or a shipped drill by name (InputError listing the shipped ones)."""
    data, source, fmt = find_drill_source(path_or_name)
    return parse_drill(data, source, fmt, spec)


def find_drill_source(name: str, stored=None) -> tuple[bytes, str, str]:
    """(bytes, source label, format) of the drill ``name`` means: a file, a stored drill, or a shipped one.

    Order: an existing file path; then a drill stored in ``stored`` (a :class:`~.hitsdb.HitsDB` or
    anything with ``drill_source(name) -> (bytes, filename) | None``) whose name or key matches;
    then a shipped drill by key.  InputError (naming ``drill``) when none matches.
    """
    import os

    if not isinstance(name, str) or not name.strip():
        raise InputError("drill: give a drill name or file")
    if os.path.exists(name):
        return read_drill_bytes(name), name, drill_format(name)
    if stored is not None:
        found = stored.drill_source(name)
        if found is not None:
            data, filename = found
            return data, f"stored drill {drill_key(name)}", drill_format(filename)
    path = shipped_path(name)
    if path is not None:
        return read_drill_bytes(path), path, drill_format(path)
    known = shipped_drills()
    where = " stored in the database," if stored is not None else ""
    raise InputError(f"drill: {name!r} is not a file,{where} nor a shipped drill (shipped: {', '.join(known)})"[:400])


__all__ = [
    "drill_from_dict",
    "parse_drill",
    "drill_record",
    "resolve_shot",
    "shipped_drills",
    "shipped_path",
    "load_drill",
    "find_drill_source",
]
