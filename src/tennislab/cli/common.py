"""Shared CLI pieces: the physics, machine, launch and output flags, and JSON output.

Every command that simulates flight accepts the physics flags (``--aero``, ``--cd``, ``--cl``,
``--mass``, ``--radius``, ``--air-density``, ``--gravity``, ``--wind``, ``--spin-decay``) so any study
can be rerun with other constants (their defaults can also come from ``tennislab.toml``:
:mod:`tennislab.cli.config`).  The other flag groups that several commands share are added here too:
the launcher's machine flags (:func:`add_machine_flags`), the launch vocabulary
(:func:`add_launch_flags`: a velocity or a speed with elevation and heading; a spin vector or a rate
about a named axis) and the output flags ``--csv`` / ``--plot`` / ``--json`` (:func:`add_output_flags`),
whose paths are checked when the command line is parsed, before any work (:func:`output_file`,
:func:`figure_file`, :func:`output_dir`).

Start-up: building the parser loads no physics (``tennislab --help`` and ``--version`` stay fast, and a
command loads only what it uses): the workflows and the core are imported where a command runs, and a
help text that lists what a registry holds (the aero models, the spin axes) is a :class:`LazyHelp`,
written when the help is shown.
"""

from __future__ import annotations

import argparse
import json
import math
import os
from collections.abc import Callable, Iterator, Sequence
from typing import TYPE_CHECKING

from tennislab.core import PRESET_TITLES, describe_preset
from tennislab.errors import InputError, is_subnormal
from tennislab.io.files import atomic_write, check_output_dir, check_output_path, same_file, shown
from tennislab.plot import FIGURE_SUFFIXES, save_figure
from tennislab.units import SPEED_UNITS as _SPEED_UNITS

if TYPE_CHECKING:
    from tennislab.core.ball import Ball
    from tennislab.core.flight import FlightParams

__all__ = [
    "LazyChoices",
    "LazyHelp",
    "PHYSICS_DESTS",
    "SPEED_UNITS",
    "add_launch_flags",
    "add_machine_flags",
    "add_output_flags",
    "add_physics_flags",
    "add_speed_flags",
    "atomic_write",
    "ball_from_args",
    "check_io",
    "checked_floats",
    "emit_json",
    "figure_file",
    "finite_float",
    "launch_from_args",
    "output_dir",
    "output_file",
    "parse_spin_axis",
    "physics_from_args",
    "physics_options",
    "save_figure",
    "speed_from_args",
]

#: dests of the physics flags, in the order of :func:`add_physics_flags`
PHYSICS_DESTS = ("aero", "cd", "cl", "aero_table", "mass", "radius", "air_density", "gravity", "wind", "spin_decay")


class LazyHelp(str):
    """A flag's help text computed when the help is shown (``fn()``, a ``%``-format as argparse's own),
    so that a text naming what a registry holds does not load it when the parser is built."""

    def __new__(cls, fn: Callable[[], str]) -> LazyHelp:
        obj = super().__new__(cls, "(help)")
        obj.fn = fn  # type: ignore[attr-defined]
        return obj

    def __mod__(self, params):  # argparse expands ``help % params``
        return self.fn() % params


class LazyChoices(Sequence):
    """A flag's choices read from their registry when first needed (a value given, the help shown)."""

    def __init__(self, fn: Callable[[], Sequence[str]]):
        self._fn = fn
        self._values: tuple[str, ...] | None = None

    def _get(self) -> tuple[str, ...]:
        if self._values is None:
            self._values = tuple(self._fn())
        return self._values

    def __getitem__(self, i):
        return self._get()[i]

    def __len__(self) -> int:
        return len(self._get())

    def __contains__(self, value: object) -> bool:
        return value in self._get()

    def __iter__(self) -> Iterator[str]:
        return iter(self._get())

    def __repr__(self) -> str:
        return repr(self._get())


# ------------------------------------------------------------------ output paths, checked at parse time
def _argparse_type(check, name: str):
    """An argparse ``type`` that runs ``check(param, value)`` when the command line is parsed, so a
    bad output path is refused (one line, exit 2) before any work.  It is marked as an output
    (:func:`check_io` compares outputs with the command's inputs)."""

    def convert(value: str) -> str:
        try:
            return check(value)
        except InputError as exc:
            msg = str(exc)
            raise argparse.ArgumentTypeError(msg.split(": ", 1)[1] if msg.startswith("output: ") else msg) from None

    convert.__name__ = name
    convert.is_output = True  # type: ignore[attr-defined]
    return convert


def finite_float(text: str) -> float:
    """argparse ``type`` of every ``float`` flag: a finite, normal number (not NaN, not inf, not a
    subnormal such as 1e-320, which no physical quantity is and dividing by which gives inf)."""
    v = float(text)  # ValueError: argparse says "invalid float value"
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"{text}: expected a finite number")
    if is_subnormal(v):
        raise argparse.ArgumentTypeError(
            f"{text} is a subnormal number (magnitude below 2.2e-308, no physical value); give 0 or a normal number"
        )
    return v


finite_float.__name__ = "float"


def _finite_floats(n: int):
    """:func:`finite_float` for a flag of ``n`` numbers (``--velocity VX VY VZ``): a refusal names the
    value's place (``[0]: nan: ...``, shown as ``--velocity[0]: ...``).  argparse converts the ``n``
    values of one use of the flag in order, so a counter modulo ``n`` knows the place."""
    place = [0]

    def convert(text: str) -> float:
        i = place[0]
        place[0] = (i + 1) % n
        try:
            return finite_float(text)
        except (argparse.ArgumentTypeError, ValueError) as exc:
            place[0] = 0
            if isinstance(exc, argparse.ArgumentTypeError):
                raise argparse.ArgumentTypeError(f"[{i}]: {exc}") from None
            raise

    convert.__name__ = "float"
    return convert


def checked_floats(parser: argparse.ArgumentParser) -> None:
    """Give every ``type=float`` flag of ``parser`` and its sub-commands :func:`finite_float`."""
    stack = [parser]
    seen: set[int] = set()
    while stack:
        p = stack.pop()
        if id(p) in seen:
            continue
        seen.add(id(p))
        for action in p._actions:
            if action.type is float:
                n = action.nargs if isinstance(action.nargs, int) else 1
                action.type = _finite_floats(n) if n > 1 else finite_float
            if isinstance(action, argparse._SubParsersAction):
                stack.extend(action.choices.values())


def _command_actions(parser: argparse.ArgumentParser, args) -> list:
    """The actions of the command ``args`` were parsed for: the top level's and each sub-command's."""
    out: list = []
    p: argparse.ArgumentParser | None = parser
    while p is not None:
        out += p._actions
        nxt = None
        for action in p._actions:
            if isinstance(action, argparse._SubParsersAction):
                chosen = getattr(args, action.dest, None) if action.dest != argparse.SUPPRESS else None
                nxt = action.choices.get(chosen) if isinstance(chosen, str) else None
        p = nxt
    return out


def _output_key(path: str) -> object:
    """One key per file an output name means: the (device, inode) of an existing file, else the
    resolved folder and the name (``./o.csv`` and ``o.csv`` are one file)."""
    try:
        st = os.stat(path)
        return (st.st_dev, st.st_ino)
    except (OSError, ValueError):
        full = os.path.abspath(path)
        return os.path.join(os.path.realpath(os.path.dirname(full)), os.path.basename(full))


def check_io(parser: argparse.ArgumentParser, args) -> None:
    """Refuse, before any work, an output flag that names one of the command's inputs, or the file
    another output flag names.

    Outputs are the flags whose type is an output checker (:func:`output_file`, :func:`figure_file`,
    :func:`output_dir`); any other value of the command line that names an existing file is an input.
    Two names of one file (a link, ``./x``) are the same file.  (Outputs named at run time are checked
    when written: :func:`tennislab.io.files.command_files`.)
    """
    outs, ins = [], []
    for action in _command_actions(parser, args):
        if not action.option_strings and not action.dest or action.dest in ("help", argparse.SUPPRESS):
            continue
        value = getattr(args, action.dest, None)
        seq = value if isinstance(value, list | tuple) else [value]
        values = [v for v in seq if isinstance(v, str)]
        flag = action.option_strings[-1] if action.option_strings else None
        flag = flag or (action.metavar if isinstance(action.metavar, str) else action.dest.upper())
        if getattr(action.type, "is_output", False):
            outs += [(flag, v) for v in values]
        else:
            ins += [(flag, v) for v in values if v and os.path.isfile(v)]
    first: dict[object, tuple[str, str]] = {}
    for flag, out in outs:  # two outputs in one file: one would overwrite the other
        key = _output_key(out)
        if key in first and first[key][0] != flag:
            raise InputError(
                f"{flag}: {shown(out)} is also the output of {first[key][0]} {shown(first[key][1])}; "
                "give each output its own file"
            )
        first.setdefault(key, (flag, out))
    for flag, out in outs:
        if not os.path.isfile(out):
            continue
        for in_flag, path in ins:
            if same_file(out, path):
                also = "" if in_flag == flag else f" ({in_flag} {shown(path)})"
                raise InputError(
                    f"{flag}: {shown(out)} is also an input of this command{also}; refusing to overwrite it - "
                    "write the output to another file"
                )


def output_file(suffixes=None):
    """argparse ``type`` for an output file (:func:`tennislab.io.files.check_output_path`; with
    ``suffixes`` such as ``(".csv",)`` the extension must be one of them)."""
    return _argparse_type(lambda v: check_output_path("output", v, suffixes), "output file")


def figure_file():
    """argparse ``type`` for ``--plot``: an output file with a figure format Matplotlib writes
    (:data:`tennislab.plot.save.FIGURE_SUFFIXES`: .png, .pdf, .svg, ...)."""
    return _argparse_type(lambda v: check_output_path("output", v, FIGURE_SUFFIXES), "figure file")


def output_dir():
    """argparse ``type`` for an output directory (created by the command if missing; its nearest
    existing ancestor must be a writable directory: :func:`tennislab.io.files.check_output_dir`)."""
    return _argparse_type(lambda v: check_output_dir("output", v), "output directory")


# ------------------------------------------------------------------ flag groups
def add_physics_flags(p, preset: str = "standard", flags=None) -> None:
    """Add the physics flags to an argparse parser; flags not given keep the values of ``preset``
    (:data:`tennislab.core.flight.PRESETS`), which :func:`physics_from_args` reads back.

    ``flags``: the dests (of :data:`PHYSICS_DESTS`) to add, for a command that uses only some of
    them (a flag a command would ignore must not be offered); default all.
    """
    chosen = PHYSICS_DESTS if flags is None else tuple(flags)
    unknown = set(chosen) - set(PHYSICS_DESTS)
    if unknown:
        raise ValueError(f"add_physics_flags: unknown physics flags {sorted(unknown)}")
    p.set_defaults(physics_preset=preset, **{d: None for d in PHYSICS_DESTS if d not in chosen})
    g = p.add_argument_group("physics")

    def preset_value(key: str, value: object) -> object:
        from tennislab.core.names import PRESETS

        return PRESETS[preset].get(key, value)

    def aero_help() -> str:  # the built-in names (core.names): no aero kernel compiled to show the help
        from tennislab.core.names import AERO_MODEL_NAMES, DEFAULT_AERO

        return f"aero model: {', '.join(AERO_MODEL_NAMES)} (default {preset_value('aero', DEFAULT_AERO)})"

    def with_default(text: str, key: str, value: float) -> LazyHelp:
        return LazyHelp(lambda: f"{text} (default {preset_value(key, value)})")

    specs = {
        "aero": dict(default=None, metavar="NAME", help=LazyHelp(aero_help)),
        "cd": dict(type=float, help="drag coefficient for models that take one [-]"),
        "cl": dict(type=float, help="lift coefficient for models that take one [-]"),
        "aero_table": dict(metavar="CSV", help="CSV for --aero table (speed_ms,spin_rpm,cd,cl)"),
        "mass": dict(type=float, metavar="KG", help=with_default("ball mass [kg]", "mass", 0.0577)),
        "radius": dict(type=float, metavar="M", help=with_default("ball radius [m]", "radius", 0.0335)),
        "air_density": dict(
            type=float, metavar="KG_M3", help=with_default("air density [kg/m^3]", "air_density", 1.199)
        ),
        "gravity": dict(type=float, metavar="M_S2", help=with_default("gravity [m/s^2]", "gravity", 9.80665)),
        "wind": dict(type=float, nargs=3, metavar=("WX", "WY", "WZ"), help="wind [m/s]"),
        "spin_decay": dict(type=float, metavar="PER_S", help="spin decay rate [1/s] (default 0: off)"),
    }
    for dest in PHYSICS_DESTS:
        if dest in chosen:
            g.add_argument("--" + dest.replace("_", "-"), **specs[dest])  # type: ignore[arg-type]
    g.add_argument(
        "--preset",
        dest="physics_preset",
        default=preset,
        action=_PresetAction,
        choices=PRESET_WORDS,
        help="base set of the physics the flags above change: "
        + "; ".join(f"{k} {v}" for k, v in PRESET_WORDS.items())
        + f" (default {preset})",
    )


class _PresetAction(argparse.Action):
    """``--preset NAME``, remembering that it was typed (``physics_preset_given``): a database compares a
    preset the user names with its own physics, never the default one."""

    def __call__(self, parser, namespace, values, option_string=None):
        setattr(namespace, self.dest, values)
        namespace.physics_preset_given = True


#: the named physics presets (tennislab.core.names.PRESETS) in words, for --help and the outputs
PRESET_WORDS = {name: f"({PRESET_TITLES[name]}: {describe_preset(name)})" for name in PRESET_TITLES}


def physics_words(flight, preset: str | None = None, whose: str = "") -> str:
    """The physics a command flew, in one line: aero model, air density, ball (and wind, spin decay when on),
    and the preset it started from.  *flight* is a :class:`~tennislab.core.flight.FlightParams` or a dict
    with its ``to_dict()`` keys (a database's physics summary); *whose* says where it comes from (``the
    file's``), and a dict's ``None`` preset is said as a physics of its own."""
    d = flight if isinstance(flight, dict) else flight.to_dict()
    extra = ""
    if any(d.get("wind") or ()):
        extra += ", wind " + " ".join(f"{w:g}" for w in d["wind"]) + " m/s"
    if d.get("spin_decay"):
        extra += f", spin decay {d['spin_decay']:g} /s"
    said = [whose] if whose else []
    if preset or whose:
        said.append(f"preset {preset}" if preset else "no preset: a physics of its own")
    base = f" ({'; '.join(said)})" if said else ""
    return (
        f"physics: {d['aero']} aero, air {d['air_density']:g} kg/m^3, g {d['gravity']:g} m/s^2, "
        f"ball {round(d['mass'] * 1e3, 2):g} g, radius {round(d['radius'] * 1e3, 2):g} mm{extra}{base}"
    )


def ball_words(ball, preset: str | None = None) -> str:
    """The physics of a command that flies nothing (``impact``, ``launcher rollers``, ``launcher power``) in
    one line: the ball it takes, and the preset it started from (no aero model or air: none is used)."""
    base = f"preset {preset}; " if preset else ""
    return (
        f"physics: ball {round(ball.mass * 1e3, 2):g} g, radius {round(ball.radius * 1e3, 2):g} mm "
        f"({base}no flight: no aero model or air)"
    )


def add_machine_flags(p, position: bool = True) -> None:
    """Add the launcher's machine flags (group "machine") to an argparse parser.

    ``--machine NAME`` (a profile of ``tennislab.toml``: it fills the flags below that are not
    given), ``--machine-position X Y`` [m] (only with *position*), ``--roller-radius`` [m] and
    ``--roller-axis-distance`` [m]; read back by :func:`tennislab.cli.launcher.spec_from_args`.
    """
    g = p.add_argument_group("machine")
    g.add_argument("--machine", metavar="NAME", help="machine profile [machines.NAME] of tennislab.toml")
    if position:
        g.add_argument(
            "--machine-position",
            type=float,
            nargs=2,
            metavar=("X", "Y"),
            help="launch point on court [m] (default -12.385 0: 0.5 m behind the near baseline)",
        )
    g.add_argument(
        "--roller-radius",
        type=float,
        help="roller radius r_r [m] (default 0.1, Wojcicki, Pucilowski & Kulesza)",
    )
    g.add_argument(
        "--roller-axis-distance",
        type=float,
        help="distance between roller axes [m] (default 0.25, Wojcicki, Pucilowski & Kulesza)",
    )


def add_output_flags(
    p, *, csv: str | None = None, plot: str | None = None, csv_metavar: str = "FILE", json_first: bool = False
) -> None:
    """Add the output flags: ``--csv`` (if *csv*, its help), ``--plot FILE.png`` (if *plot*, its help), ``--json``.

    The order is ``--csv``, ``--plot``, ``--json``; with *json_first* ``--json`` comes first (the
    launcher's sub-commands list it before the files they write).  Both paths are checked when the
    command line is parsed (:func:`output_file`, :func:`figure_file`), before any work.
    """
    if json_first:
        p.add_argument("--json", action="store_true", help="print one JSON object")
    if csv is not None:
        p.add_argument("--csv", metavar=csv_metavar, type=output_file((".csv",)), help=csv)
    if plot is not None:
        p.add_argument("--plot", metavar="FILE.png", type=figure_file(), help=plot)
    if not json_first:
        p.add_argument("--json", action="store_true", help="print one JSON object")


def physics_options(args) -> dict:
    """The physics flags as :meth:`FlightParams.from_options` keywords (a given ``--aero-table`` CSV is read here)."""
    from tennislab.io.aero_table import read_aero_table

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
    from tennislab.core.flight import FlightParams

    return FlightParams.from_options(preset=getattr(args, "physics_preset", "standard"), **physics_options(args))


def ball_from_args(args) -> Ball:
    """The ball of the physics flags ``--mass`` / ``--radius`` on top of the command's preset, the one
    :func:`physics_from_args` would build, without the flight physics (no aero model, no Numba)."""
    from tennislab.core.ball import Ball

    preset = getattr(args, "physics_preset", "standard")
    return Ball.from_options(mass=getattr(args, "mass", None), radius=getattr(args, "radius", None), preset=preset)


def emit_json(obj) -> None:
    """Print one JSON object (a :class:`~tennislab.results.Result` prints its ``to_dict()``; NaN -> null)."""
    from tennislab.results import jsonable

    print(json.dumps(jsonable(obj), indent=2))


# ------------------------------------------------------------------ launch vocabulary
# Every command that launches a ball accepts the same words (docs/conventions.md): a speed in one of
# three units, elevation and heading in degrees, a spin rate in rpm about an axis given by name
# (tennislab.core.launch.SPIN_AXES_DEG), by angle [deg] or as a vector.
#: flag dest -> [m/s] per unit (tennislab.units.SPEED_UNITS, the workflows' one statement)
SPEED_UNITS = {dest: factor for dest, (factor, _) in _SPEED_UNITS.items()}


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


def add_launch_flags(p, *, velocity_required: bool = False) -> None:
    """The launch vocabulary of every command that launches a ball from a free state (docs/conventions.md).

    Group "launch": ``--velocity VX VY VZ`` [m/s], or a speed (``--speed-kmh|--speed-ms|--speed-mph``)
    with ``--elevation-deg`` and ``--heading-deg``.  Group "spin": ``--spin WX WY WZ`` [rad/s], or
    ``--spin-rpm`` about ``--spin-axis NAME|DEG|AX AY AZ``.  Read back by :func:`launch_from_args`.
    """
    g = p.add_argument_group("launch (a velocity vector, or a speed with elevation and heading)")
    g.add_argument("--velocity", type=float, nargs=3, metavar=("VX", "VY", "VZ"), help="velocity [m/s]")
    add_speed_flags(g, note="(with --elevation-deg)")
    g.add_argument("--elevation-deg", type=float, metavar="DEG", help="launch angle above the horizontal [deg]")
    g.add_argument(
        "--heading-deg",
        type=float,
        metavar="DEG",
        help="direction from +x, positive toward +y (left) [deg] (default 0: straight down the court)",
    )
    s = p.add_argument_group("spin (a spin vector, or a rate about an axis)")
    s.add_argument("--spin", type=float, nargs=3, metavar=("WX", "WY", "WZ"), help="spin vector [rad/s]")
    s.add_argument("--spin-rpm", type=float, metavar="RPM", help="spin rate [rpm], with --spin-axis")
    s.add_argument(
        "--spin-axis",
        nargs="+",
        metavar="AXIS",
        help=LazyHelp(_spin_axis_help),
    )


def _spin_axis_help() -> str:
    from tennislab.core.launch import SPIN_AXES_DEG

    return (
        f"spin axis: a name ({', '.join(SPIN_AXES_DEG)}), an angle [deg] about the flight "
        "(0 topspin, 180 backspin, +90 curving left), or a vector AX AY AZ (right-hand rule)"
    )


def launch_from_args(args) -> dict:
    """The launch flags (:func:`add_launch_flags`) as keywords of :func:`tennislab.trajectory.fly`."""
    axis = args.spin_axis
    if axis is not None:
        kind, value = parse_spin_axis(axis)
        axis = axis[0] if kind == "angle" else value
    speeds = {k: getattr(args, k, None) for k in SPEED_UNITS}
    return dict(
        velocity=args.velocity,
        **speeds,
        elevation_deg=args.elevation_deg,
        heading_deg=args.heading_deg,
        spin=args.spin,
        spin_rpm=args.spin_rpm,
        spin_axis=axis,
    )


# ------------------------------------------------------------------ court surface
def surface_from_arg(value: str | None) -> str | None:
    """``--surface NAME|FILE``: a registered surface (clay, grass, hard, carpet, ...) or a surface file
    (``.toml``/``.json``, e.g. written by ``tennislab calibrate surface``), read and registered under
    its name; returns the name to pass to the workflows (None stays None)."""
    from tennislab.core.surfaces import Surface, get_surface, register_surface
    from tennislab.io.surface_file import is_surface_file, read_surface

    if value is None:
        return None
    if is_surface_file(value):
        d = read_surface(value)
        s = Surface(d["name"], e=d["e"], mu=d["mu"], e_x=d.get("e_x", 0.0), source=d.get("source", value))
        return register_surface(s).name
    return get_surface(value).name
