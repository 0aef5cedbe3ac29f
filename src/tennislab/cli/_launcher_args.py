"""Flags shared by the ``tennislab launcher`` sub-commands: machine, speed and spin vocabulary,
tolerances and trajectory preferences.  Parse only; the launcher's workflows check the values
(their errors name parameters, which the CLI turns into these flags)."""

from __future__ import annotations

import math
from dataclasses import replace

from tennislab.cli.common import add_speed_flags, parse_spin_axis
from tennislab.errors import InputError
from tennislab.io.files import check_output_path
from tennislab.launcher.machine import DEFAULT_SPEC, MachineSpec
from tennislab.launcher.preferences import DEFAULT_SPIN_AXIS_TOLERANCE_DEG, TRAJECTORIES
from tennislab.plot import FIGURE_SUFFIXES

#: Physics flags' dests (cli.common.add_physics_flags) a database compares with its own physics.
PHYSICS_DESTS = ("aero", "cd", "cl", "aero_table", "mass", "radius", "air_density", "gravity", "wind", "spin_decay")
MACHINE_DESTS = ("machine_position", "roller_radius", "roller_axis_distance")


def spec_from_args(args) -> MachineSpec:
    """:class:`MachineSpec` from the machine flags (defaults where not given)."""
    kw: dict = {}
    if getattr(args, "machine_position", None) is not None:
        kw["position"] = tuple(args.machine_position)
    if getattr(args, "roller_radius", None) is not None:
        kw["roller_radius"] = args.roller_radius
    if getattr(args, "roller_axis_distance", None) is not None:
        kw["roller_axis_distance"] = args.roller_axis_distance
    return replace(DEFAULT_SPEC, **kw) if kw else DEFAULT_SPEC


def check_output(path: str | None, flag: str, figure: bool = False) -> None:
    """An output file given to ``flag`` is writable before any work (:func:`tennislab.io.files.check_output_path`)."""
    if path is not None:
        check_output_path(flag.lstrip("-").replace("-", "_"), path, FIGURE_SUFFIXES if figure else None)


def given_flags(args) -> tuple[str, ...]:
    """Dests of the machine and physics flags the user gave, ``physics_preset`` for a typed ``--preset`` (a
    database compares only those)."""
    given = tuple(d for d in MACHINE_DESTS + PHYSICS_DESTS if getattr(args, d, None) is not None)
    return given + (("physics_preset",) if getattr(args, "physics_preset_given", False) else ())


def add_speed(p, *, required: bool, note: str = "") -> None:
    """``--speed-kmh | --speed-ms | --speed-mph``."""
    add_speed_flags(p, required=required, note=note)


def speed_kwargs(args) -> dict:
    """The speed flags as the workflows' keywords (``speed_kmh``, ``speed_ms``, ``speed_mph``)."""
    return {k: getattr(args, k, None) for k in ("speed_kmh", "speed_ms", "speed_mph")}


def add_spin_flags(p, *, axis: bool = True, spin_default: float | None = 0.0, axis_note: str = "") -> None:
    """``--spin-rpm`` and (with *axis*) ``--spin-axis NAME|DEG`` or ``--spin-axis-deg DEG``."""
    dflt = "" if spin_default is None else f", default {spin_default:g}"
    p.add_argument("--spin-rpm", type=float, default=spin_default, help=f"spin rate [rpm] (0-2000{dflt})")
    if axis:
        ex = p.add_mutually_exclusive_group()
        ex.add_argument(
            "--spin-axis",
            metavar="NAME|DEG",
            help="spin axis by name (topspin, backspin, slice, sidespin, sidespin-left, sidespin-right) or in "
            "degrees: 0 topspin, 180 backspin, +90 curve to +y" + axis_note,
        )
        ex.add_argument("--spin-axis-deg", type=float, help="spin-axis rotation [deg] (same as --spin-axis DEG)")


def spin_axis_deg(args, default: float | None = 0.0) -> float | None:
    """The spin axis [deg] from ``--spin-axis`` (name or degrees) or ``--spin-axis-deg``."""
    if getattr(args, "spin_axis", None) is not None:
        kind, value = parse_spin_axis(args.spin_axis, "--spin-axis")
        if kind != "angle":  # pragma: no cover - one token is always a name or an angle
            raise InputError("--spin-axis: the launcher takes a name or an angle [deg], not a vector")
        return math.degrees(float(value))
    if getattr(args, "spin_axis_deg", None) is not None:
        return float(args.spin_axis_deg)
    return default


def add_tolerance_flags(p, *, speed: float, spin: float, axis: bool = True) -> None:
    """``--speed-tolerance-kmh``, ``--spin-tolerance-rpm`` (0 = exact), with *axis* ``--spin-axis-tolerance-deg``."""
    g = p.add_argument_group("tolerances (how far the machine may move the asked speed and spin; 0 = exact)")
    g.add_argument("--speed-tolerance-kmh", type=float, default=speed, help=f"[km/h] (default {speed:g})")
    g.add_argument(
        "--spin-tolerance-rpm",
        type=float,
        default=spin,
        help=f"[rpm] (default {spin:g}" + ("; bounds the change of the spin vector, axis included)" if axis else ")"),
    )
    if axis:
        g.add_argument(
            "--spin-axis-tolerance-deg",
            type=float,
            default=DEFAULT_SPIN_AXIS_TOLERANCE_DEG,
            help="also let the spin axis turn this far [deg] at the asked rate +- the spin tolerance "
            f"(default {DEFAULT_SPIN_AXIS_TOLERANCE_DEG:g}; 0 = only within the spin tolerance as a vector)",
        )


def tolerance_kwargs(args) -> dict:
    out = {"speed_tolerance_kmh": args.speed_tolerance_kmh, "spin_tolerance_rpm": args.spin_tolerance_rpm}
    if hasattr(args, "spin_axis_tolerance_deg"):
        out["spin_axis_tolerance_deg"] = args.spin_axis_tolerance_deg
    return out


def add_preference_flags(p, *, trajectory_default: str | None = "low") -> None:
    """``--trajectory low|high|any``, ``--max-apex-m``, ``--net-clearance-m MIN MAX``, ``--max-flight-time-s``."""
    g = p.add_argument_group("trajectory preferences")
    g.add_argument(
        "--trajectory",
        choices=TRAJECTORIES,
        default=trajectory_default,
        help="low (drive: the rising branch), high (lob) or any (the nearer) (default low)",
    )
    g.add_argument("--max-apex-m", type=float, metavar="M", help="highest ball-centre height of the flight [m]")
    g.add_argument(
        "--net-clearance-m",
        type=float,
        nargs=2,
        metavar=("MIN", "MAX"),
        help="band of clearance over the net cord [m]",
    )
    g.add_argument("--max-flight-time-s", type=float, metavar="S", help="longest time to the bounce [s]")


def preference_kwargs(args) -> dict:
    return {
        "trajectory": args.trajectory,
        "max_apex_m": args.max_apex_m,
        "net_clearance_m": None if args.net_clearance_m is None else tuple(args.net_clearance_m),
        "max_flight_time_s": args.max_flight_time_s,
    }
