"""``tennislab.toml``: defaults and profiles for every command (docs/config.md).

Precedence: a flag on the command line beats the configuration, which beats the built-in default.
:func:`find_config` picks the file (``--config FILE``, else ``./tennislab.toml``), :func:`load_config`
reads it (:mod:`tennislab.io.config`) and checks its meaning (the physics options build, the surface
exists, every player profile is valid), :func:`apply_defaults` makes its values the defaults of the
matching flags of every command, :func:`register_profiles` makes its players known to ``--player``,
and :func:`resolve_profiles` fills the machine flags from ``--machine NAME`` and reads ``--player
FILE.toml``.

This module has no ``register``: it adds no command (the CLI's ``--config`` is global).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from tennislab.errors import InputError
from tennislab.io.files import check_input_file

if TYPE_CHECKING:
    from tennislab.serve import PlayerProfile

#: the file looked for in the working folder when ``--config`` is not given
CONFIG_NAME = "tennislab.toml"

#: configuration table -> {key: flag dest} for the flat tables applied as flag defaults
FLAG_DESTS: dict[str, dict[str, str]] = {
    "physics": {
        k: k
        for k in ("aero", "cd", "cl", "aero_table", "mass", "radius", "air_density", "gravity", "wind", "spin_decay")
    },
    "court": {"surface": "surface"},
    "defaults": {"player": "player", "machine": "machine"},
}
#: machine profile key -> flag dest (``--machine NAME`` fills these when not given)
MACHINE_DESTS = {
    "position": "machine_position",
    "roller_radius": "roller_radius",
    "roller_axis_distance": "roller_axis_distance",
}


@dataclass(frozen=True)
class Config:
    """A checked configuration (plain data; empty tables when there is no file)."""

    path: str | None = None
    physics: dict = field(default_factory=dict)
    court: dict = field(default_factory=dict)
    defaults: dict = field(default_factory=dict)
    players: dict = field(default_factory=dict)
    machines: dict = field(default_factory=dict)

    def flag_defaults(self) -> dict[str, object]:
        """{flag dest: value} of the flat tables (the defaults they give to every command's flags)."""
        out: dict[str, object] = {}
        for table, dests in FLAG_DESTS.items():
            for key, value in getattr(self, table).items():
                out[dests[key]] = value
        return out


def find_config(explicit: str | None, cwd: str | None = None) -> str | None:
    """The configuration file to use: ``explicit`` (must exist), else ``CONFIG_NAME`` in ``cwd``."""
    if explicit is not None:
        try:
            check_input_file(explicit)
        except InputError as exc:
            raise InputError(f"config: {exc}") from None
        return explicit
    local = CONFIG_NAME if cwd is None else os.path.join(cwd, CONFIG_NAME)
    return local if os.path.lexists(local) else None  # a FIFO or a directory of that name: refused when read


def player_from_dict(name: str, fields: dict, where: str) -> PlayerProfile:
    """A :class:`~tennislab.serve.players.PlayerProfile` from a profile's fields (the dataclass's field
    names; ``name`` optional); an unknown or missing field is a one-line error naming it."""
    from tennislab.serve import PlayerProfile

    known = [f.name for f in dataclasses.fields(PlayerProfile)]
    d: dict[str, Any] = {k: tuple(v) if isinstance(v, list) else v for k, v in fields.items()}
    d.setdefault("name", name)
    for k in d:
        if k not in known:
            raise InputError(f"{where}{k}: unknown key; allowed: {', '.join(known)}")
    missing = [k for k in known if k not in d and _required(PlayerProfile, k)]
    if missing:
        raise InputError(f"{where}{missing[0]}: missing (a player needs {', '.join(k for k in known if k != 'name')})")
    try:
        return PlayerProfile(**d)
    except InputError as exc:
        raise InputError(f"{where}{exc}") from None
    except TypeError as exc:
        raise InputError(f"{where.rstrip('.: ')}: {exc}") from None


def _required(cls, name: str) -> bool:
    f = next(f for f in dataclasses.fields(cls) if f.name == name)
    return f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING


def load_config(path: str | None) -> Config:
    """Read and check the configuration at ``path`` (None: an empty configuration).

    Relative paths in it (``physics.aero_table``) are relative to the file's folder.  The physics
    table must build (:meth:`FlightParams.from_options`), the surface must be registered, player
    profiles must be valid and the default player/machine must name a profile (or a built-in player).
    """
    if path is None:
        return Config()
    from tennislab.cli.common import surface_from_arg
    from tennislab.core.flight import FlightParams
    from tennislab.io.aero_table import read_aero_table
    from tennislab.io.config import read_config
    from tennislab.io.surface_file import is_surface_file
    from tennislab.serve import get_player

    data = read_config(path)
    base = os.path.dirname(os.path.abspath(path))
    physics = dict(data["physics"])
    if "aero_table" in physics and not os.path.isabs(physics["aero_table"]):
        physics["aero_table"] = os.path.join(base, physics["aero_table"])
    opts = dict(physics)
    if "aero_table" in opts:
        opts["aero_table"] = read_aero_table(opts["aero_table"])
    try:
        FlightParams.from_options(**opts)
    except InputError as exc:
        raise InputError(f"{path}: physics.{exc}") from None
    if "surface" in data["court"]:
        surf = data["court"]["surface"]
        if isinstance(surf, str) and is_surface_file(surf) and not os.path.isabs(surf):
            data["court"]["surface"] = surf = os.path.join(base, surf)
        try:
            surface_from_arg(surf)
        except InputError as exc:
            raise InputError(f"{path}: court.{exc}") from None
    players = {
        name: player_from_dict(name, fields, f"{path}: players.{name}.") for name, fields in data["players"].items()
    }
    machines = data["machines"]
    defaults = data["defaults"]
    if "machine" in defaults and defaults["machine"] not in machines:
        raise InputError(
            f"{path}: defaults.machine: no [machines.{defaults['machine']}] table in the file"
            + (f"; profiles: {', '.join(machines)}" if machines else "")
        )
    if "player" in defaults and defaults["player"] not in players:
        try:
            get_player(defaults["player"])
        except InputError:
            raise InputError(
                f"{path}: defaults.player: {defaults['player']!r} is neither a [players.NAME] table "
                "nor a built-in player (professional, recreational, junior)"
            ) from None
    return Config(path, physics, data["court"], defaults, players, machines)


def register_profiles(cfg: Config) -> None:
    """Make the configuration's players known to every command's ``--player NAME``."""
    from tennislab.serve import register_player

    for name, player in cfg.players.items():
        aliases = (name.lower(),) if name.lower() != player.name else ()
        register_player(player, *aliases)


def _walk(parser: argparse.ArgumentParser):
    """``parser`` and every sub-command parser below it."""
    yield parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in dict.fromkeys(action.choices.values()):  # aliases share a parser
                yield from _walk(sub)


def apply_defaults(parser: argparse.ArgumentParser, cfg: Config) -> dict[str, object]:
    """Make the configuration's values the defaults of the matching flags of every command.

    A flag given on the command line still wins (argparse only uses a default for a flag that is
    absent).  Repeatable flags (``append``) are left alone: their command reads
    ``args.config_defaults``.  Returns ``{dest: value}`` of the configuration's defaults.
    """
    values = cfg.flag_defaults()
    if not values:
        return {}
    for p in _walk(parser):
        for action in p._actions:
            if action.dest in values and action.option_strings and not isinstance(action, argparse._AppendAction):
                action.default = _as_flag_value(values[action.dest], action)
    return values


def _as_flag_value(value, action: argparse.Action):
    """A configuration value in the form argparse would give for ``action`` (lists for nargs)."""
    if isinstance(value, list):
        return [action.type(v) if callable(action.type) else v for v in value]
    if callable(action.type) and not isinstance(value, str):
        return action.type(value)
    return value


def resolve_profiles(args: argparse.Namespace, cfg: Config) -> None:
    """After parsing: ``--machine NAME`` fills the machine flags that were not given, and a
    ``--player`` naming a ``.toml`` file registers that player and selects it."""
    machine = getattr(args, "machine", None)
    if machine is not None:
        if machine not in cfg.machines:
            where = cfg.path or CONFIG_NAME
            known = ", ".join(cfg.machines) or "none"
            raise InputError(f"machine: no profile {machine!r} in {where} (profiles: {known})")
        for key, value in cfg.machines[machine].items():
            dest = MACHINE_DESTS[key]
            if hasattr(args, dest) and getattr(args, dest) is None:  # a flag given on the command line wins
                setattr(args, dest, list(value) if isinstance(value, list) else value)
    player = getattr(args, "player", None)
    if isinstance(player, str) and player.lower().endswith(".toml"):
        args.player = load_player_file(player).name


def load_player_file(path: str) -> PlayerProfile:
    """Read a one-player TOML file (:func:`tennislab.io.config.read_player_file`) and register it."""
    from tennislab.io.config import read_player_file

    try:
        check_input_file(path)
    except InputError as exc:
        raise InputError(f"player: {exc}") from None
    fields = read_player_file(path)
    name = str(fields.get("name") or os.path.splitext(os.path.basename(path))[0])
    player = player_from_dict(name, {**fields, "name": name}, f"{path}: ")
    register_profiles(Config(players={name: player}))
    return player
