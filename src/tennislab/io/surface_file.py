"""Read a court-surface file: the parameters of the bounce model for one court.

A TOML file (or a JSON object with the same keys), written by ``tennislab calibrate surface`` or by
hand::

    name = "club-court-3"    # optional (default: the file's stem)
    e = 0.78                 # vertical coefficient of restitution [-], (0, 1]
    mu = 0.61                # coefficient of sliding friction [-], [0, 2]
    e_x = 0.0                # tangential restitution of a gripping ball [-], [0, 1] (optional)
    source = "fitted to 412 bounces"   # optional

Plain data out (a dict of those keys); the ranges are checked by :class:`tennislab.core.surfaces.Surface`.
Every malformed file is a one-line :class:`~tennislab.errors.InputError` naming the file and the key.
"""

from __future__ import annotations

import math
import os
import tomllib

from tennislab.errors import InputError
from tennislab.io.files import read_text
from tennislab.io.formats import MAX_DEPTH, load_json_document, toml_message

#: largest surface file read [bytes]
MAX_BYTES = 64_000
NUMBERS = ("e", "mu", "e_x")
TEXTS = ("name", "source", "category")


def is_surface_file(value: str) -> bool:
    """True when ``value`` names a surface file rather than a registered surface (by its extension)."""
    return str(value).lower().endswith((".toml", ".json"))


def read_surface(path: str) -> dict:
    """The surface parameters of a ``.toml`` or ``.json`` file as a dict (module docstring)."""
    text = read_text(path, MAX_BYTES)
    where = f"surface file {path}"
    if path.lower().endswith(".json"):
        return _values(path, where, load_json_document(text, where, max_depth=MAX_DEPTH))
    try:
        data = tomllib.loads(text)
    except (ValueError, RecursionError) as exc:
        msg = toml_message(exc)[:160]
        raise InputError(f"{where}: not valid TOML ({msg})") from None
    return _values(path, where, data)


def _values(path: str, where: str, data) -> dict:
    """The checked values of a surface file's table."""
    if not isinstance(data, dict):
        raise InputError(f"{where}: expected a table of e, mu (and e_x, name, source)")
    unknown = sorted(set(data) - set(NUMBERS) - set(TEXTS))
    if unknown:
        raise InputError(f"{where}: {unknown[0]}: unknown key; allowed: {', '.join(NUMBERS + TEXTS)}")
    out: dict = {}
    for k in NUMBERS:
        if k not in data:
            if k == "e_x":
                continue
            raise InputError(f"{where}: {k}: missing (the surface needs e and mu)")
        v = data[k]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v)):
            raise InputError(f"{where}: {k}: expected a finite number, got {v!r}"[:200])
        out[k] = float(v)
    for k in TEXTS:
        if k in data:
            if not isinstance(data[k], str) or len(data[k]) > 200:
                raise InputError(f"{where}: {k}: expected a short text")
            out[k] = data[k]
    out.setdefault("name", os.path.splitext(os.path.basename(path))[0] or "surface")
    return out
