"""What a raw ball track shows before any fit: hits, bounces, direction of travel and noise.

* :func:`find_hits` - racket contacts: a jump of the velocity (taken over about :data:`BASELINE` on
  each side of a sample) far above what gravity and drag change in that time (|dv| > :data:`HIT_DV`
  and > 6x the track's median), single-sample outliers set aside first, with the ball in the air
  (z > :data:`BOUNCE_Z`), away from the net (|x| > :data:`NET_ZONE`), and the ball turned back along
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
MERGE = 0.15  #: [s] jumps closer than this are one event (no two hits of a rally come this close)
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
    """The velocity jump at each sample [m/s] (0 near the ends and across gaps): the larger of
    |v(i, i+s) - v(i-s, i)| (a hit at sample i) and |v(i, i+s) - v(i-1-s, i-1)| (a hit between
    samples i-1 and i, which splits the first measure over two samples), velocities over ``s``
    samples (:func:`stride`)."""
    t = np.asarray(t, dtype=float)
    xyz = np.asarray(xyz, dtype=float)
    n = t.size
    s = stride(t) if s is None else s
    out = np.zeros(n)
    if n < 2 * s + 2:
        return out

    def vel(a, b):
        dt = t[b] - t[a]
        ok = (dt > 0) & (dt <= MAX_GAP * s)
        return (xyz[b] - xyz[a]) / np.where(ok, dt, 1.0)[:, None], ok

    i = np.arange(s + 1, n - s)
    va, oka = vel(i, i + s)
    vb, okb = vel(i - s, i)
    vg, okg = vel(i - 1 - s, i - 1)
    j1 = np.where(oka & okb, np.linalg.norm(va - vb, axis=1), 0.0)
    j2 = np.where(oka & okg, np.linalg.norm(va - vg, axis=1), 0.0)
    out[i] = np.maximum(j1, j2)
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


def single_outliers(t, xyz, tol: float | None = None) -> np.ndarray:
    """Samples that leave the flight for one frame: the quadratic through the three samples before
    (or after) sample i misses it by more than max(2 ``tol``, 15 cm) but meets the sample beyond it
    within ``tol`` [m] (a hit or a bounce changes the flight for good and meets neither).  ``tol``
    defaults to max(5 cm, 30 x the track's per-axis noise): extrapolating a quadratic two frames
    multiplies the noise by sqrt(3^2 + 8^2 + 6^2) = 10.4 per axis, 18 in 3-D."""
    t = np.asarray(t, dtype=float)
    xyz = np.asarray(xyz, dtype=float)
    n = t.size
    out = np.zeros(n, dtype=bool)
    if tol is None:
        noise = noise_from_differences(t, xyz)
        tol = max(0.05, 30.0 * noise) if np.isfinite(noise) else 0.05

    def miss(idx, at) -> float:
        t0 = t[idx[-1]]
        if np.ptp(t[idx]) <= 0 or abs(t[at] - t0) > 0.2:
            return float("inf")
        c = np.polyfit(t[idx] - t0, xyz[idx], 2)  # (3 coefficients, 3 axes)
        tau = t[at] - t0
        return float(np.linalg.norm(c[0] * tau * tau + c[1] * tau + c[2] - xyz[at]))

    for i in range(n):
        for side in (-1, 1):
            if side < 0 and 3 <= i < n - 1:
                idx, beyond = np.array([i - 3, i - 2, i - 1]), i + 1
            elif side > 0 and 1 <= i < n - 3:
                idx, beyond = np.array([i + 3, i + 2, i + 1]), i - 1
            else:
                continue
            if miss(idx, i) > max(2 * tol, 0.15) and miss(idx, beyond) < tol:
                out[i] = True
                break
    return out


def find_hits(t, xyz) -> list[int]:
    """Sample indices where a racket hit starts a new shot (see the module docstring).

    Single-sample outliers (:func:`single_outliers`) are set aside first, so that an outlier next to a
    hit can neither make a hit nor hide one.
    """
    t = np.asarray(t, dtype=float)
    xyz = np.asarray(xyz, dtype=float)
    n = t.size
    s = stride(t)
    if n < 2 * s + 3:
        return []
    jump = velocity_jumps(t, xyz, s)
    thr = max(HIT_DV, 6.0 * float(np.median(jump[s:-s])))
    rows = np.nonzero(~single_outliers(t, xyz))[0]
    tc, xc = t[rows], xyz[rows]
    nc = tc.size
    if nc < 2 * s + 3:
        return []
    jump = velocity_jumps(tc, xc, s)
    hits = []
    for i in np.nonzero(jump > thr)[0]:
        if not s + 1 <= i <= nc - s - 2:  # a hit needs samples after it
            continue
        if xc[i, 2] < BOUNCE_Z or abs(xc[i, 0]) < NET_ZONE:
            continue
        vb = (xc[i - 1] - xc[i - 1 - s]) / (tc[i - 1] - tc[i - 1 - s])
        va = (xc[i + s] - xc[i]) / (tc[i + s] - tc[i])
        turned = np.sign(vb[0]) != np.sign(va[0]) and abs(va[0]) > 2.0
        faster = np.linalg.norm(va) > np.linalg.norm(vb) + HIT_DV
        if turned or faster:
            hits.append(int(i))
    return [int(rows[i]) for i in _merge(np.asarray(hits, dtype=int), tc, jump)]


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


GRID_TOL = 0.025  #: a sample further than this fraction of the spacing from the grid is off it (0.5 ms at 50 Hz)
GRID_SHARE = 0.8  #: a track is on a grid when at least this share of its samples are


def off_grid(t) -> np.ndarray:
    """Samples off a track's regular sample grid, when it has one (else none).

    Trackers add samples at the times they estimate for events (the hit, the net crossing, the
    bounce, the apex), with times rounded to the millisecond: at 20-50 m/s the rounding alone is
    10-25 mm of path (README of the 50 Hz match data), so such a sample is not a measurement of the
    flight.  A track is on a grid when at least :data:`GRID_SHARE` of its samples lie within
    :data:`GRID_TOL` of the spacing of a regular grid; raw detections with jittered times are not,
    and keep every sample."""
    t = np.asarray(t, dtype=float)
    out = np.zeros(t.size, dtype=bool)
    if t.size < 8:
        return out
    dt = float(np.median(np.diff(t)))
    if not dt > 0:
        return out
    frac = (t - t[0]) / dt
    frac = frac - np.round(frac)
    ref = float(np.median(frac))
    dev = np.abs(((frac - ref + 0.5) % 1.0) - 0.5)
    off = dev > GRID_TOL
    if np.count_nonzero(~off) < GRID_SHARE * t.size:
        return out
    return off
