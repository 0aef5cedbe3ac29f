"""``tennislab launcher``: the two-roller launcher of Wójcicki, Puciłowski & Kulesza (2010).

Sub-commands: ``aim``, ``inverse``, ``rollers``, ``power``, ``drill`` (here) and the database's ``table``,
``lookup``, ``info``, ``play``, ``drills`` (:mod:`tennislab.cli._launcher_db`).  Each parses its
flags, calls a workflow of :mod:`tennislab.launcher` and prints its result (``--json``: the
result's ``to_dict()``).  JSON keys named in the issues are a contract (extend, never rename).
"""

from __future__ import annotations

import math

import tennislab.cli._launcher_db as _launcher_db
from tennislab.cli._launcher_args import (
    add_preference_flags,
    add_speed,
    add_spin_flags,
    add_tolerance_flags,
    check_output,
    preference_kwargs,
    spec_from_args,
    speed_kwargs,
    spin_axis_deg,
    tolerance_kwargs,
)
from tennislab.cli.common import (
    add_machine_flags,
    add_output_flags,
    add_physics_flags,
    atomic_write,
    ball_from_args,
    ball_words,
    emit_json,
    physics_from_args,
    physics_words,
)
from tennislab.errors import InputError, escape_text
from tennislab.io.drill import write_csv
from tennislab.launcher import (
    DEFAULT_MOTOR_POWER,
    DEFAULT_ROLLER_MASS,
    DEFAULT_SPEC,
    DEFAULT_THROW_TIME,
    PAPER,
    power_report,
    roller_report,
    speed_in_kmh,
)
from tennislab.launcher.preferences import TRAJECTORIES
from tennislab.plot import save_figure, spin_axis_name
from tennislab.units import KMH, RPM

# (flag, help) of the optional model constants; each is a float, None = the model's default
_ROLLER_FLAGS = (
    ("--friction", "ball-roller friction coefficient (default 2.05)"),
    ("--young-modulus-mpa", "ball Young's modulus [MPa] (default 4.2)"),
    ("--contact-area-m2", "contact area s of eq 13 [m^2] (default 2.12e-4, implied by the paper's Tables 1-2)"),
)
_POWER_FLAGS = (
    ("--roller-mass", "mass of each roller [kg] (default 2.0)"),
    ("--motor-power", "power of each motor [W] (default 45)"),
    ("--throw-time", "time to restore the rollers after a throw [s] (default 1 = shortest interval)"),
)


def _float_flags(p, flags) -> None:
    """One optional float flag (default None) per (flag, help) pair."""
    for flag, text in flags:
        p.add_argument(flag, type=float, default=None, help=text)


def _model_flags(
    p, func, machine: bool = True, position: bool = True, physics: bool = True, ball_only: bool = False
) -> None:
    """The machine flags (``--machine-position`` if *position*), the physics flags (every command's
    ``standard`` preset by default, ``--preset seed002`` the paper's aero ``launcher2015``; only the ball's
    ``--mass`` and ``--radius`` if *ball_only*: a command that flies nothing must not offer flags it would
    ignore) and *func* as the sub-command's action."""
    if machine:
        add_machine_flags(p, position=position)
    if physics:
        add_physics_flags(p, flags=("mass", "radius") if ball_only else None)
    p.set_defaults(func=func)


def register(sub) -> None:
    p = sub.add_parser(
        "launcher",
        help=f"two-roller ball launcher ({PAPER}): aim, rollers, power, drills, database",
        description=f"The two-roller tennis-ball launcher of {PAPER}.",
    )
    lsub = p.add_subparsers(dest="launcher_command", metavar="SUBCOMMAND", parser_class=type(p))
    lsub.required = True

    a = lsub.add_parser(
        "aim",
        help="machine settings that land a ball on a target",
        description="Inverse aiming: settings on the machine's steps (elevation, heading, speed within "
        "--speed-tolerance-kmh, spin within --spin-tolerance-rpm; height as given, or searched on its 0.1 m "
        "steps when --height is not given) that land nearest the target and meet the trajectory preferences.",
    )
    a.add_argument("--target", type=float, nargs=2, required=True, metavar=("X", "Y"), help="bounce point on court [m]")
    add_speed(a, required=True, note="(30-200, 1 km/h steps)")
    add_spin_flags(a)
    a.add_argument(
        "--height",
        type=float,
        default=None,
        help="launch height [m] (0.1-3.0; default: searched on its 0.1 m steps, ties to the height nearest 1 m)",
    )
    a.add_argument("--solution", choices=("low", "high"), default=None, help="low or high (lob): as --trajectory")
    add_preference_flags(a, trajectory_default=None)
    add_tolerance_flags(a, speed=3.0, spin=100.0)
    add_output_flags(a, plot="draw the shot on the court", json_first=True)
    _model_flags(a, run_aim)

    v = lsub.add_parser(
        "inverse",
        help="the exact launch angles for a target, at once (the reach map and one Newton step)",
        description="Any target at once: the continuous elevation and heading that land the asked speed and spin "
        "from the asked height on the target, from the machine's reach map refined by one Newton step on the "
        "flight kernel (docs/launcher.md, 'Any target at once').  Not on the machine's steps: `launcher aim` "
        "searches those.",
    )
    v.add_argument("--target", type=float, nargs=2, required=True, metavar=("X", "Y"), help="bounce point on court [m]")
    add_speed(v, required=True, note="(30-200)")
    add_spin_flags(v)
    v.add_argument("--height", type=float, default=1.0, help="launch height [m] (0.1-3.0, default 1)")
    v.add_argument(
        "--trajectory", choices=TRAJECTORIES, default="low", help="low (default), high (lob) or any (low if it exists)"
    )
    add_output_flags(v, json_first=True)
    _model_flags(v, run_inverse)

    r = lsub.add_parser("rollers", help="roller speeds, pull-in and no-slip checks (the paper's eqs 8-17)")
    add_speed(r, required=True, note="(30-200)")
    add_spin_flags(r, axis=False)
    _float_flags(r, _ROLLER_FLAGS)
    add_output_flags(r)
    _model_flags(r, run_rollers, position=False, ball_only=True)

    w = lsub.add_parser("power", help="energy per throw, motor power, start-up time (the paper's eqs 18-31)")
    add_speed(w, required=True, note="(30-200)")
    add_spin_flags(w, axis=False)
    _float_flags(w, _POWER_FLAGS)
    w.add_argument(
        "--slip", action="store_true", help="ball starts at rest and slips (rollers give twice the ball's energy)"
    )
    add_output_flags(w)
    _model_flags(w, run_power, position=False, ball_only=True)

    d = lsub.add_parser(
        "drill",
        help="compile a training program to machine settings",
        description="Compile and check a drill (YAML or JSON; schema in docs/launcher.md).  The drill is "
        "named once: a file, a drill stored in --db, or a shipped drill (see `launcher drills list`).",
    )
    d.add_argument("file", metavar="DRILL", nargs="?", help="drill file or name (as --drill)")
    d.add_argument("--drill", metavar="NAME", help="drill: a file, a stored drill (with --db) or a shipped drill")
    d.add_argument("--db", metavar="FILE", help="database whose stored drills the name may mean")
    add_output_flags(
        d,
        csv="write the compiled shot list as CSV",
        csv_metavar="OUT.csv",
        plot="draw the drill on the court",
        json_first=True,
    )
    d.add_argument("--no-check", action="store_true", help="report failed checks without exit code 1")
    _model_flags(d, run_drill, machine=False)

    _launcher_db.register(lsub)


def _shot_request(args, spec, params) -> dict:
    """The keywords ``launcher aim`` and ``launcher inverse`` share: target, speed, spin, axis, height,
    machine and physics."""
    return dict(
        target=tuple(args.target),
        spin_rpm=args.spin_rpm,
        spin_axis_deg=spin_axis_deg(args, 0.0) or 0.0,
        height_m=args.height,
        spec=spec,
        params=params,
        **speed_kwargs(args),
    )


def run_aim(args) -> int:
    from tennislab.launcher import aim, fly_settings
    from tennislab.plot import plot_aim

    check_output(args.plot, "--plot", figure=True)
    params = physics_from_args(args)
    spec = spec_from_args(args)
    res = aim(
        **_shot_request(args, spec, params),
        solution=args.solution,
        **tolerance_kwargs(args),
        **preference_kwargs(args),
    )
    sol = res.solution
    out = res.to_dict()
    if args.plot:
        save_figure(plot_aim(sol, fly_settings(sol.settings, spec, params)), args.plot)
    if args.json:
        emit_json({**out, "physics_preset": args.physics_preset})
        return 0
    s, dv = out["settings"], out["deviation"]
    print(f"{sol.solution} solution for target ({sol.target[0]:g}, {sol.target[1]:g}) m:")
    print(
        f"  elevation {s['elevation_deg']:g} deg, heading {s['heading_deg']:g} deg "
        f"(exact {sol.exact_elevation_deg:.3f}, {sol.exact_heading_deg:.3f}); height {s['height_m']:g} m"
        f"{' (searched)' if sol.height_searched else ''}, "
        f"speed {s['speed_kmh']:g} km/h, spin {s['spin_rpm']:g} rpm, "
        f"spin axis {s['spin_axis_deg']:g} deg ({spin_axis_name(s['spin_axis_deg'])})"
    )
    print(
        f"  from what was asked: speed {dv['speed_kmh']:+g} km/h, spin {dv['spin_rpm']:+g} rpm, axis "
        f"{dv['spin_axis_deg']:+g} deg (spin vector {dv['spin_vector_rpm']:.0f} rpm); tolerances "
        f"{res.tolerances.speed_kmh:g} km/h, {res.tolerances.spin_rpm:g} rpm"
    )
    print(f"  rollers: {out['rollers']['rpm1']:.0f} / {out['rollers']['rpm2']:.0f} rpm")
    print(
        f"  lands at ({sol.landing[0]:.3f}, {sol.landing[1]:.3f}) m, miss {sol.miss_mm:.0f} mm "
        f"(rounding the angles alone: up to {sol.quantisation_bound_mm:.0f} mm); net {sol.net_result}"
        + ("" if sol.net_result == "none" else f", clearance {sol.net_clearance_m:.3f} m")
        + ("; the net keeps it from landing nearer" if sol.net_limited else "")
    )
    print(f"  apex {sol.apex_z_m:.2f} m, {sol.flight_time_s:.2f} s in the air")
    o = out["other_solution"]
    if "unavailable" in o:
        print(f"  {o['solution']} solution: {o['unavailable']}")
    else:
        print(
            f"  {o['solution']} solution: elevation {o['elevation_deg']:g} deg, heading {o['heading_deg']:g} deg, "
            f"miss {o['miss_mm']:.0f} mm, apex {o['apex_z_m']:.1f} m"
        )
    print(f"  {physics_words(params, args.physics_preset)}")
    if args.plot:
        print(f"figure: {args.plot}")
    return 0


def run_inverse(args) -> int:
    from tennislab.launcher import inverse_aim

    params = physics_from_args(args)
    res = inverse_aim(**_shot_request(args, spec_from_args(args), params), trajectory=args.trajectory)
    out = res.to_dict()
    if args.json:
        emit_json({**out, "physics_preset": args.physics_preset})
        return 0
    s, m, use = out["settings"], out["map"], out["reach_map"]
    s, m = ({k: round(v, 4) + 0.0 if isinstance(v, float) else v for k, v in d.items()} for d in (s, m))  # no -0
    print(f"{res.solution} solution for target ({res.target[0]:g}, {res.target[1]:g}) m (continuous angles):")
    print(
        f"  elevation {s['elevation_deg']:.4f} deg, heading {s['heading_deg']:.4f} deg (the map's guess "
        f"{m['elevation_deg']:.4f}, {m['heading_deg']:.4f}); height {s['height_m']:g} m, speed "
        f"{s['speed_kmh']:g} km/h, spin {s['spin_rpm']:g} rpm, spin axis {s['spin_axis_deg']:g} deg "
        f"({spin_axis_name(s['spin_axis_deg'])})"
    )
    net = f", net clearance {res.net_clearance_m:.3f} m" if math.isfinite(res.net_clearance_m) else ""
    print(
        f"  lands at ({res.landing[0]:.4f}, {res.landing[1]:.4f}) m, miss {res.miss_mm:.3f} mm; apex "
        f"{res.apex_z_m:.2f} m, {res.flight_time_s:.2f} s in the air{net}"
    )
    print(f"  {res.flights} flights, {res.elapsed_ms:.1f} ms (the reach map: {use['source']}, {use['seconds']:.2f} s)")
    print(f"  {physics_words(params, args.physics_preset)}")
    return 0


def _checked_speed_spin(args):
    v = speed_in_kmh(DEFAULT_SPEC, **speed_kwargs(args))
    w = DEFAULT_SPEC.spin.check("spin_rpm", args.spin_rpm)
    return v * KMH, w * RPM


def run_rollers(args) -> int:
    ball = ball_from_args(args)  # the ball only: no flight physics (no Numba)
    spec = spec_from_args(args)
    v, w = _checked_speed_spin(args)
    kw = {}
    if args.friction is not None:
        kw["friction"] = args.friction
    if args.young_modulus_mpa is not None:
        kw["young_modulus"] = args.young_modulus_mpa * 1e6
    if args.contact_area_m2 is not None:
        kw["contact_area"] = args.contact_area_m2
    rep = roller_report(v, w, spec, ball, **kw)
    out = rep.to_dict()
    if args.json:
        emit_json({**out, **_ball_json(ball, args.physics_preset)})
        return 0
    print(
        f"rollers: rpm1 {out['rpm1']:.0f}, rpm2 {out['rpm2']:.0f} "
        f"(surface {out['surface_speed1_ms']:.2f} / {out['surface_speed2_ms']:.2f} m/s; "
        f"deformed ball radius {out['deformed_radius_m'] * 1e3:.1f} mm)"
    )
    print(
        f"pull-in: grab angle {out['grab_angle_deg']:.1f} deg vs friction angle "
        f"{out['friction_angle_deg']:.1f} deg -> {'pulls in' if rep.pulls_in else 'does NOT pull in'}"
    )
    print(
        f"throw: friction 2T = {2 * out['friction_force_n']:.0f} N vs inertia force {out['inertia_force_n']:.0f} N "
        f"-> {'no slip' if rep.throws else 'SLIPS'} (no-slip up to {out['max_no_slip_speed_kmh']:.0f} km/h)"
    )
    print(ball_words(ball, args.physics_preset))
    return 0


def _ball_json(ball, preset: str) -> dict:
    """The JSON's statement of the physics of a command that flies nothing: the ball, and its preset."""
    return {"ball_mass": ball.mass, "ball_radius": ball.radius, "physics_preset": preset}


def run_power(args) -> int:
    ball = ball_from_args(args)  # the ball only: no flight physics (no Numba)
    spec = spec_from_args(args)
    v, w = _checked_speed_spin(args)
    rep = power_report(
        v,
        w,
        DEFAULT_ROLLER_MASS if args.roller_mass is None else args.roller_mass,
        DEFAULT_MOTOR_POWER if args.motor_power is None else args.motor_power,
        DEFAULT_THROW_TIME if args.throw_time is None else args.throw_time,
        spec,
        ball,
        slip=args.slip,
    )
    out = rep.to_dict()
    if args.json:
        emit_json({**out, **_ball_json(ball, args.physics_preset)})
        return 0
    print(
        f"energy per throw: {out['energy_per_throw_j']:.1f} J (ball {out['ball_energy_j']:.1f} J"
        f"{', with slip loss' if rep.slip else ', no slip'})"
    )
    print(
        f"throw power: {out['throw_power_w']:.1f} W per motor ({out['throw_power_total_w']:.1f} W both) "
        f"for a {rep.throw_time:g} s throw time"
    )
    print(
        f"rollers before the throw: {out['rpm_before_throw'][0]:.0f} / {out['rpm_before_throw'][1]:.0f} rpm "
        f"(drop {out['rpm_drop'][0]:.0f} / {out['rpm_drop'][1]:.0f} rpm)"
    )
    print(f"start-up time: {out['startup_time_s']:.1f} s at {rep.motor_power:g} W")
    print(ball_words(ball, args.physics_preset))
    return 0


def run_drill(args) -> int:
    from tennislab.launcher import (
        CSV_COLUMNS,
        HitsDB,
        compile_drill,
        drill_trajectories,
        find_drill_source,
        parse_drill,
    )
    from tennislab.plot import plot_drill

    if args.file and args.drill and args.file != args.drill:
        raise InputError("--drill: give the drill once (DRILL or --drill NAME)")
    name = args.drill or args.file
    if not name:
        raise InputError("--drill: give a drill (a file, a stored drill with --db, or a shipped drill)")
    check_output(args.csv, "--csv")
    check_output(args.plot, "--plot", figure=True)
    params = physics_from_args(args)
    data, source, fmt = find_drill_source(name, stored=HitsDB(args.db) if args.db else None)
    drill = parse_drill(data, source, fmt)
    comp = compile_drill(drill, params)
    out = comp.to_dict()
    if args.plot:  # figures and files only once the drill compiled
        fig = plot_drill(comp, drill_trajectories(comp, params))
    if args.csv:
        atomic_write(args.csv, lambda fh: write_csv(comp.rows(), CSV_COLUMNS, fh))
    if args.plot:
        save_figure(fig, args.plot)
    if args.json:
        emit_json({**out, "physics": params.to_dict(), "physics_preset": args.physics_preset})
    else:
        print(
            f"drill '{escape_text(drill.name)}' ({escape_text(drill.key)}): {len(comp.shots)} shots, "
            f"{len(comp.unique)} distinct, {comp.duration_s:g} s; checks {'passed' if comp.ok else 'FAILED'}"
        )
        for u in comp.unique:
            st = u.solution.settings if u.solution else None
            state = "ok" if u.ok else f"FAILED: {u.problem}"
            if st is None:
                print(f"  {escape_text(u.label)}: {escape_text(state)}")
                continue
            print(
                f"  {escape_text(u.label)}: elev {st.elevation_deg:g} head {st.heading_deg:g} speed {st.speed_kmh:g} "
                f"spin {st.spin_rpm:g}@{st.spin_axis_deg:g} h {st.height_m:g} -> "
                f"({u.solution.landing[0]:.2f}, {u.solution.landing[1]:.2f}) miss {u.solution.miss_mm:.0f} mm, "
                f"net {u.solution.net_clearance_m:.2f} m: {escape_text(state)}"
            )
        print(f"  {physics_words(params, args.physics_preset)}")
        if args.csv:
            print(f"csv: {args.csv}")
        if args.plot:
            print(f"figure: {args.plot}")
    if not comp.ok and not args.no_check:
        return 1
    return 0


__all__ = ["register", "spec_from_args", "add_machine_flags"]
