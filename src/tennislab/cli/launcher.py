"""``tennislab launcher``: the two-roller launcher of seed 002 (aim, rollers, power, drill).

Every sub-command accepts the physics flags of ``tennislab fly`` (default aero
``launcher2015``).  JSON keys named in the issue are a contract (extend, never
rename).  Other helpers add sub-commands through ``tennislab.cli._launcher_db``.
"""

from __future__ import annotations

from tennislab.cli.common import (
    add_machine_flags,
    add_output_flags,
    add_physics_flags,
    atomic_write,
    emit_json,
    physics_from_args,
    save_figure,
)
from tennislab.units import KMH, RPM

# (flag, help) of the optional model constants; each is a float, None = the model's default
_ROLLER_FLAGS = (
    ("--friction", "ball-roller friction coefficient (default 2.05)"),
    ("--young-modulus-mpa", "ball Young's modulus [MPa] (default 4.2)"),
    ("--contact-area-m2", "contact area s of eq 13 [m^2] (default 2.12e-4, implied by seed Tables 1-2)"),
)
_POWER_FLAGS = (
    ("--roller-mass", "mass of each roller [kg] (default 2.0)"),
    ("--motor-power", "power of each motor [W] (default 45)"),
    ("--throw-time", "time to restore the rollers after a throw [s] (default 1 = shortest interval)"),
)


def _speed_spin_flags(p, speed_note: str = "(30-200)", spin_note: str = "(0-2000)") -> None:
    """``--speed-kmh`` [km/h] (required) and ``--spin-rpm`` [rpm] (default 0); the notes end their help."""
    p.add_argument("--speed-kmh", type=float, required=True, help=f"ball speed [km/h] {speed_note}")
    p.add_argument("--spin-rpm", type=float, default=0.0, help=f"spin [rpm] {spin_note}")


def _float_flags(p, flags) -> None:
    """One optional float flag (default None) per (flag, help) pair."""
    for flag, text in flags:
        p.add_argument(flag, type=float, default=None, help=text)


def _model_flags(p, func, machine: bool = True, position: bool = True) -> None:
    """The machine flags (if *machine*; ``--machine-position`` if *position*), the physics flags
    (default aero ``launcher2015``), and *func* as the sub-command's action."""
    if machine:
        add_machine_flags(p, position=position)
    add_physics_flags(p, preset="seed002")
    p.set_defaults(func=func)


def spec_from_args(args):
    """:class:`MachineSpec` from the machine flags (defaults where not given)."""
    from dataclasses import replace

    from tennislab.launcher.machine import DEFAULT_SPEC, MachineSpec

    kw = {}
    if getattr(args, "machine_position", None) is not None:
        kw["position"] = tuple(args.machine_position)
    if getattr(args, "roller_radius", None) is not None:
        kw["roller_radius"] = args.roller_radius
    if getattr(args, "roller_axis_distance", None) is not None:
        kw["roller_axis_distance"] = args.roller_axis_distance
    if not kw:
        return DEFAULT_SPEC
    spec = replace(DEFAULT_SPEC, **kw)
    assert isinstance(spec, MachineSpec)
    return spec


def register(sub) -> None:
    p = sub.add_parser(
        "launcher",
        help="two-roller ball launcher (seed 002): aim, rollers, power, drills",
        description="The two-roller tennis-ball launcher of seed 002.",
    )
    launcher_subparsers = p.add_subparsers(dest="launcher_command", metavar="SUBCOMMAND", parser_class=type(p))
    launcher_subparsers.required = True

    a = launcher_subparsers.add_parser(
        "aim",
        help="machine settings that land a ball on a target",
        description="Inverse aiming: elevation and heading for a target bounce "
        "point, quantised to the machine's steps.",
    )
    a.add_argument("--target", type=float, nargs=2, required=True, metavar=("X", "Y"), help="bounce point on court [m]")
    _speed_spin_flags(a, "(30-200, 1 km/h steps)", "(0-2000, default 0)")
    a.add_argument(
        "--spin-axis-deg",
        type=float,
        default=0.0,
        help="spin-axis rotation [deg]: 0 topspin, 180 backspin, +90 curve to +y (default 0)",
    )
    a.add_argument("--height", type=float, default=1.0, help="launch height [m] (0.1-3.0, default 1.0)")
    a.add_argument("--solution", choices=("low", "high"), default="low", help="low or high (lob) solution")
    add_output_flags(a, plot="draw the shot on the court", json_first=True)
    _model_flags(a, run_aim)

    r = launcher_subparsers.add_parser("rollers", help="roller speeds, pull-in and no-slip checks (eqs 8-17)")
    _speed_spin_flags(r)
    _float_flags(r, _ROLLER_FLAGS)
    add_output_flags(r)
    _model_flags(r, run_rollers, position=False)

    w = launcher_subparsers.add_parser("power", help="energy per throw, motor power, start-up time (eqs 18-31)")
    _speed_spin_flags(w)
    _float_flags(w, _POWER_FLAGS)
    w.add_argument(
        "--slip", action="store_true", help="ball starts at rest and slips (rollers give twice the ball's energy)"
    )
    add_output_flags(w)
    _model_flags(w, run_power, position=False)

    d = launcher_subparsers.add_parser(
        "drill",
        help="compile a training program to machine settings",
        description="Compile and check a drill file (YAML or JSON; schema in "
        "docs/launcher.md).  FILE may name a shipped drill "
        "(e.g. baseline_rally).",
    )
    d.add_argument("file", metavar="FILE", help="drill file (.yaml/.yml/.json) or name of a shipped drill")
    add_output_flags(
        d,
        csv="write the compiled shot list as CSV",
        csv_metavar="OUT.csv",
        plot="draw the drill on the court",
        json_first=True,
    )
    d.add_argument("--no-check", action="store_true", help="report failed checks without exit code 1")
    _model_flags(d, run_drill, machine=False)

    try:
        from tennislab.cli._launcher_db import register_launcher
    except ImportError:
        register_launcher = None
    if register_launcher is not None:
        register_launcher(launcher_subparsers)  # the add_subparsers() object of `launcher`


def run_aim(args) -> int:
    from tennislab.launcher.aim import aim_all, aim_result_dict, pick_solution

    params = physics_from_args(args)
    spec = spec_from_args(args)
    sols, reasons = aim_all(
        tuple(args.target), args.speed_kmh, args.spin_rpm, args.spin_axis_deg, args.height, spec, params
    )
    sol = pick_solution(sols, reasons, args.solution)
    out = aim_result_dict(sol, spec, params)
    other_name = "high" if args.solution == "low" else "low"
    if other_name in sols:
        o = sols[other_name]
        out["other_solution"] = {
            "solution": other_name,
            "elevation_deg": o.settings.elevation_deg,
            "heading_deg": o.settings.heading_deg,
            "miss_mm": o.miss_mm,
            "net_clearance_m": o.net_clearance_m,
        }
    else:
        out["other_solution"] = {"solution": other_name, "unavailable": reasons[other_name]}
    if args.plot:
        from tennislab.launcher.aim import fly_settings
        from tennislab.plot.launcher import plot_aim

        tr = fly_settings(sol.settings, spec, params)
        save_figure(plot_aim(sol, tr), args.plot)
    if args.json:
        emit_json(out)
        return 0
    s = out["settings"]
    print(f"{sol.solution} solution for target ({sol.target[0]:g}, {sol.target[1]:g}) m:")
    print(
        f"  elevation {s['elevation_deg']:g} deg, heading {s['heading_deg']:g} deg "
        f"(exact {sol.exact_elevation_deg:.3f}, {sol.exact_heading_deg:.3f}); height {s['height_m']:g} m, "
        f"speed {s['speed_kmh']:g} km/h, spin {s['spin_rpm']:g} rpm, spin axis {s['spin_axis_deg']:g} deg"
    )
    print(f"  rollers: {out['rollers']['rpm1']:.0f} / {out['rollers']['rpm2']:.0f} rpm")
    print(
        f"  lands at ({sol.landing[0]:.3f}, {sol.landing[1]:.3f}) m, miss {sol.miss_mm:.0f} mm "
        f"(quantisation bound {sol.quantisation_bound_mm:.0f} mm); net {sol.net_result}"
        + ("" if sol.net_result == "none" else f", clearance {sol.net_clearance_m:.3f} m")
    )
    o = out["other_solution"]
    if "unavailable" in o:
        print(f"  {o['solution']} solution: {o['unavailable']}")
    else:
        print(
            f"  {o['solution']} solution: elevation {o['elevation_deg']:g} deg, heading {o['heading_deg']:g} deg, "
            f"miss {o['miss_mm']:.0f} mm"
        )
    if args.plot:
        print(f"figure: {args.plot}")
    return 0


def _checked_speed_spin(args):
    from tennislab.launcher.machine import DEFAULT_SPEC

    v = DEFAULT_SPEC.speed.check("speed_kmh", args.speed_kmh)
    w = DEFAULT_SPEC.spin.check("spin_rpm", args.spin_rpm)
    return v * KMH, w * RPM


def run_rollers(args) -> int:
    from tennislab.launcher.rollers import roller_report

    params = physics_from_args(args)
    spec = spec_from_args(args)
    v, w = _checked_speed_spin(args)
    kw = {}
    if args.friction is not None:
        kw["friction"] = args.friction
    if args.young_modulus_mpa is not None:
        kw["young_modulus"] = args.young_modulus_mpa * 1e6
    if args.contact_area_m2 is not None:
        kw["contact_area"] = args.contact_area_m2
    rep = roller_report(v, w, spec, params.ball, **kw)
    out = rep.as_dict()
    if args.json:
        emit_json(out)
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
    return 0


def run_power(args) -> int:
    from tennislab.launcher.power import DEFAULT_MOTOR_POWER, DEFAULT_ROLLER_MASS, DEFAULT_THROW_TIME, power_report

    params = physics_from_args(args)
    spec = spec_from_args(args)
    v, w = _checked_speed_spin(args)
    rep = power_report(
        v,
        w,
        DEFAULT_ROLLER_MASS if args.roller_mass is None else args.roller_mass,
        DEFAULT_MOTOR_POWER if args.motor_power is None else args.motor_power,
        DEFAULT_THROW_TIME if args.throw_time is None else args.throw_time,
        spec,
        params.ball,
        slip=args.slip,
    )
    out = rep.as_dict()
    if args.json:
        emit_json(out)
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
    return 0


def run_drill(args) -> int:
    from tennislab.io.drill import load_drill, write_drill_csv
    from tennislab.launcher.drills import compile_drill

    params = physics_from_args(args)
    drill = load_drill(args.file)
    comp = compile_drill(drill, params)
    out = comp.as_dict()
    if args.csv:
        atomic_write(args.csv, lambda fh: write_drill_csv(comp, fh))
    if args.plot:
        from tennislab.plot.launcher import plot_drill

        save_figure(plot_drill(comp, params), args.plot)
    if args.json:
        emit_json(out)
    else:
        print(
            f"drill {drill.name!r}: {len(comp.shots)} shots, {len(comp.unique)} distinct, "
            f"{comp.duration_s:g} s; checks {'passed' if comp.ok else 'FAILED'}"
        )
        for u in comp.unique:
            st = u.solution.settings if u.solution else None
            state = "ok" if u.ok else f"FAILED: {u.problem}"
            if st is None:
                print(f"  {u.label}: {state}")
                continue
            print(
                f"  {u.label}: elev {st.elevation_deg:g} head {st.heading_deg:g} speed {st.speed_kmh:g} "
                f"spin {st.spin_rpm:g}@{st.spin_axis_deg:g} h {st.height_m:g} -> "
                f"({u.solution.landing[0]:.2f}, {u.solution.landing[1]:.2f}) miss {u.solution.miss_mm:.0f} mm, "
                f"net {u.solution.net_clearance_m:.2f} m: {state}"
            )
        if args.csv:
            print(f"csv: {args.csv}")
        if args.plot:
            print(f"figure: {args.plot}")
    if not comp.ok and not args.no_check:
        return 1
    return 0


__all__ = ["register", "spec_from_args", "add_machine_flags"]
