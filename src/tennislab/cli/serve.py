"""``tennislab serve``, ``serve-window`` and ``serve-mc``: the serve analysis of seed 000.

All three accept the physics flags of ``tennislab fly`` (defaults: the seed's
constants, section 2.3) and the impact flags of ``tennislab impact``.
``serve-window`` and ``serve-mc`` also take ``--scheduler`` / ``--out-dir`` from
:mod:`tennislab.batch` when that package is installed.
"""

from __future__ import annotations

import csv
import functools

from tennislab.cli.common import add_output_flags, add_physics_flags, atomic_write, emit_json, save_figure
from tennislab.cli.impact import add_impact_flags, seed_physics_from_args
from tennislab.errors import InputError

try:  # issue 7's batch layer (optional)
    from tennislab.batch import add_scheduler_flag, batch_options_from_args, map_chunks
except ImportError:  # pragma: no cover - the CLI works without it
    add_scheduler_flag = batch_options_from_args = map_chunks = None


def _player_flags(p, allow_all: bool = False) -> None:
    p.add_argument(
        "--player",
        default="professional",
        help="professional (pro), recreational (rec) or junior (default professional)"
        + ("; 'all' = the seed's three players side by side" if allow_all else ""),
    )
    p.add_argument("--impact-height", type=float, metavar="M", help="override the player's impact height [m]")
    p.add_argument("--racket-speed", type=float, metavar="V", help="override the player's racket speed [m/s]")


def _player(args):
    from tennislab.serve.players import Player, get_player

    pl = get_player(args.player)
    if args.impact_height is not None or args.racket_speed is not None:
        pl = Player(
            pl.name if args.impact_height is None and args.racket_speed is None else f"{pl.name}*",
            pl.impact_height if args.impact_height is None else args.impact_height,
            pl.racket_speed if args.racket_speed is None else args.racket_speed,
        )
    return pl


def _three_d_flags(p) -> None:
    g = p.add_argument_group("3-D serve (with --target)")
    g.add_argument(
        "--target",
        choices=("deuce", "ad"),
        help="judge by the real net and this far service box (3-D); default: the seed's 2-D criteria",
    )
    g.add_argument(
        "--azimuth",
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


def _mapper(args):
    if map_chunks is None:
        return None
    opts = batch_options_from_args(args)
    if opts["scheduler"] == "local" and not opts["out"]:
        return None  # in process, no chunking overhead
    opts["progress"] = opts.get("progress", True)
    return functools.partial(map_chunks, **opts)


def _angle_flags(p, alpha_help: str, beta_help: str) -> None:
    """``--impact-angle A`` and ``--face-angle B`` [deg], both required."""
    p.add_argument("--impact-angle", type=float, required=True, metavar="A", help=alpha_help)
    p.add_argument("--face-angle", type=float, required=True, metavar="B", help=beta_help)


def _brush_flag(p) -> None:
    p.add_argument(
        "--brush",
        type=float,
        default=0.0,
        metavar="DEG",
        help="3-D brush direction in the face: 0 topspin, -90 slice, -45 kick [deg] (needs --target)",
    )


def _model_flags(p, func, *, plot_help: str, csv_help: str | None = None, batch: bool = False) -> None:
    """The 3-D, impact and physics flags (the seed's defaults), the output flags (``--plot`` / ``--csv``
    with these helps), the batch flags (if *batch* and :mod:`tennislab.batch` is installed); run *func*."""
    _three_d_flags(p)
    add_impact_flags(p)
    add_physics_flags(p, preset="seed000")
    add_output_flags(p, csv=csv_help, plot=plot_help)
    if batch and add_scheduler_flag is not None:
        add_scheduler_flag(p)
    p.set_defaults(func=func)


def register(sub) -> None:
    p = sub.add_parser(
        "serve",
        help="one serve: impact, flight, success (seed 000)",
        description="Simulate one serve of a player profile. Angles in degrees.",
    )
    _player_flags(p)
    _angle_flags(p, "impact angle alpha [deg]", "racket face angle beta [deg]")
    _brush_flag(p)
    p.add_argument(
        "--toss-velocity",
        type=float,
        default=0.0,
        metavar="VZ",
        help="vertical ball velocity at impact [m/s] (negative: falling)",
    )
    _model_flags(p, run_serve, plot_help="side and top views of the serve")

    p = sub.add_parser(
        "serve-window",
        help="all (alpha, beta) serves of a player: Table 1 of seed 000",
        description="Sweep alpha and beta over 0-90 deg; summarise successful flat and "
        "topspin serves next to the seed's Table 1.",
    )
    _player_flags(p, allow_all=True)
    p.add_argument("--step", type=float, default=1.0, metavar="DEG", help="angle step [deg] (default 1)")
    _brush_flag(p)
    _model_flags(
        p,
        run_window,
        csv_help="write every serve of the window as CSV",
        plot_help="the seed's figures 5, 6 and 7-9 for this player",
        batch=True,
    )

    p = sub.add_parser(
        "serve-mc",
        help="Monte Carlo margin of error of a serve",
        description="Scatter alpha, beta, azimuth (--sd-angle), racket speed (--sd-speed) and "
        "impact height (--sd-height); probability of success and landing ellipse.",
    )
    _player_flags(p)
    _angle_flags(p, "nominal alpha [deg]", "nominal beta [deg]")
    p.add_argument("--sd-angle", type=float, default=1.0, metavar="DEG", help="sd of alpha, beta, azimuth [deg] (1)")
    p.add_argument("--sd-azimuth", type=float, metavar="DEG", help="sd of the azimuth [deg] (default --sd-angle)")
    p.add_argument("--sd-speed", type=float, default=1.0, metavar="M/S", help="sd of racket speed [m/s] (1)")
    p.add_argument("--sd-height", type=float, default=0.0, metavar="M", help="sd of impact height [m] (0)")
    p.add_argument("--n", type=int, default=10000, metavar="N", help="number of serves (default 10000)")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="random seed (default 0)")
    _model_flags(p, run_mc, plot_help="landing points and 95%% ellipse on the court", batch=True)


def _impact_kw(args) -> dict:
    from tennislab.errors import check_range

    check_range("dt", args.dt, 0.0, 1e-3, "s")
    return {"dt": args.dt, "method": args.integrator}


def run_serve(args) -> int:
    from tennislab.serve.single import simulate_serve

    flight, imp = seed_physics_from_args(args)
    out = simulate_serve(
        _player(args),
        args.impact_angle,
        args.face_angle,
        flight=flight,
        impact_params=imp,
        target=args.target,
        azimuth_deg=args.azimuth,
        brush_deg=args.brush,
        server_y=args.server_y,
        toss_vz=args.toss_velocity,
        trajectory=bool(args.plot),
        **_impact_kw(args),
    )
    tr = out.pop("_trajectory", None)
    if args.plot:
        from tennislab.plot.trajectory import plot_trajectories

        fig = plot_trajectories(
            [tr], [f"alpha {args.impact_angle:g}, beta {args.face_angle:g}"], title=f"{out['player']} serve"
        )
        save_figure(fig, args.plot)
    if args.json:
        emit_json(out)
    else:
        print(
            f"{out['player']}: {out['speed']:.2f} m/s, {out['spin_rpm']:.0f} rpm ({out['category']}), "
            f"launch {out['launch_angle']:.2f} deg"
        )
        print(
            f"net: ball centre {out['net_height']:.3f} m; lands X = {out['landing_x']:.3f} m from the impact "
            f"point (court x = {out['landing']['x']:.3f}, y = {out['landing']['y']:.3f}): "
            f"{'IN' if out['success'] else 'FAULT'} ({out['criteria']})"
        )
    return 0


def _fmt_range(r, nd=1):
    return "-" if r is None else f"{r[0]:.{nd}f} - {r[1]:.{nd}f}"


def comparison_table(win) -> list[str]:
    """Text rows: this run's Table 1 next to the seed's."""
    from tennislab.serve.published import TABLE1

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
        f"criteria {win.mode})",
        f"{'':9s}{'n':>5s}" + "".join(f"{k:>18s}" for k, _ in keys),
    ]
    for cat in ("flat", "topspin"):
        lines.append(f"{cat:9s}{s[cat]['n']:5d}" + "".join(f"{_fmt_range(s[cat][k], nd):>18s}" for k, nd in keys))
        if pub:
            p = pub[cat]
            lines.append(f"{'  seed':9s}{p['n']:5d}" + "".join(f"{_fmt_range(p[k], nd):>18s}" for k, nd in keys))
    return lines


def _window_dict(win):
    from tennislab.serve.published import OPTIMUM, PEAK_SPIN_ALPHA, TABLE1

    out = win.to_dict()
    if win.player.name in TABLE1:
        out["published"] = {
            "summary": TABLE1[win.player.name],
            "peak_spin_alpha": PEAK_SPIN_ALPHA[win.player.name],
            "optimum": OPTIMUM[win.player.name],
        }
    return out


def run_window(args) -> int:
    from tennislab.serve.players import SEED_PLAYERS
    from tennislab.serve.published import PEAK_SPIN_ALPHA
    from tennislab.serve.window import serve_window

    flight, imp = seed_physics_from_args(args)
    if args.player == "all":
        if args.impact_height is not None or args.racket_speed is not None:
            raise InputError("--player all: --impact-height/--racket-speed need a single player")
        players = list(SEED_PLAYERS)
    else:
        players = [_player(args)]
    mapper = _mapper(args)
    wins = [
        serve_window(
            pl,
            step=args.step,
            flight=flight,
            impact=imp,
            mapper=mapper,
            target=args.target,
            server_y=args.server_y,
            azimuth_deg=args.azimuth,
            brush_deg=args.brush,
            **_impact_kw(args),
        )
        for pl in players
    ]
    outs = [_window_dict(w) for w in wins]
    out = outs[0] if len(outs) == 1 else {"players": {w.player.name: o for w, o in zip(wins, outs)}}
    if args.csv:
        cols = (
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

        def _w(fh):
            w = csv.DictWriter(fh, fieldnames=cols, extrasaction="ignore", lineterminator="\n")
            w.writeheader()
            for win in wins:
                for row in win.rows():
                    row["player"] = win.player.name
                    w.writerow(row)

        atomic_write(args.csv, _w)
    if args.plot:
        from tennislab.plot.serve import plot_window
        from tennislab.serve.single import simulate_serve

        all_trs = []
        for win, o in zip(wins, outs):
            trs = []
            for cat in ("flat", "topspin"):
                opt = o["optimum"][cat]
                trs.append(
                    None
                    if opt is None
                    else simulate_serve(
                        win.player,
                        opt["alpha"],
                        opt["beta"],
                        flight=flight,
                        impact_params=imp,
                        trajectory=True,
                        target=args.target,
                        server_y=args.server_y,
                        azimuth_deg=args.azimuth,
                        brush_deg=args.brush,
                        **_impact_kw(args),
                    )["_trajectory"]
                )
            all_trs.append(trs)
        save_figure(plot_window(wins, optimum_trajectories=all_trs), args.plot)
    if args.json:
        emit_json(out)
    else:
        for win, o in zip(wins, outs):
            print("\n".join(comparison_table(win)))
            name = win.player.name
            print(
                f"peak spin at alpha = {o['peak_spin_alpha']:g} deg"
                + (f" (seed {PEAK_SPIN_ALPHA[name]})" if name in PEAK_SPIN_ALPHA else "")
            )
            for cat in ("flat", "topspin"):
                opt = o["optimum"][cat]
                if opt:
                    print(
                        f"optimum {cat}: beta {opt['beta']:g}, alpha {opt['alpha']:g}, {opt['speed']:.2f} m/s, "
                        f"{opt['spin_rpm']:.0f} rpm, X {opt['landing_x']:.2f} m, Y {opt['net_height']:.2f} m, "
                        f"gamma {opt['launch_angle']:.1f} deg"
                    )
            print()
        for f in (args.csv, args.plot):
            if f:
                print(f"wrote {f}")
    return 0


def _mc_mapper(args):
    """``map_chunks`` over blocks of serves (:func:`tennislab.serve.mc.block_size`): ``--chunk-size``
    (serves) is rounded to whole blocks, one block per chunk by default; the numbers never change."""
    if map_chunks is None:
        return None
    from tennislab.serve.mc import block_size

    opts = batch_options_from_args(args)
    block = block_size(args.n)
    opts["chunk_size"] = max(1, round(opts["chunk_size"] / block)) if opts.get("chunk_size") else 1
    opts["desc"] = f"serve-mc (chunks of {opts['chunk_size'] * block} serves; rows/s = blocks/s)"
    return functools.partial(map_chunks, **opts)


def run_mc(args) -> int:
    from tennislab.serve.mc import run_mc as _run

    flight, imp = seed_physics_from_args(args)
    if args.n < 1 or args.n > 10**8:
        raise InputError(f"n: {args.n} is outside the allowed range [1, 100000000]")
    res = _run(
        _player(args),
        args.impact_angle,
        args.face_angle,
        n=args.n,
        seed=args.seed,
        sd_angle=args.sd_angle,
        sd_speed=args.sd_speed,
        sd_height=args.sd_height,
        sd_azimuth=args.sd_azimuth,
        target=args.target,
        azimuth_deg=args.azimuth,
        server_y=args.server_y,
        flight=flight,
        impact_params=imp,
        mapper=_mc_mapper(args),
        return_samples=bool(args.plot),
        **_impact_kw(args),
    )
    samples = res.pop("_samples", None)
    if args.plot:
        from tennislab.plot.serve import plot_mc

        save_figure(plot_mc(samples, res), args.plot)
    if args.json:
        emit_json(res)
    else:
        m = res["landing"]["mean"]
        print(
            f"{res['player']}: P(success) = {res['p_success']:.4f} +- {res['p_success_se']:.4f} "
            f"over {res['n']} serves ({res['criteria']})"
        )
        if m[0] is not None:
            e = res["landing"]["ellipse_95"]
            print(
                f"landing mean x = {m[0]:.3f} m, y = {m[1]:.3f} m"
                + (
                    ""
                    if e is None
                    else f"; 95 % ellipse semi-axes {e['semi_axes'][0]:.2f} x "
                    f"{e['semi_axes'][1]:.2f} m at {e['angle_deg']:.1f} deg"
                )
            )
    return 0
