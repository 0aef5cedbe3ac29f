"""``tennislab impact``: one racket-ball impact (Grosen, Kousted & Treichel 2021, sec. 2.2).

Parses the flags, calls :func:`tennislab.serve.impact` and prints its result.  The impact flags
(:func:`add_impact_flags`) are shared with the serve commands.  ``impact`` has no flight, so of the
physics flags it takes only the ball's ``--mass`` and ``--radius`` and ``--preset`` (the ball of every
command's ``standard`` preset by default, as the serve commands hit it; ``seed000`` the paper's ball).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from tennislab.cli.common import (
    LazyHelp,
    add_physics_flags,
    ball_from_args,
    ball_words,
    emit_json,
    figure_file,
    save_figure,
)

if TYPE_CHECKING:
    from tennislab.core import ImpactParams

PAPER = "Grosen, Kousted & Treichel 2021"


def add_impact_flags(p) -> None:
    """Racket/string/ball-impact flags shared by the impact and serve commands (group "impact")."""
    g = p.add_argument_group(f"impact (the racket-ball model of {PAPER}; defaults: the paper's constants)")
    g.add_argument("--racket-mass", type=float, metavar="KG", help="racket mass [kg] (paper: 0.2)")
    g.add_argument("--string-stiffness", type=float, metavar="N/M", help="string-bed stiffness [N/m] (paper: 50000)")
    g.add_argument("--friction", type=float, metavar="MU", help="string-ball friction coefficient (paper: 0.35)")
    g.add_argument(
        "--ball-model",
        default=None,
        metavar="NAME",
        help=LazyHelp(_ball_model_help),
    )
    g.add_argument(
        "--impact-scheme",
        default="converged",
        choices=IMPACT_CHOICES["impact_scheme"],
        help="converged (default: the physical model, converged integration) or seed-literal (the paper's "
        "equations read literally: friction clamp, eq-6 damper with the ball's mass, racket starting 0.02 m "
        "behind the ball, Euler at 1e-4 s); the flags below override single parts",
    )
    g.add_argument(
        "--friction-model",
        default=None,
        choices=IMPACT_CHOICES["friction_model"],
        help="stick-slip rule: elastoplastic (never creates energy) or seed-clamp (the paper's eq 20 read "
        "literally: the force is clamped while the spring keeps stretching; can create energy)",
    )
    g.add_argument(
        "--tangential-damping",
        default=None,
        choices=IMPACT_CHOICES["tangential_damping"],
        help="tangential damper: oscillator (restitutes 1.04 x COR, as the paper states) or ball (the paper's "
        "eq 6 with the ball's mass and contact time)",
    )
    g.add_argument(
        "--approach-gap",
        type=float,
        default=None,
        metavar="M",
        help="racket start behind the ball with the tangential spring measured from there [m] (0: springs "
        "unloaded at first touch; the paper: 0.02)",
    )
    g.add_argument(
        "--integrator",
        default=None,
        choices=("rk4", "euler"),
        help="impact integrator (rk4: converged; euler with --dt 1e-4 = the paper's)",
    )
    g.add_argument(
        "--dt",
        type=float,
        default=None,
        metavar="S",
        help="fixed impact time step [s] (default for rk4: 1/400 of the contact half period)",
    )


def _ball_model_help() -> str:
    from tennislab.core import ball_model_names

    return (
        f"contact time/COR of the ball vs impact speed: {', '.join(ball_model_names())} (default haake2003, "
        "placeholder data following Haake et al. 2003)"
    )


#: The names the impact flags accept, as the command line lists them without loading the impact's
#: compiled kernels: the keys of :data:`tennislab.serve.IMPACT_SCHEMES`, :data:`tennislab.core.FRICTION_MODELS`
#: and :data:`tennislab.core.TANGENTIAL_DAMPING` (tests/test_architecture.py checks that they are).
IMPACT_CHOICES: dict[str, tuple[str, ...]] = {
    "impact_scheme": ("converged", "seed-literal"),
    "friction_model": ("elastoplastic", "seed-clamp"),
    "tangential_damping": ("oscillator", "ball"),
}


def impact_from_args(args, ball) -> tuple[ImpactParams, str, float]:
    """(ImpactParams, integrator, dt [s]) from the impact flags, for a ball (:class:`tennislab.core.ball.Ball`)."""
    from tennislab.serve import scheme_integration, seed_impact_params

    params = seed_impact_params(
        ball=ball,
        racket_mass=args.racket_mass,
        string_stiffness=args.string_stiffness,
        friction=args.friction,
        ball_model=args.ball_model,
        impact_scheme=args.impact_scheme,
        friction_model=args.friction_model,
        tangential_damping=args.tangential_damping,
        approach_gap=args.approach_gap,
    )
    method, dt = scheme_integration(args.impact_scheme, args.integrator, args.dt)
    return params, method, dt


def register(sub) -> None:
    p = sub.add_parser(
        "impact",
        help="one racket-ball impact: ball speed, spin, contact time",
        description=f"Racket-ball impact with the spring-damper model of {PAPER}. Angles in degrees, "
        "SI otherwise; the racket, strings and contact model default to the paper's constants, the ball to "
        "the standard preset's (the serve commands' ball; --preset seed000: the paper's).",
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
        "--toss-vz",
        dest="toss_vz",
        type=float,
        default=0.0,
        metavar="VZ",
        help="vertical ball velocity at impact [m/s] (negative: falling; default 0)",
    )
    add_impact_flags(p)
    add_physics_flags(p, flags=("mass", "radius"))  # the ball only: an impact flies nothing
    p.add_argument(
        "--plot",
        metavar="FILE.png",
        type=figure_file(),
        help="force, velocity and spin histories (worksheet figs 2.2-2.6)",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run)


def run(args) -> int:
    from tennislab.serve import impact

    ball = ball_from_args(args)  # the preset's ball, --mass / --radius on top (no flight physics)
    params, method, dt = impact_from_args(args, ball)
    res = impact(
        args.racket_speed,
        args.impact_angle,
        face_angle=args.face_angle,
        toss_vz=args.toss_vz,
        params=params,
        method=method,
        dt=dt,
        history=bool(args.plot),
    )
    if args.plot:
        from tennislab.plot import plot_impact_history

        title = f"V = {args.racket_speed:g} m/s, alpha = {args.impact_angle:g} deg"
        save_figure(plot_impact_history(res.result, title=title), args.plot)
    if args.json:
        emit_json({**res.to_dict(), "physics_preset": args.physics_preset})
        return 0
    out = res.to_dict()
    bl = out["ball"]
    print(f"ball: {bl['speed']:.2f} m/s, {bl['spin_rpm']:.0f} rpm, launch angle {bl['launch_angle']:.2f} deg")
    print(f"contact: {out['contact_time_ms']:.3f} ms, {out['regime']} (peak force {out['peak_force']:.0f} N)")
    print(ball_words(ball, args.physics_preset))
    for c in out["caveats"]:
        print(f"note: {c}")
    if args.plot:
        print(f"figure: {args.plot}")
    return 0
