"""``tennislab fly``: one flight from a 3-D state; landing, net and apex."""

from __future__ import annotations

import numpy as np

from tennislab.cli.common import add_physics_flags, emit_json, physics_from_args, save_figure
from tennislab.errors import InputError, check_vector
from tennislab.trajectory import fly
from tennislab.units import RPM


def register(sub) -> None:
    p = sub.add_parser(
        "fly",
        help="integrate one flight from a position, velocity and spin",
        description="Integrate one ball flight (SI units: m, m/s, rad/s) to its landing.",
    )
    p.add_argument(
        "--position",
        type=float,
        nargs=3,
        required=True,
        metavar=("X", "Y", "Z"),
        help="ball-centre position [m] (origin: net centre on the ground)",
    )
    p.add_argument("--velocity", type=float, nargs=3, required=True, metavar=("VX", "VY", "VZ"), help="velocity [m/s]")
    p.add_argument("--spin", type=float, nargs=3, metavar=("WX", "WY", "WZ"), help="spin vector [rad/s]")
    p.add_argument("--spin-rpm", type=float, help="spin rate [rpm], with --spin-axis")
    p.add_argument(
        "--spin-axis", type=float, nargs=3, metavar=("AX", "AY", "AZ"), help="spin axis (any length; right-hand rule)"
    )
    p.add_argument(
        "--surface", default="hard", help="court surface for --bounces: clay, grass, hard, carpet (default hard)"
    )
    p.add_argument(
        "--bounces",
        type=int,
        default=0,
        help="continue through N bounces on --surface (default 0: stop at the first landing)",
    )
    add_physics_flags(p)
    p.add_argument("--plot", metavar="FILE.png", help="draw side and top views on the court")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def spin_from_args(args) -> tuple:
    """Spin vector [rad/s] from ``--spin`` or ``--spin-rpm`` + ``--spin-axis``."""
    if args.spin is not None and (args.spin_rpm is not None or args.spin_axis is not None):
        raise InputError("--spin: give either --spin or --spin-rpm with --spin-axis, not both")
    if args.spin_rpm is not None or args.spin_axis is not None:
        if args.spin_rpm is None or args.spin_axis is None:
            raise InputError("--spin-rpm and --spin-axis must be given together")
        ax = np.array(check_vector("spin-axis", args.spin_axis))
        n = np.linalg.norm(ax)
        if n == 0:
            raise InputError("--spin-axis: must not be the zero vector")
        return tuple(ax / n * args.spin_rpm * RPM)
    return tuple(args.spin) if args.spin is not None else (0.0, 0.0, 0.0)


def run(args) -> int:
    params = physics_from_args(args)
    spin = spin_from_args(args)
    res = fly(args.position, args.velocity, spin, params=params, surface=args.surface, bounces=args.bounces)
    out = res.to_dict()
    trs = res.segments
    if args.plot:
        from tennislab.plot.trajectory import plot_trajectories

        fig = plot_trajectories(trs, title="tennislab fly")
        save_figure(fig, args.plot)
    if args.json:
        emit_json(out)
    else:
        b = out["bounce"]
        print(f"landing: x = {b['x']:.3f} m, y = {b['y']:.3f} m at t = {b['t']:.3f} s, speed {b['speed']:.2f} m/s")
        n = out["net"]
        if n["result"] == "none":
            print("net: not reached")
        else:
            print(f"net: {n['result']} (centre height {n['z']:.3f} m, clearance {n['clearance']:.3f} m)")
        print(f"apex: z = {out['apex']['z']:.3f} m at t = {out['apex']['t']:.3f} s")
        for i, b in enumerate(out.get("bounces", []), 1):
            print(
                f"bounce {i} ({out['surface']}, {b['mode']}): x = {b['x']:.3f} m, y = {b['y']:.3f} m, "
                f"t = {b['t']:.3f} s, out {np.linalg.norm(b['velocity_out']):.2f} m/s; "
                f"mark {b['mark']['length'] * 1000:.0f} x {b['mark']['width'] * 1000:.0f} mm"
            )
        if args.plot:
            print(f"figure: {args.plot}")
    return 0
