"""``tennislab launcher table | lookup | drills``: the launcher's database (SQLite).

Called by :mod:`tennislab.cli.launcher` through :func:`register_launcher`::

    tennislab launcher table --db FILE [--speed-kmh MIN MAX] [--spin-rpm MIN MAX] [--spin-axis-deg MIN MAX]
                             [--elevation-deg MIN MAX] [--heading-deg MIN MAX] [--height H [H2]]
                             [--machine-position X Y] [--scheduler local|processes|tcp://HOST:PORT] [physics flags]
    tennislab launcher lookup --db FILE --target X Y [--speed-kmh S] [--spin-rpm W]
                              [machine and physics flags] [--json]
    tennislab launcher drills import|export|list --db FILE [FILE]

See docs/database.md.
"""

from __future__ import annotations

import argparse
import os
import sys

from tennislab.errors import InputError

_RANGE_FLAGS = (
    ("--speed-kmh", "speed_kmh", "ball speed [km/h]"),
    ("--spin-rpm", "spin_rpm", "spin [rpm]"),
    ("--spin-axis-deg", "spin_axis_deg", "spin-axis rotation [deg]"),
    ("--elevation-deg", "elevation_deg", "elevation [deg]"),
    ("--heading-deg", "heading_deg", "heading [deg]"),
)


# ------------------------------------------------------------ machine flags
def _launcher_cli():
    try:
        from tennislab.cli import launcher as _lc
    except ImportError:  # pragma: no cover - the launcher command is part of tennislab
        return None
    return _lc


def _add_machine_flags(p) -> None:
    """The machine flags of ``launcher aim`` (position, roller geometry), so the hash sees the same spec."""
    lc = _launcher_cli()
    fn = getattr(lc, "add_machine_flags", None) or getattr(lc, "_machine_flags", None)
    if fn is not None:
        fn(p)
        return
    g = p.add_argument_group("machine")  # pragma: no cover - fallback without the launcher command
    g.add_argument(
        "--machine-position",
        type=float,
        nargs=2,
        metavar=("X", "Y"),
        help="launch point on court [m] (default: -12.385 0, 0.5 m behind the near baseline)",
    )


def _machine_from_args(args):
    lc = _launcher_cli()
    fn = getattr(lc, "machine_from_args", None) or getattr(lc, "spec_from_args", None)
    if fn is not None:
        return fn(args)
    from tennislab.launcher.machine import DEFAULT_SPEC  # pragma: no cover - fallback

    pos = getattr(args, "machine_position", None)
    return DEFAULT_SPEC if pos is None else DEFAULT_SPEC.with_position(*pos)


def _physics(args):
    from tennislab.cli.common import physics_from_args

    return physics_from_args(args)


# ---------------------------------------------------------------- register
def register_launcher(sub) -> None:
    """Add ``table``, ``lookup`` and ``drills`` to the ``launcher`` command's subparsers."""
    from tennislab.cli.common import add_physics_flags

    p = sub.add_parser(
        "table",
        help="fill the database of hits (settings grid -> landing) in SQLite",
        description="Fly the machine's settings grid (its own steps, within the given ranges; "
        "default all of it) and store every hit that clears the net and lands in "
        "the opposite doubles court in an SQLite file.  Resumable: rerun the same "
        "command to continue.  See docs/database.md for sizes and times.",
    )
    p.add_argument("--db", required=True, metavar="FILE", help="SQLite database (created if missing)")
    for flag, _, what in _RANGE_FLAGS:
        p.add_argument(flag, type=float, nargs=2, metavar=("MIN", "MAX"), help=f"{what} range (default: all)")
    p.add_argument(
        "--height",
        type=float,
        nargs="+",
        metavar="H",
        help="launch height [m]: one value, or MIN MAX (default: all heights)",
    )
    p.add_argument(
        "--step",
        nargs=2,
        action="append",
        metavar=("SETTING", "K"),
        default=[],
        help="fly every K-th machine step of SETTING (height, speed, spin, spin-axis, elevation, "
        "heading); repeatable (default: every step)",
    )
    p.add_argument("--max-chunks", type=int, metavar="N", help="stop after N chunks (resume later)")
    p.add_argument("--json", action="store_true", help="print a JSON summary")
    _add_machine_flags(p)
    add_physics_flags(p, preset="seed002")
    from tennislab.batch.cli import add_scheduler_flag

    add_scheduler_flag(p)
    p.set_defaults(func=run_table)

    p = sub.add_parser(
        "lookup",
        help="settings that land nearest a target, from the database (no integration)",
        description="Answer 'which settings land a ball there' from a table built by "
        "`launcher table`: the stored hit nearest the target among those with the "
        "given speed and spin (ties: larger net clearance).  Opens the file "
        "read-only; refuses a table built for another machine or physics.",
    )
    p.add_argument("--db", required=True, metavar="FILE", help="SQLite database built by `launcher table`")
    p.add_argument(
        "--target",
        type=float,
        nargs=2,
        required=True,
        metavar=("X", "Y"),
        help="bounce point [m] in the doubles court opposite the machine",
    )
    p.add_argument("--speed-kmh", type=float, help="ball speed [km/h] (rounded to the machine's step; default: any)")
    p.add_argument("--spin-rpm", type=float, help="spin [rpm] (rounded to the machine's step; default: any)")
    p.add_argument("--height", type=float, help="only this launch height [m] (default: any)")
    p.add_argument("--spin-axis-deg", type=float, help="only this spin-axis rotation [deg] (default: any)")
    p.add_argument(
        "--max-miss-m",
        type=float,
        default=1.0,
        help="refuse answers landing farther than this from the target [m] (default 1.0)",
    )
    _add_machine_flags(p)
    add_physics_flags(p, preset="seed002")
    p.add_argument("--json", action="store_true", help="print one JSON object (keys as `launcher aim`)")
    p.set_defaults(func=run_lookup)

    p = sub.add_parser(
        "drills",
        help="store training programs (drills) in the database",
        description="import FILE...: store drill files verbatim (a changed drill of the same "
        "name gets the next revision); export [FILE]: write drills back byte for "
        "byte; list: the stored drills.",
    )
    dsub = p.add_subparsers(dest="drills_action", metavar="import|export|list", parser_class=type(p))
    dsub.required = True
    helps = {
        "import": "drill file(s) to store",
        "export": "FILE (the drill imported from that file name, or named so), NAME OUT, or nothing "
        "(every drill to its imported file name); OUT '-' = stdout",
        "list": None,
    }
    for action, fhelp in helps.items():
        q = dsub.add_parser(action, help=f"{action} drills")
        q.add_argument("--db", required=True, metavar="FILE", help="SQLite database")
        if fhelp:
            q.add_argument("files", nargs="+" if action == "import" else "*", metavar="FILE", help=fhelp)
        q.add_argument("--json", action="store_true", help="print JSON")
        q.set_defaults(func=run_drills, action=action)


# ------------------------------------------------------------------- table
_STEP_NAMES = {
    "height": "height_m",
    "speed": "speed_kmh",
    "spin": "spin_rpm",
    "spin-axis": "spin_axis_deg",
    "elevation": "elevation_deg",
    "heading": "heading_deg",
}


def _grid_from_args(spec, args):
    from tennislab.launcher.table import make_grid

    ranges = {}
    for _, dest, _ in _RANGE_FLAGS:
        v = getattr(args, dest, None)
        if v is not None:
            ranges[dest] = tuple(v)
    if args.height is not None:
        if len(args.height) not in (1, 2):
            raise InputError(f"--height: expected H or MIN MAX, got {len(args.height)} values")
        ranges["height_m"] = (args.height[0], args.height[-1])
    strides = {}
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
    return make_grid(spec, ranges, strides)


def run_table(args) -> int:
    from tennislab.cli.common import emit_json
    from tennislab.launcher.table import DEFAULT_CHUNK, fill_table

    spec = _machine_from_args(args)
    params = _physics(args)
    grid = _grid_from_args(spec, args)
    if args.max_chunks is not None and args.max_chunks < 1:
        raise InputError(f"--max-chunks: {args.max_chunks} is outside the allowed range [1, inf]")
    chunk = getattr(args, "chunk_size", None) or DEFAULT_CHUNK
    sched = getattr(args, "scheduler", "local")
    from tennislab.launcher import db as _db

    conn = _db.open_db(args.db)  # refuse a foreign file or another machine/physics before starting workers
    try:
        with _db.guard(args.db):
            _db.bind_config(conn, _db.config_dict(spec, params), args.db)
    finally:
        conn.close()
    with _db.guard(args.db):  # fill_table runs the chunks with tennislab.batch.run_batch
        rep = fill_table(
            args.db,
            spec,
            params,
            grid,
            chunk_size=chunk,
            scheduler=sched,
            n_workers=getattr(args, "workers", None),
            progress=getattr(args, "progress", True),
            out_dir=getattr(args, "out_dir", None),
            max_chunks=args.max_chunks,
        )
    if args.json:
        emit_json(rep.as_dict())
    else:
        back = f", {rep.chunks_restored} read back from --out-dir" if rep.chunks_restored else ""
        print(
            f"{rep.path}: {rep.chunks_run - rep.chunks_restored} chunks flown{back} "
            f"({rep.chunks_done_before} already done) of "
            f"{rep.n_chunks}; grid {rep.grid_rows} settings; {rep.hits_inserted} hits added, "
            f"{rep.hits_total} stored; {rep.seconds:.1f} s; hash {rep.hash[:12]}"
        )
    return 0


# ------------------------------------------------------------------ lookup
def lookup_result(
    path: str,
    target,
    spec,
    params,
    speed_kmh=None,
    spin_rpm=None,
    max_miss_m: float = 1.0,
    height_m=None,
    spin_axis_deg=None,
) -> dict:
    """The JSON object of ``launcher lookup`` (keys of ``launcher aim`` plus ``lookup_ms``)."""
    from tennislab.errors import check_range
    from tennislab.launcher import db
    from tennislab.launcher import lookup as lk

    check_range("--max-miss-m", max_miss_m, 0.0, 100.0, "m", lo_open=True)
    x, y = lk.check_target(target[0], target[1], spec.position[0], params.court)
    if speed_kmh is not None:
        speed_kmh = spec.speed.quantise(spec.speed.check("--speed-kmh", speed_kmh))
    if spin_rpm is not None:
        spin_rpm = spec.spin.quantise(spec.spin.check("--spin-rpm", spin_rpm))
    where = {}
    for name, field, v in (("--height", "height_m", height_m), ("--spin-axis-deg", "spin_axis_deg", spin_axis_deg)):
        if v is not None:
            rng = spec.range_of(field)
            q = rng.quantise(rng.check(name, v))
            where[field] = (q - rng.step / 3, q + rng.step / 3)
    conn = db.open_readonly(path)
    try:
        with db.guard(path):
            h = db.check_config(conn, db.config_dict(spec, params), path)
            hit = lk.lookup(
                conn,
                x,
                y,
                speed_kmh=speed_kmh,
                spin_rpm=spin_rpm,
                max_miss_m=max_miss_m,
                steps={"speed_kmh": spec.speed.step, "spin_rpm": spec.spin.step},
                path=path,
                where=where,
            )
    finally:
        conn.close()
    return _result_dict(hit, (x, y), spec, params, h, path)


def _result_dict(hit: dict, target, spec, params, h: str, path: str) -> dict:
    import math

    from tennislab.launcher.db import HIT_SETTINGS
    from tennislab.launcher.machine import Settings

    st = Settings(**{k: float(hit[k]) for k in HIT_SETTINGS})
    clr = float(hit["net_clearance_m"])
    try:
        from tennislab.launcher.aim import AimSolution, aim_result_dict
    except ImportError:  # pragma: no cover - aim is part of the launcher package
        aim_result_dict = None
    if aim_result_dict is not None:
        sol = AimSolution(
            "lookup",
            tuple(map(float, target)),
            st,
            st.elevation_deg,
            st.heading_deg,
            (float(hit["land_x"]), float(hit["land_y"])),
            hit["miss_m"] * 1e3,
            clr,
            "over",
            float(hit["flight_time_s"]),
            float(hit["apex_z_m"]),
            float(hit["bounce_speed_ms"]),
            math.nan,
            tuple(spec.position),
        )
        out = aim_result_dict(sol, spec, params)
        out.pop("exact", None)
        out.pop("quantisation_bound_mm", None)
    else:
        out = {
            "target": {"x": target[0], "y": target[1]},
            "settings": st.as_dict(),
            "landing": {"x": float(hit["land_x"]), "y": float(hit["land_y"])},
            "miss_mm": hit["miss_m"] * 1e3,
            "net_clearance_m": clr,
        }
    out["bounce_spin_rpm"] = float(hit["bounce_spin_rpm"])
    out["lookup_ms"] = float(hit["lookup_ms"])
    out["db"] = {
        "path": path,
        "hash": h,
        "hit_id": int(hit["id"]),
        "index_entries_read": int(hit["n_candidates"]),
        "hits_read": int(hit["n_read"]),
    }
    return out


def run_lookup(args) -> int:
    from tennislab.cli.common import emit_json

    spec = _machine_from_args(args)
    params = _physics(args)
    out = lookup_result(
        args.db,
        args.target,
        spec,
        params,
        args.speed_kmh,
        args.spin_rpm,
        args.max_miss_m,
        args.height,
        args.spin_axis_deg,
    )
    if args.json:
        emit_json(out)
    else:
        s = out["settings"]
        print(
            f"settings: height {s['height_m']:g} m, speed {s['speed_kmh']:g} km/h, elevation "
            f"{s['elevation_deg']:g} deg, heading {s['heading_deg']:g} deg, spin {s['spin_rpm']:g} rpm, "
            f"spin axis {s['spin_axis_deg']:g} deg"
        )
        if "rollers" in out:
            print(f"rollers: {out['rollers']['rpm1']:.0f} rpm / {out['rollers']['rpm2']:.0f} rpm")
        print(
            f"landing: x = {out['landing']['x']:.3f} m, y = {out['landing']['y']:.3f} m "
            f"(miss {out['miss_mm']:.0f} mm); net clearance {out['net_clearance_m']:.3f} m; "
            f"lookup {out['lookup_ms']:.2f} ms"
        )
    return 0


# ------------------------------------------------------------------ drills
def run_drills(args) -> int:
    from tennislab.launcher import db

    with db.guard(args.db):
        return _run_drills(args)


def _run_drills(args) -> int:
    from tennislab.cli.common import atomic_write, emit_json
    from tennislab.launcher import db

    if args.action == "list":
        conn = db.open_readonly(args.db)
        try:
            rows = db.list_drills(conn)
        finally:
            conn.close()
        if args.json:
            emit_json({"drills": rows})
        else:
            for r in rows:
                fmt = f"  format {r['format_version']}" if r["format_version"] else ""
                print(
                    f"{r['name']}  rev {r['revision']}  {r['n_shots']} shots{fmt}  {r['filename']}  {r['imported_utc']}"
                )
            if not rows:
                print("no drills stored")
        return 0
    if args.action == "import":
        if not args.files:
            raise InputError("drills import: give one or more drill files")
        for f in args.files:
            if not os.path.isfile(f):
                raise InputError(f"drills import: {f}: no such file")
        conn = db.open_db(args.db)
        try:
            infos = [db.import_drill(conn, f) for f in args.files]
        finally:
            conn.close()
        if args.json:
            emit_json({"imported": infos})
        else:
            for r in infos:
                print(f"{r['name']}: revision {r['revision']}, {r['n_shots']} shots")
        return 0
    # export [NAME|FILE] [OUT]
    if len(args.files) > 2:
        raise InputError("drills export: give [NAME] [OUT] or FILE")
    conn = db.open_readonly(args.db)
    try:
        stored = db.list_drills(conn)
        jobs = []
        if not args.files:  # every drill, under its imported file name
            jobs = [(r["name"], r["filename"]) for r in stored]
        elif len(args.files) == 2:
            jobs = [(args.files[0], args.files[1])]
        else:
            jobs = [(_drill_for(stored, args.files[0]), args.files[0])]
            if jobs[0][0] == args.files[0] and not os.path.splitext(args.files[0])[1]:
                jobs = [(jobs[0][0], next(r["filename"] for r in stored if r["name"] == jobs[0][0]))]
        blobs = [(name, out, db.drill_info(conn, name), db.drill_source(conn, name)) for name, out in jobs]
    finally:
        conn.close()
    done = []
    for name, out, info, data in blobs:
        if out == "-":
            sys.stdout.buffer.write(data)
            sys.stdout.flush()
            continue
        atomic_write(out, lambda fh, d=data: fh.write(d), mode="wb")
        done.append({"name": name, "revision": info["revision"], "path": out})
    if args.json:
        emit_json({"exported": done})
    else:
        for d in done:
            print(f"{d['name']} (revision {d['revision']}) -> {d['path']}")
    return 0


def _drill_for(stored: list, key: str) -> str:
    """The stored drill a FILE argument means: by name, by imported file name, or by file stem."""
    base = os.path.basename(key)
    stem = os.path.splitext(base)[0]
    for test in (lambda r: r["name"] == key, lambda r: r["filename"] == base, lambda r: r["name"] == stem):
        hits = [r["name"] for r in stored if test(r)]
        if hits:
            return hits[0]
    names = ", ".join(r["name"] for r in stored) or "none"
    raise InputError(f"drills export: {key!r} is neither a stored drill nor its file name (stored: {names})")


def _standalone_parser() -> argparse.ArgumentParser:  # pragma: no cover - debugging aid
    p = argparse.ArgumentParser(prog="tennislab launcher")
    register_launcher(p.add_subparsers(dest="command", required=True))
    return p
