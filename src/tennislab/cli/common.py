"""Shared CLI pieces: the physics flags of ``tennislab fly`` and JSON output.

Every command that simulates flight accepts the physics flags (``--aero``,
``--cd``, ``--cl``, ``--mass``, ``--radius``, ``--air-density``,
``--gravity``, ``--wind``, ``--spin-decay``) so any study can be rerun with
other constants.  The other flag groups that several commands share are added
here too: the launcher's machine flags (:func:`add_machine_flags`) and the
output flags ``--csv`` / ``--plot`` / ``--json`` (:func:`add_output_flags`).
"""

from __future__ import annotations

import json

from tennislab.core.aero import DEFAULT_AERO, aero_model_names
from tennislab.core.flight import PRESETS, FlightParams
from tennislab.errors import InputError
from tennislab.io.aero_table import read_aero_table
from tennislab.io.files import atomic_write  # noqa: F401  (re-exported for commands)
from tennislab.plot.save import save_figure  # noqa: F401  (re-exported for commands)
from tennislab.results import jsonable


def add_physics_flags(p, preset: str = "standard") -> None:
    """Add the physics flags to an argparse parser; flags not given keep the values of ``preset``
    (:data:`tennislab.core.flight.PRESETS`), which :func:`physics_from_args` reads back."""
    base = PRESETS[preset]
    default_aero = base.get("aero", DEFAULT_AERO)
    p.set_defaults(physics_preset=preset)
    g = p.add_argument_group("physics")
    g.add_argument(
        "--aero",
        default=None,
        help=f"aero model: {', '.join(aero_model_names())} (default {default_aero})",
    )
    g.add_argument("--cd", type=float, help="drag coefficient for models that take one [-]")
    g.add_argument("--cl", type=float, help="lift coefficient for models that take one [-]")
    g.add_argument("--aero-table", metavar="CSV", help="CSV for --aero table (speed_ms,spin_rpm,cd,cl)")
    g.add_argument("--mass", type=float, help=f"ball mass [kg] (default {base.get('mass', 0.0577)})")
    g.add_argument("--radius", type=float, help=f"ball radius [m] (default {base.get('radius', 0.0335)})")
    g.add_argument("--air-density", type=float, help=f"air density [kg/m^3] (default {base.get('air_density', 1.199)})")
    g.add_argument("--gravity", type=float, help=f"gravity [m/s^2] (default {base.get('gravity', 9.80665)})")
    g.add_argument("--wind", type=float, nargs=3, metavar=("WX", "WY", "WZ"), help="wind [m/s]")
    g.add_argument("--spin-decay", type=float, help="spin decay rate [1/s] (default 0: off)")


def add_machine_flags(p, position: bool = True) -> None:
    """Add the launcher's machine flags (group "machine") to an argparse parser.

    ``--machine-position X Y`` [m] (only with *position*), ``--roller-radius`` [m] and
    ``--roller-axis-distance`` [m]; read back by :func:`tennislab.cli.launcher.spec_from_args`.
    """
    g = p.add_argument_group("machine")
    if position:
        g.add_argument(
            "--machine-position",
            type=float,
            nargs=2,
            metavar=("X", "Y"),
            help="launch point on court [m] (default -12.385 0: 0.5 m behind the near baseline)",
        )
    g.add_argument("--roller-radius", type=float, help="roller radius r_r [m] (default 0.1, seed 002)")
    g.add_argument(
        "--roller-axis-distance", type=float, help="distance between roller axes [m] (default 0.25, seed 002)"
    )


def add_output_flags(
    p, *, csv: str | None = None, plot: str | None = None, csv_metavar: str = "FILE", json_first: bool = False
) -> None:
    """Add the output flags: ``--csv`` (if *csv*, its help), ``--plot FILE.png`` (if *plot*, its help), ``--json``.

    The order is ``--csv``, ``--plot``, ``--json``; with *json_first* ``--json`` comes first (the
    launcher's sub-commands list it before the files they write).
    """
    if json_first:
        p.add_argument("--json", action="store_true", help="print one JSON object")
    if csv is not None:
        p.add_argument("--csv", metavar=csv_metavar, help=csv)
    if plot is not None:
        p.add_argument("--plot", metavar="FILE.png", help=plot)
    if not json_first:
        p.add_argument("--json", action="store_true", help="print one JSON object")


def physics_options(args) -> dict:
    """The physics flags as :meth:`FlightParams.from_options` keywords (a given ``--aero-table`` CSV is read here)."""
    table = None
    if getattr(args, "aero_table", None):
        table = read_aero_table(args.aero_table)
    elif args.aero == "table":
        raise InputError("--aero table needs --aero-table FILE.csv")
    return dict(
        aero=args.aero,
        cd=args.cd,
        cl=args.cl,
        aero_table=table,
        mass=args.mass,
        radius=args.radius,
        air_density=args.air_density,
        gravity=args.gravity,
        wind=args.wind,
        spin_decay=args.spin_decay,
    )


def physics_from_args(args) -> FlightParams:
    """Build :class:`FlightParams` from parsed physics flags on top of the command's preset."""
    return FlightParams.from_options(preset=getattr(args, "physics_preset", "standard"), **physics_options(args))


def emit_json(obj) -> None:
    """Print one JSON object (a :class:`~tennislab.results.Result` prints its ``to_dict()``; NaN -> null)."""
    print(json.dumps(jsonable(obj), indent=2))


# ------------------------------------------------------------------ launch vocabulary
# Every command that launches a ball accepts the same words (docs/conventions.md): a speed in one of
# three units, elevation and heading in degrees, a spin rate in rpm about an axis given by name
# (tennislab.core.launch.SPIN_AXES_DEG), by angle [deg] or as a vector.
SPEED_UNITS = {"speed_ms": 1.0, "speed_kmh": 1.0 / 3.6, "speed_mph": 0.44704}  #: flag dest -> [m/s] per unit


def add_speed_flags(group, *, required: bool = False, note: str = "") -> None:
    """``--speed-kmh | --speed-ms | --speed-mph`` (one of them) on an argparse group or parser."""
    ex = group.add_mutually_exclusive_group(required=required)
    suffix = f" {note}" if note else ""
    ex.add_argument("--speed-kmh", type=float, metavar="KMH", help=f"ball speed [km/h]{suffix}")
    ex.add_argument("--speed-ms", type=float, metavar="MS", help="ball speed [m/s] (instead of --speed-kmh)")
    ex.add_argument("--speed-mph", type=float, metavar="MPH", help="ball speed [mph] (instead of --speed-kmh)")


def speed_from_args(args) -> float | None:
    """The speed [m/s] given by whichever of the speed flags was used (None if none)."""
    for dest, factor in SPEED_UNITS.items():
        value = getattr(args, dest, None)
        if value is not None:
            return value * factor
    return None


def parse_spin_axis(values, flag: str = "--spin-axis"):
    """A ``--spin-axis`` value: one token (a name such as ``topspin`` or an angle [deg]) -> ``("angle", g [rad])``;
    three numbers -> ``("vector", (ax, ay, az))`` (any length, right-hand rule)."""
    from tennislab.core.launch import spin_axis_angle

    vals = [values] if isinstance(values, str) else list(values)
    if len(vals) == 1:
        try:
            return "angle", spin_axis_angle(vals[0])
        except InputError as exc:
            raise InputError(str(exc).replace("spin_axis:", f"{flag}:", 1)) from None
    if len(vals) == 3:
        try:
            vec = tuple(float(v) for v in vals)
        except ValueError:
            raise InputError(
                f"{flag}: expected a name, an angle [deg] or three numbers, got {' '.join(vals)}"
            ) from None
        return "vector", vec
    raise InputError(f"{flag}: expected a name, an angle [deg] or three numbers, got {len(vals)} values")
