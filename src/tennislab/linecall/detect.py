"""What a raw ball track shows before any fit: hits, bounces, direction of travel and noise.

* :func:`find_hits` - racket contacts: a jump of the velocity (taken over about :data:`BASELINE` on
  each side of a sample) far above what gravity and drag change in that time (|dv| > :data:`HIT_DV`
  and > 6x the track's median),
  with the ball in the air (z > :data:`BOUNCE_Z`), away from the net (|x| > :data:`NET_ZONE`), the
  flight on either side of the sample changed (not a single outlier), and the ball turned back along
  the court or sped up (a serve out of the toss).
* :func:`find_bounces` - ground contacts: a local minimum of z below :data:`BOUNCE_Z` where the ball
  comes down and goes up again (by at least 2 cm within 0.15 s on each side), outliers (below the
  ground, or below the lines through their neighbours on both sides) set aside first.
* :func:`noise_from_differences` - the per-axis noise of the track without any model: third
  differences of equally spaced samples cancel a quadratic (drag changes the acceleration by
  ~100 m/s^3, i.e. < 1 mm at 50 Hz), and Var(p_i+3 - 3 p_i+2 + 3 p_i+1 - p_i) = 20 sigma^2 for white
  noise; the median absolute value (1.4826 MAD) keeps hits and bounces out.
* :func:`travel_direction` - +1 when the ball moves toward +x, -1 otherwise.
"""

from __future__ import annotations

import numpy as np

HIT_DV = 8.0  #: [m/s] smallest velocity jump taken as a hit
BOUNCE_Z = 0.3  #: [m] a ground contact has its lowest sample below this height (ball centre)
NET_ZONE = 1.0  #: [m] velocity jumps this close to the net plane are net contacts, not hits
MAX_GAP = 0.12  #: [s] frame pairs further apart than this are not used to detect a jump
MERGE = 0.06  #: [s] jumps closer than this are one event
BASELINE = 0.015  #: [s] velocities for the jumps are taken over about this long
BELOW_GROUND = -0.03  #: [m] a ball centre lower than this is an outlier (r minus a flattened ball and noise)


def stride(t) -> int:
    """Samples spanning about :data:`BASELINE` [s] (1 at 50 Hz, 5 at 340 Hz): velocities over this
    baseline keep the noise of high frame rates out of the jumps."""
    t = np.asarray(t, dtype=float)
    if t.size < 3:
        return 1
    dt = float(np.median(np.diff(t)))
    return max(1, int(round(BASELINE / dt))) if dt > 0 else 1


def velocity_jumps(t, xyz, s: int | None = None) -> np.ndarray:
    """|v_after - v_before| at each sample, the velocities over ``s`` samples (:func:`stride`) on
    each side [m/s] (0 near the ends and across gaps)."""
    t = np.asarray(t, dtype=float)
    xyz = np.asarray(xyz, dtype=float)
    n = t.size
    s = stride(t) if s is None else s
    out = np.zeros(n)
    if n < 2 * s + 1:
        return out
    i = np.arange(s, n - s)
    db = t[i] - t[i - s]
    da = t[i + s] - t[i]
    ok = (db > 0) & (da > 0) & (db <= MAX_GAP * s) & (da <= MAX_GAP * s)
    vb = (xyz[i] - xyz[i - s]) / np.where(ok, db, 1.0)[:, None]
    va = (xyz[i + s] - xyz[i]) / np.where(ok, da, 1.0)[:, None]
    out[i] = np.where(ok, np.linalg.norm(va - vb, axis=1), 0.0)
    return out


def _merge(idx: np.ndarray, t: np.ndarray, score: np.ndarray) -> list[int]:
    """One index per cluster of candidates closer than :data:`MERGE` (the highest score)."""
    out: list[int] = []
    for i in idx:
        if out and t[i] - t[out[-1]] < MERGE:
            if score[i] > score[out[-1]]:
                out[-1] = int(i)
        else:
            out.append(int(i))
    return out


def _side_velocity(t, xyz, i: int, side: int, s: int):
    """Velocity over ``s`` samples just before (side -1) or after (side +1) sample i, excluding i."""
    a, b = (i - 1 - s, i - 1) if side < 0 else (i + 1, i + 1 + s)
    if a < 0 or b >= t.size or not 0 < t[b] - t[a] <= MAX_GAP * s:
        return None
    return (xyz[b] - xyz[a]) / (t[b] - t[a])


def find_hits(t, xyz) -> list[int]:
    """Sample indices where a racket hit starts a new shot (see the module docstring).

    A candidate (a velocity jump at sample i) must also show the jump between the velocities of the
    two samples before i and the two after it, sample i left out: a single outlier makes two large
    jumps at i but leaves the flight on both sides of it unchanged.
    """
    t = np.asarray(t, dtype=float)
    xyz = np.asarray(xyz, dtype=float)
    n = t.size
    s = stride(t)
    if n < 2 * s + 3:
        return []
    jump = velocity_jumps(t, xyz, s)
    thr = max(HIT_DV, 6.0 * float(np.median(jump[s:-s])))
    cand = np.nonzero(jump > thr)[0]
    hits = []
    for i in _merge(cand, t, jump):
        if not s <= i <= n - s - 2:  # a hit needs samples after it to be told from an outlier
            continue
        if xyz[i, 2] < BOUNCE_Z or abs(xyz[i, 0]) < NET_ZONE:
            continue
        vb = _side_velocity(t, xyz, i, -1, s)
        va = _side_velocity(t, xyz, i, +1, s)
        if vb is None or va is None:
            vb = (xyz[i] - xyz[i - s]) / (t[i] - t[i - s]) if vb is None else vb
            va = (xyz[i + s] - xyz[i]) / (t[i + s] - t[i]) if va is None else va
        elif np.linalg.norm(va - vb) < thr:
            continue  # an outlier at i, not a hit
        turned = np.sign(vb[0]) != np.sign(va[0]) and abs(va[0]) > 2.0
        faster = np.linalg.norm(va) > np.linalg.norm(vb) + HIT_DV
        if turned or faster:
            hits.append(i)
    return hits


def find_bounces(t, xyz, rise: float = 0.02, span: float = 0.15) -> list[int]:
    """Sample indices of ground contacts (lowest sample of each), in time order.

    Samples below the ground (z < :data:`BELOW_GROUND`) or below the lines through their neighbours on
    both sides are outliers and are set aside first, so that one next to a bounce does not hide it.
    """
    t = np.asarray(t, dtype=float)
    z_all = np.asarray(xyz, dtype=float)[:, 2]
    keep = z_all >= BELOW_GROUND
    keep &= ~np.array([_below_both_sides(t, z_all, i) for i in range(t.size)], dtype=bool)
    rows = np.nonzero(keep)[0]
    t, z = t[rows], z_all[rows]
    n = t.size
    out: list[int] = []
    for i in range(1, n - 1):
        if z[i] >= BOUNCE_Z or z[i] > z[i - 1] or z[i] > z[i + 1]:
            continue
        before = (t >= t[i] - span) & (t < t[i])
        after = (t > t[i]) & (t <= t[i] + span)
        if not before.any() or not after.any():
            continue
        if z[before].max() - z[i] < rise or z[after].max() - z[i] < rise:
            continue
        if out and t[i] - t[out[-1]] < MERGE:
            if z[i] < z[out[-1]]:
                out[-1] = i
            continue
        out.append(i)
    return [int(rows[i]) for i in out]


def _below_both_sides(t, z, i: int, tol: float = 0.05) -> bool:
    """Sample i lies more than ``tol`` [m] below the straight lines through the two samples on each
    side of it: a bounce's lowest sample never does (both lines run into the ground), an outlier does."""
    if i < 2 or i > t.size - 3:
        return False
    zl = z[i - 1] + (z[i - 1] - z[i - 2]) * (t[i] - t[i - 1]) / (t[i - 1] - t[i - 2])
    zr = z[i + 1] + (z[i + 1] - z[i + 2]) * (t[i + 1] - t[i]) / (t[i + 2] - t[i + 1])
    return bool(z[i] < min(zl, zr) - tol)


def bounce_estimate(t, xyz, i: int, radius: float = 0.033) -> tuple[float, float, float]:
    """(t, x, y) where the last <= 5 samples before sample ``i`` (and ``i``) reach z = radius
    (quadratic in z, linear in x and y); the sample itself when that fails."""
    t = np.asarray(t, dtype=float)
    xyz = np.asarray(xyz, dtype=float)
    sel = np.arange(max(0, i - 5), i + 1)
    if sel.size >= 3:
        t0 = t[i]
        cz = np.polyfit(t[sel] - t0, xyz[sel, 2], 2)
        roots = np.roots(cz - np.array([0.0, 0.0, radius]))
        roots = np.real(roots[np.abs(np.imag(roots)) < 1e-9])
        roots = roots[(roots > -0.05) & (roots < 0.05)]
        if roots.size:
            tau = float(roots.min())
            cx = np.polyfit(t[sel] - t0, xyz[sel, 0], 1)
            cy = np.polyfit(t[sel] - t0, xyz[sel, 1], 1)
            return t0 + tau, float(np.polyval(cx, tau)), float(np.polyval(cy, tau))
    return float(t[i]), float(xyz[i, 0]), float(xyz[i, 1])


def noise_from_differences(t, xyz, tol: float = 0.1) -> float:
    """Per-axis noise [m] from third differences of equally spaced samples (NaN if < 4 usable)."""
    t = np.asarray(t, dtype=float)
    xyz = np.asarray(xyz, dtype=float)
    if t.size < 8:
        return float("nan")
    dt = np.diff(t)
    w = np.lib.stride_tricks.sliding_window_view(dt, 3)
    even = (w.max(axis=1) - w.min(axis=1)) <= tol * w.mean(axis=1)
    d3 = xyz[3:] - 3 * xyz[2:-1] + 3 * xyz[1:-2] - xyz[:-3]
    d3 = d3[even]
    if d3.shape[0] < 4:
        return float("nan")
    comp = d3.ravel()
    return float(1.4826 * np.median(np.abs(comp - np.median(comp))) / np.sqrt(20.0))


def travel_direction(t, xyz) -> float:
    """+1 when the ball travels toward +x over its first samples, else -1: the sign of the median
    x-velocity of the first (up to five, within 0.12 s) pairs of consecutive samples (robust to a
    stray sample; short, so that a ball the net sends back does not count)."""
    t = np.asarray(t, dtype=float)
    x = np.asarray(xyz, dtype=float)[:, 0]
    if t.size < 2:
        return 1.0
    sel = np.nonzero(t <= t[0] + 0.12)[0][:6]  # the first five pairs: the flight off the racket
    if sel.size < 3:
        sel = np.arange(min(3, t.size))
    vx = np.diff(x[sel]) / np.maximum(np.diff(t[sel]), 1e-9)
    m = float(np.median(vx))
    if m == 0.0:
        m = float(x[-1] - x[0])
    return 1.0 if m >= 0 else -1.0
