"""``tennislab impact``: one racket-ball impact (seed 000 sec. 2.2) in the racket and court frames."""

from __future__ import annotations

import math

from tennislab.cli.common import add_physics_flags, emit_json, save_figure
from tennislab.units import RPM


def add_impact_flags(p) -> None:
    """Racket/string/ball-impact flags shared by the impact and serve commands."""
    g = p.add_argument_group("impact")
    g.add_argument("--racket-mass", type=float, metavar="KG", help="racket mass [kg] (seed: 0.2)")
    g.add_argument("--string-stiffness", type=float, metavar="N/M", help="string-bed stiffness [N/m] (seed: 50000)")
    g.add_argument("--friction", type=float, metavar="MU", help="string-ball friction coefficient (seed: 0.35)")
    g.add_argument(
        "--ball-model",
        default="haake2003",
        metavar="NAME",
        help="contact time/COR model: haake2003 (speed-dependent, default) or constant",
    )
    g.add_argument(
        "--friction-model",
        default="elastoplastic",
        choices=("elastoplastic", "seed-clamp"),
        help="stick-slip rule (default elastoplastic; seed-clamp = the seed's eq 20 read literally)",
    )
    g.add_argument(
        "--integrator",
        default="rk4",
        choices=("rk4", "euler"),
        help="impact integrator (default rk4, converged; euler with --dt 1e-4 = the seed's)",
    )
    g.add_argument(
        "--dt",
        type=float,
        default=0.0,
        metavar="S",
        help="fixed impact time step [s] (default: 1/400 of the contact half period)",
    )


def seed_physics_from_args(args):
    """(FlightParams, ImpactParams) with the seed's constants, overridden by any flag given."""
    from tennislab.cli.common import physics_from_args
    from tennislab.serve.setup import seed_impact_params

    flight = physics_from_args(args)
    imp = seed_impact_params(
        ball=flight.ball,
        racket_mass=args.racket_mass,
        string_stiffness=args.string_stiffness,
        friction=args.friction,
        ball_model=args.ball_model,
    )
    if args.friction_model != "elastoplastic":
        import dataclasses

        imp = dataclasses.replace(imp, friction_model=args.friction_model)
    return flight, imp


def register(sub) -> None:
    p = sub.add_parser(
        "impact",
        help="one racket-ball impact: ball speed, spin, contact time",
        description="Racket-ball impact (seed 000 spring-damper model). Angles in degrees, "
        "SI otherwise; defaults are the seed's constants.",
    )
    p.add_argument("--racket-speed", type=float, required=True, metavar="V", help="racket speed [m/s]")
    p.add_argument(
        "--impact-angle",
        type=float,
        required=True,
        metavar="A",
        help="impact angle alpha between racket velocity and face normal [deg]",
    )
    p.add_argument(
        "--face-angle",
        type=float,
        default=0.0,
        metavar="B",
        help="face angle beta, normal tilted below the horizontal [deg] (default 0)",
    )
    p.add_argument(
        "--toss-velocity",
        type=float,
        default=0.0,
        metavar="VZ",
        help="vertical ball velocity at impact [m/s] (negative: falling; default 0)",
    )
    add_impact_flags(p)
    add_physics_flags(p, preset="seed000")
    p.add_argument("--plot", metavar="FILE.png", help="force, velocity and spin histories (worksheet figs 2.2-2.6)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def impact_summary(res, beta: float) -> dict:
    """The JSON object of ``impact`` for an :class:`ImpactResult` and face angle beta [rad]."""
    from tennislab.core.impact import to_court

    vx, vz = to_court(res.v_n, res.v_t, beta)
    return {
        "ball": {
            "speed": res.speed,
            "spin_rpm": res.omega / RPM,
            "spin": res.omega,
            "launch_angle": math.degrees(math.atan2(vz, vx)),
            "velocity": [vx, 0.0, vz],
            "v_n": res.v_n,
            "v_t": res.v_t,
        },
        "racket": {"v_n": res.racket_v_n, "v_t": res.racket_v_t},
        "contact_time_ms": res.contact_time * 1e3,
        "regime": res.regime,
        "grip_time_ms": None if res.grip_time is None else res.grip_time * 1e3,
        "peak_force": res.peak_force,
    }


def run(args) -> int:
    from tennislab.core.impact import impact
    from tennislab.errors import check_range

    _, params = seed_physics_from_args(args)
    a = math.radians(check_range("impact angle", args.impact_angle, -89.999, 89.999, "deg"))
    b = math.radians(check_range("face angle", args.face_angle, -90.0, 90.0, "deg"))
    check_range("dt", args.dt, 0.0, 1e-3, "s")
    # toss (0, 0, vz) in the racket frame: n = (cos b, -sin b), t = (sin b, cos b) in (x, z)
    tn, tt = -args.toss_velocity * math.sin(b), args.toss_velocity * math.cos(b)
    res = impact(
        args.racket_speed, a, params, toss_n=tn, toss_t=tt, dt=args.dt, method=args.integrator, history=bool(args.plot)
    )
    out = impact_summary(res, b)
    out["inputs"] = {
        "racket_speed": args.racket_speed,
        "impact_angle": args.impact_angle,
        "face_angle": args.face_angle,
        "racket_mass": params.racket_mass,
        "string_stiffness": params.string_stiffness,
        "friction": params.friction,
        "ball_mass": params.ball.mass,
        "ball_radius": params.ball.radius,
        "ball_model": params.ball_model.name,
        "friction_model": params.friction_model,
    }
    if args.plot:
        from tennislab.plot.serve import plot_impact_history

        save_figure(
            plot_impact_history(res, title=f"V = {args.racket_speed:g} m/s, alpha = {args.impact_angle:g} deg"),
            args.plot,
        )
    if args.json:
        emit_json(out)
    else:
        bl = out["ball"]
        print(f"ball: {bl['speed']:.2f} m/s, {bl['spin_rpm']:.0f} rpm, launch angle {bl['launch_angle']:.2f} deg")
        print(f"contact: {out['contact_time_ms']:.3f} ms, {out['regime']} (peak force {out['peak_force']:.0f} N)")
        if args.plot:
            print(f"figure: {args.plot}")
    return 0
