"""Reading, validating and writing drill files (YAML or JSON) for the launcher.

Schema (docs/launcher.md has the full description and examples)::

    name: str                      # required
    description: str
    version: int | str             # optional format / content version (stored, not interpreted)
    machine: {position: [x, y], roller_radius_m: r, roller_axis_distance_m: d}
    defaults: {<shot field>: value, ...}      # for every shot (not target/zone)
    shots: {<shot name>: <shot>, ...}         # named shots, or a list [<shot>, ...] (names
                                              # from their ``name`` field or ``shots[i]``)
    program: [<item>, ...]                    # default: every shot once, in order
    repeats: int                              # whole program, 1-1000 (default 1)

    <shot>: {type, target: [x, y], zone: area name | [xmin, xmax, ymin, ymax],
             speed_kmh, spin_rpm, spin_axis_deg, height_m, solution: low|high,
             interval_s, description}
    <item>: {shot: <shot name> | <shot>, repeats: n}
          | {sequence: [<item>, ...], repeats: n}
          | {random: [{shot: <shot name> | <shot>, weight: w}, ...], count: n, seed: s}

Every error is an :class:`InputError` naming the field by its path (e.g.
``program[2].random[0].weight``) and the allowed values.  A shipped drill
(``src/tennislab/data/drills/NAME.yaml``) can be loaded by NAME.
"""

from __future__ import annotations

import csv
import json
import math
import os
from importlib import resources

from tennislab.errors import InputError, check_vector
from tennislab.launcher.drills import SHOT_DEFAULTS, Drill, RandomChoice, Repeat, Sequence, resolve_shot
from tennislab.launcher.machine import DEFAULT_SPEC, MachineSpec

TOP_KEYS = {"name", "description", "version", "machine", "defaults", "shots", "program", "repeats"}
MACHINE_KEYS = {"position", "roller_radius_m", "roller_axis_distance_m"}
SHOT_KEYS = set(SHOT_DEFAULTS) | {"type", "target", "zone", "description", "name"}
MAX_REPEATS = 1000
MAX_SHOTS = 100_000

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


def shipped_drills() -> list[str]:
    """Names of the drills shipped in ``tennislab/data/drills``."""
    d = resources.files("tennislab") / "data" / "drills"
    return sorted(p.name.rsplit(".", 1)[0] for p in d.iterdir() if p.name.endswith((".yaml", ".yml", ".json")))


def _shipped_path(name: str) -> str | None:
    d = resources.files("tennislab") / "data" / "drills"
    for ext in (".yaml", ".yml", ".json"):
        p = d / (name + ext)
        if p.is_file():
            return str(p)
    return None


def load_drill(path_or_name: str, spec: MachineSpec | None = None) -> Drill:
    """Read and validate a drill file (or a shipped drill by name) into a :class:`Drill`."""
    path = path_or_name
    if not os.path.exists(path):
        shipped = _shipped_path(path_or_name)
        if shipped is None:
            raise InputError(
                f"{path_or_name}: no such drill file, and not a shipped drill (shipped: {', '.join(shipped_drills())})"
            )
        path = shipped
    with open(path) as fh:
        text = fh.read()
    return parse_drill(text, source=path, fmt="json" if path.lower().endswith(".json") else "yaml", spec=spec)


def parse_drill(text: str, source: str = "<string>", fmt: str = "yaml", spec: MachineSpec | None = None) -> Drill:
    """Parse drill text (``fmt`` yaml or json) and validate it."""
    try:
        if fmt == "json":
            data = json.loads(text)
        else:
            import yaml

            data = yaml.safe_load(text)
    except Exception as exc:  # the parsers' own errors: one line
        msg = str(exc).replace("\n", " ")
        raise InputError(f"{source}: not valid {fmt.upper()}: {msg}") from None
    try:
        return drill_from_dict(data, source, spec)
    except InputError as exc:
        raise InputError(f"{source}: {exc}") from None


def parse_drill_text(text: str, path: str = "<string>") -> dict:
    """A validated drill as a plain mapping, for storage (e.g. the launcher database).

    Keys: ``name``, ``description``, ``version`` (the file's ``version`` as a string, or None),
    ``machine`` (position, roller geometry), ``shots`` (the distinct named shots, each a dict of
    resolved fields) and ``sequence`` (shot names in firing order).
    """
    fmt = "json" if path.lower().endswith(".json") else "yaml"
    d = parse_drill(text, source=path, fmt=fmt)
    from dataclasses import asdict

    from tennislab.launcher.drills import expand_program

    shots = [asdict(s) for s in d.shots.values()]
    return {
        "name": d.name,
        "description": d.description,
        "version": d.version,
        "machine": {
            "position": list(d.spec.position),
            "roller_radius_m": d.spec.roller_radius,
            "roller_axis_distance_m": d.spec.roller_axis_distance,
        },
        "shots": shots,
        "sequence": expand_program(d),
    }


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
        raise InputError(f"{name}: expected a finite number, got {v!r}")
    return float(v)


def _shot_fields(where: str, raw) -> dict:
    raw = _dict(where, raw, SHOT_KEYS)
    f = {}
    for k, v in raw.items():
        if k in ("type", "solution", "description", "name"):
            if not isinstance(v, str):
                raise InputError(f"{where}.{k}: expected a string, got {v!r}")
            f[k] = v
        elif k == "target":
            f[k] = check_vector(f"{where}.target", v if isinstance(v, (list, tuple)) else [v], 2)
        elif k == "zone":
            if isinstance(v, str):
                f[k] = v
            elif isinstance(v, (list, tuple)):
                f[k] = check_vector(f"{where}.zone", v, 4)
            else:
                raise InputError(f"{where}.zone: expected an area name or [xmin, xmax, ymin, ymax], got {v!r}")
        else:
            f[k] = _number(f"{where}.{k}", v)
    return f


def drill_from_dict(data, source: str = "", spec: MachineSpec | None = None) -> Drill:
    """Validate a parsed drill mapping and build the :class:`Drill` (InputError naming the field)."""
    data = _dict("drill", data, TOP_KEYS)
    name = data.get("name")
    if not isinstance(name, str) or not name.strip():
        raise InputError("name: required, a non-empty string")
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
        from dataclasses import replace

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
        raise InputError(f"version: expected an integer or a string, got {version!r}")
    shots = {}
    raw_shots = data.get("shots", {}) or {}
    if isinstance(raw_shots, list):
        for i, raw in enumerate(raw_shots):
            f = _shot_fields(f"shots[{i}]", raw)
            sname = f.pop("name", f"shots[{i}]")
            if sname in shots:
                raise InputError(f"shots[{i}].name: {sname!r} is used twice")
            shots[sname] = resolve_shot(sname, f, defaults, spec, f"shots[{i}]")
    else:
        for sname, raw in _dict("shots", raw_shots).items():
            sname = str(sname)
            f = _shot_fields(f"shots.{sname}", raw)
            f.pop("name", None)
            shots[sname] = resolve_shot(sname, f, defaults, spec, f"shots.{sname}")

    def shot_ref(where, v):
        if isinstance(v, str):
            if v not in shots:
                raise InputError(f"{where}: unknown shot {v!r}; defined shots: {', '.join(shots) or '(none)'}")
            return v
        key = where
        shots[key] = resolve_shot(key, _shot_fields(where, v), defaults, spec, where)
        return key

    def item(where, raw):
        raw = _dict(where, raw)
        kinds = [k for k in ("shot", "sequence", "random") if k in raw]
        if len(kinds) != 1:
            raise InputError(f"{where}: needs exactly one of shot, sequence, random")
        kind = kinds[0]
        allowed = {
            "shot": {"shot", "repeats"},
            "sequence": {"sequence", "repeats"},
            "random": {"random", "count", "seed"},
        }[kind]
        _dict(where, raw, allowed)
        if kind == "shot":
            return Repeat(
                shot_ref(f"{where}.shot", raw["shot"]), _int(f"{where}.repeats", raw.get("repeats", 1), 1, MAX_REPEATS)
            )
        if kind == "sequence":
            seq = raw["sequence"]
            if not isinstance(seq, list) or not seq:
                raise InputError(f"{where}.sequence: expected a non-empty list of items")
            return Sequence(
                tuple(item(f"{where}.sequence[{i}]", x) for i, x in enumerate(seq)),
                _int(f"{where}.repeats", raw.get("repeats", 1), 1, MAX_REPEATS),
            )
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
        program = tuple(item(f"program[{i}]", x) for i, x in enumerate(prog))
    drill = Drill(
        name.strip(),
        desc.strip(),
        spec,
        shots,
        program,
        _int("repeats", data.get("repeats", 1), 1, MAX_REPEATS),
        source,
        None if version is None else str(version),
    )
    n = _count(program) * drill.repeats
    if n > MAX_SHOTS:
        raise InputError(f"program: expands to {n} shots, more than the allowed {MAX_SHOTS}")
    return drill


def _count(items) -> int:
    n = 0
    for it in items:
        if isinstance(it, Repeat):
            n += it.repeats
        elif isinstance(it, Sequence):
            n += it.repeats * _count(it.items)
        else:
            n += it.count
    return n


def write_drill_csv(compiled, fh) -> None:
    """Write the compiled shot list (one row per fired shot, :data:`CSV_COLUMNS`) to a text stream."""
    w = csv.DictWriter(fh, fieldnames=CSV_COLUMNS, lineterminator="\n")
    w.writeheader()
    for row in compiled.rows():
        w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})
