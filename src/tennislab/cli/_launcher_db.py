"""``tennislab launcher table | lookup | info | play | drills``: the launcher's database (SQLite).

Registered by :mod:`tennislab.cli.launcher` (:func:`register`)::

    tennislab launcher table  --db FILE [--speed-kmh MIN MAX] [--spin-rpm MIN MAX] [--spin-axis-deg MIN MAX]
                              [--elevation-deg MIN MAX] [--heading-deg MIN MAX] [--height H [H2]] [--step S K]
                              [--drill NAME] [--yes] [--scheduler ...] [machine and physics flags]
    tennislab launcher lookup --db FILE --target X Y [--speed-kmh S] [--spin-rpm W] [preferences] [--json]
    tennislab launcher info   --db FILE [--check] [--json]
    tennislab launcher play   --db FILE --drill NAME [--jsonl | --json]
    tennislab launcher drills list [--db FILE] | import --db FILE DRILL... | export --db FILE [NAME|FILE] [OUT]

See docs/database.md.  Every command calls a :class:`tennislab.launcher.HitsDB` workflow.
"""

from __future__ import annotations

import json
import os
import sys

from tennislab.cli._launcher_args import (
    add_preference_flags,
    add_speed,
    add_tolerance_flags,
    given_flags,
    preference_kwargs,
    spec_from_args,
    speed_kwargs,
    spin_axis_deg,
    tolerance_kwargs,
)
from tennislab.cli.batch_flags import add_scheduler_flag, progress_from_args
from tennislab.cli.common import (
    add_machine_flags,
    add_physics_flags,
    atomic_write,
    emit_json,
    physics_from_args,
    physics_words,
)
from tennislab.errors import InputError, escape_text
from tennislab.io.files import check_output_dir, check_output_path
from tennislab.plot import format_duration, spin_axis_name

_RANGE_FLAGS = (
    ("--speed-kmh", "speed_kmh", "ball speed [km/h]"),
    ("--spin-rpm", "spin_rpm", "spin [rpm]"),
    ("--spin-axis-deg", "spin_axis_deg", "spin-axis rotation [deg]"),
    ("--elevation-deg", "elevation_deg", "elevation [deg]"),
    ("--heading-deg", "heading_deg", "heading [deg]"),
)
_STEP_NAMES = {
    "height": "height_m",
    "speed": "speed_kmh",
    "spin": "spin_rpm",
    "spin-axis": "spin_axis_deg",
    "elevation": "elevation_deg",
    "heading": "heading_deg",
}
#: A fill estimated longer than this [s] needs ``--yes`` (the command's policy, not the library's).
LONG_FILL_S = 3600.0
#: Bytes a stored hit takes in the file, indexes included (docs/database.md).
BYTES_PER_HIT = 460
#: A practical first table (docs/database.md: 2.4e7 settings, ~3 min on 2 cores).
PRACTICAL = "--height 1 --spin-rpm 0 2000 --step spin 250 --spin-axis-deg 0 180 --step spin-axis 180"


def register(sub) -> None:
    """Add ``table``, ``lookup``, ``info``, ``play`` and ``drills`` to the ``launcher`` command's subparsers."""
    p = sub.add_parser(
        "table",
        help="fill the database of hits (settings grid -> landing) in SQLite",
        description="Fly a part of the machine's settings grid (its own steps, within the ranges given) and "
        "store every hit that clears the net and lands in the opposite doubles court in an SQLite file.  "
        "Prints the grid's size and estimated time first (--yes is needed over an hour); resumable: rerun "
        "the same command to continue.  See docs/database.md for sizes and times.",
    )
    p.add_argument("--db", required=True, metavar="FILE", help="SQLite database (created if missing)")
    for flag, _, what in _RANGE_FLAGS:
        p.add_argument(flag, type=float, nargs=2, metavar=("MIN", "MAX"), help=f"{what} range")
    for flag, unit in (("--speed-ms", "m/s"), ("--speed-mph", "mph")):
        p.add_argument(flag, type=float, nargs=2, metavar=("MIN", "MAX"), help=f"ball speed range [{unit}]")
    p.add_argument("--height", type=float, nargs="+", metavar="H", help="launch height [m]: one value, or MIN MAX")
    p.add_argument(
        "--step",
        nargs=2,
        action="append",
        metavar=("SETTING", "K"),
        default=[],
        help="fly every K-th machine step of SETTING (height, speed, spin, spin-axis, elevation, "
        "heading); repeatable (default: every step)",
    )
    p.add_argument("--drill", metavar="NAME", help="fill the settings a drill's shots need (every elevation, heading)")
    p.add_argument("--max-chunks", type=int, metavar="N", help="stop after N chunks (resume later)")
    p.add_argument("--yes", action="store_true", help="start a fill estimated to take over an hour")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    add_machine_flags(p)
    add_physics_flags(p)
    add_scheduler_flag(p)
    p.set_defaults(func=run_table)

    p = sub.add_parser(
        "lookup",
        help="settings that land nearest a target, from the database (or the machine's aim when it has nothing near)",
        description="Answer 'which settings land a ball there' from a table built by `launcher table`: the "
        "stored hit nearest the target among those with the given speed and spin (within the tolerances) "
        "that meets the trajectory preferences; ties: the smaller change of speed, then of spin, then the "
        "larger net clearance.  When the table holds nothing within 2 cm the machine's aim (started from the "
        "reach map) answers if it lands nearer, and says so (source refined or inverse-map); --no-fallback "
        "answers from the table alone.  Machine and physics come from the file; flags given and different "
        "are refused.",
    )
    p.add_argument("--db", required=True, metavar="FILE", help="SQLite database built by `launcher table`")
    p.add_argument("--target", type=float, nargs=2, required=True, metavar=("X", "Y"), help="bounce point [m]")
    add_speed(p, required=False, note="(default: any)")
    p.add_argument("--spin-rpm", type=float, help="spin rate [rpm] (default: any)")
    ex = p.add_mutually_exclusive_group()
    ex.add_argument("--spin-axis", metavar="NAME|DEG", help="only this spin axis (name or degrees; default: any)")
    ex.add_argument("--spin-axis-deg", type=float, help="only this spin-axis rotation [deg] (default: any)")
    p.add_argument("--height", type=float, help="only this launch height [m] (default: any)")
    p.add_argument("--max-miss-m", type=float, default=1.0, help="refuse answers landing farther than this [m] (1)")
    p.add_argument(
        "--no-fallback",
        action="store_true",
        help="answer from the table alone (no flight), however far its nearest hit",
    )
    add_preference_flags(p)
    add_tolerance_flags(p, speed=3.0, spin=100.0, axis=False)
    add_machine_flags(p)
    add_physics_flags(p)
    p.add_argument("--json", action="store_true", help="print one JSON object (keys as `launcher aim`, + lookup_ms)")
    p.set_defaults(func=run_lookup)

    p = sub.add_parser(
        "info",
        help="what a database holds: machine, physics, fills, hits, ranges, drills, schema, hash",
        description="Describe a launcher database without changing it (read-only).",
    )
    p.add_argument("--db", required=True, metavar="FILE", help="SQLite database")
    p.add_argument("--check", action="store_true", help="run PRAGMA quick_check whatever the file's size")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run_info)

    p = sub.add_parser(
        "play",
        help="run a drill from the database: the timed settings a controller sends (no flight)",
        description="Every distinct shot of the drill is looked up in the database (its speed, spin, axis, "
        "height and trajectory preferences); prints the sequence of settings and roller speeds with the "
        "launch interval, without integrating any flight.",
    )
    p.add_argument("--db", required=True, metavar="FILE", help="SQLite database built by `launcher table`")
    p.add_argument("--drill", required=True, metavar="NAME", help="a drill file, a stored drill or a shipped drill")
    p.add_argument("--max-miss-m", type=float, default=1.0, help="refuse shots landing farther than this [m] (1)")
    out = p.add_mutually_exclusive_group()
    out.add_argument("--jsonl", action="store_true", help="one JSON object per shot fired, in order")
    out.add_argument("--json", action="store_true", help="one JSON object")
    p.set_defaults(func=run_play)

    p = sub.add_parser(
        "drills",
        help="list, store and export training programs (drills)",
        description="list: the drills stored in --db and shipped with tennislab (one name each); import DRILL...: "
        "store drill files or shipped drills verbatim (a changed drill of the same name gets the next "
        "revision); export [NAME|FILE] [OUT]: write drills back byte for byte.",
    )
    dsub = p.add_subparsers(dest="drills_action", metavar="list|import|export", parser_class=type(p))
    dsub.required = True
    q = dsub.add_parser("list", help="stored and shipped drills")
    q.add_argument("--db", metavar="FILE", help="SQLite database (default: the shipped drills only)")
    q.add_argument("--json", action="store_true", help="print JSON")
    q.set_defaults(func=run_drills, action="list")
    q = dsub.add_parser("import", help="store drills (files or shipped drill names)")
    q.add_argument("--db", required=True, metavar="FILE", help="SQLite database")
    q.add_argument("files", nargs="+", metavar="DRILL", help="drill file(s) or shipped drill name(s)")
    q.add_argument("--json", action="store_true", help="print JSON")
    q.set_defaults(func=run_drills, action="import")
    q = dsub.add_parser("export", help="write stored drills back byte for byte")
    q.add_argument("--db", required=True, metavar="FILE", help="SQLite database")
    q.add_argument(
        "files",
        nargs="*",
        metavar="ARG",
        help="NAME|FILE (the stored drill of that name, key or file name), NAME OUT, or nothing (every drill "
        "to a safe file name in the working folder); OUT '-' = stdout",
    )
    q.add_argument("--drill", metavar="NAME", help="the stored drill to export (as the first ARG)")
    q.add_argument("--json", action="store_true", help="print JSON")
    q.set_defaults(func=run_drills, action="export")


# ------------------------------------------------------------------- table
def _ranges_from_args(spec, args) -> tuple[dict, dict]:
    ranges: dict = {}
    for _, dest, _ in _RANGE_FLAGS:
        v = getattr(args, dest, None)
        if v is not None:
            ranges[dest] = tuple(v)
    for dest, factor in (("speed_ms", 3.6), ("speed_mph", 1.609344)):
        v = getattr(args, dest, None)
        if v is not None:
            if "speed_kmh" in ranges:
                raise InputError(f"--{dest.replace('_', '-')}: give the speed range once")
            ranges["speed_kmh"] = (round(v[0] * factor, 9), round(v[1] * factor, 9))
    if args.height is not None:
        if len(args.height) not in (1, 2):
            raise InputError(f"--height: expected H or MIN MAX, got {len(args.height)} values")
        ranges["height_m"] = (args.height[0], args.height[-1])
    strides: dict = {}
    for name, k in args.step:
        key = _STEP_NAMES.get(name, name if name in _STEP_NAMES.values() else None)
        if key is None:
            raise InputError(f"--step: unknown setting {name!r}; allowed: {', '.join(_STEP_NAMES)}")
        try:
            strides[key] = int(k)
        except ValueError:
            raise InputError(f"--step {name}: expected an integer number of machine steps, got {k!r}") from None
        if strides[key] < 1:
            raise InputError(f"--step {name}: {strides[key]} is outside the allowed range [1, inf]")
    return ranges, strides


def _drill_grids(spec, params, args, ranges, strides) -> list:
    """One grid per distinct (height, speed, spin, axis) a drill needs, every elevation and heading: the
    settings its shots ask for and those ``launcher drill`` aims them with (within their tolerances)."""
    from tennislab.launcher import HitsDB, compile_drill, find_drill_source, make_grid, parse_drill

    data, source, fmt = find_drill_source(args.drill, stored=HitsDB(args.db) if os.path.exists(args.db) else None)
    d = parse_drill(data, source, fmt)
    comp = compile_drill(d, params)
    if tuple(d.spec.position) != tuple(spec.position):
        raise InputError(
            f"--drill: {d.key} is set up for a machine at ({d.spec.position[0]:g}, {d.spec.position[1]:g}) m; "
            f"give --machine-position {d.spec.position[0]:g} {d.spec.position[1]:g}"
        )
    wanted = {(s.height_m, s.speed_kmh, s.spin_rpm, s.spin_axis_deg) for s in d.shots.values()}
    wanted |= {
        (
            u.solution.settings.height_m,
            u.solution.settings.speed_kmh,
            u.solution.settings.spin_rpm,
            u.solution.settings.spin_axis_deg,
        )
        for u in comp.unique
        if u.solution is not None
    }
    combos = sorted({(h, v, w, 0.0 if w == 0 else g) for h, v, w, g in wanted})
    grids = []
    for h, v, w, g in combos:
        r = dict(ranges)
        r.update(height_m=(h, h), speed_kmh=(v, v), spin_rpm=(w, w), spin_axis_deg=(g, g))
        grids.append(make_grid(spec, r, strides))
    return grids


def run_table(args) -> int:
    # where the fill writes, checked before any work (the plan flies a sample of the grid)
    from tennislab.batch import MANIFEST, read_manifest
    from tennislab.launcher import DEFAULT_CHUNK, FillReports, HitsDB, make_grid, plan_fill

    check_output_path("db", args.db)
    if getattr(args, "out_dir", None) is not None:
        check_output_dir("out_dir", args.out_dir)
        if os.path.exists(os.path.join(args.out_dir, MANIFEST)):
            read_manifest(args.out_dir)  # a malformed manifest: one line, before the plan's sample flies
    spec = spec_from_args(args)
    params = physics_from_args(args)
    ranges, strides = _ranges_from_args(spec, args)
    if args.max_chunks is not None and args.max_chunks < 1:
        raise InputError(f"--max-chunks: {args.max_chunks} is outside the allowed range [1, inf]")
    if args.drill:
        grids = _drill_grids(spec, params, args, ranges, strides)
    elif not ranges and not strides:
        full = plan_fill(spec, params, make_grid(spec))
        raise InputError(
            f"table: no ranges given: the machine's whole grid is {full.grid_rows:.3g} settings, ~"
            f"{full.estimated_hits * BYTES_PER_HIT / 1e12:.3g} TB, estimated {format_duration(full.estimated_s)} here; "
            f"give ranges, e.g. {PRACTICAL} (2.4e7 settings, minutes), or --drill NAME"
        )
    else:
        grids = [make_grid(spec, ranges, strides)]
    chunk = getattr(args, "chunk_size", None) or DEFAULT_CHUNK
    db = HitsDB(args.db)
    db.check_writable(spec, params)  # a foreign file or another machine/physics: refused before any work
    plans = [db.plan(spec, params, g, chunk) for g in grids]
    total_s = sum(pl.estimated_s for pl in plans)
    for pl in plans:
        print(f"table: {_plan_text(pl)}", file=sys.stderr)
    if total_s > LONG_FILL_S and not args.yes:
        raise InputError(
            f"table: the fill is estimated at {format_duration(total_s)} "
            f"({sum(pl.rows_to_fly for pl in plans):,} settings); add --yes to start it, or narrow the ranges"
        )
    reports = []
    for g in grids:
        reports.append(
            db.fill(
                spec,
                params,
                g,
                chunk_size=chunk,
                scheduler=getattr(args, "scheduler", "local"),
                n_workers=getattr(args, "workers", None),
                progress=progress_from_args(args),
                out_dir=getattr(args, "out_dir", None),
                max_chunks=args.max_chunks,
            )
        )
    if args.json:
        emit_json({**FillReports(tuple(reports)).to_dict(), **_physics_json(params, args.physics_preset)})
        return 0
    for rep in reports:
        back = f", {rep.chunks_restored} read back from --out-dir" if rep.chunks_restored else ""
        print(
            f"{rep.path}: {rep.chunks_run - rep.chunks_restored} chunks flown{back} "
            f"({rep.chunks_done_before} already done) of {rep.n_chunks}; grid {rep.grid_rows} settings; "
            f"{rep.hits_inserted} hits added, {rep.hits_total} stored; {rep.seconds:.1f} s; hash {rep.hash[:12]}"
        )
    print(physics_words(params, args.physics_preset))
    return 0


def _physics_json(params, preset: str) -> dict:
    """The JSON's statement of the physics a fill flew: every setting, and the preset it started from."""
    return {"physics": params.to_dict(), "physics_preset": preset}


# ------------------------------------------------------------------ lookup
def run_lookup(args) -> int:
    from tennislab.launcher import HitsDB

    db = HitsDB(args.db)
    given = given_flags(args)
    if given:
        db.check_given(spec_from_args(args), physics_from_args(args), given)
    res = db.lookup(
        tuple(args.target),
        spin_rpm=args.spin_rpm,
        spin_axis_deg=spin_axis_deg(args, None),
        height_m=args.height,
        max_miss_m=args.max_miss_m,
        fallback=not args.no_fallback,
        **speed_kwargs(args),
        **tolerance_kwargs(args),
        **preference_kwargs(args),
    )
    out = res.to_dict()
    if args.json:
        emit_json(out)
        return 0
    s = out["settings"]
    print(
        f"settings: height {s['height_m']:g} m, speed {s['speed_kmh']:g} km/h, elevation "
        f"{s['elevation_deg']:g} deg, heading {s['heading_deg']:g} deg, spin {s['spin_rpm']:g} rpm, "
        f"spin axis {s['spin_axis_deg']:g} deg ({spin_axis_name(s['spin_axis_deg'])}; {out['branch']} trajectory)"
    )
    print(f"rollers: {out['rollers']['rpm1']:.0f} rpm / {out['rollers']['rpm2']:.0f} rpm")
    print(
        f"landing: x = {out['landing']['x']:.3f} m, y = {out['landing']['y']:.3f} m "
        f"(miss {out['miss_mm']:.0f} mm); net clearance {out['net_clearance_m']:.3f} m; apex "
        f"{out['apex_z_m']:.2f} m, {out['flight_time_s']:.2f} s; lookup {out['lookup_ms']:.2f} ms"
    )
    if out["source"] != "table":
        near = (
            "no stored hit"
            if out["table_miss_mm"] is None
            else f"the nearest stored hit lands {out['table_miss_mm']:.0f} mm off"
        )
        how = "refined by the machine's aim" if out["source"] == "refined" else "the machine's aim from its reach map"
        print(f"source: {out['source']} ({near}; {how}, {out['fallback_ms']:.1f} ms)")
    print(physics_words(out["physics"], out["physics_preset"], "the file's"))
    return 0


# -------------------------------------------------------------- info, play
def run_info(args) -> int:
    from tennislab.launcher import HitsDB

    info = HitsDB(args.db).info(check=True if args.check else None)
    if args.json:
        emit_json(info)
    else:
        print("\n".join(_info_lines(info)))
    return 0


def run_play(args) -> int:
    from tennislab.launcher import HitsDB
    from tennislab.results import jsonable

    res = HitsDB(args.db).play(args.drill, max_miss_m=args.max_miss_m)
    if args.jsonl:
        for row in res.sequence:
            print(json.dumps(jsonable(row), separators=(",", ":")))
        return 0
    if args.json:
        emit_json(res)
        return 0
    print(
        f"drill '{escape_text(res.drill)}' ({escape_text(res.key)}) from {escape_text(res.source)}: "
        f"{len(res.sequence)} shots, {len(res.distinct)} distinct, {res.duration_s:g} s"
    )
    for r in res.sequence:
        print(
            f"  t={r['time_s']:6.1f} s  {escape_text(r['shot']):<14} h {r['height_m']:g} speed {r['speed_kmh']:g} elev "
            f"{r['elevation_deg']:g} head {r['heading_deg']:g} spin {r['spin_rpm']:g}@{r['spin_axis_deg']:g}  "
            f"rollers {r['rpm1']:.0f}/{r['rpm2']:.0f} rpm  next in {r['interval_s']:g} s  (miss {r['miss_mm']:.0f} mm)"
        )
    print(physics_words(res.physics, res.physics_preset, "the file's"))
    return 0


# ------------------------------------------------------------------ drills
def run_drills(args) -> int:
    from tennislab.launcher import HitsDB

    if args.action == "list":
        lst = HitsDB(args.db or "").list_drills() if args.db else _shipped_only()
        if args.json:
            emit_json(lst)
            return 0
        for r in lst.drills:
            rev = f"  rev {r['revision']}" if r.get("revision") else ""
            if r.get("shadowed"):
                rev = "  (the stored one answers this name)"
            print(
                f"{escape_text(r['key']):<22} {chr(39) + escape_text(r['name']) + chr(39):<26} {r['source']:<8}{rev}  "
                f"{r['n_shots']} shots ({r['n_distinct']} distinct)"
            )
        return 0
    db = HitsDB(args.db)
    if args.action == "import":
        check_output_path("db", args.db)  # where it goes (a new file) or what it replaces, before anything is read
        res = db.import_drills(args.files)
        if args.json:
            emit_json(res)
        else:
            for r in res.imported:
                print(
                    f"{escape_text(r['name'])}: revision {r['revision']}, {r['n_shots']} shots "
                    f"({r['n_distinct']} distinct)"
                )
        return 0
    files = list(args.files)
    if args.drill:
        files = [args.drill, *files]
    if len(files) > 2:
        raise InputError("drills export: give [NAME] [OUT] or FILE")
    jobs = db.export_sources(files[0] if files else None)
    outs: list[tuple[str, int, str, bytes]] = []
    for dname, drev, safe, data in jobs:
        out: str
        if len(files) == 2:  # NAME OUT: where the user said
            out = files[1]
        elif files and os.path.splitext(files[0])[1].lower() in (".yaml", ".yml", ".json"):  # FILE: as named
            out = files[0]
        else:  # from the data: a safe base name in the working folder, never a stored path
            out = safe
        if out != "-":
            _check_out(out)
        outs.append((dname, drev, out, data))
    done = []
    for dname, drev, out, data in outs:
        if out == "-":
            sys.stdout.buffer.write(data)
            sys.stdout.flush()
            continue
        atomic_write(out, lambda fh, d=data: fh.write(d), mode="wb")
        done.append({"name": dname, "revision": drev, "path": out})
    if args.json:
        emit_json({"exported": done})
    else:
        for d in done:
            print(f"{escape_text(d['name'])} (revision {d['revision']}) -> {escape_text(d['path'])}")
    return 0


def _check_out(path: str) -> None:
    """Refuse an output path that is a directory, under a regular file, or an unusable name (one line,
    before writing anything); the missing folders of the path the user named are created."""
    check_output_path("drills export", path, create_dirs=True)


def _shipped_only():
    from tennislab.launcher import HitsDB

    return HitsDB("<no database>").list_drills()


def _info_lines(info) -> list[str]:
    """``launcher info``'s text: what a database holds (a :class:`~tennislab.launcher.DbInfo`)."""
    lines = [f"{info.path}: tennislab launcher database, schema {info.schema_version}, {info.size_bytes:,} bytes"]
    if info.hash is None:
        lines.append("  empty: no machine yet (fill it with `launcher table`)")
        return lines
    m, p = info.machine or {}, info.physics or {}
    lines.append(f"  hash {info.hash[:12]}, created {info.created_utc} by tennislab {info.tennislab_version}")
    lines.append(
        f"  machine at ({m['position'][0]:g}, {m['position'][1]:g}) m, rollers r {m['roller_radius']:g} m, "
        f"axes {m['roller_axis_distance']:g} m apart"
    )
    b, a = p.get("ball", {}), p.get("atmosphere", {})
    lines.append(
        f"  physics: aero {p.get('aero', {}).get('name')}, ball {b.get('mass')} kg r {b.get('radius')} m, "
        f"air {a.get('density')} kg/m^3, g {a.get('gravity')}, wind {a.get('wind')}, "
        f"spin decay {p.get('spin_decay')}; "
        + (f"preset {info.physics_preset}" if info.physics_preset else "no preset: a physics of its own")
    )
    lines.append(f"  hits: {info.hits:,} in {len(info.fills)} fill(s)")
    for f in info.fills:
        state = "finished" if f["finished_utc"] else f"{f['chunks_done']}/{f['n_chunks']} chunks"
        lines.append(f"    fill {f['id']}: {f['n_rows']:,} settings, {state}")
    for k, r in info.ranges.items():
        if r["count"]:
            lines.append(f"  {k}: {r['min']:g} .. {r['max']:g} ({r['count']} values)")
    names = ", ".join(f"{d['name']} (rev {d['revision']}, {d['n_shots']} shots)" for d in info.drills)
    lines.append(f"  drills: {names or 'none'}")
    if info.quick_check is not None:
        lines.append(f"  quick_check: {info.quick_check}")
    return lines


def _plan_text(pl) -> str:
    """A planned fill's size and estimate (a :class:`~tennislab.launcher.table.FillPlan`), printed before it starts."""
    return (
        f"{pl.grid_rows:,} settings ({' x '.join(str(v) for v in pl.shape.values())}), "
        f"{pl.rows_to_fly:,} to fly in {pl.n_chunks - pl.chunks_done} chunks; "
        f"~{pl.estimated_hits:,} hits; estimated {format_duration(pl.estimated_s)}"
    )
