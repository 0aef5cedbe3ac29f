"""``tennislab serve``, ``serve-window`` and ``serve-mc``: the serve analysis of Grosen, Kousted &
Treichel (2021).

Each command parses its flags, calls one workflow of :mod:`tennislab.serve` (``simulate``,
``window``/``windows``, ``monte_carlo``) and prints its result (``--json``: the result's
``to_dict()``).  All three take the physics flags of ``tennislab fly`` (defaults: the ``standard``
physics of every command; ``--preset seed000`` the paper's constants, its sec. 2.3) and the impact
flags of ``tennislab impact``; ``serve-window`` and ``serve-mc`` also ``--scheduler`` / ``--out-dir``
(:mod:`tennislab.batch`).
"""

from __future__ import annotations

import csv
import functools
import math
from typing import TYPE_CHECKING

from tennislab.cli.batch_flags import add_scheduler_flag, batch_options_from_args
from tennislab.cli.common import (
    add_output_flags,
    add_physics_flags,
    atomic_write,
    emit_json,
    physics_from_args,
    physics_words,
    save_figure,
)
from tennislab.cli.impact import PAPER, add_impact_flags, impact_from_args
from tennislab.errors import InputError
from tennislab.plot import num, player_words, spin_words
from tennislab.serve import PEAK_SPIN_ALPHA, TABLE1, get_player, player_names

if TYPE_CHECKING:
    from tennislab.serve import ServeWindow, ServeWindows

#: CSV columns of ``serve-window --csv``
WINDOW_CSV = (
    "player",
    "beta",
    "alpha",
    "spin_rpm",
    "speed",
    "launch_angle",
    "net_height",
    "landing_x",
    "success",
    "category",
)


def _player_flags(p, allow_all: bool = False) -> None:
    p.add_argument(
        "--player",
        default="professional",
        help=f"a registered player profile ({', '.join(player_names())}; aliases pro, rec; default professional)"
        + ("; 'all' = the paper's three players side by side" if allow_all else ""),
    )
    p.add_argument("--impact-height", type=float, metavar="M", help="override the player's impact height [m]")
    p.add_argument("--racket-speed", type=float, metavar="V", help="override the player's racket speed [m/s]")


def _player(args):
    return get_player(args.player).with_overrides(args.impact_height, args.racket_speed)


def _three_d_flags(p) -> None:
    g = p.add_argument_group("3-D serve (with --target)")
    g.add_argument(
        "--target",
        choices=("deuce", "ad"),
        help="judge by the real net and this far service box (3-D); default: the paper's 2-D criteria",
    )
    g.add_argument(
        "--azimuth",
        "--azimuth-deg",
        dest="azimuth_deg",
        type=float,
        default=0.0,
        metavar="DEG",
        help="face normal turned toward +y (left) [deg] (default 0)",
    )
    g.add_argument(
        "--server-y",
        type=float,
        default=0.0,
        metavar="M",
        help="server's lateral position at the baseline [m] (deuce: < 0; default 0)",
    )


def _brush_flag(p) -> None:
    p.add_argument(
        "--brush",
        "--brush-deg",
        dest="brush_deg",
        type=float,
        default=0.0,
        metavar="DEG",
        help="3-D brush direction in the face: 0 topspin, -90 slice, -45 kick [deg] (needs --target)",
    )


#: a failing serve's reason in words (the window's counts)
REASON_WORDS = {
    "net": "into the net",
    "short": "short of the net",
    "long": "long",
    "wide": "wide",
    "no-landing": "without landing",
}
#: the paper's spin classes in words (``other``: between its flat and its topspin serves)
CLASS_WORDS = {"other": "between flat and topspin"}
#: what alpha and beta are, in every help that takes them (docs/serve.md draws them)
ALPHA_WORDS = "the racket's path above the face normal: 0 a flat hit, more brushes up the ball for spin"
BETA_WORDS = "the face normal tilted below the horizontal: 0 a vertical face, more closes it and aims lower"
ANGLES_EPILOG = (
    "alpha (impact angle): the angle of the racket's path above the face normal (0: a flat hit; more alpha "
    "brushes up the ball: more spin, less speed). beta (face angle): the face normal tilted below the "
    "horizontal (0: a vertical face; more beta closes the face and sends the ball lower). Picture: "
    "docs/serve.md."
)


def _angle_flags(p, alpha_help: str, beta_help: str) -> None:
    """``--impact-angle A`` and ``--face-angle B`` [deg]: required unless a ball launch is given."""
    p.add_argument("--impact-angle", type=float, metavar="A", help=f"{alpha_help} ({ALPHA_WORDS}) [deg]")
    p.add_argument("--face-angle", type=float, metavar="B", help=f"{beta_help} ({BETA_WORDS}) [deg]")


def _ball_flags(p, *, elevation: bool = True) -> None:
    """A ball launch instead of the racket (the racket that gives it is solved for): speed, spin, height
    (and elevation, heading)."""
    from tennislab.cli.common import add_speed_flags

    g = p.add_argument_group(
        "ball launch (instead of --racket-speed, --impact-angle, --face-angle: the racket that gives this ball "
        "is solved for and printed)"
    )
    add_speed_flags(g, note="(the ball leaving the racket)")
    g.add_argument("--spin-rpm", type=float, metavar="RPM", help="spin rate of the ball [rpm] (default 0)")
    g.add_argument(
        "--spin-axis",
        metavar="AXIS",
        help="topspin (default) or backspin; with --target also sidespin-left, sidespin-right or an angle [deg] "
        "about the flight (0 topspin, +90 curving left)",
    )
    if elevation:
        g.add_argument(
            "--elevation-deg", type=float, metavar="DEG", help="launch angle above the horizontal [deg] (required)"
        )
    g.add_argument(
        "--heading-deg", type=float, metavar="DEG", help="direction from +x toward +y (left) [deg] (needs --target)"
    )
    g.add_argument(
        "--height",
        type=float,
        metavar="M",
        help="height of the ball at impact [m] (instead of --impact-height)",
    )


def _ball_launch(args, elevation: float | None = None):
    """The :class:`~tennislab.serve.from_ball.BallLaunch` of the ball flags, or None; refuses a mix with
    the racket's flags."""
    from tennislab.cli.common import SPEED_UNITS, parse_spin_axis
    from tennislab.serve import BallLaunch

    speeds = {k: getattr(args, k, None) for k in SPEED_UNITS}
    if all(v is None for v in speeds.values()):
        for flag in ("spin_rpm", "spin_axis", "elevation_deg", "heading_deg", "height"):
            if getattr(args, flag, None) is not None:
                raise InputError(
                    f"--{flag.replace('_', '-')}: a ball launch needs its speed "
                    "(--speed-kmh, --speed-ms or --speed-mph)"
                )
        return None
    for flag in ("impact_angle", "face_angle", "racket_speed", "impact_height"):
        if getattr(args, flag, None) is not None:
            raise InputError(
                f"--{flag.replace('_', '-')}: a ball launch (--speed-kmh ...) replaces the racket's --racket-speed, "
                "--impact-angle, --face-angle and --impact-height (use --height); give one or the other"
            )
    if getattr(args, "azimuth_deg", 0.0) or getattr(args, "brush_deg", 0.0):
        raise InputError("--azimuth: a ball launch gives its direction with --heading-deg and --spin-axis")
    elev = elevation if elevation is not None else getattr(args, "elevation_deg", None)
    if elev is None:
        raise InputError("--elevation-deg: a ball launch needs its launch angle above the horizontal [deg]")
    axis = 0.0
    if args.spin_axis is not None:
        _, g = parse_spin_axis(args.spin_axis)
        axis = math.degrees(g)
    spin = 0.0 if args.spin_rpm is None else args.spin_rpm
    return BallLaunch.of(
        **speeds, spin_rpm=spin, elevation_deg=elev, heading_deg=args.heading_deg or 0.0, spin_axis_deg=axis
    )


def _racket_words(r) -> str:
    """The racket of a ball launch in words, and the ball it gives."""
    g = r.gives
    side = f", azimuth {num(r.azimuth_deg, 1)} deg, brush {num(r.brush_deg, 1)} deg" if r.three_d else ""
    head = f", heading {num(g.heading_deg, 1)} deg" if r.three_d else ""
    return (
        f"racket for this ball: {num(r.racket_speed, 1)} m/s, alpha {num(r.alpha_deg, 1)} deg, "
        f"beta {num(r.beta_deg, 1)} deg{side} (gives {num(g.speed_ms * 3.6, 1)} km/h, "
        f"{spin_words(g.spin_rpm, g.spin_axis_deg)}, elevation {num(g.elevation_deg, 1)} deg{head}, "
        f"from {num(r.height, 2)} m)"
    )


def _solve_racket(args, ball):
    """The racket for ``ball`` with the command's player, physics and 3-D options."""
    from tennislab.serve import racket_for

    return racket_for(
        get_player(args.player),
        ball,
        height=args.height,
        target=args.target,
        server_y=args.server_y,
        toss_vz=getattr(args, "toss_vz", 0.0),
        **_physics(args),
    )


def _racket_and_angles(args):
    """(player, alpha, beta, azimuth, brush, racket-for-ball or None) of the racket's or the ball's flags."""
    ball = _ball_launch(args)
    if ball is None:
        for flag in ("impact_angle", "face_angle"):
            if getattr(args, flag) is None:
                raise InputError(
                    f"--{flag.replace('_', '-')}: required (or describe the ball: --speed-kmh, --spin-rpm, "
                    "--elevation-deg)"
                )
        return (
            _player(args),
            args.impact_angle,
            args.face_angle,
            args.azimuth_deg,
            getattr(args, "brush_deg", 0.0),
            None,
        )
    r = _solve_racket(args, ball)
    player = get_player(args.player).with_overrides(r.height, r.racket_speed)
    return player, r.alpha_deg, r.beta_deg, r.azimuth_deg, r.brush_deg, r


def _model_flags(p, func, *, plot_help: str, csv_help: str | None = None, batch: bool = False) -> None:
    """The 3-D, impact and physics flags (every command's ``standard`` physics; ``--preset seed000`` the
    paper's), the output flags (``--plot`` / ``--csv``
    with these helps), the batch flags (if *batch*); run *func*."""
    _three_d_flags(p)
    add_impact_flags(p)
    add_physics_flags(p)
    add_output_flags(p, csv=csv_help, plot=plot_help)
    if batch:
        add_scheduler_flag(p)
    p.set_defaults(func=func)


def register(sub) -> None:
    p = sub.add_parser(
        "serve",
        help=f"one serve: impact, flight, in or fault and why ({PAPER})",
        description="Simulate one serve of a player profile: impact, flight, whether it goes in, why not and "
        "what would fix it. Give the racket (--impact-angle, --face-angle; the player's racket speed) or the "
        "ball (--speed-kmh, --spin-rpm, --elevation-deg, --height: the racket that gives it is solved for). "
        "Angles in degrees.",
        epilog=ANGLES_EPILOG,
    )
    _player_flags(p)
    _angle_flags(p, "impact angle alpha", "face angle beta")
    _ball_flags(p)
    _brush_flag(p)
    p.add_argument(
        "--toss-velocity",
        "--toss-vz",
        dest="toss_vz",
        type=float,
        default=0.0,
        metavar="VZ",
        help="vertical ball velocity at impact [m/s] (negative: falling)",
    )
    _model_flags(p, run_serve, plot_help="side and top views of the serve")

    p = sub.add_parser(
        "serve-window",
        help=f"all (alpha, beta) serves of a player: Table 1 of {PAPER}",
        description="Sweep alpha and beta over 0-90 deg; summarise successful flat and topspin serves next to "
        "the paper's Table 1.",
        epilog=ANGLES_EPILOG,
    )
    _player_flags(p, allow_all=True)
    p.add_argument("--step", type=float, metavar="DEG", help="angle step [deg] (default 1; 0.5 for a ball launch)")
    p.add_argument(
        "--spin-bands",
        type=float,
        nargs=2,
        metavar=("FLAT_BELOW", "TOPSPIN_ABOVE"),
        help="spin classes of the summary [rpm]: flat below the first, topspin above the second, 'other' between "
        "(default the paper's 1200 3200)",
    )
    _brush_flag(p)
    _ball_flags(p, elevation=False)
    g = [a for a in p._action_groups if a.title and a.title.startswith("ball launch")][0]
    g.add_argument(
        "--elevation-range",
        type=float,
        nargs=2,
        default=(-15.0, 15.0),
        metavar=("LO", "HI"),
        help="launch elevations swept for a ball launch [deg] (default -15 15; at --step, default 0.5 for a ball)",
    )
    g.add_argument(
        "--heading-range",
        type=float,
        nargs=2,
        default=(-15.0, 15.0),
        metavar=("LO", "HI"),
        help="headings swept for a ball launch with --target [deg] (default -15 15)",
    )
    _model_flags(
        p,
        run_window,
        csv_help="write every serve of the window as CSV",
        plot_help="the paper's figures 5, 6 and 7-9 for this player",
        batch=True,
    )

    p = sub.add_parser(
        "serve-mc",
        help="Monte Carlo margin of error of a serve",
        description="Scatter alpha, beta, azimuth (--sd-angle), racket speed (--sd-speed) and "
        "impact height (--sd-height); probability of success and landing ellipse. The nominal serve is a "
        "racket (--impact-angle, --face-angle) or a ball (--speed-kmh, --spin-rpm, --elevation-deg, --height).",
        epilog=ANGLES_EPILOG,
    )
    _player_flags(p)
    _angle_flags(p, "nominal impact angle alpha", "nominal face angle beta")
    _ball_flags(p)
    p.add_argument("--sd-angle", type=float, default=1.0, metavar="DEG", help="sd of alpha, beta, azimuth [deg] (1)")
    p.add_argument("--sd-azimuth", type=float, metavar="DEG", help="sd of the azimuth [deg] (default --sd-angle)")
    p.add_argument("--sd-speed", type=float, default=1.0, metavar="M/S", help="sd of racket speed [m/s] (1)")
    p.add_argument("--sd-height", type=float, default=0.0, metavar="M", help="sd of impact height [m] (0)")
    p.add_argument("--n", type=int, default=10000, metavar="N", help="number of serves (default 10000)")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="random seed (default 0)")
    _model_flags(p, run_mc, plot_help="landing points and 95%% ellipse on the court", batch=True)


def _physics(args) -> dict:
    """The workflows' physics keywords from the flags: flight, impact_params, method, dt."""
    flight = physics_from_args(args)
    params, method, dt = impact_from_args(args, flight.ball)
    return {"flight": flight, "impact_params": params, "method": method, "dt": dt}


def _physics_json(args) -> dict:
    """The JSON's statement of the flight physics: every setting, and the preset it started from."""
    return {"physics": physics_from_args(args).to_dict(), "physics_preset": args.physics_preset}


def _criteria(mode: str) -> str:
    """The success test in words (the JSON keeps the value: ``seed-2d``, ``deuce-box``, ``ad-box``)."""
    return "the paper's 2-D test" if mode == "seed-2d" else f"the real net and {mode}"


def _print_caveats(caveats) -> None:
    for c in caveats:
        print(f"note: {c}")


def run_serve(args) -> int:
    from tennislab.serve import simulate

    player, alpha, beta, azimuth, brush, racket = _racket_and_angles(args)
    res = simulate(
        player,
        alpha,
        beta,
        target=args.target,
        azimuth_deg=azimuth,
        brush_deg=brush,
        server_y=args.server_y,
        toss_vz=args.toss_vz,
        trajectory=bool(args.plot),
        **_physics(args),
    )
    if args.plot:
        # matplotlib.pyplot costs ~0.9 s to import (measured, -X importtime) and every command module
        # is imported at start: plotting modules are imported only when a figure is asked for
        from tennislab.plot import plot_trajectories

        label = f"alpha {num(alpha, 1)}, beta {num(beta, 1)}"
        fl = physics_from_args(args).to_dict()
        title = (
            f"{player_words(res.player)} serve, α {num(alpha, 1)}°, β {num(beta, 1)}°: {num(res.speed * 3.6, 1)} km/h, "
            f"{num(res.spin_rpm, 0)} rpm; {'IN' if res.success else f'FAULT ({res.verdict.reason})'} by "
            f"{_criteria(res.criteria)}\n"
            f"aero {fl['aero']}, air {fl['air_density']:g} kg/m³, ball {fl['mass'] * 1e3:g} g"
        )
        save_figure(plot_trajectories([res.trajectory], [label], title=title), args.plot)
    if args.json:
        extra = {} if racket is None else {"racket_for_ball": racket.to_dict()}
        emit_json({**res.to_dict(), **extra, **_physics_json(args)})
        return 0
    if racket is not None:
        print(_racket_words(racket))
    print(
        f"{player_words(res.player)}: {res.speed:.2f} m/s ({res.speed * 3.6:.1f} km/h), {res.spin_rpm:.0f} rpm "
        f"({CLASS_WORDS.get(res.category, res.category)}), launch {res.launch_angle:.2f} deg"
    )
    net = f"ball centre {res.net_height:.3f} m" if math.isfinite(res.net_height) else "the ball does not reach it"
    print(
        f"net: {net}; lands X = {res.landing_x:.3f} m from the impact point "
        f"(court x = {res.landing['x']:.3f}, y = {res.landing['y']:.3f}); judged by {_criteria(res.criteria)}"
    )
    print(res.verdict.line())
    if res.verdict.advice:
        print(f"advice: {res.verdict.advice}")
    print(physics_words(physics_from_args(args), args.physics_preset))
    _print_caveats(res.caveats)
    return 0


def _fmt_range(r, nd=1):
    return "-" if r is None else f"{r[0]:.{nd}f} - {r[1]:.{nd}f}"


def comparison_table(win) -> list[str]:
    """Text rows: this run's Table 1 next to the paper's."""
    pub = TABLE1.get(win.player.name)
    s = win.summary()
    keys = (
        ("beta", 0),
        ("alpha", 0),
        ("spin_rpm", 0),
        ("speed", 1),
        ("landing_x", 2),
        ("net_height", 2),
        ("launch_angle", 1),
    )
    lines = [
        f"{win.player.name} (impact height {win.player.impact_height:g} m, racket {win.player.racket_speed:g} m/s; "
        f"judged by {_criteria(win.mode)})",
        f"{'':9s}{'n':>5s}" + "".join(f"{k:>18s}" for k, _ in keys),
    ]
    for cat in ("flat", "other", "topspin"):
        lines.append(f"{cat:9s}{s[cat]['n']:5d}" + "".join(f"{_fmt_range(s[cat][k], nd):>18s}" for k, nd in keys))
        if pub and cat in pub:
            p = pub[cat]
            lines.append(f"{'  paper':9s}{p['n']:5d}" + "".join(f"{_fmt_range(p[k], nd):>18s}" for k, nd in keys))
    b = win.bands()
    lines.append(
        f"spin classes: flat < {b['flat'][1]:g} rpm, other {b['other'][0]:g}-{b['other'][1]:g} rpm, "
        f"topspin > {b['topspin'][0]:g} rpm (--spin-bands)"
    )
    return lines


def empty_window_hint(win, args) -> str | None:
    """The words of :func:`tennislab.serve.hint.window_hint` for ``win``: why its serves fail and, in 3-D,
    the azimuth toward the box that lets serves in; None if some go in."""
    from tennislab.serve import window_hint

    h = window_hint(win, step=args.step)
    if h is None:
        return None
    words = ", ".join(f"{n} {REASON_WORDS.get(k, k)}" for k, n in sorted(h.failures.items(), key=lambda kv: -kv[1]))
    hint = f"no serve of the window goes in ({words})"
    if h.azimuth_deg is None:
        return hint + "; try another player (--racket-speed, --impact-height) or a finer --step"
    turn = f"(--azimuth {h.azimuth_deg:g})"
    if h.n_in:
        return hint + f"; turned toward the box's centre {turn}, {h.n_in} serves go in ({h.step_deg:g}-deg grid)"
    return hint + f"; even turned toward the box's centre {turn} none goes in ({h.step_deg:g}-deg grid)"


def _mapper(args):
    from tennislab.batch import map_chunks

    opts = batch_options_from_args(args)
    if opts["scheduler"] == "local" and not opts["out"]:
        return None  # in process, no chunking overhead
    return functools.partial(map_chunks, unit="serves", **opts)


def run_ball_window(args, ball) -> int:
    """``serve-window`` of a ball launch: its launch directions (elevation; heading with a target) that go in."""
    from tennislab.serve import ball_window

    if args.player == "all" or args.spin_bands is not None or args.plot:
        flag = "--player all" if args.player == "all" else "--spin-bands" if args.spin_bands else "--plot"
        raise InputError(f"{flag}: not with a ball launch (its window is over launch directions of one ball)")
    if args.heading_deg is not None:
        raise InputError("--heading-deg: not with serve-window (its headings are swept: --heading-range LO HI)")
    res = ball_window(
        get_player(args.player),
        ball,
        height=args.height,
        step=0.5 if args.step is None else args.step,
        elevation_deg=tuple(args.elevation_range),
        heading_deg=tuple(args.heading_range),
        target=args.target,
        server_y=args.server_y,
        **_physics(args),
    )
    if args.csv:

        def _w(fh):
            w = csv.DictWriter(fh, fieldnames=res.COLUMNS, lineterminator="\n")
            w.writeheader()
            w.writerows(res.rows())

        atomic_write(args.csv, _w)
    if args.json:
        emit_json({**res.to_dict(), **_physics_json(args)})
        return 0
    r, a = res.racket, ball
    print(
        f"ball: {num(a.speed_ms * 3.6, 1)} km/h, {spin_words(a.spin_rpm, a.spin_axis_deg)} from {num(r.height, 2)} m; "
        f"racket {num(r.racket_speed, 1)} m/s, alpha {num(r.alpha_deg, 1)} deg"
        + (f", brush {num(r.brush_deg, 1)} deg" if r.three_d else "")
        + f" (judged by {_criteria(res.criteria)})"
    )
    rg = res.ranges()
    n, total = int(res.success.sum()), int(res.success.size)
    if n:
        where = f"elevation {num(rg['elevation_deg'][0], 1)} to {num(rg['elevation_deg'][1], 1)} deg"
        where += f" (beta {num(rg['beta_deg'][0], 1)} to {num(rg['beta_deg'][1], 1)} deg)"
        if r.three_d:
            where += f", heading {num(rg['heading_deg'][0], 1)} to {num(rg['heading_deg'][1], 1)} deg"
            where += f" (azimuth {num(rg['azimuth_deg'][0], 1)} to {num(rg['azimuth_deg'][1], 1)} deg)"
        print(f"in: {n} of {total} launch directions: {where}")
    else:
        print(
            f"in: none of the {total} launch directions "
            "(hint: widen --elevation-range or --heading-range, or change the ball)"
        )
    fails = res.failures()
    if fails:
        print(
            "fails: "
            + ", ".join(f"{k_n} {REASON_WORDS.get(k, k)}" for k, k_n in sorted(fails.items(), key=lambda kv: -kv[1]))
        )
    print(physics_words(physics_from_args(args), args.physics_preset))
    _print_caveats(res.caveats)
    if args.csv:
        print(f"wrote {args.csv}")
    return 0


def run_window(args) -> int:
    from tennislab.serve import simulate, window, windows

    ball = _ball_launch(args, elevation=0.0)
    if ball is not None:
        return run_ball_window(args, ball)
    if args.step is None:
        args.step = 1.0

    criteria = None
    if args.spin_bands is not None:
        from dataclasses import replace

        from tennislab.serve import SeedCriteria

        lo, hi = args.spin_bands
        criteria = replace(SeedCriteria(), flat_max_rpm=lo, topspin_min_rpm=hi)  # (checked by SeedCriteria)
    kw = dict(
        step=args.step,
        criteria=criteria,
        mapper=_mapper(args),
        target=args.target,
        server_y=args.server_y,
        azimuth_deg=args.azimuth_deg,
        brush_deg=args.brush_deg,
        **_physics(args),
    )
    res: ServeWindow | ServeWindows
    if args.player == "all":
        if args.impact_height is not None or args.racket_speed is not None:
            raise InputError("--player all: --impact-height/--racket-speed need a single player")
        res = windows("all", **kw)
        wins = list(res.windows)
    else:
        res = window(_player(args), **kw)
        wins = [res]
    if args.csv:

        def _w(fh):
            w = csv.DictWriter(fh, fieldnames=WINDOW_CSV, extrasaction="ignore", lineterminator="\n")
            w.writeheader()
            w.writerows(res.rows())

        atomic_write(args.csv, _w)
    if args.plot:
        # matplotlib: imported only for a figure (see run_serve)
        from tennislab.plot import plot_window

        trs = [
            [
                None
                if (o := w.optimum(cat)) is None
                else simulate(
                    w.player,
                    o["alpha"],
                    o["beta"],
                    trajectory=True,
                    advice=False,
                    target=args.target,
                    server_y=args.server_y,
                    azimuth_deg=args.azimuth_deg,
                    brush_deg=args.brush_deg,
                    **_physics(args),
                ).trajectory
                for cat in ("flat", "topspin")
            ]
            for w in wins
        ]
        save_figure(plot_window(wins, optimum_trajectories=trs), args.plot)
    hints = {w.player.name: h for w in wins if (h := empty_window_hint(w, args))}
    if args.json:
        extra = {} if not hints else {"hint": hints if len(wins) > 1 else hints[wins[0].player.name]}
        emit_json({**res.to_dict(), **extra, **_physics_json(args)})
        return 0
    for win in wins:
        print("\n".join(comparison_table(win)))
        if win.player.name in hints:
            print(f"hint: {hints[win.player.name]}")
        name = win.player.name
        print(
            f"peak spin at alpha = {win.peak_spin_alpha:g} deg"
            + (f" (paper {PEAK_SPIN_ALPHA[name]})" if name in PEAK_SPIN_ALPHA else "")
        )
        for cat in ("flat", "topspin"):
            opt = win.optimum(cat)
            if opt:
                print(
                    f"optimum {cat}: beta {opt['beta']:g}, alpha {opt['alpha']:g}, {opt['speed']:.2f} m/s, "
                    f"{opt['spin_rpm']:.0f} rpm, X {opt['landing_x']:.2f} m, Y {opt['net_height']:.2f} m, "
                    f"gamma {opt['launch_angle']:.1f} deg"
                )
        print()
    print(physics_words(physics_from_args(args), args.physics_preset))
    _print_caveats(wins[0].caveats)
    for f in (args.csv, args.plot):
        if f:
            print(f"wrote {f}")
    return 0


def _mc_mapper(args):
    """``map_chunks`` over blocks of serves (:func:`tennislab.serve.mc.block_size`): ``--chunk-size``
    (serves) is rounded to whole blocks, one block per chunk by default; the numbers never change."""
    from tennislab.batch import map_chunks

    opts = batch_options_from_args(args)
    from tennislab.serve import block_size

    block = block_size(max(1, args.n))
    opts["chunk_size"] = max(1, round(opts["chunk_size"] / block)) if opts.get("chunk_size") else 1
    opts["desc"] = f"serve-mc (chunks of {opts['chunk_size'] * block} serves)"
    return functools.partial(map_chunks, unit="serves", count=_serves, total_units=max(1, args.n), **opts)


def _serves(outputs: dict) -> int:
    """Serves a chunk of Monte Carlo blocks stands for (its blocks' ``n``)."""
    return int(sum(outputs["n"]))


def run_mc(args) -> int:
    from tennislab.serve import monte_carlo

    player, alpha, beta, azimuth, brush, racket = _racket_and_angles(args)
    res = monte_carlo(
        player,
        alpha,
        beta,
        n=args.n,
        seed=args.seed,
        sd_angle=args.sd_angle,
        sd_speed=args.sd_speed,
        sd_height=args.sd_height,
        sd_azimuth=args.sd_azimuth,
        target=args.target,
        azimuth_deg=azimuth,
        brush_deg=brush,
        server_y=args.server_y,
        mapper=_mc_mapper(args),
        samples=bool(args.plot),
        **_physics(args),
    )
    if args.plot:
        # matplotlib: imported only for a figure (see run_serve)
        from tennislab.plot import plot_mc

        save_figure(plot_mc(res), args.plot)
    if args.json:
        extra = {} if racket is None else {"racket_for_ball": racket.to_dict()}
        emit_json({**res.to_dict(), **extra, **_physics_json(args)})
        return 0
    if racket is not None:
        print(_racket_words(racket))
    m = res.landing["mean"]
    print(
        f"{player_words(res.player)}: P(success) = {res.p_success:.4f} ± {res.p_success_se:.4f} "
        f"over {res.n} serves (judged by {_criteria(res.criteria)})"
    )
    if m[0] is not None:
        e = res.landing["ellipse_95"]
        print(
            f"landing mean x = {num(m[0], 3)} m, y = {num(m[1], 3)} m"
            + (
                ""
                if e is None
                else f"; 95 % ellipse semi-axes {e['semi_axes'][0]:.2f} x {e['semi_axes'][1]:.2f} m at "
                f"{num(e['angle_deg'], 1)} deg"
            )
        )
    print(physics_words(physics_from_args(args), args.physics_preset))
    _print_caveats(res.caveats)
    return 0
