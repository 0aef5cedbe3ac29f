"""Reader of ``tennislab.toml`` (the configuration file) and of one-player TOML files.

Parses TOML (:mod:`tomllib`) into plain dicts and checks the file's *form*: size, encoding, the known
tables and keys, and the type of each value (a number, a text, a list of numbers of a given length).
The meaning (physics options, surfaces, player and machine profiles) is given by the front-ends
(:mod:`tennislab.cli.config`).  Every error is one :class:`~tennislab.errors.InputError` line that
names the file and the key: ``tennislab.toml: physics.drag: unknown key; allowed: aero, cd, ...``.

The format (docs/config.md)::

    [physics]            # defaults for the physics flags of every command (SI units)
    [court]              # surface = "clay": default --surface
    [defaults]           # player = "NAME", machine = "NAME": default profiles
    [players.NAME]       # a player profile (its fields: tennislab.serve.players)
    [machines.NAME]      # a launcher profile: position, roller_radius, roller_axis_distance
"""

from __future__ import annotations

import difflib
import json
import math
import re
import tomllib

from tennislab.errors import InputError
from tennislab.io.files import read_text
from tennislab.io.formats import toml_message

#: largest configuration file read [bytes]
MAX_BYTES = 1_000_000

NUMBER = "number"
TEXT = "text"

#: type of each key of the flat tables: NUMBER, TEXT or (NUMBER, n) for a list of n numbers
PHYSICS_KEYS: dict[str, object] = {
    "aero": TEXT,
    "cd": NUMBER,
    "cl": NUMBER,
    "aero_table": TEXT,
    "mass": NUMBER,
    "radius": NUMBER,
    "air_density": NUMBER,
    "gravity": NUMBER,
    "wind": (NUMBER, 3),
    "spin_decay": NUMBER,
}
COURT_KEYS: dict[str, object] = {"surface": TEXT}
DEFAULTS_KEYS: dict[str, object] = {"player": TEXT, "machine": TEXT}
MACHINE_KEYS: dict[str, object] = {"position": (NUMBER, 2), "roller_radius": NUMBER, "roller_axis_distance": NUMBER}
#: the tables of ``tennislab.toml``: flat tables (key -> type) and tables of named profiles
FLAT_TABLES = {"physics": PHYSICS_KEYS, "court": COURT_KEYS, "defaults": DEFAULTS_KEYS}
PROFILE_TABLES = ("players", "machines")


_BARE = re.compile(r"[A-Za-z0-9_-]+")  # used with fullmatch: "$" would accept a trailing newline


def _key(key) -> str:
    """A key as TOML writes it: bare when it can be, else quoted (so a message stays on one line)."""
    k = str(key)
    return k if _BARE.fullmatch(k) else json.dumps(k)


def _unknown(where: str, key: str, allowed) -> InputError:
    allowed = sorted(allowed)
    near = difflib.get_close_matches(str(key), allowed, n=1)
    hint = f" (did you mean {near[0]}?)" if near else ""
    return InputError(f"{where}{_key(key)}: unknown key{hint}; allowed: {', '.join(allowed)}")


def read_toml(path: str, limit: int = MAX_BYTES) -> dict:
    """Parse the TOML file ``path`` (UTF-8, at most ``limit`` bytes) into a dict."""
    text = read_text(path, limit)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path}: not valid TOML: {toml_message(exc)}") from None
    except RecursionError:
        raise InputError(f"{path}: not valid TOML: nested too deeply") from None
    except ValueError as exc:  # e.g. an integer of thousands of digits (Python's int-string limit)
        raise InputError(f"{path}: not valid TOML: {' '.join(str(exc).split())[:120]}") from None


def _short(value) -> str:
    """A value for a message: its repr on one line, cut to 40 characters."""
    r = " ".join(repr(value).split())
    return r if len(r) <= 40 else r[:37] + "..."


def check_value(where: str, value, kind) -> object:
    """``value`` if it has the form ``kind`` (NUMBER, TEXT or (NUMBER, n)); numbers become floats."""
    if kind == TEXT:
        if not isinstance(value, str):
            raise InputError(f"{where}: expected a text in quotes, got {_short(value)}")
        return value
    if kind == NUMBER:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise InputError(f"{where}: expected a number, got {_short(value)}")
        f = float(value)
        if not math.isfinite(f):
            raise InputError(f"{where}: must be a finite number, got {_short(value)}")
        return f
    assert isinstance(kind, tuple)
    n = kind[1]
    if not isinstance(value, list) or len(value) != n:
        raise InputError(f"{where}: expected a list of {n} numbers, got {_short(value)}")
    return [check_value(f"{where}[{i}]", v, NUMBER) for i, v in enumerate(value)]


def _plain(where: str, v):
    """A profile's value: a number (as float), a text, true/false, or a flat list of numbers and texts."""
    if isinstance(v, (str, bool)):
        return v
    if isinstance(v, list):
        if any(isinstance(x, (dict, list)) for x in v):
            raise InputError(f"{where}: expected a list of numbers or texts, got {_short(v)}")
        return [x if isinstance(x, (str, bool)) else check_value(f"{where}[{i}]", x, NUMBER) for i, x in enumerate(v)]
    if isinstance(v, dict):
        raise InputError(f"{where}: expected a number, a text or a list, got a table")
    return check_value(where, v, NUMBER)


def check_table(where: str, table, keys: dict | None) -> dict:
    """A table whose keys are among ``keys`` (key -> kind; None: any key, values numbers, texts or
    flat lists of them)."""
    if not isinstance(table, dict):
        raise InputError(f"{where.rstrip('.')}: expected a table")
    out = {}
    for k, v in table.items():
        if keys is None:
            out[k] = _plain(f"{where}{_key(k)}", v)
        elif k not in keys:
            raise _unknown(where, k, keys)
        else:
            out[k] = check_value(f"{where}{k}", v, keys[k])
    return out


def parse_config(data: dict, where: str = "") -> dict:
    """The checked content of a configuration: ``{"physics": {...}, "court": {...}, "defaults": {...},
    "players": {name: {...}}, "machines": {name: {...}}}`` (every table present, maybe empty).

    Player profiles keep their keys as written (numbers as floats); the front-end checks them
    against the player profile's fields."""
    prefix = f"{where}: " if where else ""
    out: dict = {name: {} for name in (*FLAT_TABLES, *PROFILE_TABLES)}
    for section, value in data.items():
        if section in FLAT_TABLES:
            out[section] = check_table(f"{prefix}{section}.", value, FLAT_TABLES[section])
        elif section in PROFILE_TABLES:
            if not isinstance(value, dict):
                raise InputError(f"{prefix}{section}: expected tables [{section}.NAME]")
            keys = MACHINE_KEYS if section == "machines" else None
            for name, table in value.items():
                if not _BARE.fullmatch(str(name)):
                    raise InputError(
                        f"{prefix}{section}.{_key(name)}: a profile name uses letters, digits, '_' and '-' only"
                    )
                out[section][name] = check_table(f"{prefix}{section}.{name}.", table, keys)
        else:
            raise _unknown(prefix, section, (*FLAT_TABLES, *PROFILE_TABLES))
    return out


def read_config(path: str) -> dict:
    """Read and check ``tennislab.toml`` (:func:`parse_config`); errors name ``path`` and the key."""
    return parse_config(read_toml(path), where=path)


def read_player_file(path: str) -> dict:
    """A TOML file with one player profile: its fields at the top level (``name`` optional, default
    the file's stem), or one ``[player]`` table.  Returns the fields (numbers as floats)."""
    data = read_toml(path)
    if set(data) == {"player"} and isinstance(data["player"], dict):
        data = data["player"]
    return check_table(f"{path}: ", data, None)
