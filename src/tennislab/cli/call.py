"""``tennislab call``: where did the ball bounce, and was it in?

Three inputs (one of):

* ``--track FILE.csv``: a 3-D track (t,x,y,z[,sigma]); the physical model is
  fitted through the bounce (:mod:`tennislab.linecall.fit`).
* ``--position X Y Z --velocity VX VY VZ [--spin ...]``: a state; the drop
  point from the numerical model or seed 001's closed form.
* ``--cameras CAMS.json --detections FILE.csv``: 2-D detections from
  calibrated cameras, triangulated, then fitted as a track.

Then the mark (:mod:`tennislab.core.mark`) is called against ``--line`` or
``--target`` (default: the singles court of the half it lands in).
"""

from __future__ import annotations

import time

import numpy as np

from tennislab.cli.common import add_physics_flags, emit_json, physics_from_args, save_figure
from tennislab.errors import InputError


def register(sub) -> None:
    p = sub.add_parser(
        "call",
        help="bounce point, ball mark and line call from a track or a state",
        description="Line calling: fit a ball track (or fly a state) to its bounce, "
        "compute the mark and call it in or out. SI units.",
    )
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--track", metavar="FILE.csv", help="3-D track: columns t,x,y,z[,sigma] [s, m]")
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
        help="drop point from a state: numeric flight (default) or seed 001's closed form",
    )
    p.add_argument("--detections", metavar="FILE.csv", help="2-D detections t,camera,u,v[,sigma_px]")
    p.add_argument("--surface", default="hard", help="court surface: clay, grass, hard, carpet (default hard)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--line", help="call against one line (baseline, service, singles-left, ... near-...)")
    g.add_argument("--target", help="area the shot must land in (singles, doubles, deuce-box, ad-box, near-...)")
    p.add_argument(
        "--sigma",
        type=float,
        help="per-axis track noise [m] if the CSV has no sigma column (default: estimated from the residuals)",
    )
    p.add_argument("--fit-drag", action="store_true", help="also fit a drag scale factor")
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
        default=(0.6, 0.3),
        metavar=("BEFORE", "AFTER"),
        help="fit only points this long before/after the bounce [s] (default 0.6 0.3)",
    )
    add_physics_flags(p)
    p.add_argument("--plot", metavar="FILE.png", help="draw the mark on the lines and the fit")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def _mark_json(mark) -> dict:
    return {
        "length": mark.length,
        "width": mark.width,
        "x": float(mark.center[0]),
        "y": float(mark.center[1]),
        "start_x": float(mark.start[0]),
        "start_y": float(mark.start[1]),
        "skid": mark.skid,
        "compression": mark.compression,
        "contact_time": mark.contact_time,
        "direction": mark.direction,
    }


def _from_state(args, params, surface):
    from tennislab.core.bounce import bounce
    from tennislab.core.flight import fly
    from tennislab.core.mark import ball_mark

    if args.velocity is None:
        raise InputError("--position needs --velocity VX VY VZ")
    spin = tuple(args.spin) if args.spin is not None else (0.0, 0.0, 0.0)
    tr = fly(args.position, args.velocity, spin, params)
    if tr.landing is None:
        raise InputError(f"flight: the ball does not land within t_max = {params.t_max:g} s (no bounce in range)")
    land = tr.landing
    out = {"method": args.method}
    if args.method == "closed-form":
        from tennislab.linecall.closed_form import closed_form_from_physics

        dp = closed_form_from_physics(args.position, args.velocity, spin, params)
        pos = np.array([dp.x, dp.y])
        t = dp.t
        out["closed_form"] = dp.as_dict()
        out["numeric"] = {"x": land.x, "y": land.y, "t": land.t}
        out["closed_form_error_mm"] = float(np.hypot(dp.x - land.x, dp.y - land.y) * 1000)
    else:
        pos = land.position[:2]
        t = land.t
    b = bounce(land.velocity, land.spin, surface, params.ball)
    mark = ball_mark(pos, land.velocity, b.velocity_out, land.spin, surface, params.ball)
    out["bounce"] = {
        "x": float(pos[0]),
        "y": float(pos[1]),
        "t": float(t),
        "sigma_mm": 0.0,
        "velocity_in": land.velocity,
        "spin_in": land.spin,
        "velocity_out": b.velocity_out,
        "spin_out": b.spin_out,
        "mode": b.mode,
    }
    out["fit"] = {"rms_mm": None, "outliers": 0, "n_points": 0}
    return out, mark, None, None


def _from_track(args, params, surface, t, xyz, sigma):
    from tennislab.core.mark import ball_mark
    from tennislab.linecall.fit import fit_track

    if sigma is None and args.sigma is not None:
        if not (0 < args.sigma <= 1):
            raise InputError(f"--sigma: {args.sigma:g} m is outside the allowed range (0, 1] m")
        sigma = np.full(t.size, args.sigma)
    w = args.window
    if not (0 < w[0] <= 100 and 0 <= w[1] <= 100):
        raise InputError(f"--window: ({w[0]:g}, {w[1]:g}) s is outside the allowed range (0, 100] x [0, 100] s")
    if not (0 <= args.contact_sigma <= 10):
        raise InputError(f"--contact-sigma: {args.contact_sigma:g} ms is outside the allowed range [0, 10] ms")
    t0 = time.perf_counter()
    fit = fit_track(
        t,
        xyz,
        sigma,
        params,
        surface,
        fit_drag=args.fit_drag,
        window=tuple(w),
        contact_prior=args.contact_sigma / 1000.0,
    )
    mark = ball_mark(fit.bounce_xy, fit.velocity_in, fit.velocity_out, fit.spin_in, surface, params.ball)
    elapsed = time.perf_counter() - t0
    sb = np.sqrt(np.clip(np.diag(fit.cov), 0, None))
    out = {"method": "track-fit"}
    out["bounce"] = {
        "x": float(fit.p[0]),
        "y": float(fit.p[1]),
        "t": fit.t_bounce,
        "sigma_mm": fit.sigma_bounce * 1000.0,
        "sigma_x_mm": sb[0] * 1000,
        "sigma_y_mm": sb[1] * 1000,
        "sigma_t_ms": sb[2] * 1000,
        "cov_xy_m2": fit.bounce_cov,
        "velocity_in": fit.velocity_in,
        "spin_in": fit.spin_in,
        "velocity_out": fit.velocity_out,
        "spin_out": fit.spin_out,
    }
    out["fit"] = {
        "rms_mm": fit.rms * 1000.0,
        "outliers": int(fit.outlier.sum()),
        "outlier_rows": np.nonzero(fit.outlier)[0],
        "n_points": int(t.size),
        "n_used": int(np.count_nonzero(fit.segment >= 0)),
        "has_post_bounce": fit.has_post,
        "chi2_dof": fit.chi2_dof,
        "sigma_mm": float(np.nanmedian(fit.sigma) * 1000),
        "drag_scale": fit.drag_scale,
        "contact_offset_mm": fit.contact_offset * 1000,
        "evaluations": fit.n_iter,
        "elapsed_ms": elapsed * 1000,
    }
    return out, mark, fit, (t, xyz)


def run(args) -> int:
    from tennislab.core.surfaces import get_surface
    from tennislab.linecall.decide import call_mark

    params = physics_from_args(args)
    surface = get_surface(args.surface)
    fit = None
    track = None
    if args.position is not None:
        out, mark, fit, track = _from_state(args, params, surface)
    elif args.track is not None:
        from tennislab.io.track import read_track

        tk = read_track(args.track)
        out, mark, fit, track = _from_track(args, params, surface, tk.t, tk.xyz, tk.sigma)
    else:
        if not args.detections:
            raise InputError("--cameras needs --detections FILE.csv")
        from tennislab.io.cameras import read_cameras, read_detections
        from tennislab.linecall.cameras import triangulate_detections

        cams = read_cameras(args.cameras)
        det = read_detections(args.detections, cams)
        t, xyz, sig = triangulate_detections(cams, det)
        out, mark, fit, track = _from_track(args, params, surface, t, xyz, sig)
        out["cameras"] = {"n_cameras": len(cams), "n_triangulated": int(t.size)}
    cov = fit.bounce_cov if fit is not None else None
    dec = call_mark(mark, court=params.court, target=args.target, line=args.line, bounce_cov=cov)
    out["mark"] = _mark_json(mark)
    out.update(dec)
    out["surface"] = surface.name
    out["physics"] = {
        "aero": params.aero.name,
        "mass": params.ball.mass,
        "radius": params.ball.radius,
        "air_density": params.atmosphere.density,
        "gravity": params.atmosphere.gravity,
        "wind": params.atmosphere.wind,
    }
    if args.plot:
        from tennislab.plot.linecall import plot_call

        fig = plot_call(mark, dec, params.court, fit=fit, track=track, bounce_cov=cov)
        save_figure(fig, args.plot)
    if args.json:
        emit_json(out)
    else:
        b = out["bounce"]
        what = f"line {dec['line']}" if "line" in dec else f"target {dec['target']}"
        print(
            f"bounce: x = {b['x']:.4f} m, y = {b['y']:.4f} m at t = {b['t']:.4f} s"
            + (f" (+- {b['sigma_mm']:.1f} mm)" if b.get("sigma_mm") else "")
        )
        print(f"mark: {out['mark']['length'] * 1000:.0f} x {out['mark']['width'] * 1000:.0f} mm")
        print(
            f"call: {dec['call'].upper()} ({what}): mark reaches {dec['distance_mm']:+.1f} mm "
            f"{'inside' if dec['distance_mm'] >= 0 else 'short of'} the line, p_in = {dec['p_in']:.3f}"
        )
        for name, r in dec.get("lines", {}).items():
            if "line" not in dec:
                print(f"  {name:16s} {r['call']:3s} {r['distance_mm']:+9.1f} mm  p_in {r['p_in']:.3f}")
        if out["fit"]["rms_mm"] is not None:
            print(
                f"fit: rms {out['fit']['rms_mm']:.2f} mm, {out['fit']['outliers']} outlier(s), "
                f"{out['fit']['elapsed_ms']:.0f} ms"
            )
        if "closed_form_error_mm" in out:
            print(f"closed form vs numeric: {out['closed_form_error_mm']:.1f} mm")
        if args.plot:
            print(f"figure: {args.plot}")
    return 0
