"""Point JSON of ball trackers (Hawk-Eye-style, as analytics vendors exchange it): one point per file.

Format (SI units, court frame of :mod:`tennislab.core.court`: origin at the centre of the net on the
ground, x along the court, baselines at +-11.885 m, z up)::

    {"match": {"season": .., "tournament_id": .., "players": [{"team": 1, "external_id": "AB12"}, ..]},
     "sequences": {"set": 1, "game": 1, "point": 1, "serve": 1, "rally": 1},
     "shots": [{"shot_no": 1, "team": 2, "stroke": "serve", "time": 12.34, "duration": 0.69,
                "speed_ms": 59.6, "spin": {"type": "backspin", "rpm": -3656.0},
                "call": "out", "distance": 0.12}, ...],
     "samples": [{"time": 12.34, "ball": {"pos": {"x": -11.337, "y": -0.622, "z": 2.956}},
                  "event": "hit", "players": [...]}, ...],
     "events": [...]}

Accepted variants: a file holding one point, a list of points, ``{"points": [...]}``, JSON Lines
(one point per line), or a directory of such files (``*.json``, ``*.jsonl``; sorted by name).
Optional everywhere: ``match``, ``sequences``, ``shots`` and every shot field, ``events``, a sample's
``event`` (``"hit"``, ``"bounce"``, ``"net"``; a string or a list of strings) and its ``ball``
(a sample without a ball position, or with ``null``/non-finite coordinates, is skipped).  A ball
position is ``{"x", "y", "z"}`` or ``[x, y, z]``; a sample's time is ``time`` (or ``t``) [s].  Samples
may come unsorted and with gaps: they are sorted by time; of samples with equal times the first with a
ball position is kept.  Spin ``rpm`` is signed (negative = backspin) beside its ``type``; ``call`` may
be missing or null; ``distance`` [m] when given.  Top-level ``events`` entries are read when they carry
a time (``time``/``t``) and a kind (``type``/``event``/``name``); others are ignored.  Player positions
are not read.

Limits (checked before anything is expanded): :data:`MAX_BYTES` per file, nesting depth
:data:`MAX_DEPTH`, :data:`MAX_SAMPLES` samples per point, :data:`MAX_POINTS` points, :data:`MAX_FILES`
files in a directory.  Any malformed file raises :class:`~tennislab.errors.InputError` with one line
naming the file and the field (``points[2].samples[17].ball.pos.x: expected a number, got 'a'``).

This module parses only: it returns plain data (:class:`Point`, :class:`ShotInfo`); what a shot's
stroke or call means is :mod:`tennislab.linecall`'s business.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from tennislab.errors import InputError
from tennislab.io.files import read_input
from tennislab.io.formats import load_json, load_json_lines

MAX_BYTES = 50_000_000  #: largest point file read [bytes]
MAX_DEPTH = 32  #: deepest JSON nesting accepted (a point needs 6)
MAX_SAMPLES = 200_000  #: most samples in one point (an hour at 50 Hz)
MAX_POINTS = 100_000  #: most points read in one call
MAX_FILES = 100_000  #: most files read from a directory
MAX_COORD = 1000.0  #: [m] largest |coordinate| (beyond: wrong units)
EVENT_KINDS = ("hit", "bounce", "net")


@dataclass(frozen=True)
class ShotInfo:
    """One shot as the tracker describes it; every field may be ``None`` (absent)."""

    index: int
    shot_no: int | None = None
    team: int | None = None
    stroke: str | None = None
    time: float | None = None
    duration: float | None = None
    speed_ms: float | None = None
    spin_rpm: float | None = None
    spin_type: str | None = None
    call: str | None = None
    distance: float | None = None
    bounce_xy: tuple[float, float] | None = None


@dataclass(frozen=True)
class Point:
    """One point: sorted sample times ``t`` (N,) [s] with ball positions ``xyz`` (N, 3) [m], the
    sample events ``events`` ((time, kind), kind in :data:`EVENT_KINDS`), the shots, the sequence
    numbers and the match record (plain JSON), and counts of what was skipped."""

    name: str
    t: np.ndarray
    xyz: np.ndarray
    events: tuple[tuple[float, str], ...] = ()
    shots: tuple[ShotInfo, ...] = ()
    sequences: dict = field(default_factory=dict)
    match: dict = field(default_factory=dict)
    n_samples: int = 0
    n_without_ball: int = 0
    n_duplicate: int = 0
    event_positions: tuple[tuple[float, str, float, float, float], ...] = ()

    def __len__(self) -> int:
        return int(self.t.size)


# ---------------------------------------------------------------- checks
def _loads(text: str, name: str) -> Any:
    try:
        return load_json(text, name, max_depth=MAX_DEPTH, constants="nan")  # NaN literals: missing values
    except json.JSONDecodeError:  # "Extra data": JSON Lines, one document per line
        return load_json_lines(text, name, max_depth=MAX_DEPTH, constants="nan")


def _where(path: str, key: str | int) -> str:
    return f"{path}[{key}]" if isinstance(key, int) else (f"{path}.{key}" if path else key)


def _num(v: Any, where: str, *, optional: bool = True, lo: float | None = None, hi: float | None = None):
    """A float from a JSON number (or a numeric string); ``None`` when absent and optional."""
    if v is None:
        if optional:
            return None
        raise InputError(f"{where}: missing (expected a number)")
    if isinstance(v, bool) or not isinstance(v, (int, float, str)):
        raise InputError(f"{where}: expected a number, got {type(v).__name__}")
    try:
        f = float(v)
    except (ValueError, OverflowError):
        raise InputError(f"{where}: expected a number, got {str(v)[:30]!r}") from None
    if not math.isfinite(f):
        if optional:
            return None
        raise InputError(f"{where}: must be a finite number, got {str(v)[:30]!r}")
    if (lo is not None and f < lo) or (hi is not None and f > hi):
        raise InputError(f"{where}: {f:g} is outside the allowed range [{lo}, {hi}]")
    return f


def _int(v: Any, where: str):
    f = _num(v, where, lo=-1e9, hi=1e9)
    return None if f is None else int(f)


def _str(v: Any, where: str):
    if v is None:
        return None
    if isinstance(v, (dict, list)):
        raise InputError(f"{where}: expected a string, got {type(v).__name__}")
    return str(v)[:64].strip().lower()


def _obj(v: Any, where: str, optional: bool = True) -> dict:
    if v is None and optional:
        return {}
    if not isinstance(v, dict):
        raise InputError(f"{where}: expected an object, got {type(v).__name__}")
    return v


def _list(v: Any, where: str, optional: bool = True) -> list:
    if v is None and optional:
        return []
    if not isinstance(v, list):
        raise InputError(f"{where}: expected a list, got {type(v).__name__}")
    return v


def _xyz(pos: Any, where: str):
    """(x, y, z) or None (absent / non-finite)."""
    if pos is None:
        return None
    if isinstance(pos, dict):
        vals = [_num(pos.get(k), f"{where}.{k}", lo=-MAX_COORD, hi=MAX_COORD) for k in "xyz"]
    elif isinstance(pos, list):
        if len(pos) != 3:
            raise InputError(f"{where}: expected 3 numbers [x, y, z], got {len(pos)}")
        vals = [_num(v, f"{where}[{i}]", lo=-MAX_COORD, hi=MAX_COORD) for i, v in enumerate(pos)]
    else:
        raise InputError(f"{where}: expected an object {{x, y, z}} or a list, got {type(pos).__name__}")
    if any(v is None for v in vals):
        return None
    return vals


def _bounce_xy(b: Any, where: str):
    """(x, y) of a shot's bounce given as {"pos": {..}}, {"x", "y"[, "z"]} or [x, y[, z]]."""
    if isinstance(b, dict) and "pos" in b:
        b, where = b["pos"], f"{where}.pos"
    if isinstance(b, dict):
        x = _num(b.get("x"), f"{where}.x", lo=-MAX_COORD, hi=MAX_COORD)
        y = _num(b.get("y"), f"{where}.y", lo=-MAX_COORD, hi=MAX_COORD)
    elif isinstance(b, list) and len(b) in (2, 3):
        x = _num(b[0], f"{where}[0]", lo=-MAX_COORD, hi=MAX_COORD)
        y = _num(b[1], f"{where}[1]", lo=-MAX_COORD, hi=MAX_COORD)
    elif b is None:
        return None
    else:
        raise InputError(f"{where}: expected an object {{x, y}} or a list [x, y], got {type(b).__name__}")
    return None if x is None or y is None else (x, y)


def _shot(s: Any, k: int, where: str) -> ShotInfo:
    s = _obj(s, where, optional=False)
    spin = s.get("spin")
    rpm = stype = None
    if isinstance(spin, dict):
        rpm = _num(spin.get("rpm"), f"{where}.spin.rpm", lo=-30000, hi=30000)
        stype = _str(spin.get("type"), f"{where}.spin.type")
    elif spin is not None:
        rpm = _num(spin, f"{where}.spin", lo=-30000, hi=30000)
    if rpm is None and s.get("spin_rpm") is not None:
        rpm = _num(s.get("spin_rpm"), f"{where}.spin_rpm", lo=-30000, hi=30000)
    bxy = _bounce_xy(s.get("bounce"), f"{where}.bounce")
    call = s.get("call")
    return ShotInfo(
        index=k,
        shot_no=_int(s.get("shot_no"), f"{where}.shot_no"),
        team=_int(s.get("team"), f"{where}.team"),
        stroke=_str(s.get("stroke"), f"{where}.stroke"),
        time=_num(s.get("time"), f"{where}.time", lo=-1e7, hi=1e7),
        duration=_num(s.get("duration"), f"{where}.duration", lo=0.0, hi=1e4),
        speed_ms=_num(s.get("speed_ms"), f"{where}.speed_ms", lo=0.0, hi=200.0),
        spin_rpm=rpm,
        spin_type=stype,
        call=None if call is None else _str(call, f"{where}.call"),
        distance=_num(s.get("distance"), f"{where}.distance", lo=-100.0, hi=100.0),
        bounce_xy=bxy,
    )


def _kinds(ev: Any, where: str) -> list[str]:
    if ev is None:
        return []
    items = ev if isinstance(ev, list) else [ev]
    out = []
    for e in items:
        if isinstance(e, dict):
            e = e.get("type", e.get("name", e.get("event")))
        if isinstance(e, (dict, list)):
            raise InputError(f"{where}: expected an event name, got {type(e).__name__}")
        k = _str(e, where)
        if k in EVENT_KINDS:
            out.append(k)
    return out


def _point(doc: Any, name: str, where: str) -> Point:
    doc = _obj(doc, where or name, optional=False)
    pre = f"{where}." if where else ""
    if "samples" not in doc:
        raise InputError(f"{name}: {pre}samples: missing (a point needs its ball samples)")
    samples = _list(doc.get("samples"), f"{name}: {pre}samples", optional=False)
    if len(samples) > MAX_SAMPLES:
        raise InputError(f"{name}: {pre}samples: {len(samples)} samples, more than the {MAX_SAMPLES} allowed")
    T: list[float] = []
    P: list[list[float]] = []
    events: list[tuple[float, str]] = []
    ev_pos: list[tuple[float, str, float, float, float]] = []
    no_ball = 0
    for j, smp in enumerate(samples):
        w = f"{name}: {pre}samples[{j}]"
        smp = _obj(smp, w, optional=False)
        tv = smp.get("time", smp.get("t"))
        t = _num(tv, f"{w}.time", optional=False, lo=-1e7, hi=1e7)
        ball = smp.get("ball")
        pos = None
        if isinstance(ball, dict):
            pos = _xyz(ball.get("pos", ball if "x" in ball else None), f"{w}.ball.pos")
        elif isinstance(ball, list):
            pos = _xyz(ball, f"{w}.ball")
        elif ball is not None:
            raise InputError(f"{w}.ball: expected an object, got {type(ball).__name__}")
        for k in _kinds(smp.get("event", smp.get("events")), f"{w}.event"):
            events.append((t, k))
            if pos is not None:
                ev_pos.append((t, k, pos[0], pos[1], pos[2]))
        if pos is None:
            no_ball += 1
            continue
        T.append(t)
        P.append(pos)
    for j, ev in enumerate(_list(doc.get("events"), f"{name}: {pre}events")):
        if not isinstance(ev, dict):
            continue
        tv = ev.get("time", ev.get("t"))
        try:
            te = float(tv) if tv is not None and not isinstance(tv, (bool, dict, list)) else None
        except (TypeError, ValueError):
            te = None
        kinds = _kinds(ev.get("type", ev.get("event", ev.get("name"))), f"{name}: {pre}events[{j}].type")
        if te is not None and math.isfinite(te) and kinds:
            events.append((te, kinds[0]))
    shots = tuple(
        _shot(s, k, f"{name}: {pre}shots[{k}]") for k, s in enumerate(_list(doc.get("shots"), f"{name}: {pre}shots"))
    )
    seq_raw = _obj(doc.get("sequences"), f"{name}: {pre}sequences")
    seq = {k: _int(v, f"{name}: {pre}sequences.{k}") for k, v in seq_raw.items() if not isinstance(v, (dict, list))}
    match = _obj(doc.get("match"), f"{name}: {pre}match")
    t_arr = np.asarray(T, dtype=float).reshape(-1)
    xyz = np.asarray(P, dtype=float).reshape(-1, 3)
    order = np.argsort(t_arr, kind="stable")
    t_arr, xyz = t_arr[order], xyz[order]
    dup = np.zeros(t_arr.size, dtype=bool)
    if t_arr.size > 1:
        dup[1:] = np.diff(t_arr) <= 0.0
    label = name if not where else f"{name}:{where}"
    return Point(
        name=label,
        t=np.ascontiguousarray(t_arr[~dup]),
        xyz=np.ascontiguousarray(xyz[~dup]),
        events=tuple(sorted(events)),
        shots=shots,
        sequences=seq,
        match=match,
        n_samples=len(samples),
        n_without_ball=no_ball,
        n_duplicate=int(dup.sum()),
        event_positions=tuple(sorted(ev_pos)),
    )


def parse_points(text: str | bytes, name: str = "points") -> list[Point]:
    """Parse the text of a point file (one point, a list, ``{"points": [...]}`` or JSON Lines)."""
    if isinstance(text, (bytes, bytearray)):
        if len(text) > MAX_BYTES:
            raise InputError(f"{name}: larger than {MAX_BYTES:,} bytes")
        try:
            text = bytes(text).decode("utf-8-sig")
        except UnicodeDecodeError as exc:
            raise InputError(f"{name}: not UTF-8 text (byte {exc.start})") from None
    if len(text) > MAX_BYTES:
        raise InputError(f"{name}: larger than {MAX_BYTES:,} bytes")
    if not text.strip():
        raise InputError(f"{name}: empty (expected a point JSON object)")
    doc = _loads(text, name)
    if isinstance(doc, dict) and "points" in doc and "samples" not in doc:
        items = _list(doc["points"], f"{name}: points", optional=False)
        base = "points"
    elif isinstance(doc, list):
        items, base = doc, ""
    elif isinstance(doc, dict):
        return [_point(doc, name, "")]
    else:
        raise InputError(
            f"{name}: expected a point object (with 'samples'), a list of points or {{'points': [...]}}, "
            f"got {type(doc).__name__}"
        )
    if len(items) > MAX_POINTS:
        raise InputError(f"{name}: {len(items)} points, more than the {MAX_POINTS} allowed")
    if not items:
        raise InputError(f"{name}: no points")
    return [_point(d, name, f"{base}[{i}]") for i, d in enumerate(items)]


def _read_file(path: str) -> bytes:
    return read_input(path, MAX_BYTES)


def read_points(path: str) -> list[Point]:
    """Read a point file or a directory of point files (``*.json``, ``*.jsonl``, sorted by name)."""
    path = str(path)
    if os.path.isdir(path):
        names = sorted(f for f in os.listdir(path) if f.lower().endswith((".json", ".jsonl")))
        if not names:
            raise InputError(f"{path}: no .json point files in the directory")
        if len(names) > MAX_FILES:
            raise InputError(f"{path}: {len(names)} files, more than the {MAX_FILES} allowed")
        out: list[Point] = []
        for f in names:
            full = os.path.join(path, f)
            if os.path.isdir(full):
                continue
            out.extend(parse_points(_read_file(full), full))
            if len(out) > MAX_POINTS:
                raise InputError(f"{path}: more than the {MAX_POINTS} points allowed")
        return out
    return parse_points(_read_file(path), path)
