"""Free flights for the aerodynamic identification: hit to first bounce from tracker points, or CSV tracks.

A :class:`Flight` is one stretch of free flight (no hit, no bounce): sample times and ball-centre
positions, with what the tracker says of the shot (serve or not, its spin and speed estimates) and the
point's game (the split by game parity).

**From point JSON** (:func:`flights_from_points`; points read by :func:`tennislab.io.hawkeye.read_points`):
each hit starts a flight that ends at the first bounce before the next hit (a shot hit again before it
lands, a volley, gives none).  Hits are the samples flagged ``hit``, else the tracker's shot times, else
``find_hits(t, xyz)``; bounces the samples flagged ``bounce``, else ``find_bounces(t, xyz)`` (both return
sample indices: pass :func:`tennislab.linecall.find_hits` / :func:`~tennislab.linecall.find_bounces`;
the calibration does not import the line-calling package, so the caller supplies its detectors).  The
samples strictly between the hit and the bounce are kept; when most samples lie on a regular time grid
(a tracker's fitted trajectory stored every 20 ms, say), the samples off that grid are left out: the
tracker's hit, bounce, net and apex samples, whose times are rounded to the millisecond (0.5 ms is
10-30 mm of path at these speeds: README of ``../shared/realdata``).  A flight with a contact in it (a
net cord, or a gross outlier that looks like one: :func:`velocity_jump`) is cut before it; gross outliers
left in the rest (:func:`outliers`) are left out.

**From CSV tracks** (:func:`flights_from_tracks`): each track is one free flight as it is.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from tennislab.errors import InputError
from tennislab.io.hawkeye import Point, ShotInfo
from tennislab.io.track import Track

MIN_SAMPLES = 8  #: fewest samples of a flight used (fewer cannot tell drag from the launch state)
GRID_SHARE = 0.8  #: share of samples on one time grid above which off-grid samples are left out
GRID_TOL = 0.01  #: [grid steps] how far from the grid a sample may sit and count as on it
EVENT_GAP = 5e-4  #: [s] samples this close to a hit or bounce time are left out (the event itself)
MATCH_TOL = 0.15  #: [s] a tracker's shot record belongs to the hit within this time
SERVICE_LINE = 6.4  #: [m] without shot records, a point's first hit from behind this (|x|) is its serve
#: [m/s] a change of velocity this large between the samples before and after one sample is a contact
#: (the net cord, a frame): no drag or lift changes a ball's velocity by as much within a window
JUMP_DV = 3.0
JUMP_WINDOW = 0.08  #: [s] the windows (each side, at least 3 samples) whose quadratic fits are compared
#: [m] a sample this far from the quadratic through its six neighbours is a gross outlier (a tracker's
#: wrong detection) and is left out before the contact check (3 mm of noise moves it by ~1 cm)
OUTLIER_TOL = 0.03

#: a detector: sample indices (time order) of hits or bounces in a track ``(t (n,), xyz (n, 3))``
Detector = Callable[[np.ndarray, np.ndarray], Sequence[int]]


@dataclass(frozen=True)
class Flight:
    """One free flight: times ``t`` (n,) [s], positions ``xyz`` (n, 3) [m], optional per-sample
    ``sigma`` (n,) [m]; ``serve`` (the tracker's stroke, or a point's first hit from behind the service
    line); the tracker's ``spin_rpm`` (signed as it gives it) and ``speed_ms`` when known; ``game`` (the
    point's game number, ``None`` for a CSV track); ``index`` its place in the input (0-based)."""

    name: str
    t: np.ndarray
    xyz: np.ndarray
    sigma: np.ndarray | None = None
    serve: bool | None = None
    spin_rpm: float | None = None
    speed_ms: float | None = None
    game: int | None = None
    index: int = 0

    def __len__(self) -> int:
        return int(self.t.size)

    @property
    def duration(self) -> float:
        """[s] from the first to the last sample."""
        return float(self.t[-1] - self.t[0]) if self.t.size else 0.0

    @property
    def kind(self) -> str:
        """``serve``, ``rally`` or ``track`` (a CSV track, nothing known of its stroke)."""
        if self.serve is None:
            return "track"
        return "serve" if self.serve else "rally"


def on_grid(t: np.ndarray) -> np.ndarray:
    """Mask of the samples on the dominant regular time grid (all True when under :data:`GRID_SHARE`
    of them lie on one)."""
    t = np.asarray(t, dtype=float)
    keep = np.ones(t.size, dtype=bool)
    if t.size < 8:
        return keep
    dt = float(np.median(np.diff(t)))
    if not dt > 0.0:
        return keep
    turns = t / dt
    ref = float(np.angle(np.mean(np.exp(2j * np.pi * turns)))) / (2 * np.pi)  # the grid's phase (circular mean)
    dist = np.abs((turns - ref + 0.5) % 1.0 - 0.5)
    grid = dist < GRID_TOL
    return grid if grid.mean() >= GRID_SHARE else keep


def outliers(t: np.ndarray, xyz: np.ndarray) -> np.ndarray:
    """Mask of the samples farther than :data:`OUTLIER_TOL` from the quadratic in time through their
    (up to) three neighbours on each side."""
    n = t.size
    bad = np.zeros(n, dtype=bool)
    for i in range(n):
        nb = [j for j in range(max(0, i - 3), min(n, i + 4)) if j != i]
        if len(nb) < 5:
            continue
        tt = t[nb] - t[i]
        coef, *_ = np.linalg.lstsq(np.vander(tt, 3), xyz[nb], rcond=None)
        bad[i] = float(np.linalg.norm(xyz[i] - coef[2])) > OUTLIER_TOL
    return bad


def velocity_jump(t: np.ndarray, xyz: np.ndarray) -> int | None:
    """Index of the first sample where the velocity of a quadratic fit of the samples before it (within
    :data:`JUMP_WINDOW`, at least 3) and that of the samples after it differ by more than
    :data:`JUMP_DV` (a contact: the ball is not in free flight across it), or ``None``.

    A free flight's own jerk (drag changing with speed) moves the two estimates by ~0.1 m/s over such
    windows; a net cord or a deflection by metres per second.
    """
    n = t.size
    for i in range(3, n - 3):
        lo = min(i - 2, int(np.searchsorted(t, t[i] - JUMP_WINDOW)))
        hi = max(i + 3, int(np.searchsorted(t, t[i] + JUMP_WINDOW, side="right")))
        vb = _slope(t[lo : i + 1] - t[i], xyz[lo : i + 1])
        va = _slope(t[i:hi] - t[i], xyz[i:hi])
        if float(np.linalg.norm(va - vb)) > JUMP_DV:
            return i
    return None


def _slope(tt: np.ndarray, xx: np.ndarray) -> np.ndarray:
    """Velocity at tt = 0 of the least-squares quadratic through (tt, xx)."""
    a = np.vander(tt, 3)
    coef, *_ = np.linalg.lstsq(a, xx, rcond=None)
    return coef[1]


def _times(point: Point, kind: str, detector: Detector | None, what: str) -> list[float]:
    """Times of the point's ``kind`` events; when it has no hit or bounce events at all, the shot
    times (hits) or the detector's samples."""
    if any(k in ("hit", "bounce") for _, k in point.events):
        return sorted(te for te, k in point.events if k == kind)
    if kind == "hit":
        shots = sorted(s.time for s in point.shots if s.time is not None)
        if shots:
            return shots
    if detector is None:
        raise InputError(
            f"points: {point.name} has no {kind} events; pass a {what} detector "
            f"(find_{kind}s=tennislab.linecall.find_{kind}s) to find them in the track"
        )
    idx = [int(i) for i in detector(point.t, point.xyz)]
    return [float(point.t[i]) for i in idx if 0 <= i < point.t.size]


def _record(point: Point, t_hit: float) -> ShotInfo | None:
    best = None
    for s in point.shots:
        if s.time is not None and abs(s.time - t_hit) < MATCH_TOL:
            if best is None or abs(s.time - t_hit) < abs((best.time or 0.0) - t_hit):
                best = s
    return best


def flights_from_points(
    points: Sequence[Point],
    *,
    find_hits: Detector | None = None,
    find_bounces: Detector | None = None,
    min_samples: int = MIN_SAMPLES,
    skipped: dict | None = None,
) -> list[Flight]:
    """The hit-to-first-bounce flights of tracker points (module docstring), in point order.

    ``skipped`` (a dict, when given) counts what was left out: ``no_bounce`` (hit again or the point
    over before a bounce), ``few_samples`` (fewer than ``min_samples`` samples), ``outliers`` (samples
    left out, :func:`outliers`), and ``contact`` counts flights cut short at a contact
    (:func:`velocity_jump`; the part before it is kept).
    """
    out: list[Flight] = []
    count = skipped if skipped is not None else {}
    for key in ("no_bounce", "few_samples", "contact", "outliers"):
        count.setdefault(key, 0)
    for point in points:
        if point.t.size < min_samples:
            continue
        hits = _times(point, "hit", find_hits, "hit")
        bounces = _times(point, "bounce", find_bounces, "bounce")
        grid = on_grid(point.t)
        game = point.sequences.get("game")
        for j, th in enumerate(hits):
            tn = hits[j + 1] if j + 1 < len(hits) else math.inf
            tb = next((b for b in bounces if th < b < tn), None)
            if tb is None:
                count["no_bounce"] += 1
                continue
            sel = np.nonzero(grid & (point.t > th + EVENT_GAP) & (point.t < tb - EVENT_GAP))[0]
            jump = velocity_jump(point.t[sel], point.xyz[sel]) if sel.size >= min_samples else None
            if jump is not None:  # a net cord (or a gross outlier): the flight before it
                sel = sel[: max(jump - 1, 0)]
                count["contact"] += 1
            if sel.size >= min_samples:  # outliers after the cut: their kinks would hide a contact
                bad = outliers(point.t[sel], point.xyz[sel])
                count["outliers"] += int(bad.sum())
                sel = sel[~bad]
            if sel.size < min_samples:
                count["few_samples"] += 1
                continue
            rec = _record(point, th)
            if rec is not None and rec.stroke is not None:
                serve = "serve" in rec.stroke.lower()
            else:
                serve = j == 0 and abs(float(point.xyz[sel[0], 0])) > SERVICE_LINE
            out.append(
                Flight(
                    name=f"{point.name}#{j + 1}",
                    t=np.ascontiguousarray(point.t[sel]),
                    xyz=np.ascontiguousarray(point.xyz[sel]),
                    serve=serve,
                    spin_rpm=None if rec is None else rec.spin_rpm,
                    speed_ms=None if rec is None else rec.speed_ms,
                    game=None if game is None else int(game),
                    index=len(out),
                )
            )
    return out


def flights_from_tracks(tracks: Sequence[Track], names: Sequence[str] | None = None) -> list[Flight]:
    """Each CSV track as one free flight."""
    out = []
    for i, tr in enumerate(tracks):
        name = names[i] if names is not None else f"track {i + 1}"
        out.append(
            Flight(
                name=name,
                t=np.ascontiguousarray(tr.t, dtype=float),
                xyz=np.ascontiguousarray(tr.xyz, dtype=float),
                sigma=None if tr.sigma is None else np.ascontiguousarray(tr.sigma, dtype=float),
                index=i,
            )
        )
    return out
