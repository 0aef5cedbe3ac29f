"""The rules every reader shares for the text formats: JSON documents and CSV headers.

* :func:`load_json` - JSON text parsed with the readers' limits: nesting depth counted on the raw
  text with strings removed, *before* :func:`json.loads` builds anything (:func:`json_depth`); a key
  repeated in one object is refused (:func:`unique_pairs`); ``NaN``/``Infinity`` refused or read as
  missing; an integer of thousands of digits is one line.  Used for files (point files, cameras,
  drills, surfaces, the batch manifest) and for the JSON stored in a launcher database.
* :func:`check_header` - a CSV header whose column names repeat is refused (whichever copy a reader
  took would be a guess): the one duplicate rule of the CSV readers.

Every error is one :class:`~tennislab.errors.InputError` line that starts with the name given.
"""

from __future__ import annotations

import json
import re
from typing import Any

import numpy as np

from tennislab.errors import InputError

#: deepest JSON nesting the readers accept by default (a point file needs 6, a drill 5)
MAX_DEPTH = 32

_STRING = re.compile(r'"(?:[^"\\]|\\.)*"', re.S)


def json_depth(text: str) -> int:
    """Deepest nesting of ``[``/``{`` outside strings (without parsing: linear time, no recursion)."""
    bare = _STRING.sub('""', text)
    arr = np.frombuffer(bare.encode("utf-8", "replace"), dtype=np.uint8)
    step = np.zeros(arr.size, dtype=np.int32)
    step[(arr == ord("[")) | (arr == ord("{"))] = 1
    step[(arr == ord("]")) | (arr == ord("}"))] = -1
    return int(np.cumsum(step).max()) if step.size else 0


def unique_pairs(name: str):
    """A ``json.loads`` ``object_pairs_hook`` that refuses a key given twice in one object."""

    def hook(pairs: list[tuple[str, Any]]) -> dict:
        out: dict = {}
        for k, v in pairs:
            if k in out:
                raise InputError(f"{name}: duplicate key {_short(k)} in one object (each key once)")
            out[k] = v
        return out

    return hook


def _short(k: object) -> str:
    r = repr(k)
    return r if len(r) <= 40 else r[:37] + "..."


#: a ``\\uD800``-``\\uDFFF`` escape: JSON may spell half a UTF-16 pair, which is no character
_SURROGATE_ESCAPE = re.compile(r"\\u[dD][89a-fA-F]")


def check_unicode(text: str, doc: Any, name: str) -> Any:
    """``doc`` (parsed from the JSON ``text``) unless one of its strings holds a lone surrogate
    (``"\\ud800"``: no character, and no UTF-8 writer, database or terminal can take it); a pair that
    spells one character is fine.  Only a text with such an escape is checked (a regular expression)."""
    if _SURROGATE_ESCAPE.search(text) is None:
        return doc
    try:
        json.dumps(doc, ensure_ascii=False).encode("utf-8")
    except UnicodeEncodeError:
        raise InputError(f"{name}: a string holds a lone surrogate (\\ud800-\\udfff), which is not text") from None
    return doc


def _refuse_constant(name: str):
    def parse(c: str):
        raise InputError(f"{name}: {c} is not a number JSON allows (give a finite number)")

    return parse


def _nan(c: str) -> float:
    return float("nan")


def load_json(text: str, name: str, *, max_depth: int = MAX_DEPTH, constants: str = "refuse") -> Any:
    """Parse JSON ``text`` with the readers' rules (module docstring).

    ``constants``: ``"refuse"`` (``NaN``, ``Infinity``: one line) or ``"nan"`` (read as NaN, a
    missing value the caller handles).  Raises :class:`InputError` ``"NAME: ..."``; a
    ``json.JSONDecodeError`` with the message ``Extra data`` is re-raised as it is for a caller that
    reads JSON Lines (:func:`load_json_lines`).
    """
    depth = json_depth(text)
    if depth > max_depth:
        raise InputError(f"{name}: JSON nested deeper than {max_depth} levels")
    constant = _nan if constants == "nan" else _refuse_constant(name)
    try:
        doc = json.loads(text, object_pairs_hook=unique_pairs(name), parse_constant=constant)
    except InputError:
        raise
    except RecursionError:  # pragma: no cover - guarded by the depth check
        raise InputError(f"{name}: JSON nested too deeply") from None
    except json.JSONDecodeError as exc:
        if exc.msg == "Extra data":
            raise
        raise InputError(f"{name}: not valid JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})") from None
    except ValueError as exc:  # e.g. an integer of more than 4300 digits
        raise InputError(f"{name}: not valid JSON ({str(exc).splitlines()[0][:80]})") from None
    return check_unicode(text, doc, name)


def load_json_document(text: str, name: str, *, max_depth: int = MAX_DEPTH, constants: str = "refuse") -> Any:
    """:func:`load_json` for a text that must hold one document (extra data after it is an error)."""
    try:
        return load_json(text, name, max_depth=max_depth, constants=constants)
    except json.JSONDecodeError as exc:
        raise InputError(f"{name}: not valid JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})") from None


def load_json_lines(text: str, name: str, *, max_depth: int = MAX_DEPTH, constants: str = "refuse") -> list:
    """JSON Lines: one document per non-blank line, each with :func:`load_json_document`'s rules."""
    out = []
    for i, line in enumerate(text.splitlines(), 1):
        if line.strip():
            out.append(load_json_document(line, f"{name}: line {i}", max_depth=max_depth, constants=constants))
    return out


def toml_message(exc: BaseException) -> str:
    """One line for a :mod:`tomllib` error (a key given twice is said as such: the one duplicate rule)."""
    msg = " ".join(str(exc).split())
    if msg.startswith(("Cannot overwrite a value", "Cannot declare")):
        where = msg[msg.find("(") :] if "(" in msg else ""
        return f"duplicate key (each key once) {where}".strip()
    return msg


def check_header(name: str, header: list[str]) -> None:
    """Refuse a CSV header in which a (non-empty) column name appears twice, compared without regard
    to case and surrounding spaces (``cl`` and ``CL``: which one a reader took would be a guess)."""
    seen: set[str] = set()
    for h in header:
        key = h.strip().casefold()
        if key and key in seen:
            raise InputError(f"{name}: duplicate column {_short(h)} in the header (each column once)")
        seen.add(key)
