"""``tennislab fly``: one flight from a launch; landing, net, apex, and bounces with ``--bounces N``."""

from __future__ import annotations

import argparse
import textwrap

from tennislab.cli.common import (
    add_launch_flags,
    add_physics_flags,
    emit_json,
    figure_file,
    launch_from_args,
    physics_from_args,
    physics_words,
    save_figure,
    surface_from_arg,
)
from tennislab.core import DEFAULT_NET, NET_MODES
from tennislab.errors import InputError

#: where a ball starts when --position is not given: a groundstroke from the centre of the near
#: baseline, 1 m above the ground [m]
DEFAULT_POSITION = (-11.885, 0.0, 1.0)

EXAMPLES = """examples:
  tennislab fly --speed-kmh 120 --elevation-deg 6 --spin-rpm 2500 --spin-axis topspin
  tennislab fly --position -11.885 0.5 2.8 --velocity 49.5 -1.5 -4.5 --json
  tennislab fly --speed-mph 55 --elevation-deg 8 --heading-deg -3 --spin-rpm 1500 --spin-axis slice \\
                --bounces 2 --surface clay --plot fly.png
"""


def register(sub) -> None:
    p = sub.add_parser(
        "fly",
        help="one flight from a launch: landing, net clearance, apex (and bounces)",
        description=textwrap.fill(
            "Fly one ball from a launch to its landing (or through N bounces). Give the launch as a "
            "velocity vector [m/s] or as a speed with elevation and heading [deg], and the spin as a vector "
            "[rad/s] or as a rate [rpm] about a named axis. Frame: origin at the centre of the net on the "
            "ground, x toward the far baseline, y to the left, z up (docs/conventions.md).",
            width=100,
        ),
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "--position",
        type=float,
        nargs=3,
        metavar=("X", "Y", "Z"),
        help="ball-centre position at launch [m] (default -11.885 0 1: the centre of the near baseline, 1 m up)",
    )
    add_launch_flags(p)
    b = p.add_argument_group("bounces")
    b.add_argument(
        "--bounces",
        type=int,
        default=0,
        metavar="N",
        help="continue through N bounces (default 0: stop at the first landing)",
    )
    b.add_argument(
        "--surface",
        default=None,
        metavar="NAME",
        help="court surface of the bounces: clay, grass, hard, carpet, or a surface file FILE.toml "
        "(tennislab calibrate surface; default hard; only with --bounces)",
    )
    p.add_argument(
        "--net",
        choices=NET_MODES,
        default=DEFAULT_NET,
        help="obstacle (default): the flight ends where the ball meets the net; through: it passes (the seeds' models)",
    )
    add_physics_flags(p)
    o = p.add_argument_group("output")
    o.add_argument("--plot", metavar="FILE.png", type=figure_file(), help="draw side and top views on the court")
    o.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def run(args) -> int:
    import numpy as np

    from tennislab.plot import plot_trajectories, spin_words
    from tennislab.trajectory import fly

    from_config = getattr(args, "config_defaults", {})
    surface_given = args.surface is not None and args.surface != from_config.get("surface")
    if surface_given and args.bounces == 0:
        raise InputError("surface: the surface is used only for bounces; add --bounces N (N >= 1)")
    params = physics_from_args(args)
    position = DEFAULT_POSITION if args.position is None else args.position
    res = fly(
        position,
        **launch_from_args(args),
        params=params,
        surface=surface_from_arg(args.surface) or "hard",
        bounces=args.bounces,
        net=args.net,
    )
    out = res.to_dict()
    if args.plot:
        save_figure(plot_trajectories([res]), args.plot)  # titled with what was flown
    if args.json:
        emit_json(out)
        return 0
    la = out["launch"]
    print(
        f"launch: {la['speed_kmh']:.1f} km/h ({la['speed_ms']:.2f} m/s), elevation {la['elevation_deg']:.1f} deg, "
        f"heading {la['heading_deg']:.1f} deg, spin {spin_words(la['spin_rpm'], la['spin_axis_deg'])}"
    )
    b = out["landing"]
    if b is not None:
        areas = ", ".join(b["areas"]) if b["areas"] else "outside the court"
        print(
            f"landing: x = {b['x']:.3f} m, y = {b['y']:.3f} m at t = {b['t']:.3f} s, "
            f"speed {b['speed']:.2f} m/s ({b['speed_kmh']:.1f} km/h); {areas}"
        )
    n = out["net"]
    nc = out["net_contact"]
    if nc is not None:
        print(
            f"net: STOPPED BY THE NET ({nc['part']}) at y = {nc['y']:.3f} m, z = {nc['z']:.3f} m, t = {nc['t']:.3f} s "
            f"(clearance {n['clearance']:.3f} m)"
        )
    elif n["result"] == "none":
        print("net: not reached")
    else:
        verdict = "HITS THE NET" if n["result"] == "net" else "over"
        print(f"net: {verdict} (centre height {n['z']:.3f} m, clearance {n['clearance']:.3f} m)")
    print(f"apex: z = {out['apex']['z']:.3f} m at x = {out['apex']['x']:.3f} m, t = {out['apex']['t']:.3f} s")
    for i, bo in enumerate(out.get("bounces", []), 1):
        print(
            f"bounce {i} ({out['surface']}, {bo['mode']}): x = {bo['x']:.3f} m, y = {bo['y']:.3f} m, "
            f"t = {bo['t']:.3f} s, out {np.linalg.norm(bo['velocity_out']):.2f} m/s; "
            f"mark {bo['mark']['length'] * 1000:.0f} x {bo['mark']['width'] * 1000:.0f} mm"
        )
    print(physics_words(params, args.physics_preset))
    for c in out["caveats"]:
        print(f"note: {c}")
    if args.plot:
        print(f"figure: {args.plot}")
    return 0
