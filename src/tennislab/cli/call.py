"""``tennislab call``: where did the ball bounce, and was it in?

Inputs (one of):

* ``--track FILE.csv``: a 3-D track (t,x,y,z[,sigma]) of one shot (:func:`tennislab.linecall.call_track`);
* ``--rally FILE.json|DIR``: tracker point JSON (one point, a list, a directory of files): every shot
  called (:func:`tennislab.linecall.call_rally`); ``--csv OUT`` writes one row per shot;
* ``--position X Y Z --velocity VX VY VZ [--spin ...]``: a state (:func:`tennislab.linecall.call_state`);
* ``--cameras CAMS.json --detections FILE.csv``: 2-D detections from calibrated cameras
  (:func:`tennislab.linecall.call_detections`).

This module parses flags, calls the workflow and prints its ``to_dict()`` (``--json``) or a summary.
"""

from __future__ import annotations

import csv
import os
from typing import TYPE_CHECKING

from tennislab.cli.batch_flags import add_progress_flag, progress_from_args
from tennislab.cli.common import (
    add_physics_flags,
    atomic_write,
    emit_json,
    figure_file,
    output_file,
    physics_from_args,
    physics_words,
    save_figure,
    surface_from_arg,
)
from tennislab.core import DEFAULT_NET, NET_MODES
from tennislab.errors import InputError, escape_text
from tennislab.plot import in_out_by, plus_minus, spin_fit_words

if TYPE_CHECKING:
    from tennislab.linecall import RallyCall, TrackCall


def register(sub) -> None:
    p = sub.add_parser(
        "call",
        help="bounce point, ball mark and line call from a track, a rally of tracker output or a state",
        description="Line calling: fit a ball track (or fly a state) to its bounce, compute the mark and call "
        "it in, out, net, let or review. SI units.",
    )
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--track", metavar="FILE.csv", help="3-D track of one shot: columns t,x,y,z[,sigma] [s, m]")
    src.add_argument(
        "--rally",
        metavar="FILE.json",
        help="tracker point JSON (one point, a list of points, {'points': [...]}, or a directory of point files): "
        "every shot called",
    )
    src.add_argument(
        "--position", type=float, nargs=3, metavar=("X", "Y", "Z"), help="ball-centre position [m] (with --velocity)"
    )
    src.add_argument("--cameras", metavar="CAMS.json", help="camera calibration (with --detections)")
    p.add_argument("--velocity", type=float, nargs=3, metavar=("VX", "VY", "VZ"), help="velocity [m/s]")
    p.add_argument("--spin", type=float, nargs=3, metavar=("WX", "WY", "WZ"), help="spin vector [rad/s]")
    p.add_argument(
        "--method",
        choices=("numeric", "closed-form"),
        default="numeric",
        help="drop point from a state: numeric flight (default) or the closed form of Deng (2014)",
    )
    p.add_argument(
        "--net",
        choices=NET_MODES,
        default=DEFAULT_NET,
        help="--position: obstacle (default, as `tennislab fly`): a ball that meets the net is called net; "
        "through: it passes (the seeds' models)",
    )
    p.add_argument("--detections", metavar="FILE.csv", help="2-D detections t,camera,u,v[,sigma_px]")
    p.add_argument(
        "--surface",
        default="hard",
        help="court surface: clay, grass, hard, carpet, or a surface file FILE.toml (default hard)",
    )
    g = p.add_mutually_exclusive_group()
    g.add_argument("--line", help="call against one line (baseline, service, singles-left, ... near-...)")
    g.add_argument("--target", help="area the shot must land in (singles, doubles, deuce-box, ad-box, near-...)")
    p.add_argument("--doubles", action="store_true", help="--rally: rally shots must land in the doubles court")
    p.add_argument(
        "--sigma",
        type=float,
        help="per-axis track noise [m] if the CSV has no sigma column (default: estimated from the residuals)",
    )
    d = p.add_mutually_exclusive_group()
    d.add_argument(
        "--fit-drag",
        action="store_true",
        help="fit the drag scale (C_D) freely; default: fitted with a prior sigma 0.15 around 1. Lift separate",
    )
    d.add_argument("--fixed-drag", action="store_true", help="keep C_D as the aero model gives it (drag scale 1)")
    lg = p.add_mutually_exclusive_group()
    lg.add_argument(
        "--fit-lift",
        action="store_true",
        help="fit the lift scale (C_L) freely; default: fitted with a prior sigma 0.3 around 1 "
        "(degenerate with the spin rate unless the data pin the spin down)",
    )
    lg.add_argument("--fixed-lift", action="store_true", help="keep C_L as the aero model gives it (lift scale 1)")
    p.add_argument(
        "--contact-sigma",
        type=float,
        default=0.0,
        metavar="MS",
        help="prior sigma [ms] of the contact time: frees the ball's travel during the contact "
        "around the contact model (default 0: trust it; 0.3 spans Brody's 4-5 ms)",
    )
    p.add_argument(
        "--window",
        type=float,
        nargs=2,
        default=(30.0, 0.3),
        metavar=("BEFORE", "AFTER"),
        help="fit only points this long before/after the bounce [s] (default 30 0.3: the whole flight "
        "from the hit; the bounce itself is placed by local refits near it)",
    )
    p.add_argument("--workers", type=int, default=1, help="--rally: processes calling points in parallel (default 1)")
    add_progress_flag(p)
    add_physics_flags(p)
    p.add_argument("--csv", metavar="OUT.csv", type=output_file((".csv",)), help="--rally: write one row per shot")
    p.add_argument(
        "--plot",
        metavar="FILE.png",
        type=figure_file(),
        help="draw the mark on the lines and the fit (--rally: the bounces)",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def _fit_options(args) -> dict:
    return dict(
        drag="free" if args.fit_drag else ("fixed" if args.fixed_drag else "prior"),
        lift="free" if args.fit_lift else ("fixed" if args.fixed_lift else "prior"),
        contact_sigma=args.contact_sigma,
        window=tuple(args.window),
    )


def _single(args, params) -> TrackCall:
    from tennislab.io import read_cameras, read_detections, read_track
    from tennislab.linecall import call_detections, call_state, call_track

    if args.position is not None:
        if args.velocity is None:
            raise InputError("--position needs --velocity VX VY VZ")
        spin = tuple(args.spin) if args.spin is not None else (0.0, 0.0, 0.0)
        return call_state(
            args.position,
            args.velocity,
            spin,
            params=params,
            surface=args.surface,
            line=args.line,
            target=args.target,
            method=args.method,
            net=args.net,
        )
    opts = dict(params=params, surface=args.surface, line=args.line, target=args.target, **_fit_options(args))
    if args.track is not None:
        tk = read_track(args.track)
        sigma = tk.sigma if tk.sigma is not None else args.sigma
        # a well-formed track that cannot be called (too short, no bounce in reach) is answered
        # review with the reason, as in a rally: never refused (issue 13)
        return call_track(tk.t, tk.xyz, sigma, strict=False, **opts)
    if not args.detections:
        raise InputError("--cameras needs --detections FILE.csv")
    cams = read_cameras(args.cameras)
    det = read_detections(args.detections, cams)
    return call_detections(cams, det, **opts)


def _print_single(res: TrackCall, plot: str | None, physics: str = "") -> None:
    out = res.to_dict()
    b = out["bounce"]
    if b.get("x") is not None:
        print(
            f"bounce: x = {b['x']:.4f} m, y = {b['y']:.4f} m at t = {b['t']:.4f} s"
            + (f" (± {b['sigma_mm']:.1f} mm, 1σ in the worst direction)" if b.get("sigma_mm") else "")
        )
    if out["mark"]:
        print(f"mark: {out['mark']['length'] * 1000:.0f} x {out['mark']['width'] * 1000:.0f} mm")
    net = out.get("net") or {}
    if net.get("contact"):
        print(
            f"net: touched at y = {net['y']:.2f} m, z = {net['z']:.3f} m "
            f"({'went over' if net['crossed'] else 'stopped'})"
        )
    what = f"line {out['line']}" if "line" in out else f"target {out.get('target')}"
    if out["p_in"] is not None:
        print(f"call: {out['call'].upper()} ({what}): mark {in_out_by(out['distance_mm'])}, p_in = {out['p_in']:.3f}")
        if "line" not in out:
            for name, r in out.get("lines", {}).items():
                print(f"  {name:16s} {r['call']:3s} {in_out_by(r['distance_mm']):>18s}  p_in {r['p_in']:.3f}")
    else:
        print(f"call: {out['call'].upper()}")
    if out["reason"]:
        print(f"review: {out['reason']}")
    f = out["fit"]
    if f.get("rms_mm") is not None:
        scales = ", ".join(
            f"{k.replace('_', ' ')} {plus_minus(f[k], f.get(k + '_sigma'), digits=3)}"
            for k in ("drag_scale", "lift_scale")
            if f.get(k) is not None
        )
        print(f"fit: rms {f['rms_mm']:.2f} mm, {f['outliers']} outlier(s), {scales}, {f['elapsed_ms']:.0f} ms")
    sp = out.get("spin")
    if sp and out["method"] == "track-fit":
        print(f"spin: {spin_fit_words(sp)}")
    for lb in out.get("bounces", []):
        print(f"later bounce (not called): x = {lb['x']:.3f} m, y = {lb['y']:.3f} m at t = {lb['t']:.3f} s")
    if "closed_form_error_mm" in out:
        print(f"closed form vs numeric: {out['closed_form_error_mm']:.1f} mm")
    if physics:
        print(physics)
    if plot:
        print(f"figure: {plot}")


def _fmt(v, spec: str) -> str:
    return "-" if v is None else format(v, spec)


def _mark(distance_mm) -> str:
    """A shot's mark against its area in words ("in by 357.6 mm"; "-" when it has none)."""
    return "-" if distance_mm is None else in_out_by(distance_mm)


def _print_rally(res: RallyCall, csv_path: str | None, plot: str | None) -> None:
    print(f"{'point':>28s} {'#':>2s} {'stroke':10s} {'call':7s} {'p_in':>6s} {'mark':>16s} {'tracker':8s} note")
    for s in res.shots:
        tr = escape_text(s["tracker"]["call"] or "-")
        ag = s["agreement"]["call_agrees"]
        note = escape_text(s["reason"] or ("DISAGREES" if ag is False else ""))
        name = escape_text(os.path.basename(str(s["point"])))[-28:]
        stroke = escape_text(s["stroke"] or "-")[:10]
        print(
            f"{name:>28s} {s['shot']:2d} {stroke:10s} {s['call']:7s} "
            f"{_fmt(s['p_in'], '6.3f'):>6s} {_mark(s['distance_mm']):>16s} {tr:8s} {note}"
        )
    sm = res.summary
    print(
        f"{sm['n_shots']} shots: "
        + ", ".join(f"{k} {v}" for k, v in sm["calls"].items() if v)
        + f"; agree with the tracker {sm['tracker_calls_agree']}/{sm['tracker_calls_compared']}"
    )
    bd = sm["bounce_distance_mm_all"]
    if bd["n"]:
        print(f"bounce vs tracker: median {bd['median']:.1f} mm, p90 {bd['p90']:.1f} mm over {bd['n']} shots")
    print(f"{sm['calls_per_second']:.1f} calls per second")
    if csv_path:
        print(f"csv: {csv_path}")
    if plot:
        print(f"figure: {plot}")


def run(args) -> int:
    from tennislab.io import read_points
    from tennislab.linecall import call_rally
    from tennislab.plot import plot_call, plot_rally

    if args.csv and args.rally is None:
        raise InputError("--csv: only with --rally (one row per shot)")
    args.surface = surface_from_arg(args.surface)
    params = physics_from_args(args)
    if args.rally is not None:
        if args.line:
            raise InputError("--line: not with --rally (each shot is called against its own area)")
        if args.target:
            raise InputError("--target: not with --rally (serves go to their box, rally shots to the court)")
        points = read_points(args.rally)
        rally = call_rally(
            points,
            params=params,
            surface=args.surface,
            doubles=args.doubles,
            workers=args.workers,
            progress=progress_from_args(args),
            **_fit_options(args),
        )
        if args.csv:
            rows = rally.rows()

            def write(fh):
                w = csv.DictWriter(fh, fieldnames=list(rows[0]) if rows else ["point"])
                w.writeheader()
                w.writerows(rows)

            atomic_write(args.csv, write)
        if args.plot:
            save_figure(plot_rally(rally, params.court), args.plot)
        if args.json:
            emit_json(rally)
        else:
            _print_rally(rally, args.csv, args.plot)
            print(physics_words(params, args.physics_preset))
        return 0
    res = _single(args, params)
    if args.plot and res.mark_result is not None and res.decision is not None:
        save_figure(plot_call(res, params.court), args.plot)
    elif args.plot:
        raise InputError(f"--plot: nothing to draw: the call is {res.call} without a bounce")
    if args.json:
        emit_json(res)
    else:
        _print_single(res, args.plot, physics_words(params, args.physics_preset))
    return 0
