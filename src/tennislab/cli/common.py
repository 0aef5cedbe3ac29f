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
import math

import numpy as np

from tennislab.core.flight import FlightParams
from tennislab.io.files import atomic_write  # noqa: F401  (re-exported for commands)
from tennislab.plot.save import save_figure  # noqa: F401  (re-exported for commands)


def add_physics_flags(p, default_aero: str = "stepanek1988") -> None:
    """Add the physics flags to an argparse parser."""
    g = p.add_argument_group("physics")
    g.add_argument("--aero", default=default_aero,
                   help=f"aero model: constant, stepanek1988, launcher2015, cross2014, table (default {default_aero})")
    g.add_argument("--cd", type=float, help="drag coefficient for models that take one [-]")
    g.add_argument("--cl", type=float, help="lift coefficient for models that take one [-]")
    g.add_argument("--aero-table", metavar="CSV", help="CSV for --aero table (speed_ms,spin_rpm,cd,cl)")
    g.add_argument("--mass", type=float, help="ball mass [kg] (default 0.0577)")
    g.add_argument("--radius", type=float, help="ball radius [m] (default 0.0335)")
    g.add_argument("--air-density", type=float, help="air density [kg/m^3] (default 1.199)")
    g.add_argument("--gravity", type=float, help="gravity [m/s^2] (default 9.80665)")
    g.add_argument("--wind", type=float, nargs=3, metavar=("WX", "WY", "WZ"), help="wind [m/s]")
    g.add_argument("--spin-decay", type=float, help="spin decay rate [1/s] (default 0: off)")


def add_machine_flags(p, position: bool = True) -> None:
    """Add the launcher's machine flags (group "machine") to an argparse parser.

    ``--machine-position X Y`` [m] (only with *position*), ``--roller-radius`` [m] and
    ``--roller-axis-distance`` [m]; read back by :func:`tennislab.cli.launcher.spec_from_args`.
    """
    g = p.add_argument_group("machine")
    if position:
        g.add_argument("--machine-position", type=float, nargs=2, metavar=("X", "Y"),
                       help="launch point on court [m] (default -12.385 0: 0.5 m behind the near baseline)")
    g.add_argument("--roller-radius", type=float, help="roller radius r_r [m] (default 0.1, seed 002)")
    g.add_argument("--roller-axis-distance", type=float,
                   help="distance between roller axes [m] (default 0.25, seed 002)")


def add_output_flags(p, *, csv: str | None = None, plot: str | None = None, csv_metavar: str = "FILE",
                     json_first: bool = False) -> None:
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


def physics_from_args(args) -> FlightParams:
    """Build :class:`FlightParams` from parsed physics flags."""
    from tennislab.core.aero import get_aero_model
    aero = args.aero
    if aero == "table":
        if not getattr(args, "aero_table", None):
            from tennislab.errors import InputError
            raise InputError("--aero table needs --aero-table FILE.csv")
        model = get_aero_model("table", path=args.aero_table)
    else:
        model = get_aero_model(aero, cd=args.cd, cl=args.cl)
    return FlightParams.from_options(aero=model, mass=args.mass, radius=args.radius,
                                     air_density=args.air_density, gravity=args.gravity,
                                     wind=args.wind, spin_decay=args.spin_decay)


def _clean(obj):
    """Make an object JSON-serialisable: numpy -> python, NaN/inf -> None."""
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _clean(obj.tolist())
    if isinstance(obj, (np.floating, float)):
        f = float(obj)
        return f if math.isfinite(f) else None
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    return obj


def emit_json(obj) -> None:
    """Print one JSON object (NaN -> null)."""
    print(json.dumps(_clean(obj), indent=2))
