"""A whole rally (or match) of tracker output called shot by shot: :func:`call_rally`.

Each point (:class:`tennislab.io.hawkeye.Point`: sorted ball samples, events, the tracker's shots) is
cut into shots, hit to next hit: at the samples flagged ``hit`` when the tracker gives them, else at
the tracker's shot times, else at the hits found in the track (:func:`~tennislab.linecall.detect.find_hits`).
Each shot is called by :func:`~tennislab.linecall.calls.call_track` (net check, first bounce, robust
fit, mark, decision, quality gate; never refused: a shot that cannot be fitted is ``review`` with the
reason) against the area it must land in (a shot hit again before it comes near the ground, a volley:
no bounce found and at most one sample, an outlier, below 0.3 m, has nothing to call: ``volley``; a ball
after the point is over has nothing to call either: ``dead``, see :func:`call_point`):

* a serve (the tracker's ``stroke`` says so, or, without shot records, the first hit of a point struck
  from behind the service line): the service box diagonally opposite the server, the server's half and
  side read from the ball at the hit (the deuce court is on the server's right);
* any other shot: the opponent's singles court (the doubles court with ``doubles=True``, or when the
  match record lists four players), the opponent being on the side the ball travels to.

Samples before the first hit the track shows (without hit events) that barely move along the court are
a serve's toss and are left out.  A clock in milliseconds (median sample spacing above 1 s: no tracker
samples that slowly) is read as such.

Beside each call: the tracker's call, distance, spin and bounce (the sample flagged ``bounce`` in the
shot, or the shot's ``bounce``) and the agreement: ``call_agrees`` (both in/out and equal),
``bounce_distance_mm`` and its components along / across the ball's path (> 0 along: ours is further).
"""

from __future__ import annotations

import dataclasses
import math
import os
import time
from collections import Counter
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass

import numpy as np

from tennislab.core.flight import FlightParams
from tennislab.errors import InputError, check_range
from tennislab.io.hawkeye import Point, ShotInfo, read_points
from tennislab.linecall.answer import CALLS, review_call
from tennislab.linecall.calls import call_track
from tennislab.linecall.detect import BOUNCE_Z, find_bounces, find_hits, travel_direction
from tennislab.linecall.fit import WHOLE_FLIGHT
from tennislab.results import Table, jsonable

SERVICE_LINE = 6.4  #: [m] the first hit of a point from behind this (|x|) is its serve (without shot records)
MATCH_TOL = 0.15  #: [s] a tracker's shot belongs to the hit within this time
TOSS_SPEED = 3.0  #: [m/s] samples before the first hit moving slower than this along the court: the toss
VOLLEY = "no bounce: the ball was hit again before it landed (volley); nothing to call"
DEAD_SPEED = 6.0  #: [m/s] a "shot" slower than this off the hit is the ball dribbling or rolling, not play
DEAD_AFTER = "the point was over: {why}; nothing to call"


@dataclass(frozen=True)
class Segment:
    """One shot of a point: sample rows [start, stop), the hit, the tracker's record, the target."""

    start: int
    stop: int
    shot: ShotInfo | None
    serve: bool
    target: str


@dataclass(frozen=True)
class RallyCall(Table):
    """Calls of every shot of one or more points (``tennislab call --rally --json`` is :meth:`to_dict`;
    ``rows()`` the ``--csv`` rows, one per shot, and ``to_frame()`` the same with units in every name)."""

    FRAME_COLUMNS = {
        "t_hit": "t_hit_s",
        "bounce_x": "bounce_x_m",
        "bounce_y": "bounce_y_m",
        "bounce_t": "bounce_t_s",
        "net_y": "net_y_m",
        "net_z": "net_z_m",
        "tracker_distance": "tracker_distance_m",
        "tracker_bounce_x": "tracker_bounce_x_m",
        "tracker_bounce_y": "tracker_bounce_y_m",
    }

    shots: tuple[dict, ...]
    points: tuple[dict, ...]
    summary: dict

    def to_dict(self) -> dict:
        return jsonable({"summary": self.summary, "points": list(self.points), "shots": list(self.shots)})

    def rows(self) -> list[dict]:
        """One flat row per shot (``--csv``; pandas-ready)."""
        return [shot_row(s) for s in self.shots]


def serve_target(x_hit: float, y_hit: float, fallback_deuce: bool = True) -> str:
    """The service box a serve struck at (x_hit, y_hit) must land in: the diagonally opposite box."""
    far = x_hit < 0
    sy = -math.copysign(1.0, y_hit) if abs(y_hit) > 1e-9 else (1.0 if far else -1.0) * (1 if fallback_deuce else -1)
    if far:
        return "deuce-box" if sy > 0 else "ad-box"
    return "near-deuce-box" if sy < 0 else "near-ad-box"


def rally_target(direction: float, doubles: bool = False) -> str:
    """The opponent's court for a shot travelling along ``direction`` (+1: toward +x)."""
    area = "doubles" if doubles else "singles"
    return area if direction > 0 else f"near-{area}"


def _index_at(t: np.ndarray, time_s: float) -> int:
    """First sample at or after ``time_s`` (0.1 ms of rounding allowed): samples before a hit belong to
    the flight before it."""
    i = int(np.searchsorted(t, time_s - 1e-4))
    return min(i, t.size - 1)


def split_point(point: Point, doubles: bool = False) -> list[Segment]:
    """Cut a point into shots (see the module docstring)."""
    t, xyz = point.t, point.xyz
    n = t.size
    if n == 0:
        return []
    hit_times = [te for te, k in point.events if k == "hit"]
    shots = [s for s in point.shots if s.time is not None]
    if hit_times:
        idx = sorted({_index_at(t, te) for te in hit_times})
    elif shots:
        idx = sorted({_index_at(t, s.time) for s in shots if s.time is not None})
    else:
        idx = find_hits(t, xyz)
        if not idx:
            idx = [0]
        elif idx[0] > 0 and not _toss(t[: idx[0] + 1], xyz[: idx[0] + 1]):
            idx = [0] + idx
    idx = [i for i in idx if i < n - 1] or [0]
    bounds = idx + [n]
    used: set[int] = set()
    out = []
    for k, (a, b) in enumerate(zip(bounds[:-1], bounds[1:])):
        if b - a < 1:
            continue
        rec = _match_shot(point.shots, t[a], k, len(idx), used)
        x0, y0, z0 = xyz[a]
        if rec is not None and rec.stroke is not None:
            serve = "serve" in rec.stroke
        else:  # the first shot of a point, struck from behind the service line
            serve = k == 0 and abs(x0) > SERVICE_LINE
        seg_t, seg_x = t[a:b], xyz[a:b]
        d = travel_direction(seg_t, seg_x) if b - a >= 2 else -math.copysign(1.0, x0)
        target = serve_target(x0, y0) if serve else rally_target(d, doubles)
        out.append(Segment(a, b, rec, serve, target))
    return out


def in_seconds(point: Point) -> Point:
    """The point with its clock in seconds: a median sample spacing above 1 s means milliseconds."""
    if point.t.size < 3 or float(np.median(np.diff(point.t))) <= 1.0:
        return point
    k = 1e-3
    shots = tuple(dataclasses.replace(s, time=None if s.time is None else s.time * k) for s in point.shots)
    return dataclasses.replace(
        point,
        t=point.t * k,
        events=tuple((te * k, kind) for te, kind in point.events),
        event_positions=tuple((te * k, kind, x, y, z) for te, kind, x, y, z in point.event_positions),
        shots=shots,
    )


def four_players(match: dict) -> bool:
    """A doubles match: the match record lists four players."""
    players = match.get("players") if isinstance(match, dict) else None
    return isinstance(players, list) and len(players) >= 4


def _toss(t: np.ndarray, xyz: np.ndarray) -> bool:
    """The samples before the first hit found are a serve's toss (the ball barely moves along the court)."""
    if t.size < 2 or t[-1] <= t[0]:
        return True
    return bool(abs(xyz[-1, 0] - xyz[0, 0]) / (t[-1] - t[0]) < TOSS_SPEED)


def _match_shot(shots: Sequence[ShotInfo], t_hit: float, k: int, n_hits: int, used: set[int]):
    """The tracker's record of the shot hit at ``t_hit``: the nearest in time (within
    :data:`MATCH_TOL`), or the k-th when the records carry no times and their number matches."""
    best, best_dt = None, MATCH_TOL
    for s in shots:
        if s.time is not None and s.index not in used and abs(s.time - t_hit) <= best_dt:
            best, best_dt = s, abs(s.time - t_hit)
    if best is None and len(shots) == n_hits and shots[k].time is None:
        best = shots[k]
    if best is not None:
        used.add(best.index)
    return best


def _tracker_bounce(point: Point, t0: float, t1: float, rec: ShotInfo | None):
    for te, kind, x, y, _z in point.event_positions:
        if kind == "bounce" and t0 <= te < t1:
            return (x, y)
    return None if rec is None else rec.bounce_xy


def _agreement(res: dict, rec: ShotInfo | None, tb) -> dict:
    out: dict = {"call_agrees": None, "bounce_distance_mm": None, "along_path_mm": None, "across_mm": None}
    theirs = None if rec is None else rec.call
    if theirs in ("in", "out") and res["call"] in ("in", "out", "let"):
        ours = "in" if res["call"] == "let" else res["call"]  # a let lands in: the tracker may say "in"
        out["call_agrees"] = ours == theirs
    elif theirs in ("net", "let") and res["call"] in CALLS:
        out["call_agrees"] = res["call"] == theirs
    b = res["bounce"]
    if tb is not None and b.get("x") is not None:
        dx, dy = b["x"] - tb[0], b["y"] - tb[1]
        out["bounce_distance_mm"] = 1000.0 * math.hypot(dx, dy)
        v = b.get("velocity_in")
        if v is not None and math.hypot(v[0], v[1]) > 0:
            h = np.array(v[:2]) / math.hypot(v[0], v[1])
            out["along_path_mm"] = 1000.0 * float(dx * h[0] + dy * h[1])
            out["across_mm"] = 1000.0 * float(-dx * h[1] + dy * h[0])
    return out


def _launch_speed(t: np.ndarray, xyz: np.ndarray) -> float:
    """Speed off the hit [m/s]: the mean velocity over the first three samples (NaN for fewer)."""
    if t.size < 3 or t[2] <= t[0]:
        return float("nan")
    return float(np.linalg.norm(xyz[2] - xyz[0]) / (t[2] - t[0]))


def _answer(call: str, reason: str, params, surface, n: int) -> dict:
    """A shot with no line to call (``volley``, ``dead``): the answer and its reason."""
    d = review_call([reason], params, surface, n_points=n).to_dict()
    d.update(call=call, provisional_call=None, review_reasons=[], reason=reason)
    return d


def _over(res: dict) -> str | None:
    """Why the point is over after this shot (None: play goes on)."""
    if res["call"] in ("out", "net"):
        return f"the shot before was {res['call']}"
    if res["call"] == "let":
        return "the serve before was a let"
    if res["call"] == "in" and res.get("bounces"):
        return "the shot before bounced twice"
    return None


def call_point(point: Point, *, params: FlightParams | None = None, doubles: bool = False, **kwargs) -> list[dict]:
    """Every shot of one point called (dicts: :class:`TrackCall` keys + the shot's keys).

    Besides in / out / net / let / review, a shot hit again before it landed is ``volley`` and a
    ball after the point is over (after an out, a net ball, a let or a ball that bounced twice, or a
    "shot" slower than :data:`DEAD_SPEED`: the ball dribbling or rolling) is ``dead``: neither has a
    line to call."""
    params = params or FlightParams()
    point = in_seconds(point)
    doubles = doubles or four_players(point.match)
    surface = kwargs.get("surface", "hard")
    out = []
    over: str | None = None
    segs = split_point(point, doubles)
    for k, seg in enumerate(segs):
        t, xyz = point.t[seg.start : seg.stop], point.xyz[seg.start : seg.stop]
        rec = seg.shot
        low = int(np.count_nonzero(xyz[:, 2] < BOUNCE_Z)) if t.size else 0
        volley = k + 1 < len(segs) and t.size > 0 and low < 2 and not find_bounces(t, xyz)
        slow = _launch_speed(t, xyz) < DEAD_SPEED
        if over is not None or slow:
            why = over or f"the ball left the hit at under {DEAD_SPEED:g} m/s (dribbling or rolling)"
            res = _answer("dead", DEAD_AFTER.format(why=why), params, surface, int(t.size))
            over = over or why
        elif volley:
            res = _answer("volley", VOLLEY, params, surface, int(t.size))
        else:
            res = call_track(
                t,
                xyz,
                params=params,
                target=seg.target,
                serve=seg.serve,
                strict=False,
                tracker_spin_rpm=None if rec is None else rec.spin_rpm,
                **kwargs,
            ).to_dict()
            over = _over(res)
        res["target"] = seg.target
        t_end = point.t[seg.stop] if seg.stop < point.t.size else math.inf
        tb = _tracker_bounce(point, float(t[0]), float(t_end), rec)
        d = {
            "point": point.name,
            "sequences": point.sequences,
            "shot": k,
            "shot_no": None if rec is None else rec.shot_no,
            "team": None if rec is None else rec.team,
            "stroke": ("serve" if seg.serve else None) if rec is None else rec.stroke,
            "serve": seg.serve,
            "t_hit": float(t[0]),
            "hit": xyz[0],
            "n_samples": int(t.size),
        }
        d.update(res)
        d["tracker"] = {
            "call": None if rec is None else rec.call,
            "distance": None if rec is None else rec.distance,
            "speed_ms": None if rec is None else rec.speed_ms,
            "spin_rpm": None if rec is None else rec.spin_rpm,
            "spin_type": None if rec is None else rec.spin_type,
            "bounce_x": None if tb is None else tb[0],
            "bounce_y": None if tb is None else tb[1],
        }
        d["agreement"] = _agreement(res, rec, tb)
        out.append(jsonable(d))
    return out


def _call_points(args) -> list[list[dict]]:
    points, params, doubles, kwargs = args
    return [call_point(p, params=params, doubles=doubles, **kwargs) for p in points]


def _stats(vals) -> dict:
    a = np.asarray([v for v in vals if v is not None], dtype=float)
    if a.size == 0:
        return {"n": 0, "median": None, "p90": None, "mean": None}
    return {
        "n": int(a.size),
        "median": float(np.median(a)),
        "p90": float(np.percentile(a, 90)),
        "mean": float(a.mean()),
    }


def summarize(shots: Sequence[dict], seconds: float) -> dict:
    """Counts of calls and reasons, agreement with the tracker, bounce distances, speed."""
    calls = Counter(s["call"] for s in shots)
    agree = [s["agreement"]["call_agrees"] for s in shots if s["agreement"]["call_agrees"] is not None]
    reasons: Counter = Counter()
    for s in shots:
        for r in s.get("review_reasons") or []:
            reasons[r.split(":")[0]] += 1
    out = {
        "n_shots": len(shots),
        "calls": {c: calls.get(c, 0) for c in CALLS},
        "review_reasons": dict(reasons.most_common()),
        "tracker_calls_compared": len(agree),
        "tracker_calls_agree": int(sum(agree)),
        "disagreements": [
            {"point": s["point"], "shot": s["shot"], "call": s["call"], "tracker_call": s["tracker"]["call"]}
            for s in shots
            if s["agreement"]["call_agrees"] is False
        ],
        "seconds": seconds,
        "calls_per_second": len(shots) / seconds if seconds > 0 else None,
    }
    for label, pick in (("all", lambda s: True), ("serve", lambda s: s["serve"]), ("rally", lambda s: not s["serve"])):
        sel = [s for s in shots if pick(s) and s["call"] in ("in", "out", "let")]
        out[f"bounce_distance_mm_{label}"] = _stats(s["agreement"]["bounce_distance_mm"] for s in sel)
        out[f"along_path_mm_{label}"] = _stats(s["agreement"]["along_path_mm"] for s in sel)
    return out


def _points(points) -> list[Point]:
    """The points of ``call_rally``: a file or a folder is read; read points are taken as they are."""
    if isinstance(points, (str, os.PathLike)):
        path = os.fspath(points)
        try:
            return read_points(path)
        except OSError as exc:
            raise InputError(f"points: {path}: {exc.strerror or exc}") from None
    if isinstance(points, Point):
        return [points]
    if isinstance(points, Sequence) and all(isinstance(p, Point) for p in points):
        return list(points)
    kinds = {type(p).__name__ for p in points if not isinstance(p, Point)} if isinstance(points, Sequence) else set()
    got = ", ".join(sorted(kinds)) or type(points).__name__
    raise InputError(f"points: expected a point file, a folder of them or read points (Point), got {got}")


def call_rally(
    points: str | os.PathLike | Point | Sequence[Point],
    *,
    params: FlightParams | None = None,
    surface="hard",
    doubles: bool = False,
    drag: str = "prior",
    lift: str = "prior",
    fit_drag: bool = False,
    contact_sigma: float = 0.0,
    window=WHOLE_FLIGHT,
    workers: int = 1,
    progress="auto",
) -> RallyCall:
    """Call every shot of the points (see the module docstring): ``points`` is a point JSON file or a
    folder of them (read by :func:`tennislab.io.hawkeye.read_points`, as ``call --rally``), or points
    already read; ``workers`` > 1 calls points in
    that many processes (the shots' order and numbers do not change).  ``progress``: points done and
    calls per second on stderr (:mod:`tennislab.batch.progress`: ``"auto"`` on a terminal for work
    over ~5 s, ``"always"``, True or False)."""
    params = params or FlightParams()
    pts = _points(points)
    if not pts:
        raise InputError("points: no points to call")
    workers = int(check_range("workers", workers, 1, 64))
    kwargs = dict(surface=surface, drag=drag, lift=lift, fit_drag=fit_drag, contact_sigma=contact_sigma, window=window)
    t0 = time.perf_counter()
    from tennislab.batch.progress import ProgressBar, progress_mode  # the batch package only when calling

    per_point: list[list[dict]] = []
    mode = progress_mode(progress)
    bar = ProgressBar(len(pts), enabled=mode is not None, mode=mode, unit="calls", chunk_unit="points")
    try:
        if workers == 1 or len(pts) == 1:
            for p in pts:
                per_point.append(call_point(p, params=params, doubles=doubles, **kwargs))
                bar.update(len(per_point[-1]))
        else:
            with ProcessPoolExecutor(max_workers=workers) as ex:  # one point a task, answered in order
                for part in ex.map(_call_points, [([p], params, doubles, kwargs) for p in pts]):
                    per_point.append(part[0])
                    bar.update(len(part[0]))
    finally:
        bar.close()
    seconds = time.perf_counter() - t0
    shots = tuple(s for lst in per_point for s in lst)
    info = tuple(
        {
            "point": p.name,
            "sequences": p.sequences,
            "n_samples": p.n_samples,
            "n_ball_samples": len(p),
            "n_without_ball": p.n_without_ball,
            "n_duplicate": p.n_duplicate,
            "n_shots": len(lst),
        }
        for p, lst in zip(pts, per_point)
    )
    return RallyCall(shots, info, summarize(shots, seconds))


ROW_KEYS = (
    "point",
    "shot",
    "shot_no",
    "team",
    "stroke",
    "serve",
    "t_hit",
    "target",
    "call",
    "provisional_call",
    "reason",
    "p_in",
    "distance_mm",
)


def shot_row(s: dict) -> dict:
    """One flat row of a called shot (the ``--csv`` columns)."""
    row = {k: s.get(k) for k in ROW_KEYS}
    b = s.get("bounce") or {}
    row.update({f"bounce_{k}": b.get(k) for k in ("x", "y", "t", "sigma_mm", "speed_in_ms")})
    f = s.get("fit") or {}
    row.update({f"fit_{k}": f.get(k) for k in ("rms_mm", "outliers", "n_points", "noise_mm", "drag_scale")})
    sp = s.get("spin") or {}
    row.update({f"spin_{k}": sp.get(k) for k in ("rpm", "topspin_rpm", "sidespin_rpm", "along_path_rpm")})
    n = s.get("net") or {}
    row.update({"net_contact": n.get("contact"), "net_y": n.get("y"), "net_z": n.get("z")})
    row["net_clearance_m"] = n.get("clearance_m")
    row["n_bounces"] = s.get("n_bounces")
    tr = s.get("tracker") or {}
    row.update({f"tracker_{k}": tr.get(k) for k in ("call", "distance", "spin_rpm", "bounce_x", "bounce_y")})
    ag = s.get("agreement") or {}
    row.update({k: ag.get(k) for k in ("call_agrees", "bounce_distance_mm", "along_path_mm", "across_mm")})
    return row


RallyCall.COLUMNS = tuple(shot_row({}))
