"""``tennislab calibrate``: validate and calibrate the flight model against real balls.

Sub-commands (workflows of :mod:`tennislab.calibrate`; docs/validation.md):

* ``validate``    measured serves flown by every aero model: median / p90 miss, length and width bias
* ``serves``      fit the aero coefficients to measured serves; write an ``--aero table`` CSV
* ``sensitivity`` the misses over a grid of C_D, C_L and spin-axis assumptions
* ``tracks``      identify a ball's aerodynamic curves from timed tracks and tracker points (CSV, point JSON)

Progress goes to stderr (``--quiet`` silences it); ``--json`` prints the workflow's ``to_dict()``.
"""

from __future__ import annotations

import csv
import os
import sys

from tennislab.cli.common import (
    LazyHelp,
    atomic_write,
    emit_json,
    figure_file,
    output_file,
    save_figure,
    surface_from_arg,
)
from tennislab.errors import InputError
from tennislab.io import is_utf8_name, shown


def _default_aero() -> str:
    from tennislab.core.names import DEFAULT_AERO

    return DEFAULT_AERO


def _models_help() -> str:  # tennislab.calibrate.registered_models() from the names alone: no aero kernel compiled
    from tennislab.core.names import AERO_ALIASES, AERO_MODEL_NAMES

    models = [n for n in AERO_MODEL_NAMES if n not in AERO_ALIASES and n != "table"]
    return f"comma-separated aero models (default all: {', '.join(models)})"


def _physics_flags(p) -> None:
    g = p.add_argument_group("ball and air")
    g.add_argument("--mass", type=float, help="ball mass [kg] (default 0.0577)")
    g.add_argument("--radius", type=float, help="ball radius [m] (default 0.0335)")
    g.add_argument("--air-density", type=float, help="air density [kg/m^3] (default 1.199)")
    g.add_argument("--gravity", type=float, help="gravity [m/s^2] (default 9.80665)")
    g.add_argument("--spin-decay", type=float, help="spin decay rate [1/s] (default 0: off)")


def _physics(args) -> dict:
    out = {k: getattr(args, k) for k in ("mass", "radius", "air_density", "gravity", "spin_decay")}
    return {k: v for k, v in out.items() if v is not None}


def _common(p, *, serves: bool = True) -> None:
    if serves:
        p.add_argument(
            "--serves",
            metavar="CSV",
            required=True,
            help="CourtVision serves CSV (e.g. ../shared/realdata/courtvision_serves.csv)",
        )
        p.add_argument(
            "--split",
            default="parity",
            help="calibration split: parity (odd matches fitted, even held out; default), none, "
            "tournament:roland_garros, tour:atp, year:2020, event:australian_open_2020",
        )
    _physics_flags(p)
    p.add_argument(
        "--csv",
        metavar="FILE",
        type=output_file((".csv",)),
        help="write one row per serve (or track / grid point) as CSV",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--quiet", action="store_true", help="no progress lines on stderr")


def register(sub) -> None:
    p = sub.add_parser(
        "calibrate",
        help="validate and calibrate the flight model on real balls (CourtVision serves, tracks)",
        description="Validation and calibration of the aerodynamic model on real ball data (docs/validation.md).",
    )
    sp = p.add_subparsers(dest="calibrate_command", metavar="SUBCOMMAND", parser_class=type(p))
    sp.required = True

    v = sp.add_parser(
        "validate",
        help="fly measured serves through their net points with every aero model",
        description="Fly each measured serve from its impact point with its speed and spin, aimed through its "
        "net point, and compare the predicted bounce with the measured one, for every aero model.",
    )
    v.add_argument("--models", help=LazyHelp(_models_help))
    v.add_argument("--aero-table", metavar="CSV", help="also validate this aero table (speed_ms,spin_rpm,cd,cl)")
    v.add_argument(
        "--spin-axis",
        default="topspin",
        help="spin-axis assumption: topspin (default), none, sidespin, an angle [deg] (0 topspin, 90 sidespin "
        "curving left), or fitted (per serve family, on the fit part of --split)",
    )
    v.add_argument(
        "--plot", metavar="FILE.png", type=figure_file(), help="histograms of the length and width misses per model"
    )
    _common(v)
    v.set_defaults(func=run_validate)

    s = sp.add_parser(
        "serves",
        help="fit the aero coefficients to measured serves; write an aero table",
        description="Fit C_D = cd + cd_s S and C_L = min(cl S, 0.5) to measured serves (S = r w / v); report the "
        "misses before and after on the fit part and on the held-out part.",
    )
    s.add_argument("--fit", default="cd", help="free parameters among cd, cl, cd_s, speed_scale (default cd)")
    s.add_argument("--cd", type=float, help="drag start / fixed value (default 0.6)")
    s.add_argument("--cl", type=float, help="lift slope start / fixed value (default 0.6, Cross 2020)")
    s.add_argument("--cd-s", type=float, help="drag growth with S, start / fixed value (default 0)")
    s.add_argument("--speed-scale", type=float, help="factor on the tracker's speeds, start / fixed (default 1)")
    s.add_argument(
        "--spin-axis",
        default="fitted",
        help="fitted (default: per serve family, with cl fixed), topspin, none, sidespin or an angle [deg]",
    )
    s.add_argument("--baseline", help=LazyHelp(lambda: f"model of the 'before' figures (default {_default_aero()})"))
    s.add_argument(
        "--out-table",
        metavar="CSV",
        type=output_file((".csv",)),
        help="write the calibrated model as an --aero table CSV",
    )
    s.add_argument(
        "--plot", metavar="FILE.png", type=figure_file(), help="histograms of the misses before and after (held out)"
    )
    _common(s)
    s.set_defaults(func=run_serves)

    g = sp.add_parser(
        "sensitivity",
        help="misses over a grid of cd, cl and spin-axis assumptions",
        description="Median and p90 miss and length/width bias over a grid of the calibrated family's cd and cl, "
        "spin-axis assumptions and speed scales (a fitted axis is fitted on the fit part of --split).",
    )
    g.add_argument("--cd", default="0.5,0.6,0.7,0.8,0.9", help="comma-separated C_D values")
    g.add_argument("--cl", default="0,0.3,0.6,0.9", help="comma-separated lift slopes")
    g.add_argument("--spin-axes", default="topspin,fitted", help="comma-separated axis assumptions")
    g.add_argument("--speed-scale", default="1", help="comma-separated factors on the tracker's speeds")
    _common(g)
    g.set_defaults(func=run_sensitivity)

    t = sp.add_parser(
        "tracks",
        help="identify a ball's aerodynamics from timed tracks or tracker points (CSV tracks, point JSON)",
        description="Fit the global curves of a ball (C_D against speed and spin, C_L against the spin parameter, "
        "spin decay) jointly with every flight's launch state, spin and drag scale, on hit-to-bounce flights of "
        "point JSON and on t,x,y,z CSV tracks; report the residuals before and after on held-out flights "
        "(docs/validation.md). With --fit among cd, cl, cd_s (or --spin-rpm) fit the 3-parameter family instead.",
    )
    t.add_argument(
        "files",
        nargs="+",
        metavar="FILE|DIR",
        help="track CSVs (t,x,y,z[,sigma]; one free flight each), point JSON files or folders of them",
    )
    t.add_argument("--holdout", nargs="+", default=[], metavar="FILE|DIR", help="held-out tracks or points (no split)")
    t.add_argument(
        "--split",
        default="parity",
        help="held-out part: parity (odd games fitted, even held out; CSV tracks: odd-numbered fitted; default), "
        "parity:even (the other way round) or none",
    )
    t.add_argument(
        "--fit",
        default=None,
        help="curves among cd_v, cd_s, cl_s, decay, wind (default cd_v,cl_s,decay), or the family's cd, cl, cd_s",
    )
    t.add_argument(
        "--drag-sigma",
        type=float,
        default=0.15,
        help="prior sigma of every flight's drag scale about 1 (shot-to-shot variation; 0: none; default 0.15)",
    )
    t.add_argument("--speed-knots", help="comma-separated speeds [m/s] of the C_D curve (default 10,15,...,60)")
    t.add_argument("--s-knots", help="comma-separated spin parameters of the C_L curve (default 0.1,0.2,0.3,0.4,0.6)")
    t.add_argument("--max-iter", type=int, default=20, help="most iterations of the global curves (default 20)")
    t.add_argument("--cd", type=float, help="family: drag start / fixed value (default 0.6)")
    t.add_argument("--cl", type=float, help="family: lift slope start / fixed value (default 0.6)")
    t.add_argument("--cd-s", type=float, help="family: drag growth with S, start / fixed value (default 0)")
    t.add_argument("--spin-rpm", type=float, help="family: the tracks' spin rate [rpm] (default: none)")
    t.add_argument(
        "--spin-axis", default="topspin", help="family: its axis relative to each track's direction (default topspin)"
    )
    t.add_argument("--baseline", help=LazyHelp(lambda: f"model of the 'before' residuals (default {_default_aero()})"))
    t.add_argument(
        "--out-table",
        metavar="CSV",
        type=output_file((".csv",)),
        help="write the calibrated model as an --aero table CSV",
    )
    t.add_argument(
        "--out-config",
        metavar="FILE.toml",
        type=output_file((".toml",)),
        help="write a tennislab.toml [physics] table flying the model (the --out-table CSV and the spin decay)",
    )
    _common(t, serves=False)
    t.set_defaults(func=run_tracks)
    _register_surface(sp)


def _register_surface(sp) -> None:
    u = sp.add_parser(
        "surface",
        help="fit the court's restitution and friction to measured bounces (tracks with points after the bounce)",
        description="Fit the bounce model's e and mu (and e_x) to the bounces of real tracks: the line-call fit "
        "measures each ball's velocity and spin before the bounce and its velocity after it.",
    )
    u.add_argument("--rally", nargs="+", default=[], metavar="FILE|DIR", help="Hawk-Eye-style point JSON")
    u.add_argument("--track", nargs="+", default=[], metavar="FILE.csv", help="t,x,y,z[,sigma] tracks through a bounce")
    u.add_argument("--base", default="hard", help="surface the fit starts from and keeps the other values of")
    u.add_argument("--fit", default="e,mu", help="free parameters among e, mu, e_x (default e,mu)")
    u.add_argument("--name", default="calibrated", help="name of the fitted surface (default calibrated)")
    u.add_argument(
        "--out-surface",
        metavar="FILE.toml",
        type=output_file((".toml",)),
        help="write the fitted surface as a surface file (--surface FILE.toml of fly and call)",
    )
    u.add_argument("--csv", metavar="FILE", type=output_file((".csv",)), help="one row per bounce")
    u.add_argument("--json", action="store_true", help="print one JSON object")
    u.add_argument("--quiet", action="store_true", help="no progress lines on stderr")
    u.set_defaults(func=run_surface)


def _measured_bounces(args):
    """The line calls of every shot of ``--rally`` / ``--track``, and their measured bounces
    (:func:`tennislab.calibrate.surface.measured_bounces`)."""
    from tennislab.calibrate import measured_bounces
    from tennislab.io import read_points, read_track
    from tennislab.linecall import call_rally, call_track

    shots = []
    for f in args.rally:
        shots += call_rally(read_points(f), surface=args.base).to_dict()["shots"]
    for f in args.track:
        t = read_track(f)
        shots.append(call_track(t.t, t.xyz, t.sigma, surface=args.base).to_dict())
    vi, wi, vo = measured_bounces(shots)
    if not args.quiet:
        print(f"calibrate surface: {len(vo)} measured bounces in {len(shots)} shots", file=sys.stderr)
    return vi, wi, vo, len(shots)


def run_surface(args) -> int:
    from tennislab.calibrate import calibrate_surface

    if not args.rally and not args.track:
        raise InputError("--rally: give tracks with points after the bounce (--rally FILE or --track FILE.csv)")
    base = surface_from_arg(args.base)
    args.base = base
    vi, wi, vo, n_shots = _measured_bounces(args)
    if not vo:
        raise InputError(f"--rally: none of the {n_shots} shots has a bounce with points after it to measure")
    fit = tuple(k.strip() for k in args.fit.split(",") if k.strip())
    res = calibrate_surface(vi, wi, vo, base=base, fit=fit, name=args.name)
    if args.out_surface:
        text = res.surface_toml()
        atomic_write(args.out_surface, lambda fh: fh.write(text))
    if args.csv:
        _write_rows(args.csv, res.rows())
    if args.json:
        emit_json(res)
        return 0
    d = res.to_dict()
    vals = ", ".join(
        f"{k} = {d['surface'][k]:.3f}" + (f" ± {d['sd'][k]:.3f}" if k in d["sd"] else " (kept)")
        for k in ("e", "mu", "e_x")
    )
    print(f"surface fitted to {res.n_bounces} bounces: {vals}")
    print(
        f"outgoing velocity rms: {res.rms_before_ms:.3f} m/s ({d['base']['name']}) -> {res.rms_after_ms:.3f} m/s; "
        f"court pace rating {d['cpr']:.1f} ({d['cpr_category']})"
    )
    for extra in (args.out_surface, args.csv):
        if extra:
            print(f"wrote {extra}")
    return 0


def _progress(args):
    if args.quiet:
        return None

    def say(msg: str) -> None:
        print(msg, file=sys.stderr, flush=True)

    return say


def _floats(text: str, name: str) -> list[float]:
    try:
        vals = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise InputError(f"{name}: expected comma-separated numbers, got {text!r}") from None
    if not vals:
        raise InputError(f"{name}: give at least one value")
    return vals


def _write_rows(path: str, rows: list[dict]) -> None:
    if not rows:
        raise InputError("csv: nothing to write")
    cols = list(rows[0])

    def _w(fh):
        w = csv.DictWriter(fh, fieldnames=cols, lineterminator="\n")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if v is None else v) for k, v in r.items()})

    atomic_write(path, _w)


def _plot_misses(path: str, series: dict, title: str) -> None:
    # the figure module is imported only when a plot is asked for (Matplotlib adds ~0.3 s to a start-up)
    from tennislab.plot import close_figure, plot_misses

    fig = plot_misses(series, title)
    save_figure(fig, path)
    close_figure(fig)


def _line(label: str, s: dict) -> str:
    if not s.get("n"):
        return f"  {label:<28s} n 0"
    return (
        f"  {label:<28s} n {s['n']:5d}  median miss {s['miss_median_m']:.3f} m  p90 {s['miss_p90_m']:.3f} m  "
        f"length {s['length_median_m']:+.3f} m  width {s['width_median_m']:+.3f} m"
    )


def run_validate(args) -> int:
    from tennislab.calibrate import validate_serves
    from tennislab.io import read_aero_table

    models = [m.strip() for m in args.models.split(",") if m.strip()] if args.models else None
    table = read_aero_table(args.aero_table) if args.aero_table else None
    res = validate_serves(
        args.serves,
        models=models,
        aero_table=table,
        spin_axis=args.spin_axis,
        split=args.split,
        physics=_physics(args),
        progress=_progress(args),
    )
    if args.csv:
        _write_rows(args.csv, res.rows())
    if args.plot:
        series = {m.model: (m.prediction.length, m.prediction.width) for m in res.models}
        _plot_misses(args.plot, series, f"CourtVision serves, spin axis {res.spin_axis}")
    if args.json:
        emit_json(res)
        return 0
    print(f"{res.n_used} of {res.n_read} serves used; left out: {res.excluded or 'none'}")
    print(f"spin axis: {res.spin_axis}; split: {res.split}")
    for m in res.models:
        print(m.model)
        print(_line("all", m.overall))
        if m.held_out["n"]:
            print(_line("fit part", m.fit))
            print(_line("held out", m.held_out))
    for extra in (args.csv, args.plot):
        if extra:
            print(f"wrote {extra}")
    return 0


def run_serves(args) -> int:
    from tennislab.calibrate import calibrate_serves

    args.baseline = args.baseline or _default_aero()
    res = calibrate_serves(
        args.serves,
        fit=args.fit,
        cd=args.cd,
        cl=args.cl,
        cd_s=args.cd_s,
        speed_scale=args.speed_scale,
        spin_axis=args.spin_axis,
        split=args.split,
        baseline=args.baseline,
        physics=_physics(args),
        progress=_progress(args),
    )
    if args.out_table:
        text = res.table_csv()
        atomic_write(args.out_table, lambda fh: fh.write(text))
    if args.csv:
        _write_rows(args.csv, res.rows())
    if args.plot:
        held = ~res.fit_mask
        series = {
            f"before ({res.baseline})": (res.pred_before.length[held], res.pred_before.width[held]),
            "calibrated": (res.pred_after.length[held], res.pred_after.width[held]),
        }
        _plot_misses(args.plot, series, "held-out serves")
    if args.json:
        emit_json(res)
        return 0
    vals = ", ".join(
        f"{k} = {res.values[k]:.4f}" + (f" ± {res.sd[k]:.4f}" if k in res.sd else " (fixed)")
        for k in ("cd", "cl", "cd_s", "speed_scale")
    )
    print(f"calibrated: {vals}")
    print(f"spin axis: {res.spin_axis.name}; split: {res.split}")
    for part in ("fit", "held_out"):
        print(_line(f"{part}: before ({res.baseline})", res.before[part]))
        print(_line(f"{part}: after", res.after[part]))
    for extra in (args.out_table, args.csv, args.plot):
        if extra:
            print(f"wrote {extra}")
    return 0


def run_sensitivity(args) -> int:
    from tennislab.calibrate import sensitivity_serves

    res = sensitivity_serves(
        args.serves,
        cd=_floats(args.cd, "cd"),
        cl=_floats(args.cl, "cl"),
        spin_axes=[a.strip() for a in args.spin_axes.split(",") if a.strip()],
        speed_scale=_floats(args.speed_scale, "speed_scale"),
        split=args.split,
        physics=_physics(args),
        progress=_progress(args),
    )
    if args.csv:
        _write_rows(args.csv, res.rows())
    if args.json:
        emit_json(res)
        return 0
    part = "held_out" if res.n_held_out else "fit"
    print(f"{part} serves ({res.split})")
    for g in res.grid:
        label = f"cd {g['cd']:g} cl {g['cl']:g} {g['spin_axis']} x{g['speed_scale']:g}"
        print(_line(label, g[part]))
    return 0


def _read_flight_files(paths: list[str]) -> tuple[list, list]:
    """(CSV tracks, points) of ``paths``: folders and .json/.jsonl files are point JSON, the rest CSV."""
    from tennislab.io import read_points, read_track

    tracks, points = [], []
    for f in paths:
        if os.path.isdir(f) or f.lower().endswith((".json", ".jsonl")):
            points += read_points(f)
        else:
            tracks.append(read_track(f))
    return tracks, points


def run_tracks(args) -> int:
    from tennislab.calibrate import calibrate_tracks
    from tennislab.linecall import find_bounces, find_hits

    args.baseline = args.baseline or _default_aero()
    if args.out_config and not args.out_table:
        raise InputError("--out-config: needs --out-table (the table the configuration points to)")
    if args.out_config and not is_utf8_name(os.path.abspath(args.out_table)):
        raise InputError(
            f"--out-config: the table's name {shown(args.out_table)} is not UTF-8, which a TOML file cannot hold; "
            "give --out-table a UTF-8 name"
        )
    tracks, points = _read_flight_files(args.files)
    h_tracks, h_points = _read_flight_files(args.holdout)
    res = calibrate_tracks(
        tracks,
        points=points,
        holdout_tracks=h_tracks,
        holdout_points=h_points,
        fit=args.fit,
        cd=args.cd,
        cl=args.cl,
        cd_s=args.cd_s,
        spin_rpm=args.spin_rpm,
        spin_axis=args.spin_axis,
        baseline=args.baseline,
        physics=_physics(args),
        split=args.split,
        drag_sigma=args.drag_sigma,
        speed_knots=_floats(args.speed_knots, "speed_knots") if args.speed_knots else None,
        s_knots=_floats(args.s_knots, "s_knots") if args.s_knots else None,
        max_iter=args.max_iter,
        find_hits=find_hits,
        find_bounces=find_bounces,
        progress=_progress(args),
    )
    if args.out_table:
        text = res.table_csv()
        atomic_write(args.out_table, lambda fh: fh.write(text))
    if args.out_config:
        conf = res.config_toml(os.path.abspath(args.out_table))
        atomic_write(args.out_config, lambda fh: fh.write(conf))
    if args.csv:
        _write_rows(args.csv, res.rows())
    if args.json:
        emit_json(res)
        return 0
    if res.model == "curves":
        _print_curves(res)
    else:
        vals = ", ".join(
            f"{k} = {res.values[k]:.4f}" + (f" ± {res.sd[k]:.4f}" if k in res.sd else " (fixed)")
            for k in ("cd", "cl", "cd_s")
        )
        print(f"calibrated on {res.n_tracks} tracks ({res.n_points} points): {vals}")
        print(
            f"residual RMS: {res.rms_before_mm:.2f} mm ({res.baseline}) -> {res.rms_after_mm:.2f} mm; "
            f"chi2/dof {res.chi2_dof:.2f}"
        )
    if args.out_table:
        print(f"fly it with: --aero table --aero-table {args.out_table} --spin-decay {res.spin_decay_per_s:.4g}")
    for extra in (args.out_table, args.out_config, args.csv):
        if extra:
            print(f"wrote {extra}")
    return 0


def _pm(v, s) -> str:
    return f"{v:.3f}" + (f" ± {s:.3f}" if s is not None else "")


def _print_curves(res) -> None:
    c = res.curves
    print(f"identified on {res.split['n_fit']} flights, {res.split['n_held_out']} held out ({res.split['name']})")
    print("C_D(v): " + ", ".join(f"{v:g} m/s {_pm(a, s)}" for v, a, s in zip(c["speed_ms"], c["cd"], c["cd_sd"])))
    if "cd_s" in res.free:
        print(f"C_D growth with S: {_pm(c['cd_s'], c['cd_s_sd'])}")
    cl = ", ".join(f"S {v:g} {_pm(a, s)}" for v, a, s in zip(c["s"], c["cl"], c["cl_sd"]))
    print(f"C_L(S): {cl} (the first knot held at {c['cl_anchor_slope']:g} S)")
    decay = _pm(c["spin_decay_per_s"], c["spin_decay_sd"]) if "decay" in res.free else "0 (not fitted)"
    print(f"spin decay: {decay} /s")
    if "wind" in res.free:
        print(f"wind: {c['wind_ms'][0]:.2f}, {c['wind_ms'][1]:.2f} m/s (x, y)")
    ds = res.drag_scale
    if ds["sigma_prior"]:
        print(f"drag scale per flight: p10 {ds['p10']:.3f}, median {ds['p50']:.3f}, p90 {ds['p90']:.3f}")
    for part, label in (("fit_part", "fitted"), ("held_out", "held out")):
        for kind, s in (getattr(res, part) or {}).items():
            b, a, fl = s["before"], s["after"], s["cubic_floor"]
            print(
                f"  {label:<8s} {kind:<6s} n {s['n']:4d}  residual median {b['median_mm']:.2f} -> "
                f"{a['median_mm']:.2f} mm "
                f"[{a['median_ci95_mm'][0]:.2f}, {a['median_ci95_mm'][1]:.2f}], p90 {b['p90_mm']:.2f} -> "
                f"{a['p90_mm']:.2f} mm; cubic floor {fl['median_mm']:.2f} mm"
            )
    if res.excluded:
        print("left out: " + ", ".join(f"{k} {v}" for k, v in res.excluded.items()))
